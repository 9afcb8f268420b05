//! Bad input: every rule gets a test asserting the error names the field and says why
//! (e.g. "model.V must be symmetric positive semidefinite …"), and no input — however
//! garbled — panics.

use confset::model::{Inputs, LinearModel, MatrixSpec, ModelSpec};
use confset::scenario::{Condition, Scenario, SimulateSpec};
use confset::scf::{self, ScfOptions};
use confset::Error;
use nalgebra::{DMatrix, DVector};
use serde_json::{json, Value};

/// A valid 2-state scenario as JSON; tests break one field at a time.
fn base() -> Value {
    json!({
        "method": "scf",
        "model": {
            "F": [[0.9, 0.1], [0.0, 0.8]],
            "H": [[1.0, 0.0]],
            "V": [[0.1, 0.0], [0.0, 0.1]],
            "W": [[0.5]]
        },
        "data": {"y": [[0.1], [0.4], [-0.2], [0.3], [0.0]]},
        "alpha": 0.9,
        "scf": {}
    })
}

fn run(v: &Value) -> Result<confset::scenario::Report, Error> {
    Scenario::from_json(&v.to_string())?.run()
}

/// The scenario must fail with `field` and a message containing every one of `words`.
#[track_caller]
fn assert_err(v: &Value, field: &str, words: &[&str]) {
    match run(v) {
        Ok(_) => panic!("accepted, expected an error on {field}: {v}"),
        Err(e) => {
            assert_eq!(e.field, field, "wrong field in \"{e}\" for {v}");
            let text = e.to_string();
            assert!(
                text.starts_with(field),
                "message does not start with the field: {text}"
            );
            for w in words {
                assert!(text.contains(w), "\"{text}\" does not say {w:?}");
            }
        }
    }
}

