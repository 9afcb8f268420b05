//! Linear models with uniform innovations: L. Pavelková, "Examples of state and parameter
//! estimation for linear model with uniform innovations" (seed 004).
//!
//! The LU model (1)–(2): x_t = A x_{t−1} + B u_t + e^x_t, y_t = C x_t + D u_t + e^y_t with e^x,
//! e^y uniform on boxes of half-widths x_r, y_r. Its MAP estimates are linear programs over the
//! support (4) ∩ the prior box (5), minimizing Σ x_r + Σ y_r (Section 3.2):
//!
//! * [`state_lp`]: states and half-widths given Θ = (A, B, C, D), (6)–(10), in the Kronecker layout
//!   of (8) (rows per time τ, then K = [−1, 1]ᵀ, then component);
//! * [`parameter_lp`]: Θ and half-widths given the states, (11)–(12) — with the half-width block
//!   derived from (4): the printed (12) pairs the wrong half-width with half of the rows when
//!   its blocks are ordered as written (crate docs: errata);
//! * [`optimal_face`]: the optimum is not unique in general (always so for the paper's example,
//!   whose (A, C) is not observable: C·A = 0.5·C) — extra LPs give each state's range over the
//!   optimal face;
//! * [`consistent_polygon`]: the set of x_t consistent with the window's constraints at given
//!   half-widths — a projection of a polytope, so a polygon — for n = 2 computed exactly by the
//!   planar engine ([`crate::sets::ConvexPolygon`]: forward clips of the per-sample boxes and
//!   strips, no LP), otherwise ([`consistent_polygon_lp`], also the planar path's test oracle)
//!   from support LPs on one loaded problem ([`crate::sets::polygon_from_support`]);
//! * [`Online`]: the sliding window of length ∂ (Section 4) with swapping (4.1) or expansion
//!   (4.2, the linearization (13)) joint estimation, extending the half-width bounds when the LP
//!   is infeasible (Section 3.2's note).
//!
//! All LPs go through [`crate::solve`]: the state and parameter LPs and the face ranges
//! through its dense simplex ([`crate::solve::simplex`], warm-started across the face's
//! objectives; clarabel for what it cannot certify), the polygon (n > 2) through clarabel. Where the
//! optimum is not unique the simplex returns a vertex of the optimal face (an interior-point
//! solver returns a point inside it), so the states of the paper's example, and the Θ̂ the
//! swapping estimator fits to them, are that vertex's.

use crate::error::{Error, Result};
use crate::sets::{polygon_from_support, ConvexPolygon, SupportPolygon};
use crate::solve::{self, simplex, Blame};
use nalgebra::{DMatrix, DVector};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

/// Θ = (A, B, C, D).
#[derive(Debug, Clone, PartialEq)]
pub struct Theta {
    pub a: DMatrix<f64>,
    pub b: DMatrix<f64>,
    pub c: DMatrix<f64>,
    pub d: DMatrix<f64>,
}

impl Theta {
    pub fn n(&self) -> usize {
        self.a.nrows()
    }
    pub fn m(&self) -> usize {
        self.c.nrows()
    }
    pub fn r(&self) -> usize {
        self.b.ncols()
    }
    /// col(A), col(B), col(C), col(D) stacked (rows of each matrix in turn, (11)).
    pub fn to_vec(&self) -> DVector<f64> {
        let mut v = Vec::new();
        for mat in [&self.a, &self.b, &self.c, &self.d] {
            for i in 0..mat.nrows() {
                v.extend(mat.row(i).iter());
            }
        }
        DVector::from_vec(v)
    }
    /// Inverse of [`Theta::to_vec`] with the shapes of `like`.
    pub fn from_vec(v: &[f64], like: &Theta) -> Theta {
        let mut at = 0;
        let mut take = |m: &DMatrix<f64>| {
            let out = DMatrix::from_row_slice(m.nrows(), m.ncols(), &v[at..at + m.len()]);
            at += m.len();
            out
        };
        Theta {
            a: take(&like.a),
            b: take(&like.b),
            c: take(&like.c),
            d: take(&like.d),
        }
    }
}

/// A simulated trajectory of the LU model: x_0..x_T, u_1..u_T, y_1..y_T (index 0 of u and y
/// is unused and zero).
#[derive(Debug, Clone)]
pub struct Trajectory {
    pub x: Vec<DVector<f64>>,
    pub u: Vec<DVector<f64>>,
    pub y: Vec<DVector<f64>>,
}

fn uniform_box(half: &DVector<f64>, rng: &mut ChaCha8Rng) -> DVector<f64> {
    half.map(|h| (rng.random::<f64>() * 2.0 - 1.0) * h)
}

/// Simulate T steps from x_0 with inputs uniform on [−u_half, u_half] (the paper's "white
/// zero-mean uniform noise with half-width 0.5").
pub fn simulate(
    theta: &Theta,
    xr: &DVector<f64>,
    yr: &DVector<f64>,
    x0: &DVector<f64>,
    u_half: f64,
    steps: usize,
    seed: u64,
) -> Trajectory {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (m, r) = (theta.m(), theta.r());
    let mut t = Trajectory {
        x: vec![x0.clone()],
        u: vec![DVector::zeros(r)],
        y: vec![DVector::zeros(m)],
    };
    for k in 1..=steps {
        let u = DVector::from_fn(r, |_, _| (rng.random::<f64>() * 2.0 - 1.0) * u_half);
        let x = &theta.a * &t.x[k - 1] + &theta.b * &u + uniform_box(xr, &mut rng);
        let y = &theta.c * &x + &theta.d * &u + uniform_box(yr, &mut rng);
        t.x.push(x);
        t.u.push(u);
        t.y.push(y);
    }
    t
}

/// K = [−1, 1]ᵀ.
fn k_vec() -> DMatrix<f64> {
    DMatrix::from_column_slice(2, 1, &[-1.0, 1.0])
}

