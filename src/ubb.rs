//! Unknown-but-bounded noise: R. Tempo, "Robust estimation and filtering in the presence of
//! unknown but bounded noise" (CUCS-223-86, 1986).
//!
//! - Section II: a problem element f ∈ Rⁿ, the a-priori set K and the information
//!   ‖h − Nf‖ ≤ ε (2) are all [`NormBound`]s (a weighted l∞, l1 or l2 norm of an affine image of
//!   f); their intersection is the feasible set T(h) (3), a [`FeasibleSet`].
//! - The central (strongly optimal) algorithm for an l∞ solution norm is the midpoint of the
//!   interval hull of S·T(h), one LP per bound ([`FeasibleSet::interval_hull`], (31)); its local
//!   error (5) is the hull's largest half-width. A 2-D image S·T(h) is computed exactly as a
//!   polygon ([`FeasibleSet::polygon`]).
//! - Theorem 1 (Hilbert norms): [`hilbert`]. Theorem 2 (linear optimal algorithm from the
//!   active constraints): [`linear_optimal`], and on Section IV's window
//!   [`StateProblem::theorem_2`] (the paper's f = [x(s), u(s) … u(k)] (36), the rows of K (37)
//!   and of the information (40) in the form (20); each active row named by its time and bound,
//!   [`RowKind`]). Theorem 3 (l1 noise): the 2^{m−1}-row form (30),
//!   (34) and the lifted form with slacks, chosen by [`L1Form`].
//! - Section IV: state estimation with exponentially smoothed bounds (45)–(46), Theorem 4's
//!   asymptotic bound and Theorem 5's truncation length (58): [`StateProblem`], [`Smoothing`].
//!   Its simulation may draw a true noise other than the assumed bounds
//!   ([`StateProblem::sim_levels`]); data that contradict the bounds are then possible, and
//!   [`StateProblem::step_if_consistent`] / [`StateStep::hull_if_consistent`] say so without an
//!   error (the guarantee study counts them as misses).
//!
//! Errata followed here (see the crate docs): (50) reads u(k−i); (37) must bound u(0) too (f
//! contains it); Theorem 1's "‖N⁻¹‖ > ε⁻¹" is reversed; after Theorem 4 a pole near the unit
//! circle needs exp(1/α) close to 1 (α large, long memory).
//!
//! A 2-D state with per-sample l∞ bounds (every 2-D preset) takes the planar path instead
//! ([`planar`]): the same set, computed exactly by clipping, mapping and Minkowski sums of a
//! convex polygon, with no LP; a 1-D state the same recursion on intervals ([`interval`]). The
//! LP path stays for r ≥ 3, l1/l2 bounds, and as their test oracle ([`StateProblem::step_lp`]).
//!
//! Each step gives two sets of the same T(h): the paper's predicted X(k+1 | y(0 … k)) (38) and
//! the filtered X(k | y(0 … k)), the same unknowns read at time k ([`StateStep::filtered`]); the
//! predicted set is the filtered one mapped by A plus the noise set B·U(k), since u(k) meets no
//! measurement.
//!
//! A missing measurement (NaN in y(t), a gap of the record) drops its rows from the information
//! (40)–(41): T(h) is the intersection of the bounds on the data present, and every norm of the
//! stacked noise (l∞, l1, l2) bounds the samples present exactly as it bounds the whole
//! sequence with the missing ones at 0, so the window's constraints are the same with that row
//! left out. At a gap the set is only the dynamics (the map by A and the noise), and it can only
//! grow: each gap removes a constraint.
//!
//! Every LP goes through [`crate::solve`].

pub mod interval;
pub mod planar;

use crate::error::{Error, Result};
use crate::sets::{polygon_from_support, ConvexPolygon, SupportPolygon};
use crate::solve::{self, Family, Problem};
use nalgebra::{DMatrix, DVector};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The norm of a bound (weighted: ‖h‖^w = ‖(w_i h_i)‖).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Norm {
    Linf,
    L1,
    L2,
}

/// How an l1 bound becomes linear constraints (Theorem 3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum L1Form {
    /// |r_i| ≤ s_i, Σ s_i ≤ ε: m slack variables and 2m + 1 rows.
    Lifted,
    /// The paper's |W_i r| ≤ ε for the 2^{m−1} sign rows W_i of (30).
    Enumerated,
}

/// The largest m the enumerated form accepts (2^{m−1} = 8192 row pairs).
pub const MAX_ENUMERATED_M: usize = 14;

/// Whether an l1 bound on m residuals (`field`: `ubb.eps` or `ubb.tau`) fits Theorem 3's
/// enumerated form, m ≤ [`MAX_ENUMERATED_M`]; the scenario checks its longest window before
/// any LP, the bound again when it is built.
pub fn check_enumerated(field: &str, m: usize) -> Result<()> {
    if m > MAX_ENUMERATED_M {
        return Err(Error::field(
            field,
            format!(
                "is an l1 bound on m = {m} residuals: Theorem 3's enumerated form needs 2^(m−1) = {} sign rows; use the lifted form (l1_form \"lifted\", 2m + 1 rows) or m ≤ {MAX_ENUMERATED_M}",
                1u64 << (m - 1).min(63)
            ),
        ));
    }
    Ok(())
}

/// ‖diag(w)(M f − c)‖ ≤ bound.
#[derive(Debug, Clone)]
pub struct NormBound {
    pub map: DMatrix<f64>,
    pub center: DVector<f64>,
    pub weights: DVector<f64>,
    pub norm: Norm,
    pub bound: f64,
    /// The scenario field this bound comes from (errors name it).
    pub field: String,
}

impl NormBound {
    /// The weighted residual w ∘ (M f − c).
    fn residual(&self, f: &DVector<f64>) -> DVector<f64> {
        (&self.map * f - &self.center).component_mul(&self.weights)
    }

    /// ‖w ∘ (M f − c)‖.
    pub fn value(&self, f: &DVector<f64>) -> f64 {
        norm_of(self.norm, &self.residual(f))
    }
}

fn norm_of(norm: Norm, r: &DVector<f64>) -> f64 {
    match norm {
        Norm::Linf => r.amax(),
        Norm::L1 => r.iter().map(|v| v.abs()).sum(),
        Norm::L2 => r.norm(),
    }
}

/// Sizes of the optimization problem behind a feasible set.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct LpSize {
    pub variables: usize,
    /// Linear inequality and equality rows.
    pub rows: usize,
    /// Second-order cones (l2 bounds) and their total dimension.
    pub cones: usize,
    pub cone_rows: usize,
}

/// The interval hull of S·T(h): per component, inf and sup of S_i f over T(h).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct IntervalHull {
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
}

impl IntervalHull {
    /// The central estimate (31): the componentwise midpoint.
    pub fn center(&self) -> Vec<f64> {
        self.lo
            .iter()
            .zip(&self.hi)
            .map(|(l, h)| 0.5 * (l + h))
            .collect()
    }

    /// Local error (5) of the central estimate in the l∞ solution norm: the largest half-width.
    pub fn radius(&self) -> f64 {
        self.lo
            .iter()
            .zip(&self.hi)
            .map(|(l, h)| 0.5 * (h - l))
            .fold(0.0, f64::max)
    }

    /// Whether x lies in the hull, with tolerance `tol`.
    pub fn contains(&self, x: &[f64], tol: f64) -> bool {
        x.iter()
            .zip(self.lo.iter().zip(&self.hi))
            .all(|(v, (l, h))| *v >= l - tol && *v <= h + tol)
    }
}

/// The feasible set T(h) (3) of problem elements f ∈ R^dim.
#[derive(Debug, Clone)]
pub struct FeasibleSet {
    pub dim: usize,
    pub bounds: Vec<NormBound>,
    /// Equalities E f = e (e.g. a probability vector sums to 1).
    pub eq: Option<(DMatrix<f64>, DVector<f64>)>,
    pub l1_form: L1Form,
    /// The field of an infeasible or unbounded outcome.
    pub field: String,
}

impl FeasibleSet {
    /// Whether f satisfies every bound and equality up to `tol` (relative to each bound).
    pub fn contains(&self, f: &DVector<f64>, tol: f64) -> bool {
        self.bounds
            .iter()
            .all(|b| b.value(f) <= b.bound * (1.0 + tol) + tol)
            && self
                .eq
                .as_ref()
                .is_none_or(|(e, v)| (e * f - v).amax() <= tol * (1.0 + v.amax()))
    }

    /// Whom an empty or unbounded T(h) concerns: `field` first, then every other bound that
    /// may be too small ("ubb.eps may be too small (or ubb.tau, or ubb.delta)").
    fn blame(&self) -> solve::Blame {
        let mut others: Vec<&str> = Vec::new();
        for b in &self.bounds {
            if b.field != self.field && !others.contains(&b.field.as_str()) {
                others.push(&b.field);
            }
        }
        let also = if others.is_empty() {
            String::new()
        } else {
            format!(" (or {})", others.join(", or "))
        };
        solve::Blame::new(
            &self.field,
            "state",
            &format!("{} may be too small{also}", self.field),
        )
    }

    /// The error of an empty T(h): the data contradict the bounds (the LP's infeasibility
    /// message, word for word, for the exact paths that find it without an LP).
    pub fn infeasible_error(&self) -> Error {
        self.blame().infeasible()
    }

