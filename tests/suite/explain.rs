//! The step-through card's numbers ([`Scenario::explain`]) against the report's, at three
//! steps per method: SCF/KF's x̂ and P equal the report's KF region at t, SCF's centre and Π
//! its SCF region, the gain K recomputed here from P⁻, H and W (K = P⁻Hᵀ(HP⁻Hᵀ + W)⁻¹,
//! SCF (35b)); LSCR's verdict at a point equals whether the report's region holds the point
//! (points inside and clearly outside). Refusals name their field.

use confset::model::LinearModel;
use confset::presets;
use confset::scenario::{Scenario, StepExplanation, StepValue};
use nalgebra::DMatrix;

fn row<'a>(e: &'a StepExplanation, name: &str) -> &'a StepValue {
    &e.rows
        .iter()
        .find(|r| r.name == name)
        .unwrap_or_else(|| panic!("no row {name:?} in {e:?}"))
        .value
}

fn vector(v: &StepValue) -> Vec<f64> {
    match v {
        StepValue::Vector(v) => v.clone(),
        StepValue::Scalar(x) => vec![*x],
        other => panic!("not a vector: {other:?}"),
    }
}

fn matrix(v: &StepValue) -> DMatrix<f64> {
    match v {
        StepValue::Matrix(m) => DMatrix::from_fn(m.len(), m[0].len(), |i, j| m[i][j]),
        other => panic!("not a matrix: {other:?}"),
    }
}

fn close(a: &[f64], b: &[f64], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: lengths");
    for (x, y) in a.iter().zip(b) {
        assert!(
            (x - y).abs() <= 1e-9 * (1.0 + y.abs()),
            "{what}: {a:?} vs {b:?}"
        );
    }
}

fn rows_of(m: &[Vec<f64>]) -> Vec<f64> {
    m.iter().flatten().copied().collect()
}

fn check_scf(name: &str, method: &str) {
    let mut s: Scenario = presets::get(name).unwrap();
    s.method = confset::method::Method::from_name(method).unwrap();
    let report = s.run().unwrap();
    let model = LinearModel::from_spec(&s.model).unwrap();
    let last = report.steps.len();
    let n = model.n();
    for t in [1, n.max(2), last] {
        let e = s.explain(&report, Some(t), None).unwrap();
        assert_eq!(e.t, t);
        let st = &report.steps[t - 1];
        close(&vector(row(&e, "estimate")), &st.kf.center, "x̂ = KF centre");
        close(
            matrix(row(&e, "covariance")).as_slice(),
            DMatrix::from_row_slice(n, n, &rows_of(&st.kf.cov)).as_slice(),
            "P = KF covariance",
        );
        // K from P⁻, H, W, independently of the crate's gain (35b).
        let p_pred = matrix(row(&e, "predicted covariance"));
        let (h, w) = (model.h(t), model.w(t));
        let s_t = h * &p_pred * h.transpose() + w;
        let k = &p_pred * h.transpose() * s_t.clone().try_inverse().unwrap();
        close(matrix(row(&e, "gain")).as_slice(), k.as_slice(), "K");
        close(
            matrix(row(&e, "innovation covariance")).as_slice(),
            s_t.as_slice(),
            "S",
        );
        // x̂ = x̂⁻ + K e (35a), from the card's own rows.
        let xp = nalgebra::DVector::from_vec(vector(row(&e, "prediction")));
        let ev = nalgebra::DVector::from_vec(vector(row(&e, "innovation")));
        close((xp + &k * ev).as_slice(), &st.kf.center, "x̂⁻ + K e");
        if method == "scf" {
            close(
                matrix(row(&e, "ratio matrix")).as_slice(),
                DMatrix::from_row_slice(n, n, &rows_of(&st.ratio)).as_slice(),
                "U_tA_t",
            );
            match &st.scf {
                Some(scf) => {
                    close(&vector(row(&e, "SCF centre")), &scf.center, "SCF centre");
                    close(
                        matrix(row(&e, "SCF covariance")).as_slice(),
                        DMatrix::from_row_slice(n, n, &rows_of(&scf.cov)).as_slice(),
                        "Π",
                    );
                }
                None => assert!(matches!(row(&e, "SCF centre"), StepValue::Text(_))),
            }
        } else {
            assert!(
                e.rows.iter().all(|r| r.name != "ratio matrix"),
                "KF has no ratio row"
            );
        }
        assert!(e.rows.iter().all(|r| !r.tex.is_empty()));
    }
    // Refusals name the step's field.
    for t in [0, last + 1] {
        let err = s.explain(&report, Some(t), None).unwrap_err();
        assert_eq!(err.field, "explain.t", "{err:?}");
    }
}

#[test]
fn scf_scalar_step_equals_the_report() {
    check_scf("scf-scalar", "scf");
}

#[test]
fn kf_scalar_step_equals_the_report() {
    check_scf("scf-scalar", "kf");
}

#[test]
fn scf_robots_step_equals_the_report() {
    check_scf("scf-robots", "scf");
}

fn verdict(e: &StepExplanation) -> bool {
    match row(e, "verdict") {
        StepValue::Text(t) => t == "in the region",
        other => panic!("verdict {other:?}"),
    }
}