/// [M, 0_(α, col)] and [0_(α, col), M] (the paper's R_col and L_col).
fn pad_right(m: &DMatrix<f64>, col: usize) -> DMatrix<f64> {
    let mut out = DMatrix::zeros(m.nrows(), m.ncols() + col);
    out.columns_mut(0, m.ncols()).copy_from(m);
    out
}
fn pad_left(m: &DMatrix<f64>, col: usize) -> DMatrix<f64> {
    let mut out = DMatrix::zeros(m.nrows(), m.ncols() + col);
    out.columns_mut(col, m.ncols()).copy_from(m);
    out
}

/// Stack vectors newest first: [v_last; …; v_first].
fn newest_first(v: &[DVector<f64>]) -> DVector<f64> {
    DVector::from_iterator(
        v.iter().map(|x| x.len()).sum(),
        v.iter().rev().flat_map(|x| x.iter().copied()),
    )
}

/// A window of the data: the constraints (4) for τ = first..=last, whose states are
/// x_{first−1} … x_last.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Window {
    pub first: usize,
    pub last: usize,
}

impl Window {
    pub fn len(&self) -> usize {
        self.last + 1 - self.first
    }
    pub fn is_empty(&self) -> bool {
        self.last < self.first
    }
    /// Number of states x_{first−1} … x_last.
    pub fn states(&self) -> usize {
        self.len() + 1
    }
}

/// Prior box (5) of the state LP: bounds of the states in the window (the oldest, x_{first−1},
/// plays x_0) and of the half-widths.
#[derive(Debug, Clone, PartialEq)]
pub struct StatePrior {
    /// Bounds of every state entry of the window (±5 in the paper's example), and tighter ones
    /// for the oldest state when known (x̲_0, x̄_0).
    pub x_lo: f64,
    pub x_hi: f64,
    pub x0: Option<(DVector<f64>, DVector<f64>)>,
    pub xr_max: DVector<f64>,
    pub yr_max: DVector<f64>,
}

/// The LP (6) of one problem: minimize cᵀX subject to 𝒜X ≤ ℬ and X̲ ≤ X ≤ X̄ (∞ allowed).
#[derive(Debug, Clone)]
pub struct Lp {
    pub c: DVector<f64>,
    pub a: DMatrix<f64>,
    pub b: DVector<f64>,
    pub lo: DVector<f64>,
    pub hi: DVector<f64>,
    /// The unit the solver works in ([`solve::Problem::unit`]): the state LP's unknowns
    /// (states, half-widths) all have the data's unit; the parameter LP's Θ has none (`None`).
    pub unit: Option<f64>,
}

impl Lp {
    /// Solve, the bounds becoming rows (only the finite ones).
    pub fn solve(&self, blame: impl Into<Blame>) -> Result<solve::Solution> {
        self.solve_with(&self.c, None, blame)
    }

    /// Minimize another objective over the same set, optionally with one more row gᵀX ≤ h.
    pub fn solve_with(
        &self,
        c: &DVector<f64>,
        extra: Option<(&DVector<f64>, f64)>,
        blame: impl Into<Blame>,
    ) -> Result<solve::Solution> {
        solve::quadratic(&self.problem(c, extra, blame))
    }

    /// The LP as the solver's problem with objective `c`: 𝒜X ≤ ℬ, the finite bounds as rows,
    /// and optionally one more row gᵀX ≤ h.
    pub fn problem(
        &self,
        c: &DVector<f64>,
        extra: Option<(&DVector<f64>, f64)>,
        blame: impl Into<Blame>,
    ) -> solve::Problem {
        let nv = self.c.len();
        let bound_rows: Vec<(usize, f64, f64)> = (0..nv)
            .flat_map(|j| {
                let mut v = Vec::new();
                if self.hi[j].is_finite() {
                    v.push((j, 1.0, self.hi[j]));
                }
                if self.lo[j].is_finite() {
                    v.push((j, -1.0, -self.lo[j]));
                }
                v
            })
            .collect();
        let rows = self.a.nrows() + bound_rows.len() + extra.is_some() as usize;
        let mut a = DMatrix::zeros(rows, nv);
        let mut b = DVector::zeros(rows);
        a.rows_mut(0, self.a.nrows()).copy_from(&self.a);
        b.rows_mut(0, self.a.nrows()).copy_from(&self.b);
        for (k, &(j, sign, rhs)) in bound_rows.iter().enumerate() {
            a[(self.a.nrows() + k, j)] = sign;
            b[self.a.nrows() + k] = rhs;
        }
        if let Some((g, h)) = extra {
            a.row_mut(rows - 1).copy_from(&g.transpose());
            b[rows - 1] = h;
        }
        solve::Problem {
            p: None,
            q: c.clone(),
            eq: None,
            le: Some((a, b)),
            soc: Vec::new(),
            blame: blame.into(),
            unit: self.unit,
        }
    }
}

/// One [`Lp`] (with an optional extra row gᵀX ≤ h) loaded for many objectives: the dense
/// simplex ([`simplex`]) warm-started from its last optimal basis, and clarabel, loaded on the
/// first objective the simplex cannot certify (or for every objective under
/// [`simplex::Engine::Clarabel`], the tests' oracle). Unbounded problems go to clarabel too, for
/// its error. The simplex's duals cover the rows of 𝒜 (and the extra row) only.
struct Loaded<'a> {
    lp: &'a Lp,
    extra: Option<(&'a DVector<f64>, f64)>,
    blame: &'a Blame,
    simplex: Option<simplex::Simplex>,
    clarabel: Option<solve::Family>,
    /// The simplex could not be loaded (shapes, non-finite data): clarabel says why.
    refused: bool,
}

impl<'a> Loaded<'a> {
    fn new(lp: &'a Lp, extra: Option<(&'a DVector<f64>, f64)>, blame: &'a Blame) -> Loaded<'a> {
        Loaded {
            lp,
            extra,
            blame,
            simplex: None,
            clarabel: None,
            refused: false,
        }
    }

