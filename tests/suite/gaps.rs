//! Gaps in a user's record (a missing measurement: JSON `null`) for the Kalman filter, the SCF
//! and conformal. Against an independent textbook recursion written here (standard covariance
//! form, explicit inverses): at a step with no measurement the update is skipped
//! (x̂ₜ = x̂ₜ⁻, Pₜ = Pₜ⁻), at a step with some outputs missing it takes the observed rows of H
//! and that block of W. The SCF's ratio matrix from the recursion (38) with those gains equals
//! the closed form (41) I − PₜΓₜ⁻¹; conformal's region is the filter's at t with the updates
//! skipped, its calibration runs are filtered with the same gaps, and ACI (recomputed here)
//! scores no gap step. A gap filled with the filter's own prediction leaves the next centre
//! and shrinks no covariance; on a Nile-like local level record the variance grows through
//! each gap. Figures draw a gap as nothing, and the CSV table leaves its cells empty.

use crate::common::*;
use confset::conformal::{NoiseLaw, Simulator};
use confset::model::{Inputs, LinearModel};
use confset::plot::{self, View};
use confset::scenario::{Report, Scenario, StepValue};
use nalgebra::{DMatrix, DVector};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde_json::{json, Value};

/// A linear Gaussian model as the test knows it.
#[derive(Clone)]
struct Lgm {
    f: DMatrix<f64>,
    h: DMatrix<f64>,
    v: DMatrix<f64>,
    w: DMatrix<f64>,
    m1: DVector<f64>,
    p1: DMatrix<f64>,
    /// The prior of x₁ is the stationary law (no `x1_cov` in the JSON).
    stationary: bool,
}

fn rows(m: &DMatrix<f64>) -> Value {
    json!((0..m.nrows())
        .map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect::<Vec<_>>())
        .collect::<Vec<_>>())
}

impl Lgm {
    /// The local level model: x_{t+1} = x_t + v_t, y_t = x_t + w_t (F = H = 1).
    fn local_level(v: f64, w: f64, m1: f64, p1: f64) -> Lgm {
        let one = DMatrix::from_element(1, 1, 1.0);
        Lgm {
            f: one.clone(),
            h: one,
            v: DMatrix::from_element(1, 1, v),
            w: DMatrix::from_element(1, 1, w),
            m1: DVector::from_element(1, m1),
            p1: DMatrix::from_element(1, 1, p1),
            stationary: false,
        }
    }

    /// Conformal's preset model: F = 0.9·R(0.3), V = 0.5·I, stationary prior, observed through
    /// `h` with output noise `w`.
    fn rotation(h: DMatrix<f64>, w: DMatrix<f64>) -> Lgm {
        let (c, s) = (0.3f64.cos(), 0.3f64.sin());
        let f = DMatrix::from_row_slice(2, 2, &[0.9 * c, -0.9 * s, 0.9 * s, 0.9 * c]);
        let v = DMatrix::identity(2, 2) * 0.5;
        let p1 = lyapunov_kron(&f, &v);
        Lgm {
            f,
            h,
            v,
            w,
            m1: DVector::zeros(2),
            p1,
            stationary: true,
        }
    }

    fn one_output() -> Lgm {
        Lgm::rotation(
            DMatrix::from_row_slice(1, 2, &[1.0, 0.0]),
            DMatrix::identity(1, 1),
        )
    }

    fn two_outputs() -> Lgm {
        Lgm::rotation(
            DMatrix::identity(2, 2),
            DMatrix::from_row_slice(2, 2, &[1.0, 0.3, 0.3, 2.0]),
        )
    }

    fn json(&self) -> Value {
        let mut m =
            json!({"F": rows(&self.f), "H": rows(&self.h), "V": rows(&self.v), "W": rows(&self.w)});
        if !self.stationary {
            m["x1_mean"] = json!(self.m1.iter().copied().collect::<Vec<_>>());
            m["x1_cov"] = rows(&self.p1);
        }
        m
    }

    fn linear(&self) -> LinearModel {
        let s: Scenario = Scenario::from_json(
            &json!({"method": "kf", "model": self.json(), "data": {"y": [[0.0]]}}).to_string(),
        )
        .expect("the model parses");
        LinearModel::from_spec(&s.model).expect("a valid model")
    }