    /// The LP (or SOCP, with l2 bounds) of T(h) with a zero objective; slack variables of
    /// lifted l1 bounds come after f.
    pub fn program(&self) -> Result<(Problem, LpSize)> {
        let n = self.dim;
        let slacks: usize = match self.l1_form {
            L1Form::Lifted => self
                .bounds
                .iter()
                .filter(|b| b.norm == Norm::L1)
                .map(|b| b.map.nrows())
                .sum(),
            L1Form::Enumerated => 0,
        };
        let nv = n + slacks;
        let mut rows: Vec<(Vec<f64>, f64)> = Vec::new();
        let mut soc = Vec::new();
        let mut next_slack = n;
        for b in &self.bounds {
            let m = b.map.nrows();
            if b.map.ncols() != n || b.center.len() != m || b.weights.len() != m {
                return Err(Error::field(
                    b.field.clone(),
                    format!(
                        "has a {}×{} map, {} centre entries and {} weights for {n} unknowns",
                        b.map.nrows(),
                        b.map.ncols(),
                        b.center.len(),
                        b.weights.len()
                    ),
                ));
            }
            if !(b.bound >= 0.0 && b.bound.is_finite()) {
                return Err(Error::field(
                    b.field.clone(),
                    format!("must be a finite bound ≥ 0, found {}", b.bound),
                ));
            }
            // Row i of the weighted residual: w_i M_i f − w_i c_i.
            let wrow = |i: usize| -> (Vec<f64>, f64) {
                let mut r = vec![0.0; nv];
                for j in 0..n {
                    r[j] = b.weights[i] * b.map[(i, j)];
                }
                (r, b.weights[i] * b.center[i])
            };
            match (b.norm, self.l1_form) {
                (Norm::Linf, _) => {
                    for i in 0..m {
                        let (r, c) = wrow(i);
                        rows.push((r.clone(), b.bound + c));
                        rows.push((r.iter().map(|v| -v).collect(), b.bound - c));
                    }
                }
                (Norm::L1, L1Form::Lifted) => {
                    let mut total = vec![0.0; nv];
                    for i in 0..m {
                        let (mut r, c) = wrow(i);
                        let mut neg: Vec<f64> = r.iter().map(|v| -v).collect();
                        r[next_slack + i] = -1.0;
                        neg[next_slack + i] = -1.0;
                        rows.push((r, c));
                        rows.push((neg, -c));
                        total[next_slack + i] = 1.0;
                    }
                    rows.push((total, b.bound));
                    next_slack += m;
                }
                (Norm::L1, L1Form::Enumerated) => {
                    check_enumerated(&b.field, m)?;
                    let base: Vec<(Vec<f64>, f64)> = (0..m).map(wrow).collect();
                    // (30): the first sign is +, the others run through all 2^{m−1} patterns.
                    for pattern in 0..(1usize << (m.saturating_sub(1))) {
                        let mut r = vec![0.0; nv];
                        let mut c = 0.0;
                        for (i, (bi, ci)) in base.iter().enumerate() {
                            let sign = if i > 0 && (pattern >> (m - 1 - i)) & 1 == 1 {
                                -1.0
                            } else {
                                1.0
                            };
                            for j in 0..n {
                                r[j] += sign * bi[j];
                            }
                            c += sign * ci;
                        }
                        rows.push((r.clone(), b.bound + c));
                        rows.push((r.iter().map(|v| -v).collect(), b.bound - c));
                    }
                }
                (Norm::L2, _) => {
                    // s = [bound; W(Mf − c)] = g − G f ∈ SOC.
                    let mut g = DMatrix::zeros(m + 1, nv);
                    let mut rhs = DVector::zeros(m + 1);
                    rhs[0] = b.bound;
                    for i in 0..m {
                        let (r, c) = wrow(i);
                        for j in 0..n {
                            g[(i + 1, j)] = -r[j];
                        }
                        rhs[i + 1] = -c;
                    }
                    soc.push((g, rhs));
                }
            }
        }
        let le = if rows.is_empty() {
            None
        } else {
            let a = DMatrix::from_fn(rows.len(), nv, |i, j| rows[i].0[j]);
            let b = DVector::from_iterator(rows.len(), rows.iter().map(|r| r.1));
            Some((a, b))
        };
        let eq = match &self.eq {
            Some((e, v)) => {
                if e.ncols() != n || e.nrows() != v.len() {
                    return Err(Error::field(
                        self.field.clone(),
                        "equality has the wrong shape",
                    ));
                }
                let mut a = DMatrix::zeros(e.nrows(), nv);
                a.view_mut((0, 0), (e.nrows(), n)).copy_from(e);
                Some((a, v.clone()))
            }
            None => None,
        };
        let size = LpSize {
            variables: nv,
            rows: le.as_ref().map_or(0, |l| l.0.nrows()) + eq.as_ref().map_or(0, |e| e.0.nrows()),
            cones: soc.len(),
            cone_rows: soc.iter().map(|(g, _)| g.nrows()).sum(),
        };
        let unit = solve::power_of_two_below(
            le.iter()
                .chain(eq.iter())
                .flat_map(|(_, b)| b.iter())
                .chain(soc.iter().flat_map(|(_, g)| g.iter()))
                .fold(0.0_f64, |m, v| m.max(v.abs())),
        );
        Ok((
            Problem {
                p: None,
                q: DVector::zeros(nv),
                eq,
                le,
                // The unit of the data and bounds: every unknown (x(0), states, noise samples,
                // slacks) has it, so the LP is homogeneous in it.
                unit: Some(unit),
                soc,
                blame: self.blame(),
            },
            size,
        ))
    }

    /// The sizes [`FeasibleSet::program`] would build, counted without building it.
    pub fn size(&self) -> LpSize {
        let mut size = LpSize {
            variables: self.dim,
            ..LpSize::default()
        };
        for b in &self.bounds {
            let m = b.map.nrows();
            match (b.norm, self.l1_form) {
                (Norm::Linf, _) => size.rows += 2 * m,
                (Norm::L1, L1Form::Lifted) => {
                    size.variables += m;
                    size.rows += 2 * m + 1;
                }
                (Norm::L1, L1Form::Enumerated) => {
                    size.rows += 2usize.saturating_mul(
                        1usize
                            .checked_shl(m.saturating_sub(1) as u32)
                            .unwrap_or(usize::MAX),
                    )
                }
                (Norm::L2, _) => {
                    size.cones += 1;
                    size.cone_rows += m + 1;
                }
            }
        }
        size.rows += self.eq.as_ref().map_or(0, |(e, _)| e.nrows());
        size
    }

    /// A solver loaded with T(h), ready for many objectives.
    pub fn support_solver(&self) -> Result<SupportSolver> {
        let (problem, size) = self.program()?;
        Ok(SupportSolver {
            family: Family::new(&problem)?,
            dim: self.dim,
            size,
        })
    }

    /// Interval hull of S·T(h) (2 LPs per row of S).
    pub fn interval_hull(&self, s: &DMatrix<f64>) -> Result<IntervalHull> {
        self.support_solver()?.interval_hull(s)
    }

    /// The exact polygon of the 2-D image S·T(h) (S has 2 rows), with at most `budget` LPs.
    pub fn polygon(&self, s: &DMatrix<f64>, budget: usize) -> Result<SupportPolygon> {
        self.support_solver()?.polygon(s, budget)
    }
}

/// T(h) loaded in the solver once; each support value is one more solve with a new objective.
pub struct SupportSolver {
    family: Family,
    dim: usize,
    pub size: LpSize,
}

impl SupportSolver {
    /// sup over T(h) of dᵀf, and the maximizer.
    pub fn support(&mut self, d: &DVector<f64>) -> Result<(f64, DVector<f64>)> {
        let mut c = DVector::zeros(self.family.dim());
        for j in 0..self.dim {
            c[j] = -d[j];
        }
        let sol = self.family.minimize(Some(&c))?;
        Ok((-sol.objective, sol.x.rows(0, self.dim).into_owned()))
    }

    /// Interval hull of S·T(h).
    pub fn interval_hull(&mut self, s: &DMatrix<f64>) -> Result<IntervalHull> {
        let (mut lo, mut hi) = (Vec::new(), Vec::new());
        for i in 0..s.nrows() {
            let row = s.row(i).transpose();
            hi.push(self.support(&row)?.0);
            lo.push(-self.support(&(-row))?.0);
        }
        Ok(IntervalHull { lo, hi })
    }

    /// The support function of S·T(h) (2-row S) in `count` equally spaced directions: the data
    /// of the outer polygon, and the speed measure (one LP per direction).
    pub fn support_fan(&mut self, s: &DMatrix<f64>, count: usize) -> Result<Vec<f64>> {
        (0..count)
            .map(|i| {
                let t = 2.0 * std::f64::consts::PI * i as f64 / count as f64;
                let dir = s.row(0).transpose() * t.cos() + s.row(1).transpose() * t.sin();
                Ok(self.support(&dir)?.0)
            })
            .collect()
    }

    /// Exact polygon of S·T(h) for a 2-row S.
    pub fn polygon(&mut self, s: &DMatrix<f64>, budget: usize) -> Result<SupportPolygon> {
        let probe = |d: [f64; 2]| -> Result<(f64, [f64; 2])> {
            let dir = s.row(0).transpose() * d[0] + s.row(1).transpose() * d[1];
            let p = s * self.support(&dir)?.1;
            Ok((d[0] * p[0] + d[1] * p[1], [p[0], p[1]]))
        };
        // The interior-point solver is accurate to about 1e-8 relative to the data's scale.
        polygon_from_support(probe, budget, 1e-7)
    }
}

/// The error of a measurement y(t) whose length is not C(t)'s row count: the window's LP and
/// Theorem 2's rows both read y(t) through C(t).
fn output_mismatch(t: usize, entries: usize, rows: usize) -> Error {
    Error::field(
        "data.y",
        format!("y({t}) has {entries} entries, C has {rows} rows"),
    )
}

/// Theorem 2: the linear optimal algorithm for a linear functional S from the active constraints
/// of (22), for T(h) = {f : |P_i f − d_i| ≤ b_i}.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LinearOptimal {
    /// The active rows t₁ … t_n.
    pub active: Vec<usize>,
    /// φ(d) = Σ_j gain_j d_{t_j} = S P̃⁻¹ d̃ (25).
    pub gain: Vec<f64>,
    /// E(φ_o) = sup over T(0) of S f (22).
    pub intrinsic_error: f64,
    /// Σ_j |gain_j| b_{t_j}: the bound on |S f − φ(d)| over T(h) that the gain itself proves
    /// (S f − φ(d) = Σ_j gain_j (P_{t_j} f − d_{t_j})), and by LP duality equal to E(φ_o)
    /// when t₁ … t_n are (22)'s active constraints (the proof of Theorem 2, (26)–(29)).
    pub error: f64,
}