#[test]
fn lscr_verdict_at_a_point_is_the_regions() {
    for name in ["lscr-predict", "lscr-smooth"] {
        let s = presets::get(name).unwrap();
        let report = s.run().unwrap();
        let l = report.lscr.as_ref().unwrap();
        let blue = l.blue.as_ref().unwrap().center.clone();
        // The default point is the BLUE centre.
        let e = s.explain(&report, None, None).unwrap();
        assert_eq!(e.point.as_deref(), Some(&blue[..]));
        assert_eq!(verdict(&e), l.region.contains(&blue));
        let mut inside = 0;
        let mut points: Vec<Vec<f64>> = vec![blue.clone(), vec![1e4, -1e4], vec![-50.0, 50.0]];
        if let Some(x) = &l.x_true {
            points.push(x.clone());
        }
        for p in &points {
            let e = s.explain(&report, Some(l.t), Some(p)).unwrap();
            let holds = l.region.contains(p);
            assert_eq!(verdict(&e), holds, "{name} at {p:?}");
            inside += holds as usize;
            // Each group's verdict is its count rule on the card's own sums.
            for (i, _) in l.region.groups.iter().enumerate() {
                let sums = vector(row(&e, &format!("sums of group l = {}", i + 1)));
                assert_eq!(sums, l.region.values(i, p));
                let rank = vector(row(&e, &format!("rank of the reference, l = {}", i + 1)))[0];
                assert_eq!(rank as usize, sums.iter().filter(|v| **v < 0.0).count() + 1);
            }
        }
        // Clearly outside: far away; the BLUE centre of these presets lies inside.
        assert!(!l.region.contains(&[1e4, -1e4]));
        assert!(inside >= 1, "{name}: no point inside");
        // Refusals in words, naming the field.
        assert_eq!(
            s.explain(&report, Some(l.t + 1), None).unwrap_err().field,
            "explain.t"
        );
        assert_eq!(
            s.explain(&report, None, Some(&[f64::NAN, 0.0]))
                .unwrap_err()
                .field,
            "explain.x"
        );
    }
}

#[test]
fn a_method_without_a_step_through_refuses_in_words() {
    let s = presets::get("glls-saturate").unwrap();
    let report = s.run().unwrap();
    let err = s.explain(&report, None, None).unwrap_err();
    assert_eq!(err.field, "explain");
    assert!(err.message.contains("no step-through"), "{err:?}");
}

/// Set membership: at three steps k of ubb-track, the card's hull, central estimate and local
/// error equal the report's track at k; Theorem 2's estimate and error of each plotted
/// component equal the time cursor's detail at k (the figure's), its error is never below the
/// hull's half-width (the central estimate is optimal), and the verdict is the track's.
#[test]
fn ubb_step_equals_the_report_and_the_cursor() {
    let s = presets::get("ubb-track").unwrap();
    let report = s.run().unwrap();
    let u = report.ubb.as_ref().unwrap();
    let first = u.track[0].k;
    let mut cursor = s.cursor().unwrap().expect("ubb has a time cursor");
    for k in [first, 20, u.at.k] {
        let e = s.explain(&report, Some(k), None).unwrap();
        assert_eq!(e.t, k);
        let st = u.track.iter().find(|t| t.k == k).expect("a track step");
        let hull = matrix(row(&e, "interval hull"));
        close(
            hull.row(0).transpose().as_slice(),
            &st.lo,
            &format!("k = {k}: lower ends"),
        );
        close(
            hull.row(1).transpose().as_slice(),
            &st.hi,
            &format!("k = {k}: upper ends"),
        );
        close(
            &vector(row(&e, "central estimate")),
            &st.center,
            &format!("k = {k}: centre"),
        );
        close(
            &vector(row(&e, "local error")),
            &[st.radius],
            &format!("k = {k}: radius"),
        );
        let detail = cursor.at(k).unwrap();
        let linear = detail["linear"].as_array().expect("Theorem 2 at k");
        assert!(!linear.is_empty());
        for l in linear {
            let c = l["component"].as_u64().unwrap() as usize;
            let name = format!("x{}({})", ["₁", "₂", "₃"][c], k + 1);
            let est = vector(row(&e, &format!("Theorem 2 estimate of {name}")));
            let err = vector(row(&e, &format!("its error E for {name}")));
            close(
                &est,
                &[l["estimate"].as_f64().unwrap()],
                &format!("k = {k}: φ of {name}"),
            );
            close(
                &err,
                &[l["error"].as_f64().unwrap()],
                &format!("k = {k}: E of {name}"),
            );
            let half = 0.5 * (st.hi[c] - st.lo[c]);
            assert!(
                err[0] >= half * (1.0 - 1e-9),
                "k = {k}: E {} below the half-width {half}",
                err[0]
            );
            assert!(
                matches!(row(&e, &format!("active constraints for {name}")), StepValue::Text(t) if t.contains("gain"))
            );
        }
        let verdict = matches!(row(&e, "verdict"), StepValue::Text(t) if t == "in the hull");
        assert_eq!(
            Some(verdict),
            st.inside,
            "k = {k}: the verdict is the track's"
        );
    }
    // A step outside the report's is refused, naming the field.
    assert_eq!(
        s.explain(&report, Some(10_000), None).unwrap_err().field,
        "explain.t"
    );
}