    /// A seeded record of the model, complete.
    fn record(&self, steps: usize, seed: u64) -> Vec<DVector<f64>> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        self.linear()
            .simulate(steps, &Inputs::none(), None, &mut rng)
            .y
    }
}

/// `y` with every output of the rows `gaps` (0-based) missing.
fn with_gaps(y: &[DVector<f64>], gaps: &[usize]) -> Vec<DVector<f64>> {
    let mut y = y.to_vec();
    for &k in gaps {
        y[k].fill(f64::NAN);
    }
    y
}

fn y_json(y: &[DVector<f64>]) -> Value {
    json!(y
        .iter()
        .map(|r| r
            .iter()
            .map(|x| if x.is_nan() { Value::Null } else { json!(x) })
            .collect::<Vec<_>>())
        .collect::<Vec<_>>())
}

fn scenario(method: &str, m: &Lgm, y: &[DVector<f64>], extra: Value) -> Scenario {
    let mut v = json!({
        "method": method,
        "model": m.json(),
        "data": {"y": y_json(y)},
        "alpha": 0.9,
    });
    if let (Some(o), Value::Object(e)) = (v.as_object_mut(), extra) {
        for (k, x) in e {
            if k == "t" {
                o["data"]["t"] = x;
            } else {
                o.insert(k, x);
            }
        }
    }
    Scenario::from_json(&v.to_string()).unwrap_or_else(|e| panic!("{e}"))
}

fn run(s: &Scenario) -> Report {
    s.run().unwrap_or_else(|e| panic!("{}: {e}", s.method))
}

/// The textbook filter with gaps, standard covariance form.
struct Reference {
    x_pred: Vec<DVector<f64>>,
    p_pred: Vec<DMatrix<f64>>,
    xhat: Vec<DVector<f64>>,
    p: Vec<DMatrix<f64>>,
    /// Prior moments m_t, Γ_t.
    m: Vec<DVector<f64>>,
    gamma: Vec<DMatrix<f64>>,
}

fn textbook(m: &Lgm, y: &[DVector<f64>]) -> Reference {
    let n = m.f.nrows();
    let mut r = Reference {
        x_pred: vec![],
        p_pred: vec![],
        xhat: vec![],
        p: vec![],
        m: vec![],
        gamma: vec![],
    };
    let (mut x_pred, mut p_pred) = (m.m1.clone(), m.p1.clone());
    let (mut mean, mut gamma) = (m.m1.clone(), m.p1.clone());
    for yt in y {
        let obs: Vec<usize> = (0..yt.len()).filter(|&j| !yt[j].is_nan()).collect();
        let (xhat, p) = if obs.is_empty() {
            (x_pred.clone(), p_pred.clone())
        } else {
            let q = obs.len();
            let h = DMatrix::from_fn(q, n, |i, j| m.h[(obs[i], j)]);
            let w = DMatrix::from_fn(q, q, |i, j| m.w[(obs[i], obs[j])]);
            let yo = DVector::from_fn(q, |i, _| yt[obs[i]]);
            let s = &w + &h * &p_pred * h.transpose();
            let k = &p_pred * h.transpose() * s.try_inverse().expect("S invertible");
            let xhat = &x_pred + &k * (yo - &h * &x_pred);
            let p = (DMatrix::identity(n, n) - &k * &h) * &p_pred;
            (xhat, (&p + p.transpose()) * 0.5)
        };
        r.x_pred.push(x_pred.clone());
        r.p_pred.push(p_pred.clone());
        r.xhat.push(xhat.clone());
        r.p.push(p.clone());
        r.m.push(mean.clone());
        r.gamma.push(gamma.clone());
        x_pred = &m.f * xhat;
        p_pred = &m.f * p * m.f.transpose() + &m.v;
        mean = &m.f * mean;
        gamma = &m.f * gamma * m.f.transpose() + &m.v;
    }
    r
}

fn mat(rows: &[Vec<f64>]) -> DMatrix<f64> {
    DMatrix::from_fn(rows.len(), rows[0].len(), |i, j| rows[i][j])
}

#[track_caller]
fn assert_vec_close(a: &[f64], b: &DVector<f64>, tol: f64, what: &str) {
    let scale = b.amax().max(1.0);
    assert_eq!(a.len(), b.len(), "{what}");
    for (x, y) in a.iter().zip(b.iter()) {
        assert!((x - y).abs() <= tol * scale, "{what}: {a:?} vs {b}");
    }
}