impl LinearOptimal {
    /// φ(d) for the full data vector d (19).
    pub fn apply(&self, d: &DVector<f64>) -> f64 {
        self.active
            .iter()
            .zip(&self.gain)
            .map(|(&t, g)| g * d[t])
            .sum()
    }
}

/// Theorem 2 for P ((n+m)×n), bounds b = ε/w and the functional s.
///
/// (22) is solved by the certified dense simplex ([`solve::simplex`]): its optimum is a vertex,
/// so at most n rows carry a multiplier and they are the active constraints (an interior-point
/// optimum of a degenerate (22) may spread the multipliers over more rows than n). Where the
/// simplex cannot certify, clarabel answers and the rows with the largest multipliers are taken.
pub fn linear_optimal(
    p: &DMatrix<f64>,
    b: &DVector<f64>,
    s: &DVector<f64>,
    field: &str,
) -> Result<LinearOptimal> {
    let (rows, n) = p.shape();
    if b.len() != rows || s.len() != n {
        return Err(Error::field(
            field,
            "P, the bounds and S have inconsistent sizes",
        ));
    }
    let mut a = DMatrix::zeros(2 * rows, n);
    a.view_mut((0, 0), (rows, n)).copy_from(p);
    a.view_mut((rows, 0), (rows, n)).copy_from(&(-p));
    let mut rhs = DVector::zeros(2 * rows);
    rhs.rows_mut(0, rows).copy_from(b);
    rhs.rows_mut(rows, rows).copy_from(b);
    let free = |v: f64| DVector::from_element(n, v);
    let certified = match solve::simplex::engine() {
        solve::simplex::Engine::Simplex => match solve::simplex::minimize(
            &(-s),
            &a,
            &rhs,
            &free(f64::NEG_INFINITY),
            &free(f64::INFINITY),
        ) {
            solve::simplex::Outcome::Optimal(o) => Some((o.x, o.objective, o.duals)),
            _ => None,
        },
        solve::simplex::Engine::Clarabel => None,
    };
    let (x, objective, duals) = match certified {
        Some(v) => v,
        None => {
            let sol = solve::linear(&(-s), None, Some((a, rhs)), field)?;
            (sol.x, sol.objective, sol.duals)
        }
    };
    let intrinsic_error = -objective;
    // Rows by decreasing multiplier, then the other tight rows: any n independent rows that
    // include every row with a positive multiplier reach the same supremum (LP duality).
    let mult: Vec<f64> = (0..rows).map(|i| duals[i].max(duals[i + rows])).collect();
    let slack: Vec<f64> = (0..rows)
        .map(|i| (b[i] - (p.row(i) * &x)[0].abs()) / (1.0 + b[i]))
        .collect();
    let mut order: Vec<usize> = (0..rows).collect();
    order.sort_by(|&i, &j| {
        mult[j]
            .total_cmp(&mult[i])
            .then(slack[i].total_cmp(&slack[j]))
            .then(i.cmp(&j))
    });
    let mut active = Vec::new();
    let mut basis: Vec<DVector<f64>> = Vec::new();
    for &i in &order {
        if active.len() == n {
            break;
        }
        // Gram–Schmidt: keep row i if it adds a new direction.
        let mut v = p.row(i).transpose();
        let norm0 = v.norm();
        for q in &basis {
            let proj = q.dot(&v);
            v -= q * proj;
        }
        if norm0 > 0.0 && v.norm() > 1e-9 * norm0 {
            basis.push(v.normalize());
            active.push(i);
        }
    }
    if active.len() < n {
        return Err(Error::field(
            field,
            format!(
                "rank P̃ = {} < n = {n}: the active constraints do not determine f, so the intrinsic error is not finite (Theorem 2 needs rank n)",
                active.len()
            ),
        ));
    }
    let pt = DMatrix::from_fn(n, n, |i, j| p[(active[i], j)]);
    // gainᵀ = Sᵀ P̃⁻¹, i.e. P̃ᵀ gain = s.
    let gain = pt
        .transpose()
        .lu()
        .solve(s)
        .ok_or_else(|| Error::field(field, "P̃ is singular"))?;
    let error = active
        .iter()
        .zip(gain.iter())
        .map(|(&t, g)| g.abs() * b[t])
        .sum();
    Ok(LinearOptimal {
        active,
        gain: gain.iter().copied().collect(),
        intrinsic_error,
        error,
    })
}

/// The bound an active row of the state problem's Theorem 2 comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RowKind {
    /// |η_i(t)| ≤ ε e^{(k−t)/β} (46): the row C_i(t) x(t) of the information (40).
    Measurement,
    /// |u_i(t)| ≤ τ e^{(k−t)/α} (45): a row of K (37).
    Process,
    /// |x_i(s) − x̄_i(s)| ≤ δ_i(s): the box of the window's first state (δ at s = 0 (37); later
    /// the box moved by A^s plus the noise before the window).
    Prior,
    /// Σ x(0) = the given sum (Example 4): a row with bound 0.
    Sum,
}

/// One active constraint t_j of (22) in the state problem: the time, the bound it comes from,
/// its component (of y, u or x), its bound b_{t_j} and its gain in φ (25).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ActiveRow {
    pub t: usize,
    pub kind: RowKind,
    pub index: usize,
    pub bound: f64,
    pub gain: f64,
}

/// Theorem 2 for one component x_i(k+1) of the state problem's window (S = e_iᵀ: the unit row
/// of the component, on the paper's f = [x(s), u(s) … u(k)] (36)).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LinearEstimate {
    pub component: usize,
    /// φ(h) = x̄_i(k+1) + S P̃⁻¹ d̃ (25), x̄ the nominal trajectory (the known input).
    pub estimate: f64,
    /// E(φ_o) (22): the largest |x_i(k+1) − φ(h)| over T(h) for every h, φ's guaranteed error
    /// (Σ_j |gain_j| b_{t_j}, equal to the LP's supremum; the larger of the two if rounding
    /// parts them).
    pub error: f64,
    /// The n active rows t₁ … t_n of (22), by time.
    pub active: Vec<ActiveRow>,
}

/// Which case of Theorem 1 applies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HilbertCase {
    /// Δ(ε) ⊂ K: Gauss–Markov is optimal.
    GaussMarkov,
    /// K ⊆ Δ(ε): the zero algorithm is optimal.
    Zero,
    /// Neither: (11) with μ from (12), which this crate does not solve.
    Between,
}

/// Theorem 1 for K = {fᵀVf ≤ 1} and ‖h‖² = hᵀRh.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Hilbert {
    pub case: HilbertCase,
    /// sup{fᵀVf : ‖Nf‖ ≤ ε} (Δ(ε) ⊂ K iff ≤ 1, i.e. ‖N⁻¹‖ ≤ 1/ε: the paper's ">" is reversed);
    /// infinite when N is not one-to-one.
    pub delta_in_k: f64,
    /// sup{‖Nf‖² : fᵀVf ≤ 1} / ε² (K ⊆ Δ(ε) iff ≤ 1, i.e. ‖N‖ ≤ ε).
    pub k_in_delta: f64,
    /// S(NᵀRN)⁻¹NᵀRh, when N is one-to-one.
    pub gauss_markov: Option<Vec<f64>>,
    /// The optimal estimate of (14) (None in the case between).
    pub estimate: Option<Vec<f64>>,
}

/// Largest generalized eigenvalue max xᵀAx / xᵀBx for B positive definite.
fn max_generalized_eig(a: &DMatrix<f64>, b: &DMatrix<f64>) -> Option<f64> {
    let l = b.clone().cholesky()?.l();
    let li = l.try_inverse()?;
    let m = &li * a * li.transpose();
    let m = (&m + m.transpose()) * 0.5;
    Some(m.symmetric_eigenvalues().max())
}

/// Theorem 1.
pub fn hilbert(
    v: &DMatrix<f64>,
    r: &DMatrix<f64>,
    n_op: &DMatrix<f64>,
    s: &DMatrix<f64>,
    eps: f64,
    h: &DVector<f64>,
) -> Result<Hilbert> {
    let ntrn = n_op.transpose() * r * n_op;
    let delta_in_k = max_generalized_eig(v, &ntrn).map_or(f64::INFINITY, |l| eps * eps * l);
    let k_in_delta = max_generalized_eig(&ntrn, v)
        .ok_or_else(|| Error::field("V", "must be symmetric positive definite"))?
        / (eps * eps);
    let gauss_markov = ntrn.clone().cholesky().map(|c| {
        (s * c.solve(&(n_op.transpose() * r * h)))
            .iter()
            .copied()
            .collect::<Vec<f64>>()
    });
    let case = if delta_in_k <= 1.0 {
        HilbertCase::GaussMarkov
    } else if k_in_delta <= 1.0 {
        HilbertCase::Zero
    } else {
        HilbertCase::Between
    };
    let estimate = match case {
        HilbertCase::GaussMarkov => gauss_markov.clone(),
        HilbertCase::Zero => Some(vec![0.0; s.nrows()]),
        HilbertCase::Between => None,
    };
    Ok(Hilbert {
        case,
        delta_in_k,
        k_in_delta,
        gauss_markov,
        estimate,
    })
}

/// Theorems 4 and 5 for given ‖A‖, ‖B‖, τ and α (None: no smoothing, α = ∞).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Smoothing {
    pub a_norm: f64,
    pub b_norm: f64,
    pub tau: f64,
    pub alpha: Option<f64>,
    /// ‖A‖·exp(1/α), the ratio of the geometric series (49).
    pub ratio: f64,
}

