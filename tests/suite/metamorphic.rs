//! Metamorphic tests (issue 25): every method's sets must follow the state space when it is
//! moved, stretched or relabelled, natively and in the browser.
//!
//! For SCF and Kalman (`scf`, `kf`), GLLS, Pavelková's LP (`uniform_lp`), Tempo's
//! set-membership (`ubb`) and `compare`, a deterministic `data` scenario (built from the
//! preset's model, with data simulated here by our own generator) is transformed and run again,
//! and every set of the new report is compared with the transformation applied to the set of
//! the original report (the reference is the original report, transformed here, never the
//! crate's own transform):
//!
//! * **translation** by d_t, with d_{t+1} = F d_t (a free motion of the model, so the noise is
//!   unchanged): y'_t = y_t + H d_t and the prior (x1_mean, ubb.x0_center) moves by d_1. Every
//!   centre, hull bound, polygon vertex moves by d_t; every covariance, width, radius, area and
//!   level stays; every "truth inside" flag stays;
//! * **scaling** by s: states, data, inputs, noise standard deviations and bounds × s
//!   (covariances × s²). Every set × s (covariances and areas × s²), every level the same;
//! * **permutation** P of the state coordinates: F' = P F Pᵀ, H' = H Pᵀ, G' = P G, B' = P B,
//!   V' = P V Pᵀ, … Every set is permuted.
//!
//! Scales run from 1e-8 to 1e15 (a fixed grid, and proptest's draws with a fixed seed). At
//! scales 1e-3 … 1e6 every method must succeed; outside, a refusal is accepted only as an
//! error that names a field and speaks of precision or scale.
//!
//! Tolerances are relative (see [`Tolerance`]): a point's error is measured against the larger
//! of its magnitude and its set's size, every other number against its own magnitude.

use crate::common::patch::patched;
use confset::presets;
use nalgebra::DMatrix;
use proptest::prop_assert;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::{json, Value};

// ---------------------------------------------------------------------------------------------
// Transformations and what they do to each kind of number.

/// One metamorphic transformation of the state space.
#[derive(Debug, Clone)]
enum Transform {
    /// x'_t = x_t + d[t] (d indexed as the method indexes its states; see each method).
    Shift(Vec<Vec<f64>>),
    /// x' = s x.
    Scale(f64),
    /// x'_i = x_{p[i]}.
    Permute(Vec<usize>),
}

/// How a reported number moves under a transformation.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    /// A point of the state space at (the method's) time index t: shifted, scaled, permuted.
    State(usize),
    /// A matrix over state indices (covariance: p = 2; ratio: p = 0): P M Pᵀ, × s^p.
    Matrix(i32),
    /// A number with power p of the scale (radius 1, area 2, level 0).
    Scalar(i32),
    /// A yes/no fact (truth inside a set): must not change.
    Flag,
    /// A method of a compare gave no set; the label holds its reason.
    Refusal,
}

/// One number (or vector, or matrix, row-major) read from a report.
#[derive(Debug, Clone)]
struct Feature {
    label: String,
    kind: Kind,
    value: Vec<f64>,
    /// For a `State`: the size of the set it belongs to (its error is measured against
    /// max(|point|, size)); transforms like a length.
    size: f64,
}

fn feature(label: impl Into<String>, kind: Kind, value: Vec<f64>) -> Feature {
    Feature {
        label: label.into(),
        kind,
        value,
        size: 0.0,
    }
}

fn point(label: impl Into<String>, t: usize, value: Vec<f64>, size: f64) -> Feature {
    Feature {
        label: label.into(),
        kind: Kind::State(t),
        value,
        size,
    }
}

fn permute_vec(v: &[f64], p: &[usize]) -> Vec<f64> {
    p.iter().map(|&i| v[i]).collect()
}

/// The original feature moved by the transformation: the reference of the transformed run.
fn expected(f: &Feature, tr: &Transform) -> Feature {
    let mut out = f.clone();
    match (tr, f.kind) {
        (Transform::Shift(d), Kind::State(t)) => {
            out.value = f.value.iter().zip(&d[t]).map(|(x, d)| x + d).collect()
        }
        (Transform::Shift(_), _) => {}
        (Transform::Scale(s), kind) => {
            let power = match kind {
                Kind::State(_) => 1,
                Kind::Matrix(p) | Kind::Scalar(p) => p,
                Kind::Flag | Kind::Refusal => 0,
            };
            let factor = s.powi(power);
            out.value = f.value.iter().map(|x| x * factor).collect();
            out.size = f.size * s;
        }
        (Transform::Permute(p), Kind::State(_)) => out.value = permute_vec(&f.value, p),
        (Transform::Permute(p), Kind::Matrix(_)) => {
            let n = p.len();
            out.value = (0..n * n)
                .map(|k| f.value[p[k / n] * n + p[k % n]])
                .collect();
        }
        (Transform::Permute(_), Kind::Scalar(_) | Kind::Flag | Kind::Refusal) => {}
    }
    out
}

/// Relative error of `got` against the reference `want` (see the module's note on tolerances).
fn relative_error(got: &Feature, want: &Feature) -> f64 {
    if got.value.len() != want.value.len()
        || !got.value.iter().chain(&want.value).all(|v| v.is_finite())
    {
        return f64::INFINITY;
    }
    if want.kind == Kind::Flag {
        return if got.value == want.value {
            0.0
        } else {
            f64::INFINITY
        };
    }
    let magnitude = want.value.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let denominator = match want.kind {
        Kind::State(_) => magnitude.max(want.size),
        _ => magnitude,
    };
    let error = got
        .value
        .iter()
        .zip(&want.value)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    if error == 0.0 {
        0.0
    } else if denominator > 0.0 {
        error / denominator
    } else {
        f64::INFINITY
    }
}

// ---------------------------------------------------------------------------------------------
// Small helpers on JSON and matrices.