/// The records of the tests: gaps at the first row, a middle row, the last row and a stretch
/// of 20 rows.
const STEPS: usize = 80;
fn gap_rows() -> Vec<usize> {
    let mut g = vec![0, 30, STEPS - 1];
    g.extend(45..65);
    g
}

/// Every model of the tests with its gappy record: the local level (n = 1), the rotation seen
/// through one output, and through two outputs with only one of them missing at some rows.
fn cases() -> Vec<(&'static str, Lgm, Vec<DVector<f64>>)> {
    let level = Lgm::local_level(1469.1, 15099.0, 1120.0, 1e6);
    let one = Lgm::one_output();
    let two = Lgm::two_outputs();
    let mut y2 = with_gaps(&two.record(STEPS, 5), &gap_rows());
    // Partial gaps: one of the two outputs missing.
    for (k, j) in [(5, 0), (6, 1), (31, 0), (70, 1)] {
        y2[k][j] = f64::NAN;
    }
    vec![
        (
            "local level",
            level.clone(),
            with_gaps(&level.record(STEPS, 3), &gap_rows()),
        ),
        (
            "one output",
            one.clone(),
            with_gaps(&one.record(STEPS, 4), &gap_rows()),
        ),
        ("two outputs", two, y2),
    ]
}

/// The rows a record has a gap in (0-based).
fn gappy(y: &[DVector<f64>]) -> Vec<usize> {
    (0..y.len())
        .filter(|&k| y[k].iter().any(|x| x.is_nan()))
        .collect()
}

/// The report keeps one step per row, its y keeps the gaps where the record has them, and
/// KF's means and covariances equal the textbook recursion with the update skipped (partial
/// with one output of two missing) to 1e-12.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn kalman_skips_the_update_at_a_gap() {
    for (name, m, y) in cases() {
        let r = run(&scenario("kf", &m, &y, json!({})));
        assert_eq!(r.steps.len(), y.len(), "{name}");
        assert_eq!(r.y.len(), y.len(), "{name}");
        for (k, (a, b)) in r.y.iter().zip(&y).enumerate() {
            for (x, z) in a.iter().zip(b.iter()) {
                assert!(
                    (x.is_nan() && z.is_nan()) || x == z,
                    "{name}: y[{k}] {a:?} vs the record's {b}"
                );
            }
        }
        let reference = textbook(&m, &y);
        for (i, st) in r.steps.iter().enumerate() {
            let what = format!("{name} t = {}", i + 1);
            assert_vec_close(&st.kf.center, &reference.xhat[i], 1e-12, &what);
            assert_mat_close(&mat(&st.kf.cov), &reference.p[i], 1e-12, &what);
        }
        // At a full gap the update is skipped: the set is the prediction's.
        for &k in &gap_rows() {
            if y[k].iter().all(|x| x.is_nan()) {
                assert_vec_close(&r.steps[k].kf.center, &reference.x_pred[k], 1e-12, name);
                assert_mat_close(&mat(&r.steps[k].kf.cov), &reference.p_pred[k], 1e-12, name);
            }
        }
        // The report says where the gaps are and what was done, and reads back with them.
        let words = r.warnings.join(" ");
        let runs = if name == "two outputs" {
            "t = 1, 6 … 7, 31 … 32, 46 … 65 and 2 more stretches"
        } else {
            "t = 1, 31, 46 … 65, 80"
        };
        assert!(
            words.contains(&format!("{} rows ({runs})", gappy(&y).len()))
                && words.contains("the Kalman update is skipped"),
            "{name}: {words}"
        );
        let text = serde_json::to_string(&r).expect("JSON");
        let back: Report = serde_json::from_str(&text).expect("the report reads back");
        assert!(back.y[0].iter().all(|x| x.is_nan()), "{name}");
        assert_eq!(back.steps, r.steps, "{name}");
    }
}
in_browser!(kalman_skips_the_update_at_a_gap);

