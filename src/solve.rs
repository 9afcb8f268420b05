//! The one place that talks to the LP/QP solver (clarabel 0.11, interior point).
//!
//! Problems are stated densely in the crate's own terms:
//!
//! minimize ½ xᵀPx + qᵀx subject to A_eq x = b_eq, A_le x ≤ b_le,
//!
//! and come back as a [`Solution`] or as an [`Error`] naming the scenario field most likely
//! responsible ([`Blame`]), with clarabel's status in words a user can act on: no point
//! consistent with the data (with the caller's hint, e.g. "ubb.eps may be too small"), an
//! unbounded set, or a solver that stopped before converging (with the span of the problem's
//! coefficients, the usual cause). P = None is a linear program.
//!
//! Every solve is capped at [`MAX_ITERATIONS`] interior-point iterations and
//! [`TIME_LIMIT_SECONDS`] seconds, so no input can keep the page busy in one solve. The presets'
//! solves take at most a few dozen iterations and milliseconds; the caps only end solves that
//! would not converge anyway.

use crate::error::{Error, Result};
use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use nalgebra::{DMatrix, DVector};

pub mod simplex;

/// Most interior-point iterations of one solve (clarabel's default; the presets need at most
/// a few dozen).
pub const MAX_ITERATIONS: u32 = 200;

/// Most seconds one solve may take (clarabel times itself with `web-time`, so the cap holds in
/// the browser too). The presets' solves take milliseconds.
pub const TIME_LIMIT_SECONDS: f64 = 10.0;

/// Whom a failed solve concerns: the scenario field most likely responsible (the error names
/// it; it must be a field of the scenario schema), the unknowns in words ("state",
/// "parameter vector Θ"), and what to try when no point satisfies the constraints.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Blame {
    pub field: String,
    /// What the problem solves for, in words; empty: "solution".
    pub unknowns: String,
    /// The likely fix of an infeasible problem, e.g. "ubb.eps may be too small"; empty: a
    /// generic one.
    pub hint: String,
}

impl Blame {
    /// A blame with its unknowns and its infeasibility hint.
    pub fn new(field: &str, unknowns: &str, hint: &str) -> Blame {
        Blame {
            field: field.into(),
            unknowns: unknowns.into(),
            hint: hint.into(),
        }
    }

    /// An error about the blamed field.
    pub fn error(&self, message: String) -> Error {
        Error::field(self.field.clone(), message)
    }

    fn unknowns(&self) -> &str {
        if self.unknowns.is_empty() {
            "solution"
        } else {
            &self.unknowns
        }
    }

    /// The error of an infeasible problem.
    pub fn infeasible(&self) -> Error {
        let hint = if self.hint.is_empty() {
            "the bounds may be too tight for the data"
        } else {
            &self.hint
        };
        self.error(format!(
            "leaves no {} {INFEASIBLE} — {hint}",
            self.unknowns()
        ))
    }
}

/// The words of every infeasible problem's error ([`Blame::infeasible`]).
const INFEASIBLE: &str = "consistent with the data under these bounds";

/// Whether `e` is the error of an infeasible problem ([`Blame::infeasible`]): no unknowns
/// consistent with the data under the bounds. The set it asked for exists and is empty (the
/// data contradict the bounds), which a compare counts as a set that misses the state, not as
/// a set that could not be computed.
pub fn is_infeasible(e: &Error) -> bool {
    e.message.starts_with("leaves no ") && e.message.contains(INFEASIBLE)
}

impl From<&Blame> for Blame {
    fn from(b: &Blame) -> Blame {
        b.clone()
    }
}

/// A field alone (generic words for the unknowns and the hint): for tests and internal
/// problems.
impl From<&str> for Blame {
    fn from(field: &str) -> Blame {
        Blame::new(field, "", "")
    }
}

/// A dense LP/QP; `blame` says whom its errors concern.
#[derive(Debug, Clone, Default)]
pub struct Problem {
    pub p: Option<DMatrix<f64>>,
    pub q: DVector<f64>,
    pub eq: Option<(DMatrix<f64>, DVector<f64>)>,
    pub le: Option<(DMatrix<f64>, DVector<f64>)>,
    /// Second-order cones: each (G, g) asks that s = g − Gx has ‖(s₁, …, s_d)‖₂ ≤ s₀.
    pub soc: Vec<(DMatrix<f64>, DVector<f64>)>,
    pub blame: Blame,
    /// Solve an LP (no `p`) in a unit β of the caller's (`Some(β)`, a power of two: see
    /// [`power_of_two_below`]): x = β x̃, so that the solver's absolute tolerances are
    /// relative to the problem's own scale, and to 10⁻¹⁰ of it. The constraints are homogeneous
    /// in (x, b) when every unknown has the unit of the data (states, half-widths, noise), so
    /// the answer is the same in exact arithmetic, and b/β and β x̃ are exact. Without it a
    /// set-membership hull scaled by 10⁻⁶ came back 6.3·10⁻⁵ off (issue 25).
    pub unit: Option<f64>,
}