fn with(mut v: Value, path: &[&str], x: Value) -> Value {
    let mut cur = &mut v;
    for p in &path[..path.len() - 1] {
        cur = cur.get_mut(*p).unwrap();
    }
    cur.as_object_mut()
        .unwrap()
        .insert(path[path.len() - 1].into(), x);
    v
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn base_scenario_is_valid() {
    let r = run(&base()).unwrap();
    assert_eq!((r.n, r.q, r.steps.len()), (2, 1, 5));
}
in_browser!(base_scenario_is_valid);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn wrong_dimensions() {
    let b = base();
    assert_err(
        &with(b.clone(), &["model", "H"], json!([[1.0, 0.0, 0.0]])),
        "model.H",
        &["1×2", "1×3"],
    );
    assert_err(
        &with(b.clone(), &["model", "V"], json!([[1.0]])),
        "model.V",
        &["2×2", "1×1"],
    );
    assert_err(
        &with(b.clone(), &["model", "W"], json!([[1.0, 0.0], [0.0, 1.0]])),
        "model.W",
        &["1×1"],
    );
    assert_err(
        &with(b.clone(), &["model", "F"], json!([[0.9, 0.1]])),
        "model.F",
        &["square"],
    );
    assert_err(
        &with(b.clone(), &["model", "F"], json!([[0.9, 0.1], [0.2]])),
        "model.F",
        // Counted from 1, as the page's matrix boxes and the CSV reader count rows (issue 29).
        &["rows of different lengths (row 1 has 2, row 2 has 1)"],
    );
    assert_err(
        &with(b.clone(), &["model", "F"], json!([])),
        "model.F",
        &["non-empty"],
    );
    assert_err(
        &with(b.clone(), &["model", "x1_cov"], json!([[1.0]])),
        "model.x1_cov",
        &["2×2"],
    );
    assert_err(
        &with(b.clone(), &["model", "x1_mean"], json!([1.0])),
        "model.x1_mean",
        &["2 entries"],
    );
    assert_err(
        &with(b.clone(), &["model", "B"], json!([[1.0]])),
        "model.B",
        &["2×1"],
    );
    let mut no_h = b.clone();
    no_h["model"].as_object_mut().unwrap().remove("H");
    assert_err(&no_h, "model.H", &["missing"]);
}
in_browser!(wrong_dimensions);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn covariances_must_be_symmetric_semidefinite() {
    let b = base();
    let v = |x: Value| with(b.clone(), &["model", "V"], x);
    assert_err(
        &v(json!([[1.0, 0.5], [0.0, 1.0]])),
        "model.V",
        &["symmetric", "asymmetry"],
    );
    assert_err(
        &v(json!([[1.0, 2.0], [2.0, 1.0]])),
        "model.V",
        &["positive semidefinite", "eigenvalue"],
    );
    assert_err(
        &v(json!([[-0.1, 0.0], [0.0, 0.1]])),
        "model.V",
        &["positive semidefinite"],
    );
    // A singular (rank-deficient) V is a valid covariance.
    let ok = with(
        with(b.clone(), &["model", "V"], json!([[0.1, 0.1], [0.1, 0.1]])),
        &["model", "F"],
        json!([[0.5, 0.1], [0.2, 0.6]]),
    );
    run(&ok).unwrap();
    let w = |x: Value| with(b.clone(), &["model", "W"], x);
    assert_err(&w(json!([[0.0]])), "model.W", &["positive definite"]);
    assert_err(&w(json!([[-1.0]])), "model.W", &["positive definite"]);
    let two = with(
        with(
            with(b.clone(), &["model", "H"], json!([[1.0, 0.0], [0.0, 1.0]])),
            &["data", "y"],
            json!([[0.1, 0.2], [0.3, 0.4]]),
        ),
        &["model", "W"],
        json!([[1.0, 0.2], [0.2, 1.0]]),
    );
    run(&two).unwrap();
    assert_err(
        &with(
            two.clone(),
            &["model", "W"],
            json!([[1.0, 1.0], [1.0, 1.0]]),
        ),
        "model.W",
        &["positive definite"],
    );
    assert_err(
        &with(two, &["model", "W"], json!([[1.0, 0.0], [0.3, 1.0]])),
        "model.W",
        &["symmetric"],
    );
    assert_err(
        &with(
            b.clone(),
            &["model", "x1_cov"],
            json!([[1.0, 0.0], [0.0, -1.0]]),
        ),
        "model.x1_cov",
        &["positive semidefinite"],
    );
}
in_browser!(covariances_must_be_symmetric_semidefinite);

/// JSON has no NaN: a Rust-built ModelSpec carries it; in JSON text a string or null where a
/// number belongs must give a readable parse error that points at the field.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn non_finite_entries() {
    let mut s = Scenario::from_json(&base().to_string()).unwrap();
    s.model.f = Some(MatrixSpec::Constant(vec![
        vec![f64::NAN, 0.1],
        vec![0.0, 0.8],
    ]));
    let e = s.run().unwrap_err();
    assert_eq!(e.field, "model.F");
    assert!(
        e.to_string()
            .contains("non-finite entry at row 1, column 1"),
        "{e}"
    );

    let mut s = Scenario::from_json(&base().to_string()).unwrap();
    s.model.v = Some(MatrixSpec::Constant(vec![
        vec![0.1, 0.0],
        vec![0.0, f64::INFINITY],
    ]));
    let e = s.run().unwrap_err();
    assert_eq!(e.field, "model.V");
    assert!(e.to_string().contains("non-finite"), "{e}");

    // A NaN in data.y is a gap (JSON null), which SCF takes; an infinity is refused.
    let mut s = Scenario::from_json(&base().to_string()).unwrap();
    s.data.as_mut().unwrap().y[2][0] = f64::INFINITY;
    let e = s.run().unwrap_err();
    assert_eq!(e.field, "data.y[2]");
    assert!(e.to_string().contains("non-finite"), "{e}");
    // A NaN in data.y is a gap (a missing measurement, JSON null), never a number: a method
    // either takes it or refuses it naming the row, never computes with it.
    let mut s = Scenario::from_json(&base().to_string()).unwrap();
    s.data.as_mut().unwrap().y[2][0] = f64::NAN;
    match s.run() {
        Ok(r) => assert_eq!(r.y.len(), s.data.as_ref().unwrap().y.len()),
        Err(e) => {
            assert_eq!(e.field, "data.y[2]");
            assert!(e.to_string().contains("row 3"), "{e}");
        }
    }

    let spec = ModelSpec {
        f: Some(MatrixSpec::Constant(vec![vec![0.5]])),
        h: Some(MatrixSpec::Constant(vec![vec![f64::NEG_INFINITY]])),
        v: Some(MatrixSpec::Constant(vec![vec![1.0]])),
        w: Some(MatrixSpec::Constant(vec![vec![1.0]])),
        ..Default::default()
    };
    assert_eq!(LinearModel::from_spec(&spec).unwrap_err().field, "model.H");

    // The entry itself is named, with what was found and how to write it.
    for (bad, found) in [
        (
            json!("NaN"),
            "found the text \"NaN\" (JSON has no NaN or Infinity)",
        ),
        (Value::Null, "found null (JSON has no NaN or Infinity)"),
        (
            json!("1.0"),
            "found the text \"1.0\" (write numbers without quotes)",
        ),
        (json!(true), "found the value true"),
    ] {
        let text = with(base(), &["model", "F"], json!([[0.9, 0.1], [0.0, bad]])).to_string();
        let e = Scenario::from_json(&text).unwrap_err();
        let msg = e.to_string();
        assert_eq!(
            e.field, "model.F[1][1]",
            "parse error does not name the entry: {msg}"
        );
        assert!(
            msg.contains("must be a number") && msg.contains(found),
            "{msg}"
        );
    }
    // `null` in data.y is a gap (a missing measurement), read as such; `null` in a model
    // matrix stays an error.
    let text = with(base(), &["data", "y"], json!([[0.1], [null], [0.2]])).to_string();
    let s = Scenario::from_json(&text).unwrap();
    let d = s.data.as_ref().unwrap();
    assert_eq!((d.y.len(), d.first_gap()), (3, Some((1, 0))));
    let text = with(base(), &["model", "W"], json!([[null]])).to_string();
    let e = Scenario::from_json(&text).unwrap_err();
    assert!(e.field.starts_with("model.W"), "{e}");
    let text = with(base(), &["data", "y"], json!([[0.1], ["NaN"], [0.2]])).to_string();
    let e = Scenario::from_json(&text).unwrap_err();
    assert_eq!(e.field, "data.y[1][0]", "{e}");
    // In data.y a null is a gap (a missing measurement, `records.rs`); in data.u, which has
    // none (an input is known by definition), it is refused naming the entry.
    let text = with(base(), &["data", "u"], json!([[0.1], [null], [0.2]])).to_string();
    let e = Scenario::from_json(&text).unwrap_err();
    assert_eq!(e.field, "data.u[1][0]", "{e}");
    assert!(e.to_string().contains("found null"), "{e}");
    // A list where a number belongs: the first entry decides the reading (a sequence of
    // matrices), and the entry that breaks it is named.
    let text = with(base(), &["model", "F"], json!([[[0.9], 0.1], [0.0, 0.8]])).to_string();
    let e = Scenario::from_json(&text).unwrap_err();
    assert!(
        e.field == "model.F[0][1]" && e.message.contains("must be a row: a list of numbers"),
        "{e}"
    );
    assert!(
        !e.to_string().contains("MatrixSpec"),
        "a Rust type name in {e}"
    );
    // Bare NaN is not JSON at all.
    let e = Scenario::from_json(r#"{"method": "scf", "model": {"F": [[NaN]]}}"#).unwrap_err();
    assert_eq!(e.field, "model.F[0][0]", "{e}");
    assert!(
        e.to_string().contains("no NaN") && e.to_string().contains("line 1"),
        "{e}"
    );
    // A key given twice in one object is named (a JSON value in memory would keep one).
    let e = Scenario::from_json(r#"{"method": "scf", "model": {"F": [[0.9]], "F": [[0.5]]}}"#)
        .unwrap_err();
    assert_eq!(
        (e.field.as_str(), e.message.as_str()),
        ("model.F", "is given twice"),
        "{e}"
    );
    // Unknown fields are named.
    let e = Scenario::from_json(&with(base(), &["model", "Q"], json!([[1.0]])).to_string())
        .unwrap_err();
    assert!(
        e.field == "model.Q"
            && e.message
                .starts_with("is not a key of model: the keys are \"F\""),
        "{e}"
    );
}
in_browser!(non_finite_entries);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn unstable_f_needs_a_prior() {
    let unstable = with(base(), &["model", "F"], json!([[1.1, 0.1], [0.0, 0.5]]));
    assert_err(
        &unstable,
        "model.x1_cov",
        &["is needed", "model.F", "stable"],
    );
    // With a prior the non-stationary model is fine.
    run(&with(
        unstable.clone(),
        &["model", "x1_cov"],
        json!([[1.0, 0.0], [0.0, 1.0]]),
    ))
    .unwrap();
    // ... but not the asymptotic filter, which needs stationarity.
    let asy = with(
        with(
            unstable,
            &["model", "x1_cov"],
            json!([[1.0, 0.0], [0.0, 1.0]]),
        ),
        &["scf", "asymptotic"],
        json!(true),
    );
    assert_err(&asy, "scf.asymptotic", &["stable"]);
    // A unit-circle eigenvalue is not stable either.
    assert_err(
        &with(base(), &["model", "F"], json!([[1.0, 0.0], [0.0, 0.5]])),
        "model.x1_cov",
        &["model.F"],
    );
}
in_browser!(unstable_f_needs_a_prior);

/// (F^b, H) not observable (Assumption 3): the ratio matrix stays singular; scf::run and
/// Scenario::run say so on model.H. The KF alone does not need observability.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn unobservable_pair() {
    let zero_h = with(base(), &["model", "H"], json!([[0.0, 0.0]]));
    assert_err(&zero_h, "model.H", &["observable"]);
    // x_2 never reaches the output (diagonal F, H = [1 0]).
    let hidden = with(base(), &["model", "F"], json!([[0.5, 0.0], [0.0, 0.7]]));
    assert_err(&hidden, "model.H", &["observable"]);
    run(&with(hidden.clone(), &["method"], json!("kf"))).unwrap();
    // Directly through scf::run.
    let m = LinearModel::time_invariant(
        DMatrix::from_row_slice(2, 2, &[0.5, 0.0, 0.0, 0.7]),
        DMatrix::from_row_slice(1, 2, &[1.0, 0.0]),
        DMatrix::identity(2, 2),
        DMatrix::identity(1, 1),
    )
    .unwrap();
    let y = vec![DVector::from_element(1, 0.3); 6];
    let opts = ScfOptions {
        alpha: 0.9,
        components: None,
        tau: 0,
        asymptotic: false,
        kf_only: false,
    };
    let e = scf::run(&m, &y, &Inputs::none(), &opts)
        .err()
        .expect("must fail");
    assert_eq!(e.field, "model.H");
    // The observable component alone is fine (V-A).
    let opts = ScfOptions {
        components: Some(vec![0]),
        ..opts
    };
    let e = scf::run(&m, &y, &Inputs::none(), &opts).err();
    assert!(e.is_none() || e.unwrap().field == "model.H");
    let a = scf::asymptotic(&m).unwrap_err();
    assert_eq!(a.field, "model.H");
}
in_browser!(unobservable_pair);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn alpha_outside_unit_interval() {
    for a in [0.0, 1.0, -0.5, 1.5] {
        assert_err(
            &with(base(), &["alpha"], json!(a)),
            "alpha",
            &["strictly between 0 and 1"],
        );
    }
    let mut s = Scenario::from_json(&base().to_string()).unwrap();
    s.alpha = f64::NAN;
    assert_eq!(s.run().unwrap_err().field, "alpha");
    for a in [0.0, 1.0, -0.5, 1.5, f64::NAN] {
        assert_eq!(
            confset::stats::chi2_quantile(a, 2).unwrap_err().field,
            "alpha"
        );
    }
}
in_browser!(alpha_outside_unit_interval);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn data_problems() {
    let b = base();
    assert_err(
        &with(b.clone(), &["data", "y"], json!([[0.1]])),
        "data.y",
        &["at least n = 2"],
    );
    assert_err(
        &with(b.clone(), &["data", "y"], json!([])),
        "data.y",
        &["empty"],
    );
    assert_err(
        &with(b.clone(), &["data", "y"], json!([[0.1], [0.2, 0.3], [0.0]])),
        "data.y[1]",
        &["1 entry,", "found 2"],
    );
    assert_err(
        &with(b.clone(), &["data", "u"], json!([[1.0]])),
        "data.u",
        &["no B"],
    );
    let with_b = with(b.clone(), &["model", "B"], json!([[1.0], [0.0]]));
    assert_err(&with_b, "data.u", &["missing"]);
    assert_err(
        &with(with_b.clone(), &["data", "u"], json!([[1.0, 2.0]])),
        "data.u[0]",
        &["1 entry "],
    );
    run(&with(with_b, &["data", "u"], json!([[1.0]]))).unwrap();
    let mut neither = b.clone();
    neither.as_object_mut().unwrap().remove("data");
    assert_err(&neither, "data", &["missing"]);
    let both = with(b.clone(), &["simulate"], json!({"steps": 5}));
    assert_err(&both, "data", &["both"]);
    assert_err(
        &with(b.clone(), &["time"], json!(9)),
        "time",
        &["from 1 to 5"],
    );
    assert_err(
        &with(b.clone(), &["time"], json!(0)),
        "time",
        &["from 1 to 5"],
    );
    assert_err(&with(b.clone(), &["plot"], json!([0, 2])), "plot", &[]);
}
in_browser!(data_problems);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn simulate_problems() {
    let mut b = base();
    b.as_object_mut().unwrap().remove("data");
    let sim = |x: Value| with(b.clone(), &["simulate"], x);
    run(&sim(
        json!({"steps": 10, "seed": 3, "condition": {"t": 10, "x": [1.0, -1.0]}}),
    ))
    .unwrap();
    run(&sim(
        json!({"steps": 10, "seed": 3, "condition": {"t": 1, "x": [1.0, -1.0]}}),
    ))
    .unwrap();
    for t in [0, 11, 1000] {
        assert_err(
            &sim(json!({"steps": 10, "condition": {"t": t, "x": [1.0, -1.0]}})),
            "simulate.condition.t",
            &["from 1 to 10"],
        );
    }
    assert_err(
        &sim(json!({"steps": 10, "condition": {"t": 3, "x": [1.0]}})),
        "simulate.condition.x",
        &["2 entries"],
    );
    assert_err(&sim(json!({"steps": 0})), "simulate.steps", &[]);
    assert_err(
        &sim(json!({"steps": 1})),
        "simulate.steps",
        &["at least n = 2"],
    );
    assert_err(&sim(json!({"steps": 100_000_000})), "simulate.steps", &[]);
    // A Rust-built condition with a NaN state.
    let mut s = Scenario::from_json(&sim(json!({"steps": 10})).to_string()).unwrap();
    s.simulate = Some(SimulateSpec {
        steps: 10,
        seed: 0,
        u: vec![],
        x0: None,
        true_noise: None,
        condition: Some(Condition {
            t: 4,
            x: vec![f64::NAN, 0.0],
        }),
    });
    assert_eq!(s.run().unwrap_err().field, "simulate.condition.x");
}
in_browser!(simulate_problems);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn components_and_method() {
    let b = base();
    assert_err(
        &with(b.clone(), &["scf", "components"], json!([0, 2])),
        "scf.components",
        &["2", "0-based"],
    );
    assert_err(
        &with(b.clone(), &["scf", "components"], json!([1, 1])),
        "scf.components",
        &["twice"],
    );
    assert_err(
        &with(b.clone(), &["scf", "components"], json!([])),
        "scf.components",
        &["at least one"],
    );
    run(&with(b.clone(), &["scf", "components"], json!([1, 0]))).unwrap();
    assert_err(
        &with(b.clone(), &["method"], json!("ekf")),
        "method",
        &["\"ekf\""],
    );
    assert_err(&with(b.clone(), &["method"], json!("")), "method", &[]);
    // Directly through scf::run.
    let s = Scenario::from_json(&b.to_string()).unwrap();
    let p = s.prepare_scf().unwrap();
    for comps in [vec![5], vec![0, 0]] {
        let opts = ScfOptions {
            components: Some(comps),
            ..p.options.clone()
        };
        let e = scf::run(&p.model, &p.y, &p.inputs, &opts)
            .err()
            .expect("must fail");
        assert_eq!(e.field, "components");
    }
}
in_browser!(components_and_method);

// ---------------------------------------------------------------------------------------------
// One regression test per class of hostile input (the crate docs' three defences): each must
// be an error naming the field, before any heavy work.

/// A preset's scenario as JSON, by name.
fn preset_json(name: &str) -> Value {
    serde_json::to_value(&confset::presets::get(name).expect("preset")).expect("JSON")
}

#[test]
fn an_absurd_size_is_refused_while_parsing() {
    // 2⁶⁴ − 1 as a horizon looped for minutes before; 10⁹ as a conditioning time asked for 32 GB.
    let mut g = preset_json("glls-unstable5");
    g["glls"]["monte_carlo"]["max_horizon"] = json!(u64::MAX);
    assert_err(&g, "glls.monte_carlo.max_horizon", &["10000000"]);
    let mut l = preset_json("lscr-predict");
    l["simulate"]["condition"] = json!({"t": 1_000_000_000u64, "x": [0.0, 0.0]});
    assert_err(&l, "simulate.condition.t", &["10000000"]);
    // Within the count limit but past the simulated run: the method's own check.
    l["simulate"]["condition"]["t"] = json!(5000);
    assert_err(
        &l,
        "simulate.condition.t",
        &["must be a whole number from 1 to"],
    );
}

#[test]
fn numbers_beyond_the_magnitude_range_are_refused_by_path() {
    // 1e154 in H made the LSCR regressors overflow into an SVD that panicked on NaN.
    let mut l = preset_json("lscr-ma1");
    l["model"]["H"][0][0] = json!(1e154);
    assert_err(&l, "model.H[0][0]", &["1e100"]);
    let mut g = preset_json("glls-mixed");
    g["model"]["F"][1][1] = json!(1e-300);
    assert_err(&g, "model.F[1][1]", &["1e-100"]);
}

#[test]
fn an_oversized_model_is_refused_before_any_work() {
    let mut u = preset_json("uniform-paper");
    let big: Vec<Vec<f64>> = (0..20)
        .map(|i| (0..20).map(|j| if i == j { 0.5 } else { 0.0 }).collect())
        .collect();
    u["model"]["F"] = json!(big);
    assert_err(&u, "model.F", &["at most 8 states"]);
    let huge: Vec<Vec<f64>> = (0..101)
        .map(|i| (0..101).map(|j| if i == j { 0.5 } else { 0.0 }).collect())
        .collect();
    let mut s = preset_json("scf-scalar");
    s["model"]["F"] = json!(huge);
    assert_err(&s, "model.F", &["at most 100 rows"]);
}

#[test]
fn a_decomposition_of_non_finite_numbers_is_an_error() {
    use nalgebra::DMatrix;
    let m = DMatrix::from_row_slice(2, 2, &[1.0, f64::INFINITY, 0.0, 1.0]);
    assert!(confset::linalg::try_svd(m.clone(), false, false).is_none());
    assert!(confset::linalg::try_symmetric_eigen(m).is_none());
    let ok = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 2.0]);
    let e = confset::linalg::try_symmetric_eigen(ok).expect("a finite symmetric matrix");
    let mut ev: Vec<f64> = e.eigenvalues.iter().copied().collect();
    ev.sort_by(f64::total_cmp);
    assert!(
        (ev[0] - 1.0).abs() < 1e-12 && (ev[1] - 3.0).abs() < 1e-12,
        "{ev:?}"
    );
}