/// SCF with gaps: the ratio matrix from the recursion (38) (a gap's gain is zero in the
/// missing columns) equals the closed form (41) I − PₜΓₜ⁻¹ with the gaps' Pₜ, and the SCF
/// region is (33)–(34) from it; no region before n measured steps.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn scf_ratio_with_gaps_is_the_closed_form() {
    for (name, m, y) in cases() {
        let r = run(&scenario("scf", &m, &y, json!({})));
        assert_eq!(r.steps.len(), y.len(), "{name}");
        let reference = textbook(&m, &y);
        let n = m.f.nrows();
        let mut measured = 0;
        for (i, st) in r.steps.iter().enumerate() {
            let what = format!("{name} t = {}", i + 1);
            measured += usize::from(y[i].iter().any(|x| !x.is_nan()));
            let g_inv = reference.gamma[i].clone().try_inverse().expect("Γ_t");
            let ratio = DMatrix::identity(n, n) - &reference.p[i] * g_inv;
            // R is dimensionless, of order 1: compared to 1e-9 absolutely.
            let gap = (mat(&st.ratio) - &ratio).amax();
            assert!(
                gap <= 1e-9,
                "{what}: R from (38) {:?} vs (41) {ratio}",
                st.ratio
            );
            if measured < n {
                assert!(
                    st.scf.is_none(),
                    "{what}: an SCF region before n measured steps"
                );
                continue;
            }
            let e = st
                .scf
                .as_ref()
                .unwrap_or_else(|| panic!("{what}: no SCF region"));
            let r_inv = ratio.try_inverse().expect("R_t");
            let centre = &reference.m[i] + &r_inv * (&reference.xhat[i] - &reference.m[i]);
            assert_vec_close(&e.center, &centre, 1e-9, &what);
            assert_mat_close(&mat(&e.cov), &(&r_inv * &reference.p[i]), 1e-9, &what);
        }
        // Through the stretch of 20 the ratio only propagates (Kₜ = 0) and shrinks here:
        // the SCF region widens faster than the Kalman one.
        let grow = |k: usize| {
            let kf = mat(&r.steps[k].kf.cov).determinant();
            let scf = mat(&r.steps[k].scf.as_ref().expect("SCF").cov).determinant();
            scf / kf
        };
        assert!(grow(64) > grow(44), "{name}: {} vs {}", grow(64), grow(44));
        let words = r.warnings.join(" ");
        assert!(
            words.contains("UₜAₜ (38) only propagates"),
            "{name}: {words}"
        );
        if name == "two outputs" {
            assert!(
                words.contains("at 4 rows only some outputs are missing"),
                "{words}"
            );
        }
    }
}
in_browser!(scf_ratio_with_gaps_is_the_closed_form);

/// The asymptotic SCF (constant K̄, P̄, R̄) cannot take a gap: refused naming its option; an
/// SCF without n measured rows is refused in words; KF takes even a record of gaps only.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn what_cannot_take_a_gap_is_refused_precisely() {
    let m = Lgm::one_output();
    let y = with_gaps(&m.record(STEPS, 4), &[30]);
    let s = scenario("scf", &m, &y, json!({"scf": {"asymptotic": true}}));
    let e = s.run().expect_err("the asymptotic SCF refuses a gap");
    assert_eq!(e.field, "scf.asymptotic", "{e}");
    assert!(e.message.contains("asymptotic\": false"), "{e}");
    // Too few measured rows for an SCF region: said in words, in the singular too.
    let level = Lgm::local_level(1.0, 1.0, 0.0, 10.0);
    let y: Vec<DVector<f64>> = (0..3).map(|_| DVector::from_element(1, f64::NAN)).collect();
    let e = scenario("scf", &level, &y, json!({}))
        .run()
        .expect_err("no measurement");
    assert_eq!(e.field, "data.y", "{e}");
    assert!(e.message.contains("0 measured rows of 3"), "{e}");
    // KF takes a record with no measurement at all: the prior moved by the model.
    let r = run(&scenario("kf", &level, &y, json!({})));
    assert_eq!(r.steps[2].kf.cov[0][0], 10.0 + 2.0);
}
in_browser!(what_cannot_take_a_gap_is_refused_precisely);

