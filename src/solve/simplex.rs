//! A small dense simplex for the uniform method's LPs (issue 27): minimize cᵀx subject to
//! A x ≤ b and lo ≤ x ≤ hi (±∞ allowed), the form of [`crate::uniform::Lp`].
//!
//! Why: the uniform report solves some 270 LPs of 15–30 columns and 30–60 rows; clarabel's
//! interior point pays a sparse KKT factorization per iteration and ~10–20 iterations for
//! each, where a simplex on a 30 × 75 tableau needs a few dozen pivots cold and a handful warm.
//! Only the objective changes between the optimal face's ranges, so [`Simplex::minimize`]
//! starts from the previous optimal basis, which stays primal feasible.
//!
//! The method: a bounded-variable primal simplex on a dense tableau of [A I −E] (slacks s ≥ 0,
//! and one artificial per row whose slack starts negative), Phase I minimizing the
//! artificials, Dantzig's rule switching to Bland's after a run of degenerate pivots (which
//! rules out cycling), and an iteration cap. The rows are scaled by powers of two (exact) so
//! that every row's largest coefficient is in [1, 2) and the tolerances are relative.
//!
//! It never gives a false answer: every result is checked against the problem's data before
//! it is returned, and anything it cannot certify is [`Outcome::Uncertain`], on which the
//! caller falls back to clarabel ([`crate::solve`]).
//! * An optimum: the vertex is recomputed from the basis by a fresh LU of the data's columns,
//!   checked primal feasible (every row and bound to 10⁻⁹ of its own magnitude), and the duals
//!   λ ≤ 0 from the same basis give the Lagrangian bound
//!   cᵀx' ≥ λᵀb + Σⱼ minₓⱼ∈[loⱼ,hiⱼ] (c − Aᵀλ)ⱼ xⱼ for every feasible x'; the duality gap must
//!   be within 10⁻⁹ of the objective's terms.
//! * Infeasible: the same bound on the Phase I problem (min Σ artificials) is positive beyond
//!   rounding: no point has all artificials zero.
//! * Unbounded: a ray d with A d ≤ 0, d within the box's recession cone and cᵀd < 0, checked on
//!   the data.

use nalgebra::{DMatrix, DVector};
use std::cell::Cell;

/// Which solver the uniform method's LPs use: [`Engine::Simplex`] (the default, clarabel where
/// it cannot certify) or [`Engine::Clarabel`] only (the oracle of the tests and benchmarks).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Engine {
    Simplex,
    Clarabel,
}

thread_local! {
    static ENGINE: Cell<Engine> = const { Cell::new(Engine::Simplex) };
}

/// The engine in force on this thread.
pub fn engine() -> Engine {
    ENGINE.with(|e| e.get())
}

/// Run `f` with `engine` on this thread (restored afterwards, also on a panic): the tests
/// compare the simplex with clarabel on the same scenario this way.
pub fn with_engine<T>(engine: Engine, f: impl FnOnce() -> T) -> T {
    struct Restore(Engine);
    impl Drop for Restore {
        fn drop(&mut self) {
            ENGINE.with(|e| e.set(self.0));
        }
    }
    let _restore = Restore(ENGINE.with(|e| e.replace(engine)));
    f()
}

/// A certified optimum.
#[derive(Debug, Clone)]
pub struct Optimum {
    pub x: DVector<f64>,
    pub objective: f64,
    /// Multipliers of the rows A x ≤ b, ≥ 0 (clarabel's sign convention).
    pub duals: DVector<f64>,
    /// Simplex pivots and bound flips of this solve (both phases).
    pub iterations: u32,
}