    fn minimize(&mut self, c: &DVector<f64>) -> Result<solve::Solution> {
        match self.minimize_if_feasible(c)? {
            Some(s) => Ok(s),
            None => Err(self.blame.infeasible()),
        }
    }

    fn minimize_if_feasible(&mut self, c: &DVector<f64>) -> Result<Option<solve::Solution>> {
        if simplex::engine() == simplex::Engine::Simplex && !self.refused {
            if self.simplex.is_none() {
                let (a, b) = match self.extra {
                    None => (self.lp.a.clone(), self.lp.b.clone()),
                    Some((g, h)) => {
                        let rows = self.lp.a.nrows();
                        let a = self.lp.a.clone().insert_row(rows, 0.0);
                        let mut a = a;
                        a.row_mut(rows).copy_from(&g.transpose());
                        (a, self.lp.b.clone().push(h))
                    }
                };
                self.simplex = simplex::Simplex::new(&a, &b, &self.lp.lo, &self.lp.hi);
                self.refused = self.simplex.is_none();
            }
            if let Some(s) = self.simplex.as_mut() {
                match s.minimize(c) {
                    simplex::Outcome::Optimal(o) => {
                        return Ok(Some(solve::Solution {
                            x: o.x,
                            objective: o.objective,
                            duals: o.duals,
                            iterations: o.iterations,
                            status: "solved",
                        }))
                    }
                    simplex::Outcome::Infeasible => return Ok(None),
                    simplex::Outcome::Unbounded | simplex::Outcome::Uncertain(_) => {}
                }
            }
        }
        if self.clarabel.is_none() {
            let problem = self.lp.problem(c, self.extra, self.blame);
            self.clarabel = Some(solve::Family::new(&problem)?);
        }
        self.clarabel
            .as_mut()
            .expect("loaded")
            .minimize_if_feasible(Some(c))
    }
}

/// The state LP (6)–(10) on a window, given Θ: X = [x_last; …; x_{first−1}; x_r; y_r].
pub fn state_lp(
    theta: &Theta,
    traj_u: &[DVector<f64>],
    traj_y: &[DVector<f64>],
    w: Window,
    prior: &StatePrior,
) -> Lp {
    let (n, m) = (theta.n(), theta.m());
    let t = w.len();
    let k = k_vec();
    let it = DMatrix::<f64>::identity(t, t);
    let i_n = DMatrix::<f64>::identity(n, n);
    let i_m = DMatrix::<f64>::identity(m, m);
    let ones = DMatrix::<f64>::from_element(2 * t, 1, 1.0);
    let ik = it.kronecker(&k);
    // (8): rows of the transitions, then of the measurements.
    let a11 = pad_right(&ik.kronecker(&i_n), n) - pad_left(&ik.kronecker(&theta.a), n);
    let a12 = -ones.kronecker(&pad_right(&i_n, m));
    let a21 = pad_right(&ik.kronecker(&theta.c), n);
    let a22 = -ones.kronecker(&pad_left(&i_m, n));
    let u = newest_first(&traj_u[w.first..=w.last]);
    let y = newest_first(&traj_y[w.first..=w.last]);
    let b1 = ik.kronecker(&theta.b) * &u;
    let b2 = -(ik.kronecker(&theta.d) * &u) + ik.kronecker(&i_m) * &y;
    let nx = (t + 1) * n;
    let nv = nx + n + m;
    let mut a = DMatrix::zeros(a11.nrows() + a21.nrows(), nv);
    a.view_mut((0, 0), (a11.nrows(), nx)).copy_from(&a11);
    a.view_mut((0, nx), (a12.nrows(), n + m)).copy_from(&a12);
    a.view_mut((a11.nrows(), 0), (a21.nrows(), nx))
        .copy_from(&a21);
    a.view_mut((a11.nrows(), nx), (a22.nrows(), n + m))
        .copy_from(&a22);
    let mut b = DVector::zeros(a.nrows());
    b.rows_mut(0, b1.len()).copy_from(&b1);
    b.rows_mut(b1.len(), b2.len()).copy_from(&b2);
    // (10): the prior box; the oldest state may have its own bounds (x̲_0, x̄_0).
    let mut lo = DVector::from_element(nv, prior.x_lo);
    let mut hi = DVector::from_element(nv, prior.x_hi);
    if let Some((l, h)) = &prior.x0 {
        lo.rows_mut(t * n, n).copy_from(l);
        hi.rows_mut(t * n, n).copy_from(h);
    }
    lo.rows_mut(nx, n + m).fill(0.0);
    hi.rows_mut(nx, n).copy_from(&prior.xr_max);
    hi.rows_mut(nx + n, m).copy_from(&prior.yr_max);
    let mut c = DVector::zeros(nv);
    c.rows_mut(nx, n + m).fill(1.0);
    // The data's unit: the largest right-hand side of (8) (the prior box ±x_bound is a bound
    // the user sets wide, not a scale of the data).
    let unit = Some(solve::power_of_two_below(b.amax()));
    Lp {
        c,
        a,
        b,
        lo,
        hi,
        unit,
    }
}

/// Bounds of Θ for the parameter LP: entrywise, in the layout of [`Theta::to_vec`].
#[derive(Debug, Clone, PartialEq)]
pub struct ThetaPrior {
    pub lo: Theta,
    pub hi: Theta,
    pub xr_max: DVector<f64>,
    pub yr_max: DVector<f64>,
}