/// The step-through card at a gap: no innovation, a zero gain, the prediction as estimate,
/// equal to the report's numbers.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn explain_says_the_update_is_skipped() {
    for (name, m, y) in cases() {
        for method in ["kf", "scf"] {
            let s = scenario(method, &m, &y, json!({}));
            let r = run(&s);
            for t in [1, 31, 50, STEPS, 6] {
                let e = s
                    .explain(&r, Some(t), None)
                    .unwrap_or_else(|e| panic!("{name} {t}: {e}"));
                let value = |row: &str| {
                    e.rows
                        .iter()
                        .find(|x| x.name == row)
                        .unwrap_or_else(|| panic!("{name}: no {row}"))
                        .clone()
                };
                let StepValue::Vector(est) = value("estimate").value else {
                    panic!("{name}: estimate")
                };
                assert_slice_rel(&est, &r.steps[t - 1].kf.center, 1e-12, name);
                let full = y[t - 1].iter().all(|x| x.is_nan());
                if full {
                    assert!(
                        matches!(value("innovation").value, StepValue::Text(_)),
                        "{name}"
                    );
                    let StepValue::Matrix(k) = value("gain").value else {
                        panic!("gain")
                    };
                    assert!(
                        k.iter().flatten().all(|x| *x == 0.0),
                        "{name} t = {t}: K = {k:?}"
                    );
                    assert!(value("innovation").note.contains("skipped"), "{name}");
                }
            }
        }
    }
}
in_browser!(explain_says_the_update_is_skipped);

/// Metamorphic: a gap filled with the filter's own prediction H x̂ₜ⁻ leaves the Kalman set of
/// the next state, x_{t+1} from y₁ … yₜ (KF's τ = 1 region), with the same centre (1e-12) and
/// no smaller: P(gap) − P(filled) ⪰ 0; so is the filtered set at the gap itself, and every
/// later filtered covariance is no smaller either.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_gap_filled_by_the_prediction_keeps_the_centre_and_is_no_smaller() {
    #[track_caller]
    fn no_smaller(a: &[Vec<f64>], b: &[Vec<f64>], what: &str) {
        let diff = mat(a) - mat(b);
        let lowest = diff.clone().symmetric_eigen().eigenvalues.min();
        assert!(
            lowest >= -1e-12 * mat(a).amax(),
            "{what}: P(gap) − P(filled) has eigenvalue {lowest}"
        );
        assert!(diff.amax() > 0.0, "{what}: the filled step tells nothing");
    }
    let next = json!({"scf": {"tau": 1}});
    for (name, m, y) in cases() {
        let gap = run(&scenario("kf", &m, &y, next.clone()));
        for k in [30usize, 45, 64] {
            if !y[k].iter().all(|x| x.is_nan()) {
                continue;
            }
            // At a gap the report's centre is the prediction x̂ₜ⁻ itself.
            let pred = DVector::from_vec(gap.steps[k].kf.center.clone());
            let mut filled = y.clone();
            filled[k] = &m.h * pred;
            let full = run(&scenario("kf", &m, &filled, next.clone()));
            let what = format!("{name}: gap at row {k}");
            let target = |r: &Report| r.steps[k].target.clone().expect("the τ = 1 region").kf;
            let (a, b) = (target(&gap), target(&full));
            let centre = DVector::from_vec(b.center.clone());
            assert_vec_close(&a.center, &centre, 1e-12, &format!("{what}, x_{{t+1}}"));
            no_smaller(&a.cov, &b.cov, &format!("{what}, x_{{t+1}}"));
            let (a, b) = (&gap.steps[k].kf, &full.steps[k].kf);
            let centre = DVector::from_vec(b.center.clone());
            assert_vec_close(&a.center, &centre, 1e-12, &format!("{what}, x_t"));
            no_smaller(&a.cov, &b.cov, &format!("{what}, x_t"));
            for i in k + 1..y.len() {
                let (a, b) = (&gap.steps[i].kf.cov, &full.steps[i].kf.cov);
                let lowest = (mat(a) - mat(b)).symmetric_eigen().eigenvalues.min();
                assert!(
                    lowest >= -1e-12 * mat(a).amax(),
                    "{what}, t = {}: {lowest}",
                    i + 1
                );
            }
        }
    }
}
in_browser!(a_gap_filled_by_the_prediction_keeps_the_centre_and_is_no_smaller);