/// The power of two at or below |v| (1 for 0, a subnormal or a non-finite v), read from the
/// exponent bits so that native and wasm agree to the bit (no libm `log2`).
pub fn power_of_two_below(v: f64) -> f64 {
    let exponent = v.abs().to_bits() & 0x7ff0_0000_0000_0000;
    if exponent == 0 || exponent == 0x7ff0_0000_0000_0000 {
        1.0
    } else {
        f64::from_bits(exponent)
    }
}

/// An optimal point.
#[derive(Debug, Clone)]
pub struct Solution {
    pub x: DVector<f64>,
    pub objective: f64,
    /// Dual multipliers of the constraints, in the order eq, le, soc (≥ 0 for `le`).
    pub duals: DVector<f64>,
    /// Interior-point iterations.
    pub iterations: u32,
    /// "solved" or "almost solved" (clarabel's reduced-accuracy success).
    pub status: &'static str,
}

/// Column-compressed copy of a dense matrix (upper triangle only when `upper`).
fn csc(m: &DMatrix<f64>, upper: bool) -> CscMatrix<f64> {
    let (rows, cols) = m.shape();
    let mut colptr = Vec::with_capacity(cols + 1);
    let (mut rowval, mut nzval) = (Vec::new(), Vec::new());
    colptr.push(0);
    for j in 0..cols {
        let last = if upper { (j + 1).min(rows) } else { rows };
        for i in 0..last {
            let v = m[(i, j)];
            if v != 0.0 {
                rowval.push(i);
                nzval.push(v);
            }
        }
        colptr.push(rowval.len());
    }
    CscMatrix::new(rows, cols, colptr, rowval, nzval)
}

/// A problem handed to clarabel once and then solved for many linear objectives (support
/// functions, interval hulls): the KKT structure is built once, only q changes.
pub struct Family {
    solver: DefaultSolver<f64>,
    blame: Blame,
    n: usize,
    /// The smallest and largest nonzero |coefficient| of the loaded problem: the first thing
    /// to look at when the solver does not converge.
    span: (f64, f64),
    /// β of [`Problem::unit`] (1 when not scaled).
    unit: f64,
}