impl Smoothing {
    pub fn new(a_norm: f64, b_norm: f64, tau: f64, alpha: Option<f64>) -> Self {
        let ratio = a_norm * alpha.map_or(1.0, |a| (1.0 / a).exp());
        Smoothing {
            a_norm,
            b_norm,
            tau,
            alpha,
            ratio,
        }
    }

    /// Theorem 4 (47): limsup ‖x(k+1)‖ ≤ τ‖B‖ / (1 − ‖A‖e^{1/α}), when the ratio is < 1.
    pub fn limit(&self) -> Option<f64> {
        (self.ratio < 1.0).then(|| self.tau * self.b_norm / (1.0 - self.ratio))
    }

    /// (55): the bound on ‖Σ_{i=j+1}^k AⁱBu(k−i)‖ at time k (k = None: its limit (56)).
    pub fn tail(&self, j: usize, k: Option<usize>) -> f64 {
        let q = self.ratio;
        let head = q.powi(j as i32 + 1);
        let rest = k.map_or(0.0, |k| if k > j { q.powi(k as i32 + 1) } else { head });
        self.tau * self.b_norm * (head - rest) / (1.0 - q)
    }

    /// Theorem 5: the smallest j with (ratio)^{j+1} ≤ γ(1 − ratio)/(τ‖B‖) (52), i.e. (58).
    pub fn truncation(&self, gamma: f64, field: &str) -> Result<usize> {
        if !(gamma > 0.0 && gamma.is_finite()) {
            return Err(Error::field(
                field,
                format!("must be a positive number, found {gamma}"),
            ));
        }
        if self.ratio >= 1.0 {
            return Err(Error::field(
                field,
                format!(
                    "cannot be met: Theorem 5 needs ‖A‖∞·exp(1/α) < 1, but it is {:.4} (raise α, or the system is not contractive in this norm)",
                    self.ratio
                ),
            ));
        }
        if self.tau * self.b_norm == 0.0 {
            return Ok(0);
        }
        // (58): (j+1)·ln(ratio) ≤ ln(1 − ratio) + ln γ − ln τ − ln‖B‖.
        let rhs = (1.0 - self.ratio).ln() + gamma.ln() - self.tau.ln() - self.b_norm.ln();
        if rhs >= 0.0 {
            return Ok(0);
        }
        let mut j = ((rhs / self.ratio.ln()).ceil() as usize).saturating_sub(1);
        // Guard the rounding of the logarithms with (52) itself.
        while self.tail(j, None) > gamma {
            j += 1;
        }
        while j > 0 && self.tail(j - 1, None) <= gamma {
            j -= 1;
        }
        Ok(j)
    }
}

/// The dynamic system (35) with a known input v (the Remark after (44)) and output matrices C(t)
/// (time-varying for the basis-function series of Example 1).
#[derive(Debug, Clone)]
pub struct System {
    pub a: DMatrix<f64>,
    /// r×p; p = 0 means no process noise.
    pub b: DMatrix<f64>,
    /// C(t) for t = 0 … (at least the measured times); q = 0 rows means no measurements.
    pub c: Vec<DMatrix<f64>>,
    /// Known input v(t) (empty: none).
    pub v: Vec<DVector<f64>>,
}

impl System {
    pub fn r(&self) -> usize {
        self.a.nrows()
    }
    pub fn p(&self) -> usize {
        self.b.ncols()
    }
    fn c_at(&self, t: usize) -> &DMatrix<f64> {
        &self.c[t.min(self.c.len() - 1)]
    }
    fn v_at(&self, t: usize) -> Option<&DVector<f64>> {
        if self.v.is_empty() {
            None
        } else {
            Some(&self.v[t.min(self.v.len() - 1)])
        }
    }

    /// The nominal trajectory x̄(t) from x̄(0) = c₀ with the known input only.
    fn nominal(&self, c0: &DVector<f64>, steps: usize) -> Vec<DVector<f64>> {
        let mut x = vec![c0.clone()];
        for t in 0..steps {
            let mut next = &self.a * &x[t];
            if let Some(v) = self.v_at(t) {
                next += v;
            }
            x.push(next);
        }
        x
    }
}

/// The a-priori bounds (37), (45)–(46).
#[derive(Debug, Clone)]
pub struct Bounds {
    /// Norm of the stacked (smoothing-weighted) noise sequences.
    pub norm: Norm,
    pub l1_form: L1Form,
    /// τ of (37)/(45) and ε of (46).
    pub tau: f64,
    pub eps: f64,
    /// Half-widths of the box of x(0) around `x0_center` (None: δ = ∞).
    pub delta: Option<DVector<f64>>,
    pub x0_center: DVector<f64>,
    /// Σ x(0) = this (a probability vector, Example 4).
    pub x0_sum: Option<f64>,
    /// Smoothing constants (None: ∞, no smoothing).
    pub alpha: Option<f64>,
    pub beta: Option<f64>,
}

/// Weight of a sample of age `age` under smoothing constant `c` (45)–(46): bound·e^{age/c}
/// on the sample is weight e^{−age/c} on the residual.
fn age_weight(c: Option<f64>, age: usize) -> f64 {
    c.map_or(1.0, |c| (-(age as f64) / c).exp())
}

/// One step of the state estimator: T(h) at time k for f = [e(s) … e(k+1), u(s) … u(k)],
/// e = x − x̄ (f = e(0) without process noise).
#[derive(Debug, Clone)]
pub struct StateStep {
    pub k: usize,
    /// First time of the window (s).
    pub first: usize,
    /// T(h) of the window, shared by the predicted set and its filtered view.
    pub set: Arc<FeasibleSet>,
    /// The state this step's set is of, x = offset + S f: x(k+1) (the predicted set), or x(k)
    /// on the filtered view ([`StateStep::filtered`]).
    pub s_map: DMatrix<f64>,
    pub offset: DVector<f64>,
    /// The planar path ran: the exact polygon of x − offset (r = 2, l∞ bounds, the data
    /// close the set). `None`: the LP path (the set's support LPs) answers.
    pub planar: Option<ConvexPolygon>,
    /// The line path ran ([`interval`]): the exact interval of x − offset (r = 1, l∞ bounds).
    pub interval: Option<[f64; 2]>,
    /// The filtered set X(k | y(s … k)): the same T(h) read at time k (the same step with
    /// S = the map of x(k), its own exact polygon or interval). `None` on the filtered view
    /// itself, and when that set is unbounded though the predicted one is not (δ = ∞ and a
    /// singular A that annihilates what the data leave free only by its last power:
    /// [`StateProblem::step`]'s boundedness test).
    pub filtered: Option<Box<StateStep>>,
}

/// The largest rows·n·(rows + n) of Theorem 2's LP (22) solved at a step (a window of about
/// 110 steps with one noise input and one output): beyond it one component's estimate would
/// take over 0.2 s natively.
pub const THEOREM_2_MAX_WORK: f64 = 1e7;
/// Operations per unit of rows·n·(rows + n) of one dense simplex solve of (22) (measured: a
/// window of 400 steps, 802 rows and 402 unknowns, 8.6 s natively).
pub const THEOREM_2_OPS: f64 = 22.0;

/// Section IV: the state x(k+1) from y(0 … k) with a window of `window` steps.
#[derive(Debug, Clone)]
pub struct StateProblem {
    pub system: System,
    pub bounds: Bounds,
    /// Window length j + 1 (Theorem 5); ignored when p = 0 (then all data are used: the
    /// unknowns do not grow).
    pub window: usize,
    /// Simulation only: true levels (τ, ε) when they differ from the bounds.
    pub sim_levels: (Option<f64>, Option<f64>),
}

impl StateProblem {
    /// T(h) at time k given y(0 … k) (y may be longer), with its exact polygon when the
    /// planar path applies (a 2-D state, l∞ bounds): then contradicting data are refused here,
    /// with the LP path's message.
    pub fn step(&self, y: &[DVector<f64>], k: usize) -> Result<StateStep> {
        self.build(y, k, true)?.map_err(|e| *e)
    }

    /// [`StateProblem::step`], with data that contradict the bounds as `Ok(None)` (no set)
    /// where the planar path finds its polygon empty; on the LP path the set's first LP
    /// decides ([`StateStep::hull_if_consistent`]). The guarantee study counts such a run as
    /// the truth outside the set: its noise exceeded the bounds the estimator assumes.
    pub fn step_if_consistent(&self, y: &[DVector<f64>], k: usize) -> Result<Option<StateStep>> {
        Ok(self.build(y, k, true)?.ok())
    }

    /// T(h) at time k for the LP path only (the planar path's test oracle).
    pub fn step_lp(&self, y: &[DVector<f64>], k: usize) -> Result<StateStep> {
        self.build(y, k, false)?.map_err(|e| *e)
    }