/// A Nile-like record (Durbin & Koopman's local level at their MLEs, V = 1469.1, W = 15099;
/// 100 flows drawn with a seed here, the times 1871–1970) with gaps at 21–40 and 61–80: the
/// Kalman variance grows at every step of each gap (Pₜ = Pₜ₋₁ + V), and the report names the
/// gaps with the record's years.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn nile_variance_grows_through_each_gap() {
    let m = Lgm::local_level(1469.1, 15099.0, 1120.0, 1e7);
    let gaps: Vec<usize> = (20..40).chain(60..80).collect();
    let y = with_gaps(&m.record(100, 1871), &gaps);
    let years: Vec<i64> = (1871..1971).collect();
    for method in ["kf", "scf", "conformal"] {
        let extra = json!({"t": years});
        let r = run(&scenario(method, &m, &y, extra));
        let words = r.warnings.join(" ");
        assert!(
            words.contains("40 rows (t = 21 … 40, 61 … 80; times 1891 … 1910, 1931 … 1950)"),
            "{method}: {words}"
        );
        if method == "conformal" {
            let a = &r.conformal.as_ref().expect("conformal").aci;
            assert_eq!((a.gaps, a.scored), (40, 60));
            continue;
        }
        let p: Vec<f64> = r.steps.iter().map(|s| s.kf.cov[0][0]).collect();
        let reference = textbook(&m, &y);
        for (i, x) in p.iter().enumerate() {
            assert!(
                rel_close(*x, reference.p[i][(0, 0)], 1e-12),
                "t = {}",
                i + 1
            );
        }
        for stretch in [20..40usize, 60..80] {
            for k in stretch {
                assert!(
                    p[k] > p[k - 1],
                    "{method}: P at t = {} not above t = {}",
                    k + 1,
                    k
                );
                assert!(
                    rel_close(p[k], p[k - 1] + 1469.1, 1e-12),
                    "{method} t = {}",
                    k + 1
                );
            }
        }
        // The CSV table: the record's years beside t, the gap's cells empty, never NaN.
        let csv = r.table().expect("the table").to_csv();
        assert!(
            csv.starts_with("# warning: The record has gaps at 40 rows"),
            "{csv}"
        );
        let row21 = csv.lines().find(|l| l.starts_with("21,")).expect("row 21");
        assert!(row21.starts_with("21,1891,,"), "{row21}");
        assert!(!csv.contains("NaN") && !csv.contains("nan"), "{csv}");
    }
}
in_browser!(nile_variance_grows_through_each_gap);

/// Conformal with gaps: the region at a gap time is the filter's with the updates skipped,
/// and the N calibration scores, recomputed here from the same seeded runs filtered with the
/// record's gaps, are the report's.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn conformal_region_uses_the_filter_with_skipped_updates() {
    for (name, m, y) in cases() {
        let time = 50; // inside the stretch of 20
        let s = scenario(
            "conformal",
            &m,
            &y,
            json!({"time": time, "conformal": {"calibration": 49}}),
        );
        let r = run(&s);
        let c = r.conformal.as_ref().expect("conformal");
        let reference = textbook(&m, &y);
        assert_vec_close(&c.region.center, &reference.xhat[time - 1], 1e-12, name);
        assert_mat_close(&mat(&c.region.cov), &reference.p[time - 1], 1e-12, name);
        assert_eq!(c.aci.steps.len(), y.len(), "{name}");
        // The calibration runs: drawn as the method draws them, filtered here with the gaps.
        let model = m.linear();
        let sim = Simulator::new(&model, time, &Inputs::none(), NoiseLaw::Gaussian);
        let mut rng = ChaCha8Rng::seed_from_u64(1000);
        let p_inv = reference.p[time - 1].clone().try_inverse().expect("P_t");
        let mut scores: Vec<f64> = (0..49)
            .map(|_| {
                let run = sim.draw(&model, &mut rng);
                let mut ys = run.y.clone();
                for (k, row) in ys.iter_mut().enumerate() {
                    for j in 0..row.len() {
                        if y[k][j].is_nan() {
                            row[j] = f64::NAN;
                        }
                    }
                }
                let own = textbook(&m, &ys);
                let d = &run.x[time - 1] - &own.xhat[time - 1];
                (d.transpose() * &p_inv * &d)[0]
            })
            .collect();
        scores.sort_by(f64::total_cmp);
        assert_slice_rel(&c.scores, &scores, 1e-9, name);
    }
}
in_browser!(conformal_region_uses_the_filter_with_skipped_updates);