impl Family {
    /// Check and load `problem` (its `q` is the first objective).
    pub fn new(problem: &Problem) -> Result<Family> {
        let n = problem.q.len();
        let bad = |what: &str| problem.blame.error(what.to_string());
        let finite = |m: &DMatrix<f64>| m.iter().all(|v| v.is_finite());
        if !problem.q.iter().all(|v| v.is_finite())
            || problem.p.as_ref().is_some_and(|p| !finite(p))
        {
            return Err(bad("the optimization problem has non-finite coefficients"));
        }
        let mut blocks: Vec<(&DMatrix<f64>, &DVector<f64>, SupportedConeT<f64>)> = Vec::new();
        let parts = [(0, problem.eq.as_ref()), (1, problem.le.as_ref())];
        let socs = problem.soc.iter().map(|c| (2, Some(c)));
        for (kind, part) in parts.into_iter().chain(socs) {
            let Some((a, rhs)) = part else { continue };
            if a.ncols() != n || a.nrows() != rhs.len() {
                return Err(bad(&format!(
                    "constraint matrix is {}×{} for {} variables and {} right-hand sides",
                    a.nrows(),
                    a.ncols(),
                    n,
                    rhs.len()
                )));
            }
            if !finite(a) || !rhs.iter().all(|v| v.is_finite()) {
                return Err(bad("the optimization problem has non-finite constraints"));
            }
            if a.nrows() == 0 {
                continue;
            }
            let cone = match kind {
                0 => SupportedConeT::ZeroConeT(a.nrows()),
                1 => SupportedConeT::NonnegativeConeT(a.nrows()),
                _ => SupportedConeT::SecondOrderConeT(a.nrows()),
            };
            blocks.push((a, rhs, cone));
        }
        let unit = match problem.unit {
            Some(u) if problem.p.is_none() && u.is_finite() && u > 0.0 => u,
            _ => 1.0,
        };
        let rows: usize = blocks.iter().map(|(a, _, _)| a.nrows()).sum();
        let mut a = DMatrix::zeros(rows, n);
        let mut b = Vec::with_capacity(rows);
        let mut at = 0;
        for (blk, rhs, _) in &blocks {
            a.view_mut((at, 0), (blk.nrows(), n)).copy_from(*blk);
            b.extend(rhs.iter().map(|v| v / unit));
            at += blk.nrows();
        }
        let cones: Vec<SupportedConeT<f64>> = blocks.into_iter().map(|(_, _, c)| c).collect();
        let p = match &problem.p {
            Some(p) if p.shape() == (n, n) => csc(&((p + p.transpose()) * 0.5), true),
            Some(p) => {
                return Err(bad(&format!(
                    "objective matrix is {}×{} for {n_variables}",
                    p.nrows(),
                    p.ncols(),
                    n_variables = crate::error::counted(n, "variable", "variables")
                )))
            }
            None => CscMatrix::zeros((n, n)),
        };
        // No presolve and no dropped zeros, so that `update_q` is allowed. A problem in its own
        // unit ([`Problem::unit`]) can ask for 10⁻¹⁰ of it: a hull to that relative accuracy.
        let tolerance = if problem.unit.is_some() { 1e-10 } else { 1e-8 };
        let settings = DefaultSettingsBuilder::default()
            .verbose(false)
            .tol_gap_abs(tolerance)
            .tol_gap_rel(tolerance)
            .tol_feas(tolerance)
            .max_iter(MAX_ITERATIONS)
            .time_limit(TIME_LIMIT_SECONDS)
            .presolve_enable(false)
            .build()
            .map_err(|e| {
                bad(&format!(
                    "could not be solved: the solver settings are wrong ({e})"
                ))
            })?;
        let q: Vec<f64> = problem.q.iter().copied().collect();
        let span = a
            .iter()
            .chain(&b)
            .chain(&q)
            .chain(problem.p.iter().flat_map(|p| p.iter()))
            .map(|v| v.abs())
            .filter(|&v| v > 0.0)
            .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            });
        let solver =
            DefaultSolver::new(&p, &q, &csc(&a, false), &b, &cones, settings).map_err(|e| {
                bad(&format!(
                    "could not be solved: the solver refused the problem ({e})"
                ))
            })?;
        Ok(Family {
            solver,
            blame: problem.blame.clone(),
            n,
            span,
            unit,
        })
    }

    /// Number of variables.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Solve with objective ½xᵀPx + cᵀx (c = None: the objective the family was built with).
    pub fn minimize(&mut self, c: Option<&DVector<f64>>) -> Result<Solution> {
        match self.minimize_if_feasible(c)? {
            Some(solution) => Ok(solution),
            None => Err(self.blame.infeasible()),
        }
    }

    /// [`Family::minimize`], with an infeasible problem as `Ok(None)` rather than an error:
    /// for callers that loosen bounds until the problem is feasible.
    pub fn minimize_if_feasible(&mut self, c: Option<&DVector<f64>>) -> Result<Option<Solution>> {
        if let Some(c) = c {
            if c.len() != self.n || !c.iter().all(|v| v.is_finite()) {
                return Err(self.blame.error(
                    "could not be solved: the objective has the wrong length or non-finite entries"
                        .into(),
                ));
            }
            self.solver.update_q(&c.as_slice().to_vec()).map_err(|e| {
                self.blame.error(format!(
                    "could not be solved: the objective was refused ({e})"
                ))
            })?;
        }
        self.solver.solve();
        let sol = &self.solver.solution;
        let blame = &self.blame;
        let scaled = || {
            let (lo, hi) = self.span;
            if hi > 0.0 {
                format!(
                    "the problem may be badly scaled: its coefficients span {lo:.1e} … {hi:.1e} (data and bounds of similar magnitude help)"
                )
            } else {
                "the problem may be badly scaled".to_string()
            }
        };
        let stopped = |why: String| {
            blame.error(format!(
                "could not be solved: the solver stopped before converging ({why}) — {}",
                scaled()
            ))
        };
        let status = match sol.status {
            SolverStatus::Solved => "solved",
            // Clarabel's reduced-accuracy optimum: its residuals meet the loose tolerances.
            SolverStatus::AlmostSolved => "almost solved",
            SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
                return Ok(None)
            }
            SolverStatus::DualInfeasible | SolverStatus::AlmostDualInfeasible => {
                return Err(blame.error(format!(
                    "leaves the {} unbounded: nothing in the data or the bounds limits it in some direction — a bound may be missing",
                    blame.unknowns()
                )))
            }
            SolverStatus::MaxIterations => {
                return Err(stopped(format!(
                    "its limit of {MAX_ITERATIONS} iterations"
                )))
            }
            SolverStatus::MaxTime => {
                return Err(stopped(format!(
                    "its limit of {TIME_LIMIT_SECONDS} s per solve, after {} iterations",
                    sol.iterations
                )))
            }
            SolverStatus::InsufficientProgress => {
                return Err(stopped(format!(
                    "no progress after {} iterations",
                    sol.iterations
                )))
            }
            SolverStatus::NumericalError => {
                return Err(blame.error(format!(
                    "could not be solved: the solver hit a numerical error after {} iterations — {}",
                    sol.iterations,
                    scaled()
                )))
            }
            SolverStatus::Unsolved | SolverStatus::CallbackTerminated => {
                return Err(blame.error(
                    "could not be solved: the solver ended without an answer".into(),
                ))
            }
        };
        Ok(Some(Solution {
            x: DVector::from_vec(sol.x.clone()) * self.unit,
            objective: sol.obj_val * self.unit,
            duals: DVector::from_vec(sol.z.clone()),
            iterations: sol.iterations,
            status,
        }))
    }
}