    /// The step, or (inner `Err`) the error of an empty planar polygon: the data contradict the
    /// bounds.
    #[allow(clippy::type_complexity)]
    fn build(
        &self,
        y: &[DVector<f64>],
        k: usize,
        exact: bool,
    ) -> Result<std::result::Result<StateStep, Box<Error>>> {
        let sys = &self.system;
        let bd = &self.bounds;
        let (r, p) = (sys.r(), sys.p());
        if y.len() <= k {
            return Err(Error::field(
                "ubb.time",
                format!("k = {k} needs y(0 … {k}), only {} given", y.len()),
            ));
        }
        let len = if p == 0 {
            k + 1
        } else {
            self.window.clamp(1, k + 1)
        };
        let s = k + 1 - len;
        let nominal = sys.nominal(&bd.x0_center, k + 1);
        // Powers A⁰ … A^{k+1}.
        let mut pow = vec![DMatrix::identity(r, r)];
        for i in 0..=k {
            let next = &sys.a * &pow[i];
            pow.push(next);
        }
        // With process noise the unknowns are stage-wise, f = [e(s) … e(k+1), u(s) … u(k)]
        // with e = x − x̄ and the dynamics as equalities: a banded KKT system, several times
        // faster to factor than the condensed (39), whose N is a dense triangle. Without
        // process noise f = e(s) = e(0) alone and (39) is x(t) − x̄(t) = A^t e(0).
        let stagewise = p > 0;
        let dim = if stagewise {
            r * (len + 1) + p * len
        } else {
            r
        };
        let xcol = |t: usize| r * (t - s);
        let ucol = |l: usize| r * (len + 1) + p * (l - s);
        let state_map = |t: usize| -> DMatrix<f64> {
            let mut m = DMatrix::zeros(r, dim);
            if stagewise {
                m.view_mut((0, xcol(t)), (r, r)).fill_with_identity();
            } else {
                m.view_mut((0, 0), (r, r)).copy_from(&pow[t - s]);
            }
            m
        };
        let mut eq_rows: Vec<(DMatrix<f64>, DVector<f64>)> = Vec::new();
        if stagewise {
            // (35): e(t+1) − A e(t) − B u(t) = 0 (the known input cancels with x̄).
            let mut e = DMatrix::zeros(r * len, dim);
            for t in s..=k {
                let row = r * (t - s);
                e.view_mut((row, xcol(t + 1)), (r, r)).fill_with_identity();
                e.view_mut((row, xcol(t)), (r, r)).copy_from(&(-&sys.a));
                e.view_mut((row, ucol(t)), (r, p)).copy_from(&(-&sys.b));
            }
            eq_rows.push((e, DVector::zeros(r * len)));
        }
        let mut bounds = Vec::new();
        // Measurements (40)–(42) with the smoothed bound (46): the rows of the data present
        // (a gap, NaN, drops its row: the module's note).
        let q = sys.c_at(0).nrows();
        if q > 0 {
            for t in s..=k {
                let c = sys.c_at(t);
                if c.nrows() != q || y[t].len() != q {
                    return Err(output_mismatch(t, y[t].len(), c.nrows()));
                }
            }
            let present = (s..=k)
                .map(|t| y[t].iter().filter(|v| !v.is_nan()).count())
                .sum::<usize>();
            if present > 0 {
                let mut n_op = DMatrix::zeros(present, dim);
                let mut h = DVector::zeros(present);
                let mut w = DVector::zeros(present);
                let mut row = 0;
                for t in s..=k {
                    let c = sys.c_at(t);
                    let cm = c * state_map(t);
                    let cx = c * &nominal[t];
                    for i in (0..q).filter(|&i| !y[t][i].is_nan()) {
                        n_op.row_mut(row).copy_from(&cm.row(i));
                        h[row] = y[t][i] - cx[i];
                        w[row] = age_weight(bd.beta, k - t);
                        row += 1;
                    }
                }
                bounds.push(NormBound {
                    map: n_op,
                    center: h,
                    weights: w,
                    norm: bd.norm,
                    bound: bd.eps,
                    field: "ubb.eps".into(),
                });
            }
        }
        // Process noise in the window (37) with the smoothed bound (45).
        if p > 0 {
            let mut map = DMatrix::zeros(p * len, dim);
            map.view_mut((0, ucol(s)), (p * len, p * len))
                .fill_with_identity();
            let w = DVector::from_fn(p * len, |i, _| age_weight(bd.alpha, k - (s + i / p)));
            bounds.push(NormBound {
                map,
                center: DVector::zeros(p * len),
                weights: w,
                norm: bd.norm,
                bound: bd.tau,
                field: "ubb.tau".into(),
            });
        }
        // The window's initial state z = x(s) − x̄(s) in its box ([`StateProblem::start_half`]).
        let start_half = self.start_half(&pow, s, k);
        if let Some(half) = &start_half {
            let map = state_map(s);
            // |z_i| ≤ half_i as an l∞ ball of radius h = max half_i with weights h/half_i
            // (half_i = 0 pins z_i): the bound keeps the problem's unit, so scaling the
            // data, ε, τ and δ by s scales every right-hand side by s (a unit ball here
            // put 1 beside data of 10⁻⁶ and the LP's tolerances decided the hull).
            let radius = half.amax();
            let weights = if radius > 0.0 {
                half.map(|v| if v > 0.0 { radius / v } else { 1e12 })
            } else {
                DVector::from_element(r, 1.0)
            };
            bounds.push(NormBound {
                map,
                center: DVector::zeros(r),
                weights,
                norm: Norm::Linf,
                bound: radius,
                field: "ubb.delta".into(),
            });
        }
        if let (Some(total), 0) = (bd.x0_sum, s) {
            let e = DMatrix::from_element(1, r, 1.0) * state_map(0);
            eq_rows.push((e, DVector::from_element(1, total - bd.x0_center.sum())));
        }
        let eq = (!eq_rows.is_empty()).then(|| {
            let rows: usize = eq_rows.iter().map(|(e, _)| e.nrows()).sum();
            let mut e = DMatrix::zeros(rows, dim);
            let mut v = DVector::zeros(rows);
            let mut at = 0;
            for (blk, rhs) in &eq_rows {
                e.view_mut((at, 0), (blk.nrows(), dim)).copy_from(blk);
                v.rows_mut(at, blk.nrows()).copy_from(rhs);
                at += blk.nrows();
            }
            (e, v)
        });
        let filtered_bounded = if bd.delta.is_none() {
            self.check_reconstructible(&pow, y, s, k)?
        } else {
            true
        };
        let set = Arc::new(FeasibleSet {
            dim,
            bounds,
            eq,
            l1_form: bd.l1_form,
            field: "ubb.eps".into(),
        });
        // The exact paths (no LP): (predicted, filtered) polygons or intervals.
        let (mut planar, mut planar_filtered) = (None, None);
        let (mut interval, mut interval_filtered) = (None, None);
        if exact && r == 2 && bd.norm == Norm::Linf {
            match self.planar(y, k, s, &nominal, start_half.as_ref()) {
                planar::Outcome::Polygon {
                    predicted,
                    filtered,
                } => (planar, planar_filtered) = (Some(predicted), filtered),
                // The LP would be infeasible: its error, word for word.
                planar::Outcome::Empty => return Ok(Err(Box::new(set.infeasible_error()))),
                planar::Outcome::Open => {}
            }
        } else if exact && r == 1 && bd.norm == Norm::Linf {
            match self.line(y, k, s, &nominal, start_half.as_ref()) {
                interval::Outcome::Interval {
                    predicted,
                    filtered,
                } => (interval, interval_filtered) = (Some(predicted), filtered),
                interval::Outcome::Empty => return Ok(Err(Box::new(set.infeasible_error()))),
                interval::Outcome::Open => {}
            }
        }
        let filtered = filtered_bounded.then(|| {
            Box::new(StateStep {
                k,
                first: s,
                set: Arc::clone(&set),
                s_map: state_map(k),
                offset: nominal[k].clone(),
                planar: planar_filtered,
                interval: interval_filtered,
                filtered: None,
            })
        });
        Ok(Ok(StateStep {
            k,
            first: s,
            set,
            s_map: state_map(k + 1),
            offset: nominal[k + 1].clone(),
            planar,
            interval,
            filtered,
        }))
    }

    /// Theorem 2 at step k for the state components `components`: the linear optimal estimate
    /// (25) of each x_i(k+1) from the active constraints of (22), with its error E(φ_o), for
    /// l∞ bounds (`None` for l1 and l2, where Theorem 2 does not apply).
    ///
    /// The problem is the paper's (36)–(41) on the window s … k: f = [z, u(s) … u(k)] with
    /// z = x(s) − x̄(s), n = r + p·len unknowns, and T(h) = {f : |P_i f − d_i| ≤ b_i} (20) with
    /// the rows of K (37) (the box of z, the process noise (45), Example 4's Σx(0) with b = 0)
    /// and the rows of the information (40) (C(t)x(t), d = y(t) − C(t)x̄(t), b from (46)). It is
    /// the set [`StateProblem::step`] builds, with the dynamics substituted (39) instead of kept
    /// as equalities: Theorem 2 needs the form (20).
    pub fn theorem_2(
        &self,
        y: &[DVector<f64>],
        k: usize,
        components: &[usize],
    ) -> Result<Option<Vec<LinearEstimate>>> {
        self.linear_estimates(y, k, components, false)
    }

    /// [`StateProblem::theorem_2`] for the filtered state x_i(k) (S = the row of M_k in (39):
    /// the same rows of (22), the solution operator read one step earlier).
    pub fn theorem_2_filtered(
        &self,
        y: &[DVector<f64>],
        k: usize,
        components: &[usize],
    ) -> Result<Option<Vec<LinearEstimate>>> {
        self.linear_estimates(y, k, components, true)
    }