fn matrix(v: &Value) -> DMatrix<f64> {
    let rows: Vec<Vec<f64>> = serde_json::from_value(v.clone()).expect("a matrix");
    DMatrix::from_fn(rows.len(), rows[0].len(), |i, j| rows[i][j])
}

fn rows(m: &DMatrix<f64>) -> Value {
    json!((0..m.nrows())
        .map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect::<Vec<_>>())
        .collect::<Vec<_>>())
}

fn vector(v: &Value) -> Vec<f64> {
    serde_json::from_value(v.clone()).expect("a vector")
}

fn flat(v: &Value) -> Vec<f64> {
    matrix(v).transpose().as_slice().to_vec()
}

/// The permutation matrix P with (P x)_i = x_{p[i]}.
fn perm_matrix(p: &[usize]) -> DMatrix<f64> {
    DMatrix::from_fn(p.len(), p.len(), |i, j| if p[i] == j { 1.0 } else { 0.0 })
}

/// The free motion d_t = F^t d_0, t = 0 … len − 1.
fn free_motion(f: &DMatrix<f64>, d0: &[f64], len: usize) -> Vec<Vec<f64>> {
    let mut d = nalgebra::DVector::from_column_slice(d0);
    let mut out = Vec::with_capacity(len);
    for _ in 0..len {
        out.push(d.as_slice().to_vec());
        d = f * d;
    }
    out
}

/// Scale a JSON number, vector or matrix in place by `factor`.
fn scale_json(v: &mut Value, factor: f64) {
    match v {
        Value::Number(x) => *v = json!(x.as_f64().unwrap() * factor),
        Value::Array(items) => items.iter_mut().for_each(|x| scale_json(x, factor)),
        _ => {}
    }
}

/// Apply the transformation to the scenario's model block: F, H, and the noise/input matrices.
/// `shift_prior`: the prior mean field moved by d_1 (SCF/KF's `x1_mean`).
fn transform_model(model: &mut Value, tr: &Transform) {
    match tr {
        Transform::Shift(d) => {
            if model.get("x1_mean").is_some() {
                let m = vector(&model["x1_mean"]);
                model["x1_mean"] =
                    json!(m.iter().zip(&d[0]).map(|(a, b)| a + b).collect::<Vec<_>>());
            }
        }
        Transform::Scale(s) => {
            for key in ["V", "W", "x1_cov", "sigma_v2", "sigma_w2"] {
                if let Some(x) = model.get_mut(key) {
                    scale_json(x, s * s);
                }
            }
            if let Some(x) = model.get_mut("x1_mean") {
                scale_json(x, *s);
            }
        }
        Transform::Permute(p) => {
            let pm = perm_matrix(p);
            for key in ["F", "V", "x1_cov"] {
                if model.get(key).is_some_and(|x| !x.is_null()) {
                    model[key] = rows(&(&pm * matrix(&model[key]) * pm.transpose()));
                }
            }
            if model.get("H").is_some_and(|x| !x.is_null()) {
                model["H"] = rows(&(matrix(&model["H"]) * pm.transpose()));
            }
            for key in ["G", "B"] {
                if model.get(key).is_some_and(|x| !x.is_null()) {
                    model[key] = rows(&(&pm * matrix(&model[key])));
                }
            }
            if model.get("x1_mean").is_some() {
                model["x1_mean"] = json!(permute_vec(&vector(&model["x1_mean"]), p));
            }
        }
    }
}

/// data.y (and data.u) moved: y_t + H d_t for a shift (row i paired with d[i + offset]), s·y
/// (and s·u) for a scale, unchanged for a permutation (H' x' = H x).
fn transform_data(sc: &mut Value, tr: &Transform, offset: usize) {
    let h = matrix(&sc["model"]["H"]);
    let data = &mut sc["data"];
    match tr {
        Transform::Shift(d) => {
            let y: Vec<Vec<f64>> = serde_json::from_value(data["y"].clone()).unwrap();
            let moved: Vec<Vec<f64>> = y
                .iter()
                .enumerate()
                .map(|(i, yi)| {
                    let hd = &h * nalgebra::DVector::from_column_slice(&d[i + offset]);
                    yi.iter().zip(hd.iter()).map(|(a, b)| a + b).collect()
                })
                .collect();
            data["y"] = json!(moved);
        }
        Transform::Scale(s) => {
            scale_json(&mut data["y"], *s);
            if let Some(u) = data.get_mut("u") {
                scale_json(u, *s);
            }
        }
        Transform::Permute(_) => {}
    }
}

/// Permute (or scale, or shift by d[t]) a JSON vector field of the state space.
fn transform_state_field(v: &mut Value, tr: &Transform, t: usize) {
    let x = vector(v);
    *v = json!(match tr {
        Transform::Shift(d) => x.iter().zip(&d[t]).map(|(a, b)| a + b).collect::<Vec<_>>(),
        Transform::Scale(s) => x.iter().map(|a| a * s).collect(),
        Transform::Permute(p) => permute_vec(&x, p),
    });
}

// ---------------------------------------------------------------------------------------------
// Running a scenario.

/// A run refused at an extreme scale: acceptable only if the error names a field and says the
/// scale or the precision is why.
#[derive(Debug)]
enum Outcome {
    Report(Value),
    Refused(String, String),
}

fn run(sc: &Value) -> Outcome {
    match confset::scenario::Scenario::from_json(&sc.to_string()).and_then(|s| s.run()) {
        Ok(report) => Outcome::Report(serde_json::to_value(&report).expect("report as JSON")),
        Err(e) => Outcome::Refused(e.field, e.message),
    }
}

fn acceptable_refusal(field: &str, message: &str) -> bool {
    let m = message.to_lowercase();
    !field.is_empty() && (m.contains("precision") || m.contains("scale"))
}