/// The parameter LP (11)–(12) given states x_{first−1} … x_last:
/// X = [col(A); col(B); col(C); col(D); x_r; y_r]. Rows per τ (newest first), K, component;
/// each row carries the half-width of its own component (derived from (4)).
pub fn parameter_lp(
    like: &Theta,
    x: &[DVector<f64>],
    u: &[DVector<f64>],
    y: &[DVector<f64>],
    w: Window,
    prior: &ThetaPrior,
) -> Lp {
    let (n, m, r) = (like.n(), like.m(), like.r());
    let (na, nb, nc, nd) = (n * n, n * r, m * n, m * r);
    let nth = na + nb + nc + nd;
    let nv = nth + n + m;
    let k = k_vec();
    let i_n = DMatrix::<f64>::identity(n, n);
    let i_m = DMatrix::<f64>::identity(m, m);
    let t = w.len();
    let mut a = DMatrix::zeros(2 * t * (n + m), nv);
    let mut b = DVector::zeros(2 * t * (n + m));
    let mut row = 0;
    for tau in (w.first..=w.last).rev() {
        // K ⊗ (A x_{τ−1} + B u_τ) − 1 ⊗ x_r ≤ K ⊗ x_τ : (I_n ⊗ x'_{τ−1}) col(A) = A x_{τ−1}.
        let xa = i_n.kronecker(&x[tau - 1].transpose());
        let ub = i_n.kronecker(&u[tau].transpose());
        let blk_x = k.kronecker(&xa);
        let blk_u = k.kronecker(&ub);
        let hw = -DMatrix::<f64>::from_element(2, 1, 1.0).kronecker(&i_n);
        let rows = 2 * n;
        a.view_mut((row, 0), (rows, na)).copy_from(&blk_x);
        if nb > 0 {
            a.view_mut((row, na), (rows, nb)).copy_from(&blk_u);
        }
        a.view_mut((row, nth), (rows, n)).copy_from(&hw);
        b.rows_mut(row, rows)
            .copy_from(&(k.kronecker(&x[tau].clone().into_owned()).column(0)));
        row += rows;
        // K ⊗ (C x_τ + D u_τ) − 1 ⊗ y_r ≤ K ⊗ y_τ.
        let xc = i_m.kronecker(&x[tau].transpose());
        let ud = i_m.kronecker(&u[tau].transpose());
        let rows = 2 * m;
        a.view_mut((row, na + nb), (rows, nc))
            .copy_from(&k.kronecker(&xc));
        if nd > 0 {
            a.view_mut((row, na + nb + nc), (rows, nd))
                .copy_from(&k.kronecker(&ud));
        }
        a.view_mut((row, nth + n), (rows, m))
            .copy_from(&(-DMatrix::<f64>::from_element(2, 1, 1.0).kronecker(&i_m)));
        b.rows_mut(row, rows)
            .copy_from(&(k.kronecker(&y[tau].clone().into_owned()).column(0)));
        row += rows;
    }
    let mut lo = DVector::zeros(nv);
    let mut hi = DVector::zeros(nv);
    lo.rows_mut(0, nth).copy_from(&prior.lo.to_vec());
    hi.rows_mut(0, nth).copy_from(&prior.hi.to_vec());
    hi.rows_mut(nth, n).copy_from(&prior.xr_max);
    hi.rows_mut(nth + n, m).copy_from(&prior.yr_max);
    let mut c = DVector::zeros(nv);
    c.rows_mut(nth, n + m).fill(1.0);
    Lp {
        c,
        a,
        b,
        lo,
        hi,
        unit: None,
    }
}

/// The MAP state window: states newest first, half-widths, optimum.
#[derive(Debug, Clone)]
pub struct StateEstimate {
    /// x_last … x_{first−1}.
    pub x: Vec<DVector<f64>>,
    pub xr: DVector<f64>,
    pub yr: DVector<f64>,
    pub objective: f64,
    /// How many times the half-width bounds had to be doubled before the LP was feasible.
    pub extended: usize,
}

/// Most doublings of the half-width bounds [`solve_extending`] tries.
pub const MAX_EXTENSIONS: usize = 20;

/// Solve an LP, doubling the half-width bounds (the last n + m entries of `hi`) while it is
/// infeasible (Section 3.2: "LP will fail if these are chosen too restrictive"; the paper's
/// example extends them automatically), at most [`MAX_EXTENSIONS`] times.
pub fn solve_extending(lp: &mut Lp, nhw: usize, blame: &Blame) -> Result<(solve::Solution, usize)> {
    let nv = lp.c.len();
    for extended in 0..=MAX_EXTENSIONS {
        if let Some(s) = Loaded::new(lp, None, blame).minimize_if_feasible(&lp.c)? {
            return Ok((s, extended));
        }
        if extended < MAX_EXTENSIONS {
            for j in nv - nhw..nv {
                lp.hi[j] *= 2.0;
            }
        }
    }
    let e = blame.infeasible();
    Err(Error::field(
        e.field,
        format!(
            "{} (the half-width bounds were doubled {MAX_EXTENSIONS} times first)",
            e.message
        ),
    ))
}

/// Whom the state LP's failures concern: its box |x| ≤ x_bound is the bound the automatic
/// extension of the half-widths does not loosen.
fn state_blame() -> Blame {
    Blame::new(
        "uniform.x_bound",
        "state trajectory",
        "uniform.x_bound may be too small: every state of the window must lie in |x| ≤ x_bound",
    )
}

/// Whom the parameter LP's failures concern: the prior box of Θ.
fn parameter_blame() -> Blame {
    Blame::new(
        "uniform.prior_rel",
        "parameter vector Θ",
        "uniform.prior_rel may be too small: Θ must lie within ±prior_rel·|θ| of the model's Θ (and within uniform.prior_overrides)",
    )
}

/// MAP states and half-widths of a window given Θ.
pub fn estimate_states(
    theta: &Theta,
    u: &[DVector<f64>],
    y: &[DVector<f64>],
    w: Window,
    prior: &StatePrior,
) -> Result<(StateEstimate, Lp)> {
    let (n, m) = (theta.n(), theta.m());
    let mut lp = state_lp(theta, u, y, w, prior);
    let (sol, extended) = solve_extending(&mut lp, n + m, &state_blame())?;
    let nx = w.states() * n;
    let x = (0..w.states())
        .map(|i| sol.x.rows(i * n, n).into_owned())
        .collect();
    Ok((
        StateEstimate {
            x,
            xr: sol.x.rows(nx, n).into_owned(),
            yr: sol.x.rows(nx + n, m).into_owned(),
            objective: sol.objective,
            extended,
        },
        lp,
    ))
}