/// What a solve found.
#[derive(Debug, Clone)]
pub enum Outcome {
    Optimal(Optimum),
    /// Certified: no x satisfies the constraints.
    Infeasible,
    /// Certified: the objective decreases without bound.
    Unbounded,
    /// No certificate (iteration cap, a singular basis, a check that failed): ask clarabel.
    Uncertain(&'static str),
}

/// Relative accuracy every certificate is checked to.
pub const CERTIFY: f64 = 1e-9;

/// Pivots smaller than this (the rows' largest coefficient is about 1) are refused.
const PIVOT: f64 = 1e-9;

/// Degenerate pivots in a row after which Bland's rule takes over.
const DEGENERATE_RUN: usize = 30;

/// a · b with four partial sums (a plain `sum` keeps the order of the additions, which stops
/// the compiler from vectorizing it: this dot was a quarter of a long window's solve).
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail: f64 = ca
        .remainder()
        .iter()
        .zip(cb.remainder())
        .map(|(x, y)| x * y)
        .sum();
    for (x, y) in ca.zip(cb) {
        for k in 0..4 {
            acc[k] += x[k] * y[k];
        }
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// The bounds a variable is held between.
#[derive(Debug, Clone, Copy)]
struct Bounds {
    lo: f64,
    hi: f64,
}

/// A loaded LP and its current basis: min cᵀx s.t. A x ≤ b, lo ≤ x ≤ hi.
#[derive(Debug, Clone)]
pub struct Simplex {
    /// Rows scaled by `scale` (powers of two).
    a: DMatrix<f64>,
    b: DVector<f64>,
    scale: Vec<f64>,
    /// x (n), slacks (m), artificials (m).
    n: usize,
    m: usize,
    bounds: Vec<Bounds>,
    /// B⁻¹ [A I −E], row-major m × (n + 2m).
    tableau: Vec<f64>,
    /// The basic variable of each row.
    basis: Vec<usize>,
    /// Whether each variable is basic.
    is_basic: Vec<bool>,
    /// Every variable's value (nonbasic ones at a bound, or 0 when free).
    value: Vec<f64>,
    /// Phase I is done and the basis is primal feasible.
    feasible: bool,
    /// The problem has been certified infeasible.
    infeasible: bool,
    /// The artificial block of the tableau is kept up to date (Phase I may run).
    artificials_live: bool,
}

impl Simplex {
    /// Load the LP. `None` when the shapes disagree or a coefficient is not finite (the
    /// caller's solver reports those).
    pub fn new(
        a: &DMatrix<f64>,
        b: &DVector<f64>,
        lo: &DVector<f64>,
        hi: &DVector<f64>,
    ) -> Option<Simplex> {
        let (m, n) = a.shape();
        if b.len() != m || lo.len() != n || hi.len() != n {
            return None;
        }
        if !a.iter().chain(b.iter()).all(|v| v.is_finite())
            || lo.iter().chain(hi.iter()).any(|v| v.is_nan())
            || (0..n).any(|j| lo[j] > hi[j] || lo[j] == f64::INFINITY || hi[j] == -f64::INFINITY)
        {
            return None;
        }
        let mut a = a.clone();
        let mut b = b.clone();
        let mut scale = vec![1.0; m];
        for i in 0..m {
            let big = a.row(i).amax();
            if big > 0.0 {
                // 1 / the power of two at or below the row's largest |coefficient|: exact.
                let s = 1.0 / super::power_of_two_below(big);
                if !s.is_finite() {
                    return None;
                }
                scale[i] = s;
                a.row_mut(i).scale_mut(s);
                b[i] *= s;
            }
        }
        let width = n + 2 * m;
        let mut bounds = Vec::with_capacity(width);
        bounds.extend((0..n).map(|j| Bounds {
            lo: lo[j],
            hi: hi[j],
        }));
        bounds.extend((0..m).map(|_| Bounds {
            lo: 0.0,
            hi: f64::INFINITY,
        }));
        bounds.extend((0..m).map(|_| Bounds { lo: 0.0, hi: 0.0 }));
        let mut s = Simplex {
            a,
            b,
            scale,
            n,
            m,
            bounds,
            tableau: vec![0.0; m * width],
            basis: vec![0; m],
            is_basic: vec![false; width],
            value: vec![0.0; width],
            feasible: false,
            infeasible: false,
            artificials_live: true,
        };
        s.slack_basis();
        Some(s)
    }

    fn width(&self) -> usize {
        self.n + 2 * self.m
    }

    /// The starting basis: x at a finite bound (the lower one first; 0 when free), each row's
    /// slack basic where it comes out ≥ 0, else its artificial (−e_i) at the shortfall.
    fn slack_basis(&mut self) {
        let (n, m, w) = (self.n, self.m, self.width());
        for j in 0..n {
            let bd = self.bounds[j];
            self.value[j] = if bd.lo.is_finite() {
                bd.lo
            } else if bd.hi.is_finite() {
                bd.hi
            } else {
                0.0
            };
        }
        self.is_basic.iter_mut().for_each(|v| *v = false);
        for i in 0..m {
            let r = self.b[i] - (0..n).map(|j| self.a[(i, j)] * self.value[j]).sum::<f64>();
            let (var, sign) = if r >= 0.0 {
                (n + i, 1.0)
            } else {
                (n + m + i, -1.0)
            };
            let row = &mut self.tableau[i * w..(i + 1) * w];
            row.iter_mut().for_each(|v| *v = 0.0);
            for (j, v) in row[..n].iter_mut().enumerate() {
                *v = sign * self.a[(i, j)];
            }
            row[n + i] = sign;
            row[n + m + i] = -sign;
            self.basis[i] = var;
            self.is_basic[var] = true;
            self.value[n + i] = r.max(0.0);
            self.value[n + m + i] = (-r).max(0.0);
            // Artificials may hold a value during Phase I only.
            self.bounds[n + m + i] = Bounds {
                lo: 0.0,
                hi: if r < 0.0 { f64::INFINITY } else { 0.0 },
            };
        }
        self.feasible = false;
        self.infeasible = false;
        self.artificials_live = true;
    }

    /// Gauss–Jordan pivot on (row r, column j).
    fn pivot(&mut self, r: usize, j: usize) {
        let w = self.width();
        // The artificial block is read only by Phase I; outside it, it is left stale (every
        // path into Phase I rebuilds the tableau: `slack_basis`).
        let live = if self.artificials_live {
            w
        } else {
            self.n + self.m
        };
        let p = self.tableau[r * w + j];
        let (before, rest) = self.tableau.split_at_mut(r * w);
        let (prow, after) = rest.split_at_mut(w);
        prow[..live].iter_mut().for_each(|v| *v /= p);
        prow[j] = 1.0;
        // The pivot row's nonzeros: the LPs' rows are sparse, and so mostly stays B⁻¹ M.
        let nonzero: Vec<usize> = (0..live).filter(|&k| prow[k] != 0.0).collect();
        for row in before.chunks_mut(w).chain(after.chunks_mut(w)) {
            let f = row[j];
            if f != 0.0 {
                for &k in &nonzero {
                    row[k] -= f * prow[k];
                }
                row[j] = 0.0;
            }
        }
        let leaving = self.basis[r];
        self.is_basic[leaving] = false;
        self.is_basic[j] = true;
        self.basis[r] = j;
    }

    /// Reduced costs d = c − c_Bᵀ B⁻¹ M of every variable for costs `cost`.
    fn reduced_costs(&self, cost: &[f64]) -> Vec<f64> {
        let w = self.width();
        let mut d = cost.to_vec();
        for (i, &bv) in self.basis.iter().enumerate() {
            let cb = cost[bv];
            if cb != 0.0 {
                for (dj, &t) in d.iter_mut().zip(&self.tableau[i * w..(i + 1) * w]) {
                    *dj -= cb * t;
                }
            }
        }
        d
    }

    /// Primal simplex from the current (primal feasible) basis for costs `cost` over all
    /// variables; artificials enter only when `phase_one`. Returns Ok(iterations), or Err when
    /// unbounded (with the entering column) or stuck.
    fn iterate(&mut self, cost: &[f64], phase_one: bool, cap: usize) -> Result<usize, Stop> {
        let (n, m, w) = (self.n, self.m, self.width());
        let entering_limit = if phase_one { w } else { n + m };
        let cmax = cost
            .iter()
            .fold(0.0f64, |a, v| a.max(v.abs()))
            .max(f64::MIN_POSITIVE);
        let dtol = 1e-11 * cmax;
        let mut d = self.reduced_costs(cost);
        let mut degenerate = 0usize;
        for iteration in 0..cap {
            let bland = degenerate >= DEGENERATE_RUN;
            // Pricing: Dantzig (largest |d_j|) or Bland (smallest index).
            let mut enter: Option<(usize, f64)> = None;
            for (j, &dj) in d.iter().enumerate().take(entering_limit) {
                if self.is_basic[j] {
                    continue;
                }
                let bd = self.bounds[j];
                let up = dj < -dtol && self.value[j] < bd.hi;
                let down = dj > dtol && self.value[j] > bd.lo;
                if !(up || down) {
                    continue;
                }
                if bland {
                    enter = Some((j, dj));
                    break;
                }
                if enter.is_none_or(|(_, best)| dj.abs() > best.abs()) {
                    enter = Some((j, dj));
                }
            }
            let Some((j, dj)) = enter else {
                return Ok(iteration);
            };
            let dir = if dj < 0.0 { 1.0 } else { -1.0 };
            // Ratio test: the entering variable's own range, then every basic variable's.
            let bd = self.bounds[j];
            let mut theta = bd.hi - bd.lo;
            let mut leave: Option<(usize, f64)> = None;
            for i in 0..m {
                let alpha = dir * self.tableau[i * w + j];
                if alpha.abs() <= PIVOT {
                    continue;
                }
                let bv = self.basis[i];
                let (v, bb) = (self.value[bv], self.bounds[bv]);
                let limit = if alpha > 0.0 {
                    if bb.lo == f64::NEG_INFINITY {
                        continue;
                    }
                    (v - bb.lo).max(0.0) / alpha
                } else {
                    if bb.hi == f64::INFINITY {
                        continue;
                    }
                    (bb.hi - v).max(0.0) / -alpha
                };
                let better = match leave {
                    None => limit < theta,
                    Some((r, _)) => {
                        let tie = (limit - theta).abs() <= 1e-12 * (1.0 + theta.abs());
                        if tie {
                            if bland {
                                bv < self.basis[r]
                            } else {
                                alpha.abs() > self.tableau[r * w + j].abs()
                            }
                        } else {
                            limit < theta
                        }
                    }
                };
                if better {
                    theta = limit;
                    leave = Some((i, alpha));
                }
            }
            if theta == f64::INFINITY {
                return Err(Stop::Unbounded(j, dir));
            }
            if theta <= 1e-13 * (1.0 + self.value[j].abs()) {
                degenerate += 1;
            } else {
                degenerate = 0;
            }
            // Move: the entering variable by dir·θ, the basic ones along its column.
            self.value[j] += dir * theta;
            for i in 0..m {
                let t = self.tableau[i * w + j];
                if t != 0.0 {
                    self.value[self.basis[i]] -= dir * t * theta;
                }
            }
            match leave {
                None => {
                    // A bound flip: the entering variable crossed its own range.
                    self.value[j] = if dir > 0.0 { bd.hi } else { bd.lo };
                }
                Some((r, alpha)) => {
                    let bv = self.basis[r];
                    let bb = self.bounds[bv];
                    self.value[bv] = if alpha > 0.0 { bb.lo } else { bb.hi };
                    self.pivot(r, j);
                    // d ← d − d_j · (new row r).
                    let f = d[j];
                    for (dk, &t) in d.iter_mut().zip(&self.tableau[r * w..(r + 1) * w]) {
                        *dk -= f * t;
                    }
                    d[j] = 0.0;
                }
            }
        }
        Err(Stop::Cap)
    }

    /// Phase I: minimize the artificials; then drive the zero ones out of the basis and fix
    /// them at 0. Ok(true) feasible, Ok(false) certified infeasible.
    fn phase_one(&mut self, cap: usize) -> Result<(bool, usize), &'static str> {
        let (n, m, w) = (self.n, self.m, self.width());
        let mut cost = vec![0.0; w];
        let mut any = false;
        for i in 0..m {
            if self.bounds[n + m + i].hi > 0.0 {
                cost[n + m + i] = 1.0;
                any = true;
            }
        }
        let mut iterations = 0;
        if any {
            iterations = match self.iterate(&cost, true, cap) {
                Ok(k) => k,
                Err(_) => return Err("phase I did not finish"),
            };
            let left: f64 = (0..m).map(|i| self.value[n + m + i]).sum();
            let magnitude: f64 = self
                .b
                .iter()
                .map(|v| v.abs())
                .sum::<f64>()
                .max(f64::MIN_POSITIVE);
            if left > 1e-12 * magnitude {
                return if self.certify_infeasible(&cost) {
                    self.infeasible = true;
                    Ok((false, iterations))
                } else {
                    Err("phase I ended infeasible without a certificate")
                };
            }
        }
        // Artificials out: pivot each basic one out on any usable column, else leave it (a
        // redundant row) fixed at 0.
        for r in 0..m {
            let bv = self.basis[r];
            if bv < n + m {
                continue;
            }
            let row = &self.tableau[r * w..r * w + n + m];
            let best = (0..n + m)
                .filter(|&j| !self.is_basic[j])
                .max_by(|&p, &q| row[p].abs().total_cmp(&row[q].abs()));
            if let Some(j) = best {
                if row[j].abs() > 1e-7 {
                    // Degenerate: the artificial is at 0, so no value moves.
                    self.value[bv] = 0.0;
                    self.pivot(r, j);
                    self.value[bv] = 0.0;
                }
            }
        }
        for i in 0..m {
            self.bounds[n + m + i] = Bounds { lo: 0.0, hi: 0.0 };
            self.value[n + m + i] = 0.0;
        }
        self.feasible = true;
        self.artificials_live = false;
        Ok((true, iterations))
    }

    /// The all-slack basis with each x at the bound its cost prefers, when that basis is dual
    /// feasible for `c` (every x with cⱼ > 0 has a finite lower bound, every one with cⱼ < 0 a
    /// finite upper one, free ones cost nothing): the state and parameter LPs (6), (11) are,
    /// as their costs are the half-widths, bounded below by 0. False leaves the basis as it was.
    fn dual_start(&mut self, c: &DVector<f64>) -> bool {
        let (n, m, w) = (self.n, self.m, self.width());
        let mut start = vec![0.0; n];
        for j in 0..n {
            let bd = self.bounds[j];
            start[j] = if c[j] > 0.0 || (c[j] == 0.0 && bd.lo.is_finite()) {
                bd.lo
            } else if c[j] < 0.0 || bd.hi.is_finite() {
                bd.hi
            } else {
                0.0
            };
            if !start[j].is_finite() {
                return false;
            }
        }
        self.value[..n].copy_from_slice(&start);
        self.is_basic.iter_mut().for_each(|v| *v = false);
        for i in 0..m {
            let r = self.b[i] - (0..n).map(|j| self.a[(i, j)] * start[j]).sum::<f64>();
            let row = &mut self.tableau[i * w..(i + 1) * w];
            row.iter_mut().for_each(|v| *v = 0.0);
            for (j, v) in row[..n].iter_mut().enumerate() {
                *v = self.a[(i, j)];
            }
            row[n + i] = 1.0;
            row[n + m + i] = -1.0;
            self.basis[i] = n + i;
            self.is_basic[n + i] = true;
            self.value[n + i] = r;
            self.value[n + m + i] = 0.0;
            self.bounds[n + m + i] = Bounds { lo: 0.0, hi: 0.0 };
        }
        // No artificial is basic or may enter: the dual simplex and Phase II never read them.
        self.artificials_live = false;
        true
    }

    /// The dual simplex from a dual feasible basis: the most infeasible basic variable leaves
    /// at the bound it violates, the entering column keeps the reduced costs' signs (the
    /// smallest ratio |dⱼ / αⱼ|, ties to the largest |αⱼ|). Some(iterations) when every basic
    /// variable is within its bounds; None at the cap or when no column can enter (then the
    /// rows may be infeasible: Phase I certifies that).
    fn dual(&mut self, c: &DVector<f64>, cap: usize) -> Option<usize> {
        let (n, m, w) = (self.n, self.m, self.width());
        let mut cost = vec![0.0; w];
        cost[..n].copy_from_slice(c.as_slice());
        let mut d = self.reduced_costs(&cost);
        let data = self.b.amax().max(f64::MIN_POSITIVE);
        for iteration in 0..cap {
            // Leaving: the largest bound violation (relative to the data's size).
            let mut leave: Option<(usize, f64)> = None;
            for i in 0..m {
                let bv = self.basis[i];
                let (v, bb) = (self.value[bv], self.bounds[bv]);
                let tol = 1e-12 * (data + v.abs());
                let excess = if v < bb.lo - tol {
                    v - bb.lo
                } else if v > bb.hi + tol {
                    v - bb.hi
                } else {
                    continue;
                };
                if leave.is_none_or(|(_, e)| excess.abs() > e.abs()) {
                    leave = Some((i, excess));
                }
            }
            let Some((r, excess)) = leave else {
                return Some(iteration);
            };
            // The basic variable must move by −excess: x_B,r − α_rj Δx_j, so Δx_j has the sign
            // of excess·α_rj, allowed by x_j's bounds; the reduced costs keep their signs while
            // Δ ≤ |d_j / α_rj|.
            let row = &self.tableau[r * w..(r + 1) * w];
            let mut enter: Option<(usize, f64, f64)> = None;
            for j in 0..n + m {
                if self.is_basic[j] {
                    continue;
                }
                let alpha = row[j];
                if alpha.abs() <= PIVOT {
                    continue;
                }
                let bd = self.bounds[j];
                let up = excess * alpha > 0.0;
                if (up && self.value[j] >= bd.hi) || (!up && self.value[j] <= bd.lo) {
                    continue;
                }
                let ratio = d[j].abs() / alpha.abs();
                let better = match enter {
                    None => true,
                    Some((_, best, a)) => {
                        ratio < best - 1e-12 * (1.0 + best)
                            || (ratio <= best + 1e-12 * (1.0 + best) && alpha.abs() > a.abs())
                    }
                };
                if better {
                    enter = Some((j, ratio, alpha));
                }
            }
            let (j, _, alpha) = enter?;
            let step = excess / alpha;
            self.value[j] += step;
            for i in 0..m {
                let t = self.tableau[i * w + j];
                if t != 0.0 {
                    self.value[self.basis[i]] -= t * step;
                }
            }
            let bv = self.basis[r];
            let bb = self.bounds[bv];
            self.value[bv] = if excess < 0.0 { bb.lo } else { bb.hi };
            self.pivot(r, j);
            let f = d[j];
            for (dk, &t) in d.iter_mut().zip(&self.tableau[r * w..(r + 1) * w]) {
                *dk -= f * t;
            }
            d[j] = 0.0;
        }
        None
    }

    /// Solve for objective `c` (length n) from the current basis.
    pub fn minimize(&mut self, c: &DVector<f64>) -> Outcome {
        let (n, m, w) = (self.n, self.m, self.width());
        if c.len() != n || !c.iter().all(|v| v.is_finite()) {
            return Outcome::Uncertain("bad objective");
        }
        if self.infeasible {
            return Outcome::Infeasible;
        }
        let cap = 50 * (n + m) + 500;
        let mut iterations = 0;
        if !self.feasible && self.dual_start(c) {
            match self.dual(c, cap) {
                Some(k) => {
                    iterations += k;
                    self.feasible = true;
                }
                // No entering column (the rows may be infeasible) or the cap: Phase I decides.
                None => self.slack_basis(),
            }
        }
        if !self.feasible {
            match self.phase_one(cap) {
                Ok((true, k)) => iterations += k,
                Ok((false, _)) => return Outcome::Infeasible,
                Err(why) => {
                    self.slack_basis();
                    return Outcome::Uncertain(why);
                }
            }
        }
        let mut cost = vec![0.0; w];
        cost[..n].copy_from_slice(c.as_slice());
        match self.iterate(&cost, false, cap) {
            Ok(k) => iterations += k,
            Err(Stop::Cap) => {
                self.slack_basis();
                return Outcome::Uncertain("iteration cap");
            }
            Err(Stop::Unbounded(j, dir)) => {
                return if self.certify_ray(c, j, dir) {
                    Outcome::Unbounded
                } else {
                    Outcome::Uncertain("unbounded without a certificate")
                };
            }
        }
        match self.certify_optimum(c) {
            Some((x, objective, lambda)) => Outcome::Optimal(Optimum {
                x,
                objective,
                duals: DVector::from_iterator(m, (0..m).map(|i| -lambda[i] * self.scale[i])),
                iterations: iterations as u32,
            }),
            None => {
                // The basis may have drifted: the next solve starts afresh.
                self.slack_basis();
                Outcome::Uncertain("the optimum did not pass its check")
            }
        }
    }

    /// The basis matrix B (columns of [A I −E] of the basic variables).
    fn basis_matrix(&self) -> DMatrix<f64> {
        let (n, m) = (self.n, self.m);
        DMatrix::from_fn(m, m, |i, k| {
            let v = self.basis[k];
            if v < n {
                self.a[(i, v)]
            } else if v < n + m {
                f64::from(u8::from(v - n == i))
            } else {
                -f64::from(u8::from(v - n - m == i))
            }
        })
    }

    /// B⁻¹ v, B⁻¹ being the tableau's slack block.
    fn inverse_mul(&self, v: &DVector<f64>) -> DVector<f64> {
        let (n, m, w) = (self.n, self.m, self.width());
        DVector::from_fn(m, |i, _| {
            dot(&self.tableau[i * w + n..i * w + n + m], v.as_slice())
        })
    }

    /// B⁻ᵀ v.
    fn inverse_tr_mul(&self, v: &DVector<f64>) -> DVector<f64> {
        let (n, m, w) = (self.n, self.m, self.width());
        let mut out = DVector::zeros(m);
        for (i, &vi) in v.iter().enumerate() {
            if vi != 0.0 {
                let row = &self.tableau[i * w + n..i * w + n + m];
                out.iter_mut().zip(row).for_each(|(o, a)| *o += vi * a);
            }
        }
        out
    }

    /// B x over the basic columns of [A I −E] (unit columns for slacks and artificials).
    fn basis_mul(&self, x: &DVector<f64>) -> DVector<f64> {
        let (n, m) = (self.n, self.m);
        let mut out = DVector::zeros(m);
        for (k, &v) in self.basis.iter().enumerate() {
            if v < n {
                out.axpy(x[k], &self.a.column(v), 1.0);
            } else if v < n + m {
                out[v - n] += x[k];
            } else {
                out[v - n - m] -= x[k];
            }
        }
        out
    }

    /// Bᵀ λ.
    fn basis_tr_mul(&self, lambda: &DVector<f64>) -> DVector<f64> {
        let (n, m) = (self.n, self.m);
        DVector::from_fn(m, |k, _| {
            let v = self.basis[k];
            if v < n {
                self.a.column(v).dot(lambda)
            } else if v < n + m {
                lambda[v - n]
            } else {
                -lambda[v - n - m]
            }
        })
    }

    /// The basic solution recomputed from the data, and the duals λ of cost `cost` (over all
    /// variables): B x_B = b − N x_N, Bᵀλ = c_B, by a fresh LU.
    fn recompute(&self, cost: &[f64], fresh: bool) -> Option<(Vec<f64>, DVector<f64>)> {
        let (n, m) = (self.n, self.m);
        let mut rhs = self.b.clone();
        for j in 0..n {
            if !self.is_basic[j] && self.value[j] != 0.0 {
                rhs.axpy(-self.value[j], &self.a.column(j), 1.0);
            }
        }
        // Nonbasic slacks and artificials are at 0.
        let cb = DVector::from_iterator(m, self.basis.iter().map(|&v| cost[v]));
        let (xb, lambda) = if fresh {
            let bm = self.basis_matrix();
            let xb = bm.clone().lu().solve(&rhs)?;
            (xb, bm.transpose().lu().solve(&cb)?)
        } else {
            // B⁻¹ is the tableau's slack block (B⁻¹ [A I −E]); two steps of refinement on the
            // data's residuals, for x_B and for λ (without them the check failed on most
            // optimal-face solves of a long window, and each fell back to two LUs).
            let mut xb = self.inverse_mul(&rhs);
            let mut lambda = self.inverse_tr_mul(&cb);
            for _ in 0..2 {
                xb += self.inverse_mul(&(&rhs - self.basis_mul(&xb)));
                lambda += self.inverse_tr_mul(&(&cb - self.basis_tr_mul(&lambda)));
            }
            (xb, lambda)
        };
        if !xb.iter().chain(lambda.iter()).all(|v| v.is_finite()) {
            return None;
        }
        let mut value = self.value.clone();
        for (i, &v) in self.basis.iter().enumerate() {
            value[v] = xb[i];
        }
        Some((value, lambda))
    }

    /// The Lagrangian lower bound λᵀb + Σⱼ min over [loⱼ, hiⱼ] of (c − Aᵀλ)ⱼ xⱼ (λ ≤ 0, and
    /// for Phase I λ ≥ −1 on the rows with an artificial) and the size of its terms; None when
    /// a reduced cost faces an infinite bound.
    fn lower_bound(&self, c: &[f64], lambda: &DVector<f64>) -> Option<(f64, f64)> {
        let n = self.n;
        let d = DVector::from_column_slice(c) - self.a.tr_mul(lambda);
        let mut bound = lambda.dot(&self.b);
        let mut size: f64 = lambda
            .iter()
            .zip(self.b.iter())
            .map(|(l, b)| (l * b).abs())
            .sum();
        for j in 0..n {
            let bd = self.bounds[j];
            let at = if d[j] > 0.0 { bd.lo } else { bd.hi };
            if d[j] == 0.0 {
                continue;
            }
            if !at.is_finite() {
                return None;
            }
            bound += d[j] * at;
            size += (d[j] * at).abs();
        }
        Some((bound, size))
    }

    /// Check the current basis's vertex: primal feasible on the data, and within [`CERTIFY`]
    /// of the Lagrangian bound of its own duals. Returns x, cᵀx and λ (scaled rows, ≤ 0).
    fn certify_optimum(&self, c: &DVector<f64>) -> Option<(DVector<f64>, f64, DVector<f64>)> {
        let n = self.n;
        let mut cost = vec![0.0; self.width()];
        cost[..n].copy_from_slice(c.as_slice());
        self.check_optimum(c, &cost, false)
            .or_else(|| self.check_optimum(c, &cost, true))
    }

    /// [`Simplex::certify_optimum`] with the vertex and duals from the tableau or, `fresh`, by LU.
    fn check_optimum(
        &self,
        c: &DVector<f64>,
        cost: &[f64],
        fresh: bool,
    ) -> Option<(DVector<f64>, f64, DVector<f64>)> {
        let (n, m) = (self.n, self.m);
        let (value, lambda) = self.recompute(cost, fresh)?;
        // +0.0: no −0 in the reports.
        let x = DVector::from_iterator(n, value[..n].iter().map(|v| v + 0.0));
        // Primal: every row and bound to CERTIFY of its own terms.
        let ax = &self.a * &x;
        for i in 0..m {
            let size = self.b[i].abs() + (0..n).map(|j| (self.a[(i, j)] * x[j]).abs()).sum::<f64>();
            if ax[i] - self.b[i] > CERTIFY * size {
                return None;
            }
        }
        let data = self.b.amax().max(f64::MIN_POSITIVE);
        for j in 0..n {
            let bd = self.bounds[j];
            let slack = CERTIFY * (x[j].abs() + 1e-3 * data);
            if x[j] < bd.lo - slack || x[j] > bd.hi + slack {
                return None;
            }
        }
        // Dual: λ ≤ 0 (clipped: any λ ≤ 0 gives a valid bound), the gap within CERTIFY.
        let lambda = lambda.map(|v| v.min(0.0));
        let (bound, size) = self.lower_bound(&cost[..n], &lambda)?;
        let objective = c.dot(&x);
        let scale = size
            + c.iter()
                .zip(x.iter())
                .map(|(c, x)| (c * x).abs())
                .sum::<f64>();
        if objective - bound > CERTIFY * scale.max(f64::MIN_POSITIVE) {
            return None;
        }
        Some((x, objective, lambda))
    }

    /// Phase I ended with artificials left: its duals λ (clipped to [−1, 0] on artificial rows
    /// and ≤ 0 elsewhere) must give a positive bound on Σ artificials, beyond rounding.
    fn certify_infeasible(&self, cost: &[f64]) -> bool {
        let (n, m) = (self.n, self.m);
        let Some((_, lambda)) = self.recompute(cost, true) else {
            return false;
        };
        let lambda = DVector::from_iterator(
            m,
            (0..m).map(|i| {
                let floor = if cost[n + m + i] > 0.0 {
                    -1.0
                } else {
                    f64::NEG_INFINITY
                };
                lambda[i].clamp(floor, 0.0)
            }),
        );
        let zero = vec![0.0; n];
        match self.lower_bound(&zero, &lambda) {
            Some((bound, size)) => bound > 1e3 * f64::EPSILON * size.max(f64::MIN_POSITIVE),
            None => false,
        }
    }

    /// The ray of an unbounded ratio test, on the data: x_j moves by `dir`, the basic
    /// variables along the column; A d ≤ 0 up to rounding, d within the box's recession cone
    /// and cᵀd < 0.
    fn certify_ray(&self, c: &DVector<f64>, j: usize, dir: f64) -> bool {
        let (n, m, w) = (self.n, self.m, self.width());
        let mut d = vec![0.0; w];
        d[j] = dir;
        for i in 0..m {
            d[self.basis[i]] -= dir * self.tableau[i * w + j];
        }
        let dx = DVector::from_column_slice(&d[..n]);
        let norm = dx.amax();
        if norm == 0.0 {
            return false;
        }
        let ad = &self.a * &dx;
        if ad.iter().any(|&v| v > 1e-9 * norm) {
            return false;
        }
        for k in 0..n {
            let bd = self.bounds[k];
            if (dx[k] > 1e-12 * norm && bd.hi.is_finite())
                || (dx[k] < -1e-12 * norm && bd.lo.is_finite())
            {
                return false;
            }
        }
        c.dot(&dx) < -1e-9 * c.amax() * norm
    }
}

/// Why an iteration stopped without an optimum.
enum Stop {
    Cap,
    Unbounded(usize, f64),
}

/// Minimize cᵀx subject to A x ≤ b, lo ≤ x ≤ hi once.
pub fn minimize(
    c: &DVector<f64>,
    a: &DMatrix<f64>,
    b: &DVector<f64>,
    lo: &DVector<f64>,
    hi: &DVector<f64>,
) -> Outcome {
    match Simplex::new(a, b, lo, hi) {
        Some(mut s) => s.minimize(c),
        None => Outcome::Uncertain("the problem could not be loaded"),
    }
}