/// Data simulated here (not by the crate): x_{t+1} = F x_t + G w_t, y_t = H x_t + e_t with
/// uniform w, e of the given half-widths, from x_1 = x1. Returns (x_1 … x_T, y_1 … y_T).
fn simulate(
    f: &DMatrix<f64>,
    g: &DMatrix<f64>,
    h: &DMatrix<f64>,
    x1: &[f64],
    w_half: f64,
    e_half: f64,
    steps: usize,
    seed: u64,
) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut x = nalgebra::DVector::from_column_slice(x1);
    let (mut xs, mut ys) = (Vec::new(), Vec::new());
    for _ in 0..steps {
        let e = nalgebra::DVector::from_fn(h.nrows(), |_, _| {
            (rng.random::<f64>() * 2.0 - 1.0) * e_half
        });
        ys.push((h * &x + e).as_slice().to_vec());
        xs.push(x.as_slice().to_vec());
        let w = nalgebra::DVector::from_fn(g.ncols(), |_, _| {
            (rng.random::<f64>() * 2.0 - 1.0) * w_half
        });
        x = f * &x + g * w;
    }
    (xs, ys)
}

// ---------------------------------------------------------------------------------------------
// The methods: a base scenario, how each transformation patches it, and its features.

/// One method under test.
#[derive(Clone)]
struct Case {
    name: &'static str,
    /// The data scenario.
    scenario: Value,
    /// The true states x_t (indexed as the features' times), for the "truth inside" flags.
    truth: Vec<Vec<f64>>,
    /// F, to build d_t.
    f: DMatrix<f64>,
    /// Number of time indices d must cover.
    times: usize,
    /// The scenario under a transformation (model and data patched; method fields too).
    patch: fn(&Value, &Transform) -> Value,
    /// The report's features, with flags computed against the (transformed) truth.
    features: fn(&Value, &[Vec<f64>]) -> Vec<Feature>,
    /// The relative tolerance and why (see each method).
    tolerance: f64,
    /// How much the tolerance grows per unit of a shift |d|: an LP works in the unit of its
    /// right-hand sides, which a shift raises to about |d|, and is accurate to 10⁻¹⁰ of that
    /// unit (`solve::Problem::unit`), so its sets, about 0.1 wide, hold 10⁻⁹·|d| relative.
    /// 0 for the closed-form methods.
    shift_tolerance: f64,
    /// Whether a shift is a symmetry of the case (LSCR assumes a zero-mean stationary process
    /// and takes no prior mean, so a moved record is not the same problem moved).
    shifts: bool,
}

fn truth_moved(truth: &[Vec<f64>], tr: &Transform) -> Vec<Vec<f64>> {
    truth
        .iter()
        .enumerate()
        .map(|(t, x)| {
            let mut v = json!(x);
            transform_state_field(&mut v, tr, t);
            vector(&v)
        })
        .collect()
}

fn inside_ellipsoid(x: &[f64], e: &Value) -> bool {
    let c = vector(&e["center"]);
    let cov = matrix(&e["cov"]);
    let r = nalgebra::DVector::from_fn(c.len(), |i, _| x[i] - c[i]);
    let Some(inv) = cov.try_inverse() else {
        return false;
    };
    (r.transpose() * inv * &r)[0] <= e["radius2"].as_f64().unwrap()
}

fn ellipsoid_features(label: &str, t: usize, e: &Value, out: &mut Vec<Feature>) {
    let cov = matrix(&e["cov"]);
    let r2 = e["radius2"].as_f64().unwrap();
    let size = (cov.diagonal().max() * r2).sqrt();
    out.push(point(
        format!("{label}.center"),
        t,
        vector(&e["center"]),
        size,
    ));
    out.push(feature(
        format!("{label}.cov"),
        Kind::Matrix(2),
        flat(&e["cov"]),
    ));
    out.push(feature(
        format!("{label}.radius2"),
        Kind::Scalar(0),
        vec![r2],
    ));
}

fn flag(label: impl Into<String>, yes: bool) -> Feature {
    feature(label, Kind::Flag, vec![if yes { 1.0 } else { 0.0 }])
}

/// A copy of the scenario with its model and data moved by the transformation (what every case
/// moves; a method's own block is the case's).
fn moved(sc: &Value, tr: &Transform) -> Value {
    let mut sc = sc.clone();
    transform_model(&mut sc["model"], tr);
    transform_data(&mut sc, tr, 0);
    sc
}

/// The corners (lo, hi) of the box around planar points.
fn bounding_box<V: std::ops::Index<usize, Output = f64>>(points: &[V]) -> (Vec<f64>, Vec<f64>) {
    let lo: Vec<f64> = (0..2)
        .map(|k| points.iter().map(|v| v[k]).fold(f64::INFINITY, f64::min))
        .collect();
    let hi: Vec<f64> = (0..2)
        .map(|k| {
            points
                .iter()
                .map(|v| v[k])
                .fold(f64::NEG_INFINITY, f64::max)
        })
        .collect();
    (lo, hi)
}