/// The range of the variable `index` over the optimal face {X : 𝒜X ≤ ℬ, bounds,
/// cᵀX ≤ J* + tol}: two LPs.
pub fn face_range(lp: &Lp, objective: f64, index: usize) -> Result<(f64, f64)> {
    Ok(face_ranges(lp, objective, &[index])?[0])
}

/// The ranges of the variables `indices` over the optimal face: the face (the LP's rows with
/// cᵀX ≤ J* + tol, tol = max(1e-7·|J*|, 1e-8·unit) for the solver's accuracy) is loaded once in a
/// [`solve::Family`] and solved for ±e_i, two LPs per index.
pub fn face_ranges(lp: &Lp, objective: f64, indices: &[usize]) -> Result<Vec<(f64, f64)>> {
    // Relative to J* (so the face scales with the problem), with a floor at the solver's
    // accuracy in the LP's unit: a floor of 10⁻⁷ absolute let the face of data at 10⁻⁶ hold
    // points 10 % off the optimum.
    let tol = (1e-7 * objective.abs()).max(1e-8 * lp.unit.unwrap_or(1.0));
    let nv = lp.c.len();
    // The face holds the optimum found just before, so only the solver's accuracy can make it
    // empty; the window is what the user can change.
    let blame = Blame::new(
        "uniform.window",
        "point of the optimal face",
        "the LP's optimum was not reproduced within the solver's accuracy",
    );
    let mut face = Loaded::new(lp, Some((&lp.c, objective + tol)), &blame);
    indices
        .iter()
        .map(|&index| {
            let mut e = DVector::zeros(nv);
            e[index] = 1.0;
            let lo = face.minimize(&e)?.objective;
            let hi = -face.minimize(&(-e))?.objective;
            Ok((lo, hi))
        })
        .collect()
}

/// Each state entry's range over the optimal face ([`face_ranges`]), per state newest first.
pub fn optimal_face(
    lp: &Lp,
    objective: f64,
    n: usize,
    states: usize,
) -> Result<Vec<(DVector<f64>, DVector<f64>)>> {
    let ranges = face_ranges(lp, objective, &(0..states * n).collect::<Vec<_>>())?;
    Ok(ranges
        .chunks(n)
        .map(|state| {
            (
                DVector::from_iterator(n, state.iter().map(|r| r.0)),
                DVector::from_iterator(n, state.iter().map(|r| r.1)),
            )
        })
        .collect())
}

/// The polygon of x_last (components `plane`) consistent with the window's constraints (4) and
/// the prior box (10) at fixed half-widths x_r, y_r: the projection of a polytope on a plane,
/// hence a polygon. For n = 2 with a finite prior box it is computed exactly without an LP
/// ([`consistent_polygon_planar`]: `calls` = 0); otherwise by [`consistent_polygon_lp`].
#[allow(clippy::too_many_arguments)]
pub fn consistent_polygon(
    theta: &Theta,
    u: &[DVector<f64>],
    y: &[DVector<f64>],
    w: Window,
    prior: &StatePrior,
    xr: &DVector<f64>,
    yr: &DVector<f64>,
    plane: [usize; 2],
    budget: usize,
) -> Result<SupportPolygon> {
    match consistent_polygon_planar(theta, u, y, w, prior, xr, yr, plane)? {
        Some(p) => Ok(p),
        None => consistent_polygon_lp(theta, u, y, w, prior, xr, yr, plane, budget),
    }
}

/// The consistent polygon of a 2-D state by forward recursion over the window: the box of
/// x_{first−1} (x̲_0, x̄_0 or the prior box (10)); then per τ the transition (4)
/// x_τ ∈ A x_{τ−1} + B u_τ ⊕ [−x_r, x_r] (a map, a shift and a Minkowski sum), the prior box
/// of x_τ and the measurement strips |y_τ − C x_τ − D u_τ| ≤ y_r, one per output. The chain
/// links only consecutive states, so the last set is the projection of the LP's polytope on
/// x_last: the same polygon, exact. `None` when it does not apply (n ≠ 2, an infinite bound).
#[allow(clippy::too_many_arguments)]
pub fn consistent_polygon_planar(
    theta: &Theta,
    u: &[DVector<f64>],
    y: &[DVector<f64>],
    w: Window,
    prior: &StatePrior,
    xr: &DVector<f64>,
    yr: &DVector<f64>,
    plane: [usize; 2],
) -> Result<Option<SupportPolygon>> {
    let (n, m) = (theta.n(), theta.m());
    if n != 2 || !matches!(plane, [0, 1] | [1, 0]) {
        return Ok(None);
    }
    let (lo0, hi0) = match &prior.x0 {
        Some((l, h)) => ([l[0], l[1]], [h[0], h[1]]),
        None => ([prior.x_lo; 2], [prior.x_hi; 2]),
    };
    let finite = lo0
        .iter()
        .chain(&hi0)
        .chain(xr.iter())
        .chain(yr.iter())
        .chain([&prior.x_lo, &prior.x_hi])
        .all(|v| v.is_finite());
    if !finite {
        return Ok(None);
    }
    let empty = || {
        Blame::new(
            "uniform.window",
            "state",
            "the window's estimated half-widths admit no state within the solver's accuracy",
        )
        .infeasible()
    };
    if lo0[0] > hi0[0] || lo0[1] > hi0[1] || prior.x_lo > prior.x_hi {
        return Err(empty());
    }
    let a = [
        [theta.a[(0, 0)], theta.a[(0, 1)]],
        [theta.a[(1, 0)], theta.a[(1, 1)]],
    ];
    let mut set = ConvexPolygon::rectangle(lo0, hi0);
    for tau in w.first..=w.last {
        let bu = &theta.b * &u[tau];
        let du = &theta.d * &u[tau];
        set = set.map(a).translate([bu[0], bu[1]]).add_box([xr[0], xr[1]]);
        let mut next = set
            .clip_strip([1.0, 0.0], prior.x_lo, prior.x_hi)
            .and_then(|p| p.clip_strip([0.0, 1.0], prior.x_lo, prior.x_hi));
        for i in 0..m {
            let v = y[tau][i] - du[i];
            next = next.and_then(|p| {
                p.clip_strip([theta.c[(i, 0)], theta.c[(i, 1)]], v - yr[i], v + yr[i])
            });
        }
        set = next.ok_or_else(empty)?;
    }
    if plane == [1, 0] {
        set = set.swapped();
    }
    Ok(Some(SupportPolygon {
        vertices: set.vertices().to_vec(),
        exact: true,
        gap: 0.0,
        calls: 0,
        hull: set.interval_hull(),
    }))
}