#[test]
fn powers_that_overflow_are_named_not_written_as_null() {
    // An unstable F within the magnitude range: its powers overflow over a long simulation.
    let mut g = preset_json("glls-grow");
    g["simulate"]["steps"] = json!(5000);
    // Without its Monte Carlo (2000 runs of 5000 steps is past the work budget).
    g["glls"]
        .as_object_mut()
        .expect("a glls block")
        .remove("monte_carlo");
    match run(&g) {
        Ok(r) => panic!(
            "accepted an overflowing run: {}",
            serde_json::to_string(&r).unwrap_or_default().len()
        ),
        Err(e) => assert!(
            e.field.starts_with("simulate.steps") || e.field.starts_with("report."),
            "{e}"
        ),
    }
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn fields_at_their_limits_together_are_refused_by_the_work_budget() {
    // Each size field at its own limit is accepted alone (or nearly); all of a preset's at once
    // (100 states × 10,000 steps, 100,000 LSCR strings × 800 measurements, an 80-step window
    // of 8 states over 2000 steps, …) would take minutes. The estimate refuses them before any
    // work: the run's error is the estimate's, and it names one of those fields, the limit and
    // what to change.
    use crate::common::limits::{at, first_presets, knobs, Knob};
    use confset::scenario::budget::{MAX_BYTES, MAX_OPERATIONS};
    use confset::scenario::Job;
    let (ops, bytes) = (
        format!("{MAX_OPERATIONS:.1e} operations"),
        format!("{:.0} MB", MAX_BYTES / 1e6),
    );
    for (method, base) in first_presets() {
        // A compare at its limits is not refused as a whole: each member past its own budget
        // gives no set and says why (its `reason`), and the compare runs the others.
        if method == confset::Method::Compare {
            continue;
        }
        let ks = knobs(&base);
        assert!(
            ks.len() >= 2,
            "{method}: fewer than two size fields to combine"
        );
        let s = at(&base, &ks.iter().collect::<Vec<_>>(), 1.0);
        let sc = Scenario::from_json(&s.to_string())
            .unwrap_or_else(|e| panic!("{method}: every field is within its own limit: {e}"));
        let estimate = sc
            .work(Job::Report)
            .check(Job::Report)
            .err()
            .unwrap_or_else(|| {
                panic!("{method}: the fields at their limits together exceed the budget")
            });
        let e = sc.run().expect_err("refused");
        assert_eq!(
            e, estimate,
            "{method}: refused by the estimate, before any work"
        );
        let fields: Vec<String> = ks
            .iter()
            .map(|k| match k {
                Knob::States { .. } => "model.F".to_string(),
                Knob::Count { .. } => k.name(),
            })
            .collect();
        assert!(
            fields.contains(&e.field),
            "{method}: {e} names none of {fields:?}"
        );
        let text = e.to_string();
        assert!(
            text.contains(&format!("is limited to about {ops}"))
                || text.contains(&format!("is limited to about {bytes}")),
            "{method}: the limit is not named: {text}"
        );
        assert!(text.contains("asks for about"), "{method}: {text}");
        let advice = text.rsplit("): ").next().unwrap_or("");
        assert!(
            advice.starts_with("fewer") || advice.starts_with("a "),
            "{method}: no advice: {text}"
        );
    }
}
in_browser!(fields_at_their_limits_together_are_refused_by_the_work_budget);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_monte_carlo_in_a_report_points_to_the_chunked_study() {
    // 10⁶ GLLS runs of 5000 steps inside one report: the study runs them in chunks.
    let mut g = preset_json("glls-saturate");
    g["simulate"]["steps"] = json!(5000);
    g["glls"]["monte_carlo"]["runs"] = json!(1_000_000);
    assert_err(
        &g,
        "glls.monte_carlo.runs",
        &[
            "operations",
            "fewer runs",
            "chunked study",
            "confset experiment",
        ],
    );
}
in_browser!(a_monte_carlo_in_a_report_points_to_the_chunked_study);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_study_whose_preparation_is_too_big_is_refused_before_it_is_prepared() {
    // Section 5.2's comparison over the horizons 0..4000 prepares one state-noise estimator
    // per horizon, each O(s³): refused by the estimate of the study's preparation and one run.
    let mut g = preset_json("glls-unstable5");
    g["simulate"]["steps"] = json!(5000);
    g["glls"]["monte_carlo"]["max_horizon"] = json!(4000);
    let s = Scenario::from_json(&g.to_string()).expect("valid");
    let e = s.study(None).err().expect("refused");
    assert_eq!(e.field, "glls.monte_carlo.max_horizon", "{e}");
    assert!(
        e.message
            .contains("a study's preparation and one run is limited to about"),
        "{e}"
    );
}
in_browser!(a_study_whose_preparation_is_too_big_is_refused_before_it_is_prepared);