    fn linear_estimates(
        &self,
        y: &[DVector<f64>],
        k: usize,
        components: &[usize],
        filtered: bool,
    ) -> Result<Option<Vec<LinearEstimate>>> {
        let sys = &self.system;
        let bd = &self.bounds;
        if bd.norm != Norm::Linf {
            return Ok(None);
        }
        let (r, p) = (sys.r(), sys.p());
        if y.len() <= k {
            return Err(Error::field(
                "ubb.time",
                format!("k = {k} needs y(0 … {k}), only {} given", y.len()),
            ));
        }
        if let Some(&c) = components.iter().find(|&&c| c >= r) {
            return Err(Error::field(
                "ubb.plane",
                format!("names component {c}, but the state has {r}"),
            ));
        }
        let len = if p == 0 {
            k + 1
        } else {
            self.window.clamp(1, k + 1)
        };
        let s = k + 1 - len;
        let n = r + p * len;
        let nominal = sys.nominal(&bd.x0_center, k + 1);
        let mut pow = vec![DMatrix::identity(r, r)];
        for i in 0..=k {
            let next = &sys.a * &pow[i];
            pow.push(next);
        }
        let ucol = |l: usize| r + p * (l - s);
        let mut rows: Vec<(Vec<f64>, f64, f64, RowKind, usize, usize)> = Vec::new();
        let unit = |col: usize| {
            let mut v = vec![0.0; n];
            v[col] = 1.0;
            v
        };
        if let Some(half) = self.start_half(&pow, s, k) {
            for i in 0..r {
                rows.push((unit(i), 0.0, half[i], RowKind::Prior, s, i));
            }
        }
        if let (Some(total), 0) = (bd.x0_sum, s) {
            let mut v = vec![0.0; n];
            v[..r].fill(1.0);
            rows.push((v, total - bd.x0_center.sum(), 0.0, RowKind::Sum, 0, 0));
        }
        // e(t) = M_t f (39): M_s = [I 0], M_{t+1} = A M_t + B on u(t)'s columns.
        let mut m_t = DMatrix::zeros(r, n);
        m_t.view_mut((0, 0), (r, r)).fill_with_identity();
        let mut m_k = m_t.clone();
        for t in s..=k {
            let c = sys.c_at(t);
            if c.nrows() > 0 && y[t].len() != c.nrows() {
                return Err(output_mismatch(t, y[t].len(), c.nrows()));
            }
            let eps = bd.eps / age_weight(bd.beta, k - t);
            let cm = c * &m_t;
            let cx = c * &nominal[t];
            if t == k {
                m_k = m_t.clone();
            }
            // A gap (NaN) has no row in the information (40).
            for i in (0..c.nrows()).filter(|&i| !y[t][i].is_nan()) {
                let row: Vec<f64> = cm.row(i).iter().copied().collect();
                rows.push((row, y[t][i] - cx[i], eps, RowKind::Measurement, t, i));
            }
            if p > 0 {
                let tau = bd.tau / age_weight(bd.alpha, k - t);
                for j in 0..p {
                    rows.push((unit(ucol(t) + j), 0.0, tau, RowKind::Process, t, j));
                }
            }
            let mut next = &sys.a * &m_t;
            if p > 0 {
                let mut bcols = next.view_mut((0, ucol(t)), (r, p));
                bcols += &sys.b;
            }
            m_t = next;
        }
        // The dense simplex of (22) costs about rows·n·(rows + n) per solve (window 100: 0.1 s,
        // window 400: 9 s natively): past THEOREM_2_MAX_WORK the estimate is left out, and the
        // step says why (the set and its hull do not depend on it).
        let work = (rows.len() * n) as f64 * (rows.len() + n) as f64;
        if work > THEOREM_2_MAX_WORK {
            return Err(Error::field(
                "ubb.window",
                format!(
                    "is {len} steps: Theorem 2's LP (22) has {n} unknowns and {} rows there, about {:.1} s per component with the dense simplex; it is computed for windows up to about 100 steps (the set and its hull stand without it)",
                    rows.len(),
                    work * THEOREM_2_OPS / 1e9
                ),
            ));
        }
        let pm = DMatrix::from_fn(rows.len(), n, |i, j| rows[i].0[j]);
        let d = DVector::from_iterator(rows.len(), rows.iter().map(|row| row.1));
        let b = DVector::from_iterator(rows.len(), rows.iter().map(|row| row.2));
        let kind_order = |k: RowKind| match k {
            RowKind::Prior => 0,
            RowKind::Sum => 1,
            RowKind::Process => 2,
            RowKind::Measurement => 3,
        };
        // S: the row of x(k+1) = x̄(k+1) + M_{k+1} f, or of x(k) for the filtered set.
        let (m_s, x_bar) = if filtered {
            (&m_k, &nominal[k])
        } else {
            (&m_t, &nominal[k + 1])
        };
        components
            .iter()
            .map(|&i| {
                let sv = m_s.row(i).transpose();
                let lin = linear_optimal(&pm, &b, &sv, "ubb.eps")?;
                let mut active: Vec<ActiveRow> = lin
                    .active
                    .iter()
                    .zip(&lin.gain)
                    .map(|(&row, &gain)| {
                        let (_, _, bound, kind, t, index) = rows[row].clone();
                        ActiveRow {
                            t,
                            kind,
                            index,
                            bound,
                            gain,
                        }
                    })
                    .collect();
                active.sort_by_key(|a| (a.t, kind_order(a.kind), a.index));
                Ok(LinearEstimate {
                    component: i,
                    estimate: x_bar[i] + lin.apply(&d),
                    error: lin.error.max(lin.intrinsic_error),
                    active,
                })
            })
            .collect::<Result<Vec<_>>>()
            .map(Some)
    }

    /// The half-widths of the box of the window's initial state z = x(s) − x̄(s) at step k: the
    /// box of x(0) moved by A^s, plus the noise before the window, each sample bounded by
    /// τe^{(k−l)/α} (45) in the noise norm. `None` with δ = ∞, or when a half-width is not
    /// finite (the start is then left free).
    fn start_half(&self, pow: &[DMatrix<f64>], s: usize, k: usize) -> Option<DVector<f64>> {
        let (sys, bd) = (&self.system, &self.bounds);
        let delta = bd.delta.as_ref()?;
        let r = sys.r();
        let mut half = DVector::zeros(r);
        for i in 0..r {
            let prior: f64 = (0..r).map(|j| pow[s][(i, j)].abs() * delta[j]).sum();
            let mut noise = 0.0;
            for l in 0..s {
                let m = &pow[s - 1 - l] * &sys.b;
                let row = m.row(i).transpose();
                // Dual norm of the row: the largest |row·u| over ‖u‖ ≤ 1.
                let dual = match bd.norm {
                    Norm::Linf => row.iter().map(|v| v.abs()).sum::<f64>(),
                    Norm::L1 => row.amax(),
                    Norm::L2 => row.norm(),
                };
                noise += dual * bd.tau * (1.0 / age_weight(bd.alpha, k - l));
            }
            half[i] = prior + noise;
        }
        half.iter().all(|v| v.is_finite()).then_some(half)
    }

    /// The planar recursion of the window s … k ([`planar`]): the same constraints as the LP
    /// (the δ box of e(s), the strips (46), the noise (45), Example 4's Σx(0)), in deviations
    /// e = x − x̄ from the nominal trajectory.
    fn planar(
        &self,
        y: &[DVector<f64>],
        k: usize,
        s: usize,
        nominal: &[DVector<f64>],
        start: Option<&DVector<f64>>,
    ) -> planar::Outcome {
        let sys = &self.system;
        let bd = &self.bounds;
        let a = [
            [sys.a[(0, 0)], sys.a[(0, 1)]],
            [sys.a[(1, 0)], sys.a[(1, 1)]],
        ];
        let noise: Vec<[f64; 2]> = (0..sys.p())
            .map(|j| [sys.b[(0, j)], sys.b[(1, j)]])
            .collect();
        let samples: Vec<planar::Sample> = (s..=k)
            .map(|t| {
                let c = sys.c_at(t);
                let eps = bd.eps / age_weight(bd.beta, k - t);
                // A gap (NaN) has no strip: that time is the map and the noise alone.
                let strips = (0..c.nrows())
                    .filter(|&i| !y[t][i].is_nan())
                    .map(|i| {
                        // h_i = y_i − C_i x̄(t): the residual (40) in deviations.
                        let h = y[t][i] - (c[(i, 0)] * nominal[t][0] + c[(i, 1)] * nominal[t][1]);
                        ([c[(i, 0)], c[(i, 1)]], h - eps, h + eps)
                    })
                    .collect();
                let tau = if sys.p() > 0 {
                    bd.tau / age_weight(bd.alpha, k - t)
                } else {
                    0.0
                };
                planar::Sample { strips, tau }
            })
            .collect();
        let equal = match (bd.x0_sum, s) {
            (Some(total), 0) => Some(([1.0, 1.0], total - bd.x0_center.sum())),
            _ => None,
        };
        planar::propagate(a, &noise, start.map(|h| [h[0], h[1]]), equal, &samples)
    }

    /// The line path of the window s … k ([`interval`]): the planar recursion's constraints on
    /// a 1-D state, in deviations e = x − x̄.
    fn line(
        &self,
        y: &[DVector<f64>],
        k: usize,
        s: usize,
        nominal: &[DVector<f64>],
        start: Option<&DVector<f64>>,
    ) -> interval::Outcome {
        let sys = &self.system;
        let bd = &self.bounds;
        // Σ_j |b_j|: the noise segments B·[−τ, τ]^p add up to one interval on a line.
        let b_sum: f64 = sys.b.iter().map(|v| v.abs()).sum();
        let samples: Vec<interval::Sample> = (s..=k)
            .map(|t| {
                let c = sys.c_at(t);
                let eps = bd.eps / age_weight(bd.beta, k - t);
                let strips = (0..c.nrows())
                    .filter(|&i| !y[t][i].is_nan())
                    .map(|i| {
                        let h = y[t][i] - c[(i, 0)] * nominal[t][0];
                        (c[(i, 0)], h - eps, h + eps)
                    })
                    .collect();
                let noise = if sys.p() > 0 {
                    b_sum * bd.tau / age_weight(bd.alpha, k - t)
                } else {
                    0.0
                };
                interval::Sample { strips, noise }
            })
            .collect();
        let equal = match (bd.x0_sum, s) {
            (Some(total), 0) => Some(total - bd.x0_center.sum()),
            _ => None,
        };
        interval::propagate(sys.a[(0, 0)], start.map(|h| h[0]), equal, &samples)
    }