/// The consistent polygon of a window at the half-width bounds its state LP ends with, found
/// without the LP: [`solve_extending`] doubles the bounds (x̄_r, ȳ_r) until the LP is feasible,
/// and the LP is feasible exactly when the polygon at those bounds is not empty, so the first
/// k ≤ [`MAX_EXTENSIONS`] whose polygon at 2ᵏ·(x̄_r, ȳ_r) is not empty is the LP's (the
/// doublings are exact in binary). Returns the polygon and k; `None` where the planar path does
/// not apply; the state LP's error when no k is feasible. What it leaves out is the LP's
/// optimum (the MAP half-widths and states), which the polygon does not depend on.
pub fn consistent_polygon_extending(
    theta: &Theta,
    u: &[DVector<f64>],
    y: &[DVector<f64>],
    w: Window,
    prior: &StatePrior,
    plane: [usize; 2],
) -> Result<Option<(SupportPolygon, usize)>> {
    let (mut xr, mut yr) = (prior.xr_max.clone(), prior.yr_max.clone());
    for extended in 0..=MAX_EXTENSIONS {
        match consistent_polygon_planar(theta, u, y, w, prior, &xr, &yr, plane) {
            Ok(None) => return Ok(None),
            Ok(Some(polygon)) => return Ok(Some((polygon, extended))),
            // Empty: the bounds are doubled, as the LP's are.
            Err(_) => {
                xr *= 2.0;
                yr *= 2.0;
            }
        }
    }
    let e = state_blame().infeasible();
    Err(Error::field(
        e.field,
        format!(
            "{} (the half-width bounds were doubled {MAX_EXTENSIONS} times first)",
            e.message
        ),
    ))
}

/// [`consistent_polygon`] by support LPs, for any n (the planar path's oracle). With the
/// half-widths fixed they leave the LP — the rows of (8) read
/// 𝒜_x X ≤ ℬ − 𝒜_r (x_r; y_r) — and the state LP is loaded once in a [`solve::Family`]; the
/// exact polygon comes from [`polygon_from_support`] with at most `budget` support LPs (every
/// stretch between two boundary points closed by a support call normal to it), with `exact`
/// and the remaining `gap` when the budget runs out. Its vertices are points of the set.
#[allow(clippy::too_many_arguments)]
pub fn consistent_polygon_lp(
    theta: &Theta,
    u: &[DVector<f64>],
    y: &[DVector<f64>],
    w: Window,
    prior: &StatePrior,
    xr: &DVector<f64>,
    yr: &DVector<f64>,
    plane: [usize; 2],
    budget: usize,
) -> Result<SupportPolygon> {
    let (n, m) = (theta.n(), theta.m());
    let lp = state_lp(theta, u, y, w, prior);
    let nx = w.states() * n;
    let mut hw = DVector::zeros(n + m);
    hw.rows_mut(0, n).copy_from(xr);
    hw.rows_mut(n, m).copy_from(yr);
    let states = Lp {
        c: DVector::zeros(nx),
        a: lp.a.columns(0, nx).into_owned(),
        b: &lp.b - lp.a.columns(nx, n + m) * hw,
        lo: lp.lo.rows(0, nx).into_owned(),
        hi: lp.hi.rows(0, nx).into_owned(),
        unit: lp.unit,
    };
    // The half-widths are the window's own estimate, so the set holds at least that estimate's
    // states; only the solver's accuracy can make it empty.
    let blame = Blame::new(
        "uniform.window",
        "state",
        "the window's estimated half-widths admit no state within the solver's accuracy",
    );
    let mut family = solve::Family::new(&states.problem(&states.c, None, blame))?;
    // x_last comes first in the layout of (8): its components are X[plane[0]], X[plane[1]].
    let probe = |d: [f64; 2]| -> Result<(f64, [f64; 2])> {
        let mut c = DVector::zeros(nx);
        c[plane[0]] = -d[0];
        c[plane[1]] = -d[1];
        let x = family.minimize(Some(&c))?.x;
        let p = [x[plane[0]], x[plane[1]]];
        Ok((d[0] * p[0] + d[1] * p[1], p))
    };
    // The interior-point solver is accurate to about 1e-8 relative to the data's scale.
    polygon_from_support(probe, budget, 1e-7)
}

/// Joint on-line estimation method (Section 4). JSON (`uniform.estimator`): `"states"`,
/// `"parameters"`, `"swapping"` (the default) or `"expansion"`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Joint {
    /// Θ known: states only (Section 3.3 on the window).
    States,
    /// States known (measured): Θ and half-widths only (Section 3.4 on the window).
    Parameters,
    /// 4.1: states given Θ̂, then Θ̂ given the states, per step.
    #[default]
    Swapping,
    /// 4.2: one LP in states, Θ and half-widths with A x ≈ Â x + A x̂ − Â x̂ (13).
    Expansion,
}

/// The longest window ∂ the on-line estimator takes (its LP grows with ∂ · n).
pub const MAX_WINDOW: usize = 80;