/// A polygon's hull corners (lo, hi), signed-area magnitude and centroid.
fn polygon_features(label: &str, t: usize, vertices: &[Vec<f64>], out: &mut Vec<Feature>) {
    let n = vertices.len();
    let (mut area, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for i in 0..n {
        let (a, b) = (&vertices[i], &vertices[(i + 1) % n]);
        let cross = a[0] * b[1] - b[0] * a[1];
        area += cross;
        cx += (a[0] + b[0]) * cross;
        cy += (a[1] + b[1]) * cross;
    }
    area /= 2.0;
    let (lo, hi) = bounding_box(vertices);
    let size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    out.push(point(format!("{label}.hull_lo"), t, lo, size));
    out.push(point(format!("{label}.hull_hi"), t, hi, size));
    out.push(feature(
        format!("{label}.area"),
        Kind::Scalar(2),
        vec![area.abs()],
    ));
    // A degenerate polygon (area 0) has no centroid: NaN, which no reference matches.
    out.push(point(
        format!("{label}.centroid"),
        t,
        vec![cx / (6.0 * area), cy / (6.0 * area)],
        size,
    ));
}

// --- SCF and Kalman ---------------------------------------------------------------------------

/// SCF/KF: a 2-state model with a correlated V and an explicit prior (so a shift moves the
/// prior mean with the states). Time index t = 0 … T − 1 is x_{t+1}.
///
/// Tolerance 1e-9: the filters are a few dozen flops per step on 2×2 matrices with condition
/// ≲ 10 over 8 steps, so rounding stays near 1e-14 relative; 1e-9 is the crate's native =
/// wasm bound (crate docs), far above that and far below any real disagreement.
fn scf_case(method: &'static str) -> Case {
    let f = DMatrix::from_row_slice(2, 2, &[0.9, 0.2, -0.1, 0.7]);
    let h = DMatrix::from_row_slice(1, 2, &[1.0, 0.5]);
    let g = DMatrix::identity(2, 2);
    let (truth, y) = simulate(&f, &g, &h, &[0.5, -0.3], 1.0, 0.5, 8, 7);
    let mut sc = serde_json::to_value(presets::get("scf-scalar").unwrap()).unwrap();
    let obj = sc.as_object_mut().unwrap();
    obj.remove("simulate");
    obj.remove("scf");
    sc["method"] = json!(method);
    sc["model"] = json!({
        "F": rows(&f), "H": rows(&h),
        "V": [[1.0, 0.2], [0.2, 0.5]], "W": [[0.3]],
        "x1_mean": [0.5, -0.3], "x1_cov": [[2.0, 0.1], [0.1, 1.0]],
    });
    sc["data"] = json!({ "y": y });
    Case {
        name: method,
        scenario: sc,
        truth,
        f,
        times: 8,
        patch: |sc, tr| moved(sc, tr),
        features: |r, truth| {
            let mut out = Vec::new();
            for (i, st) in r["steps"].as_array().unwrap().iter().enumerate() {
                let t = st["t"].as_u64().unwrap() as usize - 1;
                assert_eq!(t, i);
                for key in ["kf", "scf"] {
                    if !st[key].is_null() {
                        ellipsoid_features(&format!("t{}.{key}", t + 1), t, &st[key], &mut out);
                        out.push(flag(
                            format!("t{}.{key}.truth_inside", t + 1),
                            inside_ellipsoid(&truth[t], &st[key]),
                        ));
                    }
                }
                if !st["ratio"].is_null() {
                    out.push(feature(
                        format!("t{}.ratio", t + 1),
                        Kind::Matrix(0),
                        flat(&st["ratio"]),
                    ));
                }
            }
            for (t, m) in r["prior_mean"].as_array().unwrap().iter().enumerate() {
                out.push(point(format!("t{}.prior_mean", t + 1), t, vector(m), 0.0));
            }
            out
        },
        tolerance: 1e-9,
        shift_tolerance: 0.0,
        shifts: true,
    }
}

// --- GLLS ---------------------------------------------------------------------------------------

/// GLLS: the glls-saturate model (3 states: a stable mode and a rotation), LLS at a fixed
/// horizon s = 8 (the automatic horizon is an argmin, and which of two near-equal values wins
/// is not a property of the sets). Data row i is y at x_true[i], so d[i] = F^i d_0; the current
/// estimate is at k = T − 1 and the past one at k − s.
///
/// Tolerance 1e-9: the estimate is a least-squares solve through the SVD of Γ_{s+1} whose
/// condition is σ₁/σ₃ ≈ 2.7 here; rounding is ~1e-14 relative.
fn glls_case() -> Case {
    let mut sc = serde_json::to_value(presets::get("glls-saturate").unwrap()).unwrap();
    let f = matrix(&sc["model"]["F"]);
    let h = matrix(&sc["model"]["H"]);
    let steps = 30;
    let (truth, y) = simulate(
        &f,
        &DMatrix::zeros(3, 1),
        &h,
        &[1.0, 1.0, 0.0],
        0.0,
        0.05,
        steps,
        3,
    );
    let obj = sc.as_object_mut().unwrap();
    obj.remove("simulate");
    sc["data"] = json!({ "y": y });
    sc["model"].as_object_mut().unwrap().remove("x1_mean");
    sc["glls"] = json!({ "horizon": 8, "max_horizon": 12, "estimator": "lls", "mu": 0.1,
                         "plane": [1, 2] });
    Case {
        name: "glls",
        scenario: sc,
        truth,
        f,
        times: steps,
        patch: |sc, tr| {
            let mut sc = moved(sc, tr);
            if let Transform::Scale(s) = tr {
                scale_json(&mut sc["glls"]["mu"], *s);
            }
            sc
        },
        features: |r, truth| {
            let g = &r["glls"];
            let k = g["k"].as_u64().unwrap() as usize;
            let s = g["s"].as_u64().unwrap() as usize;
            let mut out = Vec::new();
            for (when, t) in [("current", k), ("past", k - s)] {
                let ball = &g[format!("ball_{when}")];
                let radius = (matrix(&ball["cov"]).diagonal().max()).sqrt();
                out.push(point(
                    format!("estimate_{when}"),
                    t,
                    vector(&g[format!("estimate_{when}")]),
                    radius,
                ));
                ellipsoid_features(&format!("ball_{when}"), t, ball, &mut out);
                let bx = &g[format!("box_{when}")];
                let (lo, hi) = (vector(&bx["lo"]), vector(&bx["hi"]));
                let width = lo.iter().zip(&hi).fold(0.0f64, |m, (a, b)| m.max(b - a));
                let inside = (0..lo.len()).all(|i| lo[i] <= truth[t][i] && truth[t][i] <= hi[i]);
                out.push(point(format!("box_{when}.lo"), t, lo, width));
                out.push(point(format!("box_{when}.hi"), t, hi, width));
                out.push(flag(format!("box_{when}.truth_inside"), inside));
                out.push(flag(
                    format!("ball_{when}.truth_inside"),
                    inside_ellipsoid(&truth[t], ball),
                ));
            }
            out.push(feature(
                "expected_bound",
                Kind::Scalar(1),
                vec![g["expected_bound"].as_f64().unwrap()],
            ));
            out.push(feature(
                "kappa_current",
                Kind::Scalar(0),
                vec![g["kappa_current"].as_f64().unwrap()],
            ));
            out.push(feature(
                "kappa_past",
                Kind::Scalar(0),
                vec![g["kappa_past"].as_f64().unwrap()],
            ));
            out
        },
        tolerance: 1e-9,
        shift_tolerance: 0.0,
        shifts: true,
    }
}

// --- Tempo's set-membership (ubb) -----------------------------------------------------------------

/// ubb: the ubb-track system (‖u‖ ≤ τ through G, |η| ≤ ε, x(0) in x0_center ± δ, smoothed
/// bounds) with a fixed window of 6 steps over 14 steps. Time index k is x(k): data row k is
/// y(k), the track's step k bounds x(k + 1), and a shift moves x0_center by d_0.
///
/// Tolerance 1e-9 on hulls, the target for the LP hulls (a hull is an LP optimum:
/// clarabel's tolerances are set relative to the problem's data, so it can be met once the LP
/// is scaled; see the report of the scaling test for where it is not met yet).
fn ubb_case() -> Case {
    let mut sc = serde_json::to_value(presets::get("ubb-track").unwrap()).unwrap();
    let f = matrix(&sc["model"]["F"]);
    let h = matrix(&sc["model"]["H"]);
    let g = matrix(&sc["model"]["G"]);
    let steps = 14;
    let (truth, y) = simulate(&f, &g, &h, &[0.3, -0.5], 0.1, 0.2, steps + 1, 5);
    sc.as_object_mut().unwrap().remove("simulate");
    sc["data"] = json!({ "y": y[..steps] });
    let sc = patched(
        &sc,
        &json!({"ubb": {"window": 6, "time": 10, "x0_center": [0.0, 0.0]}}),
    );
    Case {
        name: "ubb",
        scenario: sc,
        truth,
        f,
        times: steps + 1,
        patch: |sc, tr| {
            let mut sc = moved(sc, tr);
            let ubb = &mut sc["ubb"];
            transform_state_field(&mut ubb["x0_center"], tr, 0);
            match tr {
                Transform::Scale(s) => {
                    for key in ["eps", "tau", "delta"] {
                        scale_json(&mut ubb[key], *s);
                    }
                }
                Transform::Permute(p) if ubb["delta"].as_array().unwrap().len() > 1 => {
                    ubb["delta"] = json!(permute_vec(&vector(&ubb["delta"]), p));
                }
                _ => {}
            }
            sc
        },
        features: |r, truth| {
            let u = &r["ubb"];
            let mut out = Vec::new();
            for st in u["track"].as_array().unwrap() {
                let k = st["k"].as_u64().unwrap() as usize;
                let (lo, hi) = (vector(&st["lo"]), vector(&st["hi"]));
                let radius = st["radius"].as_f64().unwrap();
                let x = &truth[k + 1];
                out.push(point(format!("k{k}.lo"), k + 1, lo.clone(), radius));
                out.push(point(format!("k{k}.hi"), k + 1, hi.clone(), radius));
                out.push(point(
                    format!("k{k}.center"),
                    k + 1,
                    vector(&st["center"]),
                    radius,
                ));
                out.push(feature(
                    format!("k{k}.radius"),
                    Kind::Scalar(1),
                    vec![radius],
                ));
                out.push(flag(
                    format!("k{k}.truth_inside"),
                    (0..x.len()).all(|i| lo[i] <= x[i] && x[i] <= hi[i]),
                ));
            }
            let at = &u["at"];
            let k = at["k"].as_u64().unwrap() as usize;
            let vertices: Vec<Vec<f64>> =
                serde_json::from_value(at["polygon"]["vertices"].clone()).unwrap();
            polygon_features("at.polygon", k + 1, &vertices, &mut out);
            out
        },
        tolerance: 1e-9,
        shift_tolerance: 1e-9,
        shifts: true,
    }
}

// --- Pavelková's uniform LP ---------------------------------------------------------------------

/// uniform_lp: the paper's system with H = [1 0] (observable, so the consistent states are
/// bounded by the data and not by the ±x_bound box, which is centred at 0 and would break a
/// shift), Θ known (`"states"`: a joint estimate of Θ is not shift-equivariant, since a wrong
/// A' sees (A − A') d_t), inputs in `data.u`. Time index t is x_{t+1}: data row t is y_{t+1}.
///
/// Tolerance 1e-9, as for ubb (LP optima).
fn uniform_case() -> Case {
    let mut sc = serde_json::to_value(presets::get("uniform-paper").unwrap()).unwrap();
    let f = matrix(&sc["model"]["F"]);
    let b = matrix(&sc["model"]["B"]);
    let h = DMatrix::from_row_slice(1, 2, &[1.0, 0.0]);
    let steps = 12;
    // Inputs, then states and outputs with uniform innovations of half-width 0.3 (the paper's).
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let u: Vec<Vec<f64>> = (0..steps)
        .map(|_| vec![rng.random::<f64>() - 0.5])
        .collect();
    let mut x = nalgebra::DVector::from_column_slice(&[0.2, -0.1]);
    let (mut truth, mut y) = (Vec::new(), Vec::new());
    for ut in &u {
        let e = (rng.random::<f64>() * 2.0 - 1.0) * 0.3;
        y.push(vec![(&h * &x)[0] + e]);
        truth.push(x.as_slice().to_vec());
        let w = nalgebra::DVector::from_fn(2, |_, _| (rng.random::<f64>() * 2.0 - 1.0) * 0.3);
        x = &f * &x + &b * ut[0] + w;
    }
    truth.push(x.as_slice().to_vec());
    sc.as_object_mut().unwrap().remove("simulate");
    sc["model"]["H"] = rows(&h);
    sc["data"] = json!({ "y": y, "u": u });
    let sc = patched(
        &sc,
        &json!({"uniform": {
            "estimator": "states",
            "prior_overrides": [],
            "x_bound": 1000.0,
            "directions": 32
        }}),
    );
    Case {
        name: "uniform_lp",
        scenario: sc,
        truth,
        f,
        times: steps + 1,
        patch: |sc, tr| {
            let mut sc = moved(sc, tr);
            let uni = &mut sc["uniform"];
            match tr {
                Transform::Scale(s) => {
                    for key in ["xr_max", "yr_max", "x_bound", "xr", "yr", "u_half"] {
                        if let Some(v) = uni.get_mut(key) {
                            scale_json(v, *s);
                        }
                    }
                }
                Transform::Permute(p) => {
                    for key in ["xr_max", "xr"] {
                        if uni.get(key).is_some_and(|v| !v.is_null()) {
                            uni[key] = json!(permute_vec(&vector(&uni[key]), p));
                        }
                    }
                }
                // The ±x_bound box on every state entry is centred at 0, not at the data: it is
                // a prior that does not move with a shift, so it is widened to stay inactive.
                Transform::Shift(d) => {
                    let far = d.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
                    uni["x_bound"] = json!(1000.0 + 10.0 * far);
                }
            }
            sc
        },
        features: |r, _truth| {
            let at = &r["uniform"]["at"];
            let time = at["time"].as_u64().unwrap() as usize;
            let mut out = Vec::new();
            let lo: Vec<Vec<f64>> = serde_json::from_value(at["face_lo"].clone()).unwrap();
            let hi: Vec<Vec<f64>> = serde_json::from_value(at["face_hi"].clone()).unwrap();
            let polygon: Vec<Vec<f64>> =
                serde_json::from_value(at["polygon"]["vertices"].clone()).unwrap();
            let mut pf = Vec::new();
            polygon_features("at.polygon", time - 1, &polygon, &mut pf);
            let size = pf[0].size;
            // face_lo[j] is x_{time − j} (time index time − 1 − j).
            for (j, (l, h)) in lo.iter().zip(&hi).enumerate() {
                out.push(point(
                    format!("face_lo[{j}]"),
                    time - 1 - j,
                    l.clone(),
                    size,
                ));
                out.push(point(
                    format!("face_hi[{j}]"),
                    time - 1 - j,
                    h.clone(),
                    size,
                ));
            }
            out.push(feature(
                "at.objective",
                Kind::Scalar(1),
                vec![at["objective"].as_f64().unwrap()],
            ));
            out.extend(pf);
            out
        },
        tolerance: 1e-9,
        shift_tolerance: 1e-9,
        shifts: true,
    }
}

// --- compare ------------------------------------------------------------------------------------

/// compare: the compare-uniform cascade (G form with σ_v², σ_w²) on our data, every method's
/// set for x_{t+1}, each read as its bounding box (ellipse: centre ± √(r² cov_ii); polygon and
/// region: their points), its area, and (ellipses) centre and covariance. The prior mean
/// (`model.x1_mean`) moves with a shift. Time index t is x_{t+1}; the target x_{T+1} is index T.
///
/// Tolerance 1e-9: the sets are their methods' own (the LP ones as for ubb; LSCR's region is
/// exact line arithmetic).
fn compare_case(name: &'static str, methods: &[&str], shifts: bool) -> Case {
    let mut sc = serde_json::to_value(presets::get("compare-uniform").unwrap()).unwrap();
    let f = matrix(&sc["model"]["F"]);
    let h = matrix(&sc["model"]["H"]);
    let g = matrix(&sc["model"]["G"]);
    let steps = 16;
    let bound = 0.1224744871391589; // the preset's b = 3σ/√3 … as the report prints it
    let (truth, y) = simulate(&f, &g, &h, &[0.05, -0.02], bound, bound, steps + 1, 11);
    let obj = sc.as_object_mut().unwrap();
    obj.remove("simulate");
    sc["data"] = json!({ "y": y[..steps] });
    if shifts {
        sc["model"]["x1_mean"] = json!([0.0, 0.0]);
    }
    sc["compare"].as_object_mut().unwrap().remove("study");
    sc["compare"]["window"] = json!(8);
    sc["compare"]["methods"] = json!(methods);
    Case {
        name,
        scenario: sc,
        truth,
        f,
        times: steps + 1,
        patch: |sc, tr| moved(sc, tr),
        features: |r, truth| {
            let at = &r["compare"]["at"];
            let t = at["target_time"].as_u64().unwrap() as usize - 1;
            let x = &truth[t];
            let mut out = Vec::new();
            for set in at["sets"].as_array().unwrap() {
                let m = set["method"].as_str().unwrap();
                let shape = &set["set"];
                if !shape.is_object() {
                    // The row's reason, e.g. "ubb.eps could not be solved: … badly scaled".
                    let reason = set["reason"].as_str().unwrap_or("no reason given");
                    out.push(Feature {
                        label: format!("{m}.refused: {reason}"),
                        kind: Kind::Refusal,
                        value: vec![],
                        size: 0.0,
                    });
                    continue;
                }
                let points: Vec<Vec<f64>> = match shape["kind"].as_str().unwrap() {
                    "ellipse" => {
                        ellipsoid_features(m, t, shape, &mut out);
                        let c = vector(&shape["center"]);
                        let cov = matrix(&shape["cov"]);
                        let r2 = shape["radius2"].as_f64().unwrap();
                        let half: Vec<f64> = (0..2).map(|i| (r2 * cov[(i, i)]).sqrt()).collect();
                        vec![
                            vec![c[0] - half[0], c[1] - half[1]],
                            vec![c[0] + half[0], c[1] + half[1]],
                        ]
                    }
                    "polygon" => serde_json::from_value(shape["vertices"].clone()).unwrap(),
                    "region" => shape["loops"]
                        .as_array()
                        .unwrap()
                        .iter()
                        .flat_map(|l| {
                            serde_json::from_value::<Vec<Vec<f64>>>(l["points"].clone()).unwrap()
                        })
                        .collect(),
                    other => panic!("{m}: unknown set kind {other}"),
                };
                if points.is_empty() {
                    continue;
                }
                let (lo, hi) = bounding_box(&points);
                let size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
                out.push(flag(
                    format!("{m}.truth_in_box"),
                    (0..2).all(|i| lo[i] <= x[i] && x[i] <= hi[i]),
                ));
                out.push(point(format!("{m}.box_lo"), t, lo, size));
                out.push(point(format!("{m}.box_hi"), t, hi, size));
                if let Some(a) = set["area"].as_f64() {
                    out.push(feature(format!("{m}.area"), Kind::Scalar(2), vec![a]));
                }
            }
            out
        },
        tolerance: 1e-9,
        shift_tolerance: if methods.iter().any(|m| ["ubb", "uniform_lp"].contains(m)) {
            1e-9
        } else {
            0.0
        },
        shifts,
    }
}

// ---------------------------------------------------------------------------------------------
// The check.

/// What one transformed run gave: the worst relative error (and where), or a refusal.
#[derive(Debug)]
enum Verdict {
    Agrees { worst: f64, at: String },
    Refused(String, String),
}

fn base_report(case: &Case) -> Value {
    match run(&case.scenario) {
        Outcome::Report(r) => r,
        Outcome::Refused(f, m) => panic!("{}: the base scenario is refused: {f}: {m}", case.name),
    }
}

fn check(case: &Case, base: &Value, tr: &Transform) -> Verdict {
    let want: Vec<Feature> = (case.features)(base, &case.truth)
        .iter()
        .map(|f| expected(f, tr))
        .collect();
    let moved = (case.patch)(&case.scenario, tr);
    let report = match run(&moved) {
        Outcome::Report(r) => r,
        Outcome::Refused(f, m) => return Verdict::Refused(f, m),
    };
    let got = (case.features)(&report, &truth_moved(&case.truth, tr));
    // A compare method that gives no set at this scale is a refusal (its reason must say why);
    // its features are not compared.
    let refused: Vec<(String, String)> = got
        .iter()
        .filter(|f| f.kind == Kind::Refusal)
        .map(|f| {
            let (method, reason) = f.label.split_once(".refused: ").unwrap();
            let field = reason.split([' ', ':']).next().unwrap_or("").to_string();
            (format!("compare row {method}: {field}"), reason.to_string())
        })
        .collect();
    let (mut worst, mut at) = (0.0, String::new());
    for w in &want {
        let method = w.label.split('.').next().unwrap();
        if refused
            .iter()
            .any(|(who, _)| who.starts_with(&format!("compare row {method}:")))
        {
            continue;
        }
        let e = match got.iter().find(|g| g.label == w.label) {
            Some(g) => relative_error(g, w),
            None => f64::INFINITY,
        };
        if !(e <= worst) {
            worst = e;
            at = match got.iter().find(|g| g.label == w.label) {
                Some(g) => format!("{}: got {:?}, expected {:?}", g.label, g.value, w.value),
                None => format!("{}: missing from the transformed report", w.label),
            };
        }
    }
    if let Some((who, reason)) = refused.into_iter().next() {
        if worst <= case.tolerance {
            return Verdict::Refused(who, reason);
        }
    }
    Verdict::Agrees { worst, at }
}

/// The scales of the fixed grid (the range) and where success is required.
const SCALES: [f64; 10] = [1e-8, 1e-6, 1e-3, 1e-1, 1.0, 1e3, 1e6, 1e9, 1e12, 1e15];
const MUST_SUCCEED: (f64, f64) = (1e-3, 1e6);

/// Shifts d_0 = magnitude · (cos a, sin a, …): magnitudes up to 1e6 (a shift far larger than
/// the set costs the set's digits in any frame that is not moved with it: ε·|d| against the
/// set's width; that boundary is the precision work's, not a metamorphic property).
const SHIFTS: [f64; 4] = [1e-3, 1.0, 1e3, 1e6];

fn shift(case: &Case, magnitude: f64, angle: f64) -> Transform {
    let n = case.f.nrows();
    let d0: Vec<f64> = (0..n)
        .map(|i| magnitude * (angle + 1.3 * i as f64).cos())
        .collect();
    Transform::Shift(free_motion(&case.f, &d0, case.times))
}

fn permutations(n: usize) -> Vec<Vec<usize>> {
    if n == 1 {
        return vec![vec![0]];
    }
    let mut out = Vec::new();
    for p in permutations(n - 1) {
        for at in 0..n {
            let mut q = p.clone();
            q.insert(at, n - 1);
            out.push(q);
        }
    }
    out
}

/// One line of the measurement table (printed; `--nocapture` shows it).
fn line(case: &Case, what: &str, verdict: &Verdict) -> String {
    match verdict {
        Verdict::Agrees { worst, at } => format!(
            "{:<10} {what:<28} worst relative error {worst:.2e} (tolerance {:.0e}){}",
            case.name,
            case.tolerance,
            if *worst > case.tolerance {
                format!("  ✗ at {at}")
            } else {
                String::new()
            }
        ),
        Verdict::Refused(f, m) => format!("{:<10} {what:<28} refused: {f}: {m}", case.name),
    }
}

/// Is this verdict acceptable for a transformation at this scale (1 for shifts and
/// permutations)?
fn acceptable(case: &Case, scale: f64, verdict: &Verdict) -> bool {
    match verdict {
        Verdict::Agrees { worst, .. } => *worst <= case.tolerance,
        Verdict::Refused(f, m) => {
            !(MUST_SUCCEED.0..=MUST_SUCCEED.1).contains(&scale) && acceptable_refusal(f, m)
        }
    }
}

/// Every transformation of the fixed grid for one case; returns the failures (and prints the
/// table).
fn grid(case: &Case, scales: &[f64]) -> Vec<String> {
    let base = base_report(case);
    let mut failures = Vec::new();
    let mut table = Vec::new();
    let mut record = |judged: &Case, what: String, scale: f64, verdict: Verdict| {
        let l = line(judged, &what, &verdict);
        if !acceptable(judged, scale, &verdict) {
            failures.push(l.clone());
        }
        table.push(l);
    };
    for &s in scales {
        let verdict = check(case, &base, &Transform::Scale(s));
        record(case, format!("scale {s:.0e}"), s, verdict);
    }
    for &m in SHIFTS.iter().filter(|_| case.shifts) {
        let moved = shifted(case, m);
        let verdict = check(&moved, &base, &shift(case, m, 0.4));
        record(&moved, format!("shift |d| {m:.0e}"), 1.0, verdict);
    }
    for p in permutations(case.f.nrows()) {
        let verdict = check(case, &base, &Transform::Permute(p.clone()));
        record(case, format!("permute {p:?}"), 1.0, verdict);
    }
    eprintln!("{}", table.join("\n"));
    failures
}

/// The case as judged under a shift of magnitude `m` (see [`Case::shift_tolerance`]).
fn shifted(case: &Case, m: f64) -> Case {
    Case {
        tolerance: case.tolerance + case.shift_tolerance * m,
        ..case.clone()
    }
}

/// proptest's draws: a scale 10^u (u uniform in −8 … 15), a shift (magnitude 10^u, u in
/// −3 … 6, any direction) or a permutation, 16 cases from a fixed seed, no failure file.
fn property(case: &Case) {
    let base = base_report(case);
    let n = case.f.nrows();
    let perms = permutations(n);
    let config = Config {
        cases: 16,
        failure_persistence: None,
        rng_algorithm: RngAlgorithm::ChaCha,
        ..Config::default()
    };
    let mut runner =
        TestRunner::new_with_rng(config, TestRng::from_seed(RngAlgorithm::ChaCha, &[25; 32]));
    let strategy = (
        0usize..3,
        -8.0f64..15.0,
        -3.0f64..6.0,
        0.0f64..6.3,
        0..perms.len(),
    );
    let outcome = runner.run(&strategy, |(which, log_scale, log_shift, angle, p)| {
        let which = if which == 1 && !case.shifts { 0 } else { which };
        let (what, scale, tr) = match which {
            0 => {
                let s = 10f64.powf(log_scale);
                (format!("scale {s:.3e}"), s, Transform::Scale(s))
            }
            1 => (
                format!("shift |d| {:.3e} at {angle:.2}", 10f64.powf(log_shift)),
                1.0,
                shift(case, 10f64.powf(log_shift), angle),
            ),
            _ => (
                format!("permute {:?}", perms[p]),
                1.0,
                Transform::Permute(perms[p].clone()),
            ),
        };
        let judged = if which == 1 {
            shifted(case, 10f64.powf(log_shift))
        } else {
            case.clone()
        };
        let verdict = check(&judged, &base, &tr);
        prop_assert!(
            acceptable(&judged, scale, &verdict),
            "{}",
            line(&judged, &what, &verdict)
        );
        Ok(())
    });
    if let Err(e) = outcome {
        panic!("{}: {e}", case.name);
    }
}

#[track_caller]
fn assert_none(failures: Vec<String>) {
    assert!(
        failures.is_empty(),
        "metamorphic failures:\n{}",
        failures.join("\n")
    );
}

/// The case's report agrees with its transformed scenario's: on the fixed grid of scales, shifts
/// and permutations, then on proptest's draws.
fn follows_every_transformation(case: &Case) {
    assert_none(grid(case, &SCALES));
    property(case);
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn scf_and_kf_follow_translation_scaling_permutation() {
    for case in [scf_case("scf"), scf_case("kf")] {
        follows_every_transformation(&case);
    }
}
in_browser!(scf_and_kf_follow_translation_scaling_permutation);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn glls_follows_translation_scaling_permutation() {
    follows_every_transformation(&glls_case());
}
in_browser!(glls_follows_translation_scaling_permutation);

// The LP methods (measured on 73c1dd3, before the LPs were solved in their own unit, worst
// relative error of any hull bound, face range, polygon area or centroid): ubb 4.5e-1 at scale
// 1e-6, uniform_lp 8.0e-1, compare's LP sets 1.5e-1, and a set 1e-8 wide collapsed to a point
// (the polygon's tolerance had an absolute floor of 1e-9); `ubb.tau` ≥ 1e7 was refused as a
// count. Now every scale 1e-8 … 1e15 agrees within 1e-9; shifts within 1e-9·|d| (see
// `Case::shift_tolerance`).

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn uniform_lp_follows_translation_scaling_permutation() {
    follows_every_transformation(&uniform_case());
}
in_browser!(uniform_lp_follows_translation_scaling_permutation);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn ubb_follows_translation_scaling_permutation() {
    follows_every_transformation(&ubb_case());
}
in_browser!(ubb_follows_translation_scaling_permutation);

/// compare's closed-form and exact sets (Kalman, SCF, LSCR, GLLS) under scaling and
/// permutation, and (without LSCR, which takes no prior mean) under shifts.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn compare_follows_translation_scaling_permutation() {
    for case in [
        compare_case("compare", &["kf", "scf", "lscr", "glls"], false),
        compare_case("compare", &["kf", "scf", "glls"], true),
    ] {
        follows_every_transformation(&case);
    }
}
in_browser!(compare_follows_translation_scaling_permutation);

/// compare's set-membership sets (Tempo, Pavelková): as their own methods' tests above.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn compare_lp_sets_follow_translation_scaling_permutation() {
    follows_every_transformation(&compare_case("compare", &["ubb", "uniform_lp"], true));
}
in_browser!(compare_lp_sets_follow_translation_scaling_permutation);