/// One ACI step as recomputed here.
#[derive(Debug)]
struct OwnAci {
    alpha_t: f64,
    q: f64,
    empty: bool,
    err: Option<bool>,
    warmup: bool,
    sd: Vec<f64>,
    y_hat: Vec<f64>,
}

/// ACI (Gibbs & Candès (2)) on the normalized innovations of the textbook filter, a gap step
/// unscored and α not moved there.
fn own_aci(m: &Lgm, y: &[DVector<f64>], level: f64, gamma: f64) -> Vec<OwnAci> {
    let reference = textbook(m, y);
    let miss = 1.0 - level;
    let mut alpha = miss;
    let mut past: Vec<f64> = vec![];
    let mut warming = true;
    let mut out = vec![];
    for (i, yt) in y.iter().enumerate() {
        let s = &m.w + &m.h * &reference.p_pred[i] * m.h.transpose();
        let y_hat = &m.h * &reference.x_pred[i];
        let complete = yt.iter().all(|x| !x.is_nan());
        let score = complete.then(|| {
            let e = yt - &y_hat;
            (e.transpose() * s.clone().try_inverse().expect("S") * &e)[0].sqrt()
        });
        let (q, empty) = if alpha >= 1.0 {
            (0.0, true)
        } else {
            let n = past.len();
            let k = ((n as f64 + 1.0) * (1.0 - alpha)).ceil() as usize;
            if alpha > 0.0 && k >= 1 && k <= n {
                let mut sorted = past.clone();
                sorted.sort_by(f64::total_cmp);
                (sorted[k - 1], false)
            } else {
                (f64::INFINITY, false)
            }
        };
        warming &= q.is_infinite() && !empty;
        let err = score.map(|r| empty || r > q);
        out.push(OwnAci {
            alpha_t: alpha,
            q,
            empty,
            err,
            warmup: warming && score.is_some(),
            sd: (0..s.nrows()).map(|j| s[(j, j)].sqrt()).collect(),
            y_hat: y_hat.iter().copied().collect(),
        });
        if let (Some(r), Some(e)) = (score, err) {
            alpha += gamma * (miss - if e { 1.0 } else { 0.0 });
            past.push(r);
        }
    }
    out
}