/// One step of the on-line estimation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OnlineStep {
    pub t: usize,
    pub x: Vec<f64>,
    pub xr: Vec<f64>,
    pub yr: Vec<f64>,
    /// Θ̂ after the step (rows of A, B, C, D).
    pub a: Vec<Vec<f64>>,
    pub b: Vec<Vec<f64>>,
    pub c: Vec<Vec<f64>>,
    pub d: Vec<Vec<f64>>,
    /// ŷ_t|t−1 = Ĉ(Â x̂_{t−1} + B̂ u_t) + D̂ u_t, the one-step output prediction (Fig. 2).
    pub y_pred: Vec<f64>,
    /// Half-width bound doublings needed at this step.
    pub extended: usize,
}

fn rows(m: &DMatrix<f64>) -> Vec<Vec<f64>> {
    crate::linalg::to_rows(m)
}

/// The sliding-window estimator of Section 4.
pub struct Online {
    pub joint: Joint,
    pub window: usize,
    pub theta: Theta,
    pub theta_prior: ThetaPrior,
    pub state_prior: StatePrior,
    pub steps: Vec<OnlineStep>,
    /// Last window estimate (newest first), the expansion point of (13).
    last_x: Option<Vec<DVector<f64>>>,
}

impl Online {
    pub fn new(
        joint: Joint,
        window: usize,
        theta0: Theta,
        theta_prior: ThetaPrior,
        state_prior: StatePrior,
    ) -> Result<Self> {
        if window == 0 || window > MAX_WINDOW {
            return Err(Error::field(
                "uniform.window",
                format!("must be a whole number from 1 to {MAX_WINDOW}, found {window}"),
            ));
        }
        Ok(Online {
            joint,
            window,
            theta: theta0,
            theta_prior,
            state_prior,
            steps: Vec::new(),
            last_x: None,
        })
    }

    /// The window τ = max(1, t−∂+1) … t.
    fn window_ending(&self, t: usize) -> Window {
        Window {
            first: t.saturating_sub(self.window - 1).max(1),
            last: t,
        }
    }

    /// Record step t with the current Θ̂ and the one-step output prediction
    /// ŷ_t|t−1 = Ĉ(Â x_{t−1} + B̂ u_t) + D̂ u_t from the previous state `x_prev`.
    #[allow(clippy::too_many_arguments)]
    fn record(
        &mut self,
        t: usize,
        x: &DVector<f64>,
        xr: &DVector<f64>,
        yr: &DVector<f64>,
        x_prev: &DVector<f64>,
        u_t: &DVector<f64>,
        extended: usize,
    ) {
        let th = &self.theta;
        let y_pred = &th.c * (&th.a * x_prev + &th.b * u_t) + &th.d * u_t;
        let v = |x: &DVector<f64>| x.iter().copied().collect();
        self.steps.push(OnlineStep {
            t,
            x: v(x),
            xr: v(xr),
            yr: v(yr),
            a: rows(&th.a),
            b: rows(&th.b),
            c: rows(&th.c),
            d: rows(&th.d),
            y_pred: v(&y_pred),
            extended,
        });
    }

    /// Process time t (needs u, y up to t; t ≥ 1). The window is τ = max(1, t−∂+1) … t.
    pub fn step(
        &mut self,
        t: usize,
        u: &[DVector<f64>],
        y: &[DVector<f64>],
    ) -> Result<&OnlineStep> {
        let w = self.window_ending(t);
        let (n, m) = (self.theta.n(), self.theta.m());
        let prev_x = self.steps.last().map(|s| DVector::from_vec(s.x.clone()));
        let est = match self.joint {
            Joint::Expansion if self.last_x.is_some() => self.expansion_step(w, u, y)?,
            _ => estimate_states(&self.theta, u, y, w, &self.state_prior)?.0,
        };
        if self.joint == Joint::Swapping && w.len() >= 1 {
            // Θ̂ given the window's states (oldest first in time order).
            let mut xs: Vec<DVector<f64>> = est.x.clone();
            xs.reverse(); // x_{first−1} … x_last
            let mut x_full = vec![DVector::zeros(n); w.first - 1];
            x_full.extend(xs);
            let mut lp = parameter_lp(&self.theta, &x_full, u, y, w, &self.theta_prior);
            if let Ok((sol, _)) = solve_extending(&mut lp, n + m, &parameter_blame()) {
                self.theta = Theta::from_vec(sol.x.as_slice(), &self.theta);
            }
        }
        let x_prev =
            prev_x.unwrap_or_else(|| est.x.get(1).cloned().unwrap_or_else(|| DVector::zeros(n)));
        self.last_x = Some(est.x.clone());
        self.record(t, &est.x[0], &est.xr, &est.yr, &x_prev, &u[t], est.extended);
        Ok(self.steps.last().expect("pushed"))
    }

    /// Section 3.4 on the window: Θ̂ and the half-widths given known states x_0 … x_t (a
    /// directly measured state); the step records the given x_t.
    pub fn step_parameters(
        &mut self,
        t: usize,
        x: &[DVector<f64>],
        u: &[DVector<f64>],
        y: &[DVector<f64>],
    ) -> Result<&OnlineStep> {
        let w = self.window_ending(t);
        let (n, m) = (self.theta.n(), self.theta.m());
        let mut lp = parameter_lp(&self.theta, x, u, y, w, &self.theta_prior);
        let (sol, extended) = solve_extending(&mut lp, n + m, &parameter_blame())?;
        let nth = self.theta.to_vec().len();
        self.theta = Theta::from_vec(&sol.x.as_slice()[..nth], &self.theta);
        let (xr, yr) = (
            sol.x.rows(nth, n).into_owned(),
            sol.x.rows(nth + n, m).into_owned(),
        );
        self.record(t, &x[t], &xr, &yr, &x[t - 1], &u[t], extended);
        Ok(self.steps.last().expect("pushed"))
    }