    /// With δ = ∞ (no bound on the window's first state e(s)), whether the window's data
    /// determine the state: an unbounded set of x(k+1) is the error (`ubb.delta`), and the
    /// answer is whether the set of x(k) is bounded too.
    ///
    /// The Remark after (44) asks for observability, rank [C; CA; …] = r, which is enough but
    /// not necessary. T(h) is a polyhedron in the unknowns (e(s), u(s … k)) whose noise parts
    /// are bounded, so its unbounded directions (its recession cone) are {(e, 0) : O e = 0},
    /// O = [C(s); C(s+1)A; …; C(k)A^{k−s}] with the rows of the measurements present (a gap
    /// drops its row; Example 4's Σx(0) adds a row of ones at s = 0). A linear image of a
    /// polyhedron is bounded exactly when every recession direction maps to 0, and
    /// x(k+1) = A^{len} e(s) + Σ A^i B u(k − i) (39): the set of x(k+1) is bounded iff
    /// A^{len} ker O = {0}, the pair (A, C) reconstructible over the window (a singular A may
    /// annihilate what the data leave free), and that of x(k) iff A^{len−1} ker O = {0}.
    fn check_reconstructible(
        &self,
        pow: &[DMatrix<f64>],
        y: &[DVector<f64>],
        s: usize,
        k: usize,
    ) -> Result<bool> {
        let sys = &self.system;
        let r = sys.r();
        let len = k + 1 - s;
        let mut rows: Vec<nalgebra::RowDVector<f64>> = Vec::new();
        let mut missing = 0;
        for t in s..=k {
            let m = sys.c_at(t) * &pow[t - s];
            for (i, row) in m.row_iter().enumerate() {
                if y[t].get(i).is_some_and(|v| v.is_nan()) {
                    missing += 1;
                } else {
                    rows.push(row.into_owned());
                }
            }
        }
        if let (Some(_), 0) = (self.bounds.x0_sum, s) {
            rows.push(nalgebra::RowDVector::from_element(r, 1.0));
        }
        // nalgebra's SVD panics on a NaN; overflowing powers of A must be an error. The outputs'
        // rows (model.H, or ubb.basis) are checked finite when prepared, so a non-finite entry
        // here is A's powers, or their product with those rows.
        if rows.iter().flat_map(|r| r.iter()).any(|x| !x.is_finite()) {
            return Err(Error::field(
                "model.F",
                format!("has powers that overflow double precision over the window y({s} … {k}): A^{} times the output rows passes 1.8e308; shorten ubb.window or scale the model", k - s),
            ));
        }
        // ker O: the right singular vectors of O with a singular value below 1e-9 of its
        // largest entry (zero rows pad O to r rows, so its thin SVD has every one of them).
        while rows.len() < r {
            rows.push(nalgebra::RowDVector::zeros(r));
        }
        let o = DMatrix::from_rows(&rows);
        let tol = 1e-9 * o.amax().max(1e-300);
        let svd = crate::linalg::try_svd(o, false, true).ok_or_else(|| {
            Error::field(
                "model.F",
                format!("has an observability matrix over y({s} … {k}) without an SVD (an entry is not finite)"),
            )
        })?;
        let v_t = svd.v_t.as_ref().ok_or_else(|| {
            Error::field(
                "model.F",
                "has an observability matrix without right singular vectors",
            )
        })?;
        let free: Vec<DVector<f64>> = (0..r)
            .filter(|&i| svd.singular_values[i] <= tol)
            .map(|i| v_t.row(i).transpose())
            .collect();
        let rank = r - free.len();
        let predicted = annihilated(&sys.a, &free, len);
        if !predicted {
            let gaps = if missing > 0 {
                format!(", {missing} of its measurements missing")
            } else {
                String::new()
            };
            return Err(Error::field(
                "ubb.delta",
                format!(
                    "is ∞ (no bound on x(0)), and y({s} … {k}) leave x({}) unbounded: they determine {rank} of the {r} state directions of x({s}) (rank [C; CA; …; CA^{}] = {rank} over the window{gaps}), and A^{len} does not map the rest to 0 (the pair (A, C) is not reconstructible over the window of {len} {}: the feasible set is unbounded); give δ or wait for more data",
                    k + 1,
                    len - 1,
                    if len == 1 { "step" } else { "steps" },
                ),
            ));
        }
        Ok(annihilated(&sys.a, &free, len - 1))
    }
}

/// Whether A^steps maps the span of the orthonormal `free` vectors to 0, without forming the
/// power (whose entries under- or overflow): the image's orthonormal basis is mapped one step
/// at a time, dropping the directions A shrinks below 1e-9 of its norm (rounding of an exact
/// 0). The dimension of A^j V stops changing by j = r (past it A^j V lies in A^r's range,
/// where A is invertible), so at most r steps decide.
fn annihilated(a: &DMatrix<f64>, free: &[DVector<f64>], steps: usize) -> bool {
    let r = a.nrows();
    let tol = 1e-9 * a.norm();
    let mut basis: Vec<DVector<f64>> = free.to_vec();
    for _ in 0..steps.min(r) {
        if basis.is_empty() {
            return true;
        }
        let image = DMatrix::from_columns(&basis.iter().map(|v| a * v).collect::<Vec<_>>());
        let Some(svd) = crate::linalg::try_svd(image, true, false) else {
            return false;
        };
        let Some(u) = svd.u.as_ref() else {
            return false;
        };
        basis = (0..svd.singular_values.len())
            .filter(|&i| svd.singular_values[i] > tol)
            .map(|i| u.column(i).into_owned())
            .collect();
    }
    basis.is_empty()
}

impl StateStep {
    /// Interval hull of x(k+1) (of x(k) on the filtered view): the polygon's min and max on
    /// the planar path, the interval itself on the line path, 2r LPs on the LP path.
    pub fn hull(&self) -> Result<IntervalHull> {
        if let Some([lo, hi]) = self.interval {
            return Ok(self.shift(IntervalHull {
                lo: vec![lo],
                hi: vec![hi],
            }));
        }
        if let Some(p) = &self.planar {
            let h = p.interval_hull();
            return Ok(self.shift(IntervalHull {
                lo: vec![h[0], h[2]],
                hi: vec![h[1], h[3]],
            }));
        }
        let h = self.set.interval_hull(&self.s_map)?;
        Ok(self.shift(h))
    }

    /// The interval hulls of the predicted set and of its filtered view (when bounded), from
    /// one loaded solver on the LP path (4r support LPs on T(h) loaded once), with no LP on
    /// the exact paths.
    pub fn hulls(&self) -> Result<(IntervalHull, Option<IntervalHull>)> {
        let exact = |s: &StateStep| s.planar.is_some() || s.interval.is_some();
        let both_exact = exact(self) && self.filtered.as_deref().is_none_or(exact);
        if both_exact {
            let f = match &self.filtered {
                Some(f) => Some(f.hull()?),
                None => None,
            };
            return Ok((self.hull()?, f));
        }
        let mut solver = self.set.support_solver()?;
        let mut hull_of = |s: &StateStep| -> Result<IntervalHull> {
            if exact(s) {
                return s.hull();
            }
            Ok(s.shift(solver.interval_hull(&s.s_map)?))
        };
        let predicted = hull_of(self)?;
        let filtered = match &self.filtered {
            Some(f) => Some(hull_of(f)?),
            None => None,
        };
        Ok((predicted, filtered))
    }

    /// [`StateStep::hull`], or `None` when the data contradict the bounds (the LP path's first
    /// support LP is infeasible; the planar path has already been checked when the step was
    /// built).
    pub fn hull_if_consistent(&self) -> Result<Option<IntervalHull>> {
        if self.planar.is_some() || self.interval.is_some() {
            return self.hull().map(Some);
        }
        let mut solver = self.set.support_solver()?;
        // The first support LP of the hull, asked whether T(h) is empty at all.
        let first = self.s_map.row(0).transpose();
        let mut c = DVector::zeros(solver.family.dim());
        for j in 0..solver.dim {
            c[j] = -first[j];
        }
        if solver.family.minimize_if_feasible(Some(&c))?.is_none() {
            return Ok(None);
        }
        Ok(Some(self.shift(solver.interval_hull(&self.s_map)?)))
    }

    /// Interval hull of M·x(k+1) for a matrix M with r columns (the outputs H(k+1) of the
    /// prediction interval): support values of the polygon on the planar path, LPs otherwise.
    pub fn image_hull(&self, m: &DMatrix<f64>) -> Result<IntervalHull> {
        let off = m * &self.offset;
        let h = match (&self.planar, self.interval) {
            (_, Some([lo, hi])) => {
                // m·e over e ∈ [lo, hi]: the ends in the order of m's sign.
                let ends = |c: f64| {
                    let (a, b) = (c * lo, c * hi);
                    (a.min(b), a.max(b))
                };
                let rows: Vec<(f64, f64)> = (0..m.nrows()).map(|i| ends(m[(i, 0)])).collect();
                IntervalHull {
                    lo: rows.iter().map(|e| e.0).collect(),
                    hi: rows.iter().map(|e| e.1).collect(),
                }
            }
            (Some(p), _) => {
                let (mut lo, mut hi) = (Vec::new(), Vec::new());
                for i in 0..m.nrows() {
                    let d = [m[(i, 0)], m[(i, 1)]];
                    hi.push(p.support(d).0);
                    lo.push(-p.support([-d[0], -d[1]]).0);
                }
                IntervalHull { lo, hi }
            }
            (None, None) => self.set.interval_hull(&(m * &self.s_map))?,
        };
        let add = |v: &[f64]| crate::linalg::zip_with(v, off.as_slice(), |a, b| a + b);
        Ok(IntervalHull {
            lo: add(&h.lo),
            hi: add(&h.hi),
        })
    }

    fn shift(&self, h: IntervalHull) -> IntervalHull {
        let add = |v: &[f64]| crate::linalg::zip_with(v, self.offset.as_slice(), |a, b| a + b);
        IntervalHull {
            lo: add(&h.lo),
            hi: add(&h.hi),
        }
    }

    /// The rows of S for the `plane` components.
    pub fn plane_map(&self, plane: [usize; 2]) -> DMatrix<f64> {
        DMatrix::from_fn(2, self.s_map.ncols(), |i, j| self.s_map[(plane[i], j)])
    }