/// ACI against the one recomputed here: αₜ, qₜ, the verdicts, the warm-up; the coverage over
/// the steps with an interval and the warm-up count apart; the long-run coverage and
/// Proposition 4.1's bound over the scored steps; the CSV table's √S, qₜ and interval bounds.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn aci_is_counted_honestly_against_an_independent_aci() {
    let mut all = cases();
    // And a record without gaps, long enough for α_t to move.
    let one = Lgm::one_output();
    all.push(("no gaps", one.clone(), one.record(300, 9)));
    for (name, m, y) in all {
        for gamma in [0.005, 0.05, 0.5] {
            let s = scenario(
                "conformal",
                &m,
                &y,
                json!({"conformal": {"gamma": gamma, "calibration": 19}}),
            );
            let r = run(&s);
            let a = &r.conformal.as_ref().expect("conformal").aci;
            let own = own_aci(&m, &y, 0.9, gamma);
            let what = format!("{name} γ = {gamma}");
            for (st, o) in a.steps.iter().zip(&own) {
                let w = format!("{what} t = {}", st.t);
                assert!(
                    rel_close(st.alpha_t, o.alpha_t, 1e-12),
                    "{w}: α {} vs {}",
                    st.alpha_t,
                    o.alpha_t
                );
                assert_eq!(st.q.is_none(), o.q.is_infinite(), "{w}");
                if let Some(q) = st.q {
                    assert!(rel_close(q, o.q, 1e-9), "{w}: q {q} vs {}", o.q);
                }
                assert_eq!(
                    (st.empty, st.err, st.warmup),
                    (o.empty, o.err, o.warmup),
                    "{w}"
                );
                assert_eq!(
                    st.err.is_none(),
                    y[st.t - 1].iter().any(|x| x.is_nan()),
                    "{w}"
                );
            }
            let scored: Vec<&OwnAci> = own.iter().filter(|o| o.err.is_some()).collect();
            let with_interval: Vec<&&OwnAci> = scored
                .iter()
                .filter(|o| o.q.is_finite() || o.empty)
                .collect();
            let warmup = scored
                .iter()
                .take_while(|o| o.q.is_infinite() && !o.empty)
                .count();
            let cover = |v: &[&&OwnAci]| {
                v.iter().filter(|o| o.err == Some(false)).count() as f64 / v.len() as f64
            };
            assert_eq!(a.warmup, warmup, "{what}");
            assert!(warmup >= 1, "{what}: the first step has no past");
            assert_eq!(a.covered_steps, with_interval.len(), "{what}");
            assert_eq!(a.scored, scored.len(), "{what}");
            assert!(
                rel_close(a.coverage, cover(&with_interval), 1e-12),
                "{what}"
            );
            let long_run =
                scored.iter().filter(|o| o.err == Some(false)).count() as f64 / scored.len() as f64;
            assert!(rel_close(a.long_run_coverage, long_run, 1e-12), "{what}");
            let t = scored.len() as f64;
            let bound = (0.9f64.max(0.1) + gamma) / (gamma * t);
            assert!(rel_close(a.bound, bound, 1e-12), "{what}");
            assert!((long_run - 0.9).abs() <= bound, "{what}: Prop. 4.1");
            // Vacuous: the bound at or above max(α, 1 − α) = 0.9 rules out nothing, said so.
            let vacuous = bound >= 0.9;
            assert_eq!(a.bound_vacuous, vacuous, "{what}");
            let said = r
                .warnings
                .iter()
                .any(|w| w.contains("rules out no coverage at all"));
            assert_eq!(said, vacuous, "{what}: {:?}", r.warnings);
            // The table: √S, qₜ, ŷ ± qₜ√S, and the warm-up flag.
            let table = r.table().expect("table");
            let col = |c: &str| {
                table
                    .columns
                    .iter()
                    .position(|x| x == c)
                    .unwrap_or_else(|| panic!("no column {c}: {:?}", table.columns))
            };
            for (row, o) in table.rows.iter().zip(&own) {
                let w = format!("{what} t = {:?}", row[0]);
                assert!(
                    rel_close(row[col("sd_1")].expect("sd"), o.sd[0], 1e-12),
                    "{w}"
                );
                let bounds = (o.q.is_finite() && !o.empty)
                    .then(|| (o.y_hat[0] - o.q * o.sd[0], o.y_hat[0] + o.q * o.sd[0]));
                match bounds {
                    Some((lo, hi)) => {
                        assert!(rel_close(row[col("aci_q")].expect("q"), o.q, 1e-9), "{w}");
                        let (l, h) = (
                            row[col("aci_lower_1")].expect("lo"),
                            row[col("aci_upper_1")].expect("hi"),
                        );
                        assert!(
                            (l - lo).abs() <= 1e-9 * (1.0 + lo.abs()),
                            "{w}: {l} vs {lo}"
                        );
                        assert!(
                            (h - hi).abs() <= 1e-9 * (1.0 + hi.abs()),
                            "{w}: {h} vs {hi}"
                        );
                    }
                    None => {
                        assert_eq!(row[col("aci_lower_1")], None, "{w}");
                        assert_eq!(row[col("aci_upper_1")], None, "{w}");
                    }
                }
                assert_eq!(
                    row[col("aci_warmup")],
                    Some(if o.warmup { 1.0 } else { 0.0 }),
                    "{w}"
                );
                assert_eq!(
                    row[col("aci_miss")],
                    o.err.map(|e| if e { 1.0 } else { 0.0 }),
                    "{w}"
                );
            }
        }
    }
}
in_browser!(aci_is_counted_honestly_against_an_independent_aci);

/// Every figure of a gappy report draws, at the report's time and at a gap, with no NaN in
/// its SVG (a gap is a break in the measurement dots).
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn figures_draw_a_gap_as_nothing() {
    for (name, m, y) in cases() {
        for method in ["kf", "scf", "conformal"] {
            let r = run(&scenario(method, &m, &y, json!({})));
            for panel in plot::useful_panels(&r) {
                for time in [None, Some(50), Some(1)] {
                    let mut view = View::new(panel);
                    view.time = time;
                    let what = format!("{name} {method} {} at {time:?}", panel.name());
                    let svg = plot::report_svg(&r, &view, 800, 560)
                        .unwrap_or_else(|e| panic!("{what}: {e}"));
                    assert!(!svg.contains("NaN"), "{what}: NaN in the SVG");
                }
            }
        }
    }
}
in_browser!(figures_draw_a_gap_as_nothing);
