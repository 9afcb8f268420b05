//! The one place that talks to the LP/QP solver (clarabel 0.11, interior point).
//!
//! Problems are stated densely in the crate's own terms:
//!
//! minimize ½ xᵀPx + qᵀx subject to A_eq x = b_eq, A_le x ≤ b_le,
//!
//! and come back as a [`Solution`] or as an [`Error`] naming the scenario field the problem
//! belongs to, with the outcome in words (infeasible data, unbounded objective, no convergence).
//! P = None is a linear program.

use crate::error::{Error, Result};
use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use nalgebra::{DMatrix, DVector};

/// A dense LP/QP; `field` names the scenario field its errors belong to.
#[derive(Debug, Clone, Default)]
pub struct Problem {
    pub p: Option<DMatrix<f64>>,
    pub q: DVector<f64>,
    pub eq: Option<(DMatrix<f64>, DVector<f64>)>,
    pub le: Option<(DMatrix<f64>, DVector<f64>)>,
    /// Second-order cones: each (G, g) asks that s = g − Gx has ‖(s₁, …, s_d)‖₂ ≤ s₀.
    pub soc: Vec<(DMatrix<f64>, DVector<f64>)>,
    pub field: String,
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
    field: String,
    n: usize,
}

impl Family {
    /// Check and load `problem` (its `q` is the first objective).
    pub fn new(problem: &Problem) -> Result<Family> {
        let n = problem.q.len();
        let bad = |what: &str| Error::field(problem.field.clone(), what.to_string());
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
        let rows: usize = blocks.iter().map(|(a, _, _)| a.nrows()).sum();
        let mut a = DMatrix::zeros(rows, n);
        let mut b = Vec::with_capacity(rows);
        let mut at = 0;
        for (blk, rhs, _) in &blocks {
            a.view_mut((at, 0), (blk.nrows(), n)).copy_from(*blk);
            b.extend(rhs.iter());
            at += blk.nrows();
        }
        let cones: Vec<SupportedConeT<f64>> = blocks.into_iter().map(|(_, _, c)| c).collect();
        let p = match &problem.p {
            Some(p) if p.shape() == (n, n) => csc(&((p + p.transpose()) * 0.5), true),
            Some(p) => {
                return Err(bad(&format!(
                    "objective matrix is {}×{} for {n} variables",
                    p.nrows(),
                    p.ncols()
                )))
            }
            None => CscMatrix::zeros((n, n)),
        };
        // No presolve and no dropped zeros, so that `update_q` is allowed.
        let settings = DefaultSettingsBuilder::default()
            .verbose(false)
            .max_iter(200)
            .presolve_enable(false)
            .build()
            .map_err(|e| bad(&format!("solver settings: {e:?}")))?;
        let q: Vec<f64> = problem.q.iter().copied().collect();
        let solver = DefaultSolver::new(&p, &q, &csc(&a, false), &b, &cones, settings)
            .map_err(|e| bad(&format!("the solver refused the problem: {e:?}")))?;
        Ok(Family {
            solver,
            field: problem.field.clone(),
            n,
        })
    }

    /// Number of variables.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Solve with objective ½xᵀPx + cᵀx (c = None: the objective the family was built with).
    pub fn minimize(&mut self, c: Option<&DVector<f64>>) -> Result<Solution> {
        let bad = |what: &str| Error::field(self.field.clone(), what.to_string());
        if let Some(c) = c {
            if c.len() != self.n || !c.iter().all(|v| v.is_finite()) {
                return Err(bad(
                    "the objective has the wrong length or non-finite entries",
                ));
            }
            self.solver
                .update_q(&c.as_slice().to_vec())
                .map_err(|e| bad(&format!("could not update the objective: {e}")))?;
        }
        self.solver.solve();
        let sol = &self.solver.solution;
        let status = match sol.status {
            SolverStatus::Solved => "solved",
            SolverStatus::AlmostSolved => "almost solved",
            SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
                return Err(bad("is infeasible: no point satisfies all the constraints (the data contradict the bounds)"))
            }
            SolverStatus::DualInfeasible | SolverStatus::AlmostDualInfeasible => {
                return Err(bad("is unbounded: the objective can decrease without limit"))
            }
            other => {
                return Err(bad(&format!(
                    "could not be solved ({other:?} after {} iterations)",
                    sol.iterations
                )))
            }
        };
        Ok(Solution {
            x: DVector::from_vec(sol.x.clone()),
            objective: sol.obj_val,
            duals: DVector::from_vec(sol.z.clone()),
            iterations: sol.iterations,
            status,
        })
    }
}

/// Solve; every outcome other than an optimum is an error naming `problem.field`.
pub fn quadratic(problem: &Problem) -> Result<Solution> {
    Family::new(problem)?.minimize(None)
}

/// A linear program: minimize cᵀx subject to the constraints.
pub fn linear(
    c: &DVector<f64>,
    eq: Option<(DMatrix<f64>, DVector<f64>)>,
    le: Option<(DMatrix<f64>, DVector<f64>)>,
    field: &str,
) -> Result<Solution> {
    quadratic(&Problem {
        p: None,
        q: c.clone(),
        eq,
        le,
        soc: Vec::new(),
        field: field.into(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

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
            field: "t".into(),
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
        assert!(bad.message.contains("infeasible"), "{}", bad.message);
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
