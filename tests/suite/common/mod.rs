//! Reference computations for the integration tests, written independently of the crate:
//! a textbook Kalman filter, the Lyapunov equation by a Kronecker (vec) solve, exact binomial
//! acceptance intervals. Nothing here calls confset's numerics, so a test comparing against these
//! compares two independent derivations. (`patch` holds the bad-input table plumbing.)

#![allow(dead_code)]

pub mod contract;
pub mod limits;
pub mod mutate;
pub mod patch;
pub mod timing;

use nalgebra::{DMatrix, DVector};
use statrs::distribution::{Binomial, DiscreteCDF};

/// A matrix from rows.
pub fn mat(rows: &[&[f64]]) -> DMatrix<f64> {
    DMatrix::from_fn(rows.len(), rows[0].len(), |i, j| rows[i][j])
}

/// Rows of a matrix (the report's layout).
pub fn rows(m: &DMatrix<f64>) -> Vec<Vec<f64>> {
    (0..m.nrows())
        .map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect())
        .collect()
}

/// A matrix from the report's rows.
pub fn from_rows(r: &[Vec<f64>]) -> DMatrix<f64> {
    DMatrix::from_fn(r.len(), r[0].len(), |i, j| r[i][j])
}

/// Γ solving Γ = FΓFᵀ + V by the linear system (I − F⊗F) vec Γ = vec V (column-major vec:
/// vec(FΓFᵀ) = (F⊗F) vec Γ). Independent of the crate's doubling iteration.
pub fn lyapunov_kron(f: &DMatrix<f64>, v: &DMatrix<f64>) -> DMatrix<f64> {
    let n = f.nrows();
    let a = DMatrix::identity(n * n, n * n) - f.kronecker(f);
    let b = DVector::from_column_slice(v.as_slice());
    let x = a
        .lu()
        .solve(&b)
        .expect("I − F⊗F is invertible for a stable F");
    let g = DMatrix::from_column_slice(n, n, x.as_slice());
    (&g + g.transpose()) * 0.5
}

/// Output of [`reference_kf`] at one time t.
#[derive(Debug, Clone)]
pub struct KfStep {
    pub p_pred: DMatrix<f64>,
    pub k: DMatrix<f64>,
    pub p: DMatrix<f64>,
    pub xhat: DVector<f64>,
    /// Prior moments m_t = E[x_t], Γ_t = Cov(x_t).
    pub m: DVector<f64>,
    pub gamma: DMatrix<f64>,
}

/// The textbook Kalman filter (standard, not Joseph, covariance form) from the prior
/// x_1 ~ N(m1, g1), time-invariant F, H, V, W and a constant input term `bu` (B u), together
/// with the propagated prior moments. Returns one entry per measurement.
pub fn reference_kf(
    f: &DMatrix<f64>,
    h: &DMatrix<f64>,
    v: &DMatrix<f64>,
    w: &DMatrix<f64>,
    m1: &DVector<f64>,
    g1: &DMatrix<f64>,
    bu: &DVector<f64>,
    y: &[DVector<f64>],
) -> Vec<KfStep> {
    let n = f.nrows();
    let mut out = Vec::new();
    let (mut x_pred, mut p_pred) = (m1.clone(), g1.clone());
    let (mut m, mut gamma) = (m1.clone(), g1.clone());
    for yt in y {
        let s = w + h * &p_pred * h.transpose();
        let k = &p_pred * h.transpose() * s.try_inverse().expect("S invertible");
        let xhat = &x_pred + &k * (yt - h * &x_pred);
        let p = (DMatrix::identity(n, n) - &k * h) * &p_pred;
        let p = (&p + p.transpose()) * 0.5;
        out.push(KfStep {
            p_pred: p_pred.clone(),
            k,
            p: p.clone(),
            xhat: xhat.clone(),
            m: m.clone(),
            gamma: gamma.clone(),
        });
        x_pred = f * xhat + bu;
        p_pred = f * p * f.transpose() + v;
        m = f * m + bu;
        gamma = f * gamma * f.transpose() + v;
    }
    out
}

/// Equal-tailed acceptance interval [lo, hi] of a Binomial(n, p) count with probability at
/// least `conf` (each tail ≤ (1 − conf)/2), from the exact binomial CDF.
pub fn binomial_interval(n: usize, p: f64, conf: f64) -> (usize, usize) {
    let b = Binomial::new(p, n as u64).expect("valid binomial");
    let tail = (1.0 - conf) / 2.0;
    // lo: smallest k with P(X < k) ≤ tail < P(X ≤ k), i.e. P(X ≤ lo − 1) ≤ tail.
    let lo = (0..=n as u64).find(|&k| b.cdf(k) > tail).unwrap() as usize;
    // hi: smallest k with P(X > k) ≤ tail.
    let hi = (0..=n as u64).find(|&k| 1.0 - b.cdf(k) <= tail).unwrap() as usize;
    (lo, hi)
}

/// |a − b| ≤ tol · max(1, |b|).
pub fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * b.abs().max(1.0)
}

/// |a − b| ≤ tol · max(|a|, |b|) (pure relative; equal zeros pass).
pub fn rel_close(a: f64, b: f64, tol: f64) -> bool {
    a == b || (a - b).abs() <= tol * a.abs().max(b.abs())
}

/// Assert every entry of `a` equals `b` to `tol` relative to the largest entry of `b` (or 1).
#[track_caller]
pub fn assert_mat_close(a: &DMatrix<f64>, b: &DMatrix<f64>, tol: f64, what: &str) {
    assert_eq!(a.shape(), b.shape(), "{what}: shapes differ");
    let scale = b.amax().max(1e-300);
    let err = (a - b).amax();
    assert!(
        err <= tol * scale,
        "{what}: max |difference| {err:.3e} > {tol:.0e}·{scale:.3e}\n got {a}\n expected {b}"
    );
}

/// Assert each entry relatively close (1e-9 style), entry by entry.
#[track_caller]
pub fn assert_slice_rel(a: &[f64], b: &[f64], tol: f64, what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: lengths differ");
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            rel_close(*x, *y, tol),
            "{what}[{i}]: {x:.17e} vs expected {y:.17e}"
        );
    }
}

/// One turn of the browser's event loop: a promise resolved by `setTimeout(0)`, so the tasks
/// queued meanwhile (the test runner's WebDriver scripts) run before the caller goes on.
#[cfg(target_arch = "wasm32")]
pub async fn event_loop_turn() {
    use wasm_bindgen::JsCast;
    let turn = js_sys::Promise::new(&mut |resolve, _| {
        let set_timeout: js_sys::Function =
            js_sys::Reflect::get(&js_sys::global(), &"setTimeout".into())
                .expect("setTimeout")
                .unchecked_into();
        set_timeout
            .call2(&wasm_bindgen::JsValue::UNDEFINED, &resolve, &0.into())
            .expect("setTimeout(resolve, 0)");
    });
    wasm_bindgen_futures::JsFuture::from(turn)
        .await
        .expect("a setTimeout promise resolves");
}