/// Solve; every outcome other than an optimum is an error naming `problem.blame.field`.
pub fn quadratic(problem: &Problem) -> Result<Solution> {
    Family::new(problem)?.minimize(None)
}

/// [`quadratic`], with an infeasible problem as `Ok(None)`.
pub fn quadratic_if_feasible(problem: &Problem) -> Result<Option<Solution>> {
    Family::new(problem)?.minimize_if_feasible(None)
}

/// A linear program: minimize cᵀx subject to the constraints.
pub fn linear(
    c: &DVector<f64>,
    eq: Option<(DMatrix<f64>, DVector<f64>)>,
    le: Option<(DMatrix<f64>, DVector<f64>)>,
    blame: impl Into<Blame>,
) -> Result<Solution> {
    quadratic(&Problem {
        p: None,
        q: c.clone(),
        eq,
        le,
        soc: Vec::new(),
        blame: blame.into(),
        unit: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_of_two_below_reads_the_exponent() {
        assert_eq!(power_of_two_below(1.0), 1.0);
        assert_eq!(power_of_two_below(-3.0), 2.0);
        assert_eq!(power_of_two_below(1e-6), 2f64.powi(-20));
        assert_eq!(power_of_two_below(1e15), 2f64.powi(49));
        for v in [0.0, 5e-324, f64::INFINITY, f64::NAN] {
            assert_eq!(power_of_two_below(v), 1.0, "{v}");
        }
    }

    #[test]
    fn qp_with_equality_matches_the_closed_form() {
        // min ½(x₁² + 2x₂²) s.t. x₁ + x₂ = 3: x = (2, 1), objective 3.
        let p = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, 2.0]);
        let eq = (
            DMatrix::from_row_slice(1, 2, &[1.0, 1.0]),
            DVector::from_vec(vec![3.0]),
        );
        let s = quadratic(&Problem {
            p: Some(p),
            q: DVector::zeros(2),
            eq: Some(eq),
            le: None,
            soc: Vec::new(),
            blame: "t".into(),
            unit: None,
        })
        .unwrap();
        assert!(
            (s.x[0] - 2.0).abs() < 1e-7 && (s.x[1] - 1.0).abs() < 1e-7,
            "{:?}",
            s.x
        );
        assert!((s.objective - 3.0).abs() < 1e-6);
    }

    #[test]
    fn lp_box_and_infeasible_and_unbounded() {
        // min x₁ − x₂ on the box [−1, 1]²: (−1, 1), objective −2.
        let a = DMatrix::from_row_slice(4, 2, &[1.0, 0.0, 0.0, 1.0, -1.0, 0.0, 0.0, -1.0]);
        let b = DVector::from_element(4, 1.0);
        let c = DVector::from_vec(vec![1.0, -1.0]);
        let s = linear(&c, None, Some((a.clone(), b)), "t").unwrap();
        assert!((s.objective + 2.0).abs() < 1e-7, "{}", s.objective);
        // x₁ ≤ −1 and −x₁ ≤ −1 (x₁ ≥ 1): infeasible.
        let bad = linear(
            &c,
            None,
            Some((
                DMatrix::from_row_slice(2, 2, &[1.0, 0.0, -1.0, 0.0]),
                DVector::from_vec(vec![-1.0, -1.0]),
            )),
            "ubb.eps",
        )
        .unwrap_err();
        assert_eq!(bad.field, "ubb.eps");
        assert!(
            bad.message
                .contains("leaves no solution consistent with the data"),
            "{}",
            bad.message
        );
        // min x₁ with x₁ ≤ 0 only: unbounded below.
        let unb = linear(
            &DVector::from_vec(vec![1.0]),
            None,
            Some((
                DMatrix::from_row_slice(1, 1, &[1.0]),
                DVector::from_vec(vec![0.0]),
            )),
            "t",
        )
        .unwrap_err();
        assert!(unb.message.contains("unbounded"), "{}", unb.message);
    }
}