    /// 4.2: variables [x_last … x_{first−1}; col(Θ); x_r; y_r], the products A x_{τ−1} and
    /// C x_τ linearized at (Â, x̂) by (13).
    fn expansion_step(
        &mut self,
        w: Window,
        u: &[DVector<f64>],
        y: &[DVector<f64>],
    ) -> Result<StateEstimate> {
        let th = &self.theta;
        let (n, m, r) = (th.n(), th.m(), th.r());
        let ns = w.states();
        let nx = ns * n;
        let nth = th.to_vec().len();
        let nv = nx + nth + n + m;
        // Expansion points: the previous window shifted by one (newest first), the newest
        // predicted by Â.
        let prev = self.last_x.clone().unwrap_or_default();
        let mut xhat: Vec<DVector<f64>> = Vec::with_capacity(ns);
        for i in 0..ns {
            // State x_{last−i}: previous window held x_{last−1−j} at j.
            let v = if i == 0 {
                prev.first().map(|x0| &th.a * x0 + &th.b * &u[w.last])
            } else {
                prev.get(i - 1).cloned()
            };
            xhat.push(v.unwrap_or_else(|| DVector::zeros(n)));
        }
        let (na, nb, nc) = (n * n, n * r, m * n);
        let mut a = DMatrix::zeros(2 * w.len() * (n + m), nv);
        let mut b = DVector::zeros(a.nrows());
        let i_n = DMatrix::<f64>::identity(n, n);
        let i_m = DMatrix::<f64>::identity(m, m);
        let mut row = 0;
        for (j, tau) in (w.first..=w.last).rev().enumerate() {
            // x_τ is state j, x_{τ−1} is state j + 1 (newest first).
            // x_τ − [Â x_{τ−1} + A x̂_{τ−1} − Â x̂_{τ−1}] − B u_τ ∈ [−x_r, x_r].
            let mut g = DMatrix::zeros(n, nv);
            g.view_mut((0, j * n), (n, n)).copy_from(&i_n);
            g.view_mut((0, (j + 1) * n), (n, n)).copy_from(&(-&th.a));
            g.view_mut((0, nx), (n, na))
                .copy_from(&(-i_n.kronecker(&xhat[j + 1].transpose())));
            if nb > 0 {
                g.view_mut((0, nx + na), (n, nb))
                    .copy_from(&(-i_n.kronecker(&u[tau].transpose())));
            }
            let rhs = -(&th.a * &xhat[j + 1]);
            for (kk, &sgn) in [-1.0, 1.0].iter().enumerate() {
                a.view_mut((row + kk * n, 0), (n, nv))
                    .copy_from(&(&g * sgn));
                a.view_mut((row + kk * n, nx + nth), (n, n))
                    .copy_from(&(-&i_n));
                b.rows_mut(row + kk * n, n).copy_from(&(&rhs * sgn));
            }
            row += 2 * n;
            // y_τ − [Ĉ x_τ + C x̂_τ − Ĉ x̂_τ] − D u_τ ∈ [−y_r, y_r]  ⇔  with K as in (8).
            let mut h = DMatrix::zeros(m, nv);
            h.view_mut((0, j * n), (m, n)).copy_from(&th.c);
            h.view_mut((0, nx + na + nb), (m, nc))
                .copy_from(&i_m.kronecker(&xhat[j].transpose()));
            if r > 0 {
                h.view_mut((0, nx + na + nb + nc), (m, m * r))
                    .copy_from(&i_m.kronecker(&u[tau].transpose()));
            }
            let rhs = &y[tau] + &th.c * &xhat[j];
            for (kk, &sgn) in [-1.0, 1.0].iter().enumerate() {
                // sgn·(model − y) ≤ y_r, i.e. sgn·h X − y_r ≤ sgn·(y + Ĉ x̂).
                a.view_mut((row + kk * m, 0), (m, nv))
                    .copy_from(&(&h * sgn));
                a.view_mut((row + kk * m, nx + nth + n), (m, m))
                    .copy_from(&(-&i_m));
                b.rows_mut(row + kk * m, m).copy_from(&(&rhs * sgn));
            }
            row += 2 * m;
        }
        let mut lo = DVector::from_element(nv, self.state_prior.x_lo);
        let mut hi = DVector::from_element(nv, self.state_prior.x_hi);
        lo.rows_mut(nx, nth)
            .copy_from(&self.theta_prior.lo.to_vec());
        hi.rows_mut(nx, nth)
            .copy_from(&self.theta_prior.hi.to_vec());
        lo.rows_mut(nx + nth, n + m).fill(0.0);
        hi.rows_mut(nx + nth, n).copy_from(&self.state_prior.xr_max);
        hi.rows_mut(nx + nth + n, m)
            .copy_from(&self.state_prior.yr_max);
        let mut c = DVector::zeros(nv);
        c.rows_mut(nx + nth, n + m).fill(1.0);
        // Θ has no unit of the data: solved as given.
        let mut lp = Lp {
            c,
            a,
            b,
            lo,
            hi,
            unit: None,
        };
        // States and Θ at once: both prior boxes bound it.
        let blame = Blame::new(
            "uniform.x_bound",
            "joint estimate of the states and Θ",
            "uniform.x_bound or uniform.prior_rel may be too small: the states must lie in |x| ≤ x_bound and Θ within ±prior_rel·|θ|",
        );
        let (sol, extended) = solve_extending(&mut lp, n + m, &blame)?;
        self.theta = Theta::from_vec(&sol.x.as_slice()[nx..nx + nth], &self.theta);
        let x = (0..ns).map(|i| sol.x.rows(i * n, n).into_owned()).collect();
        let est = StateEstimate {
            x,
            xr: sol.x.rows(nx + nth, n).into_owned(),
            yr: sol.x.rows(nx + nth + n, m).into_owned(),
            objective: sol.objective,
            extended,
        };
        Ok(est)
    }
}