    /// Interval hull of all of x(k+1) (x(k) on the filtered view) and the exact polygon of the
    /// `plane` components: on the planar path from the polygon itself (no LP: `calls` = 0, the
    /// LP's size reported as counted), otherwise from one loaded solver. With one state
    /// (plane [0, 0]) the set is the interval [lo, hi] and its image in the plane (x₁, x₁) the
    /// segment from (lo, lo) to (hi, hi).
    pub fn hull_and_polygon(
        &self,
        plane: [usize; 2],
        budget: usize,
    ) -> Result<(IntervalHull, SupportPolygon, LpSize)> {
        if self.s_map.nrows() == 1 {
            if plane != [0, 0] {
                return Err(Error::field(
                    "ubb.plane",
                    format!("names {plane:?}, but the state has one component: its set is an interval (leave ubb.plane out)"),
                ));
            }
            let (hull, calls) = match self.interval {
                Some(_) => (self.hull()?, 0),
                None => (self.hull()?, 2),
            };
            let (lo, hi) = (hull.lo[0], hull.hi[0]);
            let polygon = SupportPolygon {
                vertices: if hi > lo {
                    vec![[lo, lo], [hi, hi]]
                } else {
                    vec![[lo, lo]]
                },
                exact: true,
                gap: 0.0,
                calls,
                hull: [lo, hi, lo, hi],
            };
            return Ok((hull, polygon, self.set.size()));
        }
        if let Some(p) = &self.planar {
            let p = match plane {
                [0, 1] => p.clone(),
                [1, 0] => p.swapped(),
                _ => {
                    return Err(Error::field(
                        "ubb.plane",
                        format!(
                            "must name two different components of the 2 states, found {plane:?}"
                        ),
                    ))
                }
            };
            let (ox, oy) = (self.offset[plane[0]], self.offset[plane[1]]);
            let p = p.translate([ox, oy]);
            let polygon = SupportPolygon {
                vertices: p.vertices().to_vec(),
                exact: true,
                gap: 0.0,
                calls: 0,
                hull: p.interval_hull(),
            };
            return Ok((self.hull()?, polygon, self.set.size()));
        }
        let mut solver = self.set.support_solver()?;
        let hull = self.shift(solver.interval_hull(&self.s_map)?);
        let mut poly = solver.polygon(&self.plane_map(plane), budget)?;
        let (ox, oy) = (self.offset[plane[0]], self.offset[plane[1]]);
        for v in &mut poly.vertices {
            v[0] += ox;
            v[1] += oy;
        }
        poly.hull = [
            poly.hull[0] + ox,
            poly.hull[1] + ox,
            poly.hull[2] + oy,
            poly.hull[3] + oy,
        ];
        Ok((hull, poly, solver.size))
    }
}

/// One step of the Kalman filter beside the sets: the filtered x(k|k) and the prediction
/// x(k+1|k), each (mean, covariance).
#[derive(Debug, Clone)]
pub struct KalmanStep {
    pub filtered: (DVector<f64>, DMatrix<f64>),
    pub predicted: (DVector<f64>, DMatrix<f64>),
}

/// Noise in simulations: uniform within the bound, or at the bound with random signs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum NoiseMode {
    Random,
    Bound,
}

/// A simulated run: x(0 … steps), y(0 … steps−1), u(0 … steps−1).
#[derive(Debug, Clone)]
pub struct Run {
    pub x: Vec<DVector<f64>>,
    pub y: Vec<DVector<f64>>,
    pub u: Vec<DVector<f64>>,
    /// Per-component magnitude bound of the process and measurement noise used.
    pub u_level: f64,
    pub eta_level: f64,
}

/// Per-component level c such that every window's stacked, weighted noise norm stays within
/// `bound` when each component is at most c (the sum of the weights over the longest window).
fn component_level(
    norm: Norm,
    bound: f64,
    smoothing: Option<f64>,
    longest: usize,
    dim: usize,
) -> f64 {
    let weights = (0..longest.max(1)).map(|a| age_weight(smoothing, a));
    let d = dim.max(1) as f64;
    match norm {
        Norm::Linf => bound,
        Norm::L1 => bound / (weights.sum::<f64>() * d),
        Norm::L2 => bound / (weights.map(|w| w * w).sum::<f64>() * d).sqrt(),
    }
}

impl StateProblem {
    /// The longest window any step uses over `steps` steps.
    fn longest(&self, steps: usize) -> usize {
        if self.system.p() == 0 {
            steps
        } else {
            self.window.min(steps)
        }
    }

    /// Simulate `steps` steps; x(0) is `x0` or drawn in its box (at a corner with `Bound`).
    pub fn simulate(
        &self,
        steps: usize,
        mode: NoiseMode,
        x0: Option<&DVector<f64>>,
        seed: u64,
    ) -> Run {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let sys = &self.system;
        let bd = &self.bounds;
        let (r, p) = (sys.r(), sys.p());
        let q = sys.c_at(0).nrows();
        let longest = self.longest(steps);
        let u_level = component_level(
            bd.norm,
            self.sim_levels.0.unwrap_or(bd.tau),
            bd.alpha,
            longest,
            p,
        );
        let eta_level = component_level(
            bd.norm,
            self.sim_levels.1.unwrap_or(bd.eps),
            bd.beta,
            longest,
            q,
        );
        let mut draw = |level: f64| -> f64 {
            match mode {
                NoiseMode::Random => (rng.random::<f64>() * 2.0 - 1.0) * level,
                NoiseMode::Bound => {
                    if rng.random::<bool>() {
                        level
                    } else {
                        -level
                    }
                }
            }
        };
        let x_start = match (x0, &bd.delta) {
            (Some(x), _) => x.clone(),
            (None, Some(d)) => DVector::from_fn(r, |i, _| bd.x0_center[i] + draw(d[i])),
            (None, None) => bd.x0_center.clone(),
        };
        let mut x = vec![x_start];
        let (mut y, mut u) = (Vec::new(), Vec::new());
        for t in 0..steps {
            let eta = DVector::from_fn(q, |_, _| draw(eta_level));
            y.push(sys.c_at(t) * &x[t] + eta);
            let ut = DVector::from_fn(p, |_, _| draw(u_level));
            let mut next = &sys.a * &x[t] + &sys.b * &ut;
            if let Some(v) = sys.v_at(t) {
                next += v;
            }
            x.push(next);
            u.push(ut);
        }
        Run {
            x,
            y,
            u,
            u_level,
            eta_level,
        }
    }

    /// The Kalman filter beside the sets, k = 0 … steps−1: the filtered x(k|k) and the
    /// one-step prediction x(k+1|k) with their covariances, under the stated assumption that
    /// the noise is Gaussian with the variances of the simulated noise: level²/3, the variance
    /// of the uniform law on [−level, level] (`noise` "random"), or level² at the bound
    /// (`noise` "bound"); x(0) the same within δ. A missing measurement (NaN) skips its row of
    /// the update. With δ = ∞ the prior is diffuse in the data's own unit
    /// ([`StateProblem::diffuse_prior`]).
    pub fn kalman(&self, run: &Run, mode: NoiseMode) -> Vec<KalmanStep> {
        let sys = &self.system;
        let (r, p) = (sys.r(), sys.p());
        let var = |level: f64| match mode {
            NoiseMode::Random => level * level / 3.0,
            NoiseMode::Bound => level * level,
        };
        let qn = &sys.b * DMatrix::identity(p, p) * var(run.u_level) * sys.b.transpose();
        let mut x = self.bounds.x0_center.clone();
        let mut pm = match &self.bounds.delta {
            Some(d) => DMatrix::from_diagonal(&d.map(|v| var(v))),
            None => DMatrix::identity(r, r) * self.diffuse_prior(&run.y),
        };
        let mut out = Vec::new();
        for (t, yt) in run.y.iter().enumerate() {
            let c_all = sys.c_at(t);
            let present: Vec<usize> = (0..c_all.nrows())
                .filter(|&i| yt.get(i).is_some_and(|v| !v.is_nan()))
                .collect();
            if !present.is_empty() {
                let c = c_all.select_rows(&present);
                let yp = yt.select_rows(&present);
                let rn = DMatrix::identity(c.nrows(), c.nrows()) * var(run.eta_level).max(1e-300);
                let s = &c * &pm * c.transpose() + rn;
                if let Some(si) = s.try_inverse() {
                    let g = &pm * c.transpose() * si;
                    x = &x + &g * (yp - &c * &x);
                    pm = (DMatrix::identity(r, r) - &g * &c) * &pm;
                    pm = (&pm + pm.transpose()) * 0.5;
                }
            }
            let filtered = (x.clone(), pm.clone());
            x = &sys.a * &x;
            if let Some(v) = sys.v_at(t) {
                x += v;
            }
            pm = &sys.a * &pm * sys.a.transpose() + &qn;
            out.push(KalmanStep {
                filtered,
                predicted: (x.clone(), pm.clone()),
            });
        }
        out
    }

    /// The Kalman filter's prior variance with δ = ∞ (issue 40, P2): diffuse in the data's own
    /// unit, (10⁴·m)² with m the largest of |x̄(0)|, ε and the measurements' magnitudes. A fixed
    /// 10⁸ was a constant in the data's unit: the same record in other units (×10⁴) met a prior
    /// as tight as its data and gave other Kalman verdicts; scaled with the data, every verdict
    /// is unit-free.
    pub fn diffuse_prior(&self, y: &[DVector<f64>]) -> f64 {
        let data = y
            .iter()
            .flat_map(|v| v.iter())
            .filter(|v| v.is_finite())
            .fold(0.0_f64, |m, v| m.max(v.abs()));
        let m = data.max(self.bounds.eps).max(self.bounds.x0_center.amax());
        if m > 0.0 && (1e4 * m).powi(2).is_finite() {
            (1e4 * m).powi(2)
        } else {
            1e8
        }
    }
}
