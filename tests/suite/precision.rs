//! Correct or refused (issue 25): LSCR's precision boundary and its metamorphic properties, and
//! the set-membership hull's scale, natively and in the browser.
//!
//! * The coverage study at x̄ = (10¹⁵, 0), which counted rounding as "36.8 % ✗", is refused
//!   before any run, naming `simulate.condition.x`; below the derived limit it runs and its
//!   counts are those of x̄ = (0, 0) run for run (the method is translation-equivariant).
//! * With explicit data (the smoothing preset's record, x₁₅ from y₁ … y₃₀):
//!   - translation by a free trajectory d_t = F^{t−1} d₁ of the model (y′ = y + H d_t) moves
//!     the region by d₁₅ = F¹⁴ d₁: the same area, and probes p ↦ p + d₁₅ keep their verdicts;
//!   - scaling the data by s and the noise variances by s² scales the region by s (area s²);
//!   - swapping the two state coordinates (F′ = PFP, H′ = HP, G′ = PG) swaps the region;
//!   over scales 10⁻⁸ … 10¹⁵, and translations up to the limit, past which `data.y` is refused.
//! * The set-membership interval hull of a problem whose data and bounds are scaled by
//!   10⁻⁶ … 10⁹ is the scaled hull (the LP is solved in the unit of its right-hand sides).

use confset::presets;
use confset::scenario::Scenario;
use serde_json::{json, Value};

fn report(sc: &Value) -> Result<Value, confset::Error> {
    let r = Scenario::from_json(&sc.to_string())?.run()?;
    Ok(serde_json::to_value(r).unwrap())
}

fn preset(name: &str) -> Value {
    serde_json::to_value(presets::get(name).unwrap()).unwrap()
}

/// lscr-smooth with its simulated record as explicit data, and `probes` as LSCR probes.
fn smoothing_with_data() -> (Value, Vec<f64>) {
    let base = preset("lscr-smooth");
    let y: Vec<f64> = report(&base).unwrap()["y"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| {
            v.as_array()
                .map_or_else(|| v.as_f64(), |a| a[0].as_f64())
                .unwrap()
        })
        .collect();
    let mut sc = base.clone();
    sc.as_object_mut().unwrap().remove("simulate");
    sc["data"] = json!({ "y": y.iter().map(|v| vec![*v]).collect::<Vec<_>>() });
    (sc, y)
}

/// A 21 × 21 grid of probes over the base report's window, which holds the region.
fn probes(window: &Value) -> Vec<[f64; 2]> {
    let lo = [
        window["lo"][0].as_f64().unwrap(),
        window["lo"][1].as_f64().unwrap(),
    ];
    let hi = [
        window["hi"][0].as_f64().unwrap(),
        window["hi"][1].as_f64().unwrap(),
    ];
    let mut out = Vec::new();
    for i in 0..21 {
        for j in 0..21 {
            // Off-grid fractions, so that no probe sits on a boundary line by construction.
            let (a, b) = ((i as f64 + 0.37) / 21.3, (j as f64 + 0.61) / 21.7);
            out.push([lo[0] + a * (hi[0] - lo[0]), lo[1] + b * (hi[1] - lo[1])]);
        }
    }
    out
}

fn with_probes(sc: &Value, probes: &[[f64; 2]]) -> Value {
    let mut sc = sc.clone();
    sc["lscr"]["probes"] = json!(probes);
    sc
}

fn verdicts(r: &Value) -> Vec<bool> {
    r["lscr"]["probes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["inside"].as_bool().unwrap())
        .collect()
}

fn area(r: &Value) -> f64 {
    r["lscr"]["area"].as_f64().unwrap()
}

fn mat(v: &Value) -> Vec<Vec<f64>> {
    serde_json::from_value(v.clone()).unwrap()
}

fn mul(a: &[Vec<f64>], x: &[f64]) -> Vec<f64> {
    a.iter()
        .map(|r| r.iter().zip(x).map(|(p, q)| p * q).sum())
        .collect()
}

/// The base report and its probes' verdicts: the reference every transformed run is held to.
fn base() -> (Value, Vec<[f64; 2]>, Value) {
    let (sc, _) = smoothing_with_data();
    let first = report(&sc).unwrap();
    let p = probes(&first["lscr"]["window"]);
    let r = report(&with_probes(&sc, &p)).unwrap();
    let inside = verdicts(&r).iter().filter(|&&v| v).count();
    // The grid must straddle the boundary, or the verdicts would test nothing.
    assert!(
        inside > 20 && inside < p.len() - 20,
        "{inside} of {} probes inside",
        p.len()
    );
    (sc, p, r)
}

/// Relative tolerance on areas: the boundary's vertices are intersections of lines computed
/// from the data, each to about 10⁻¹³ relative, and the area sums a few hundred of them.
const AREA_TOL: f64 = 1e-9;

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn lscr_scaling_scales_the_region() {
    let (sc, p, r0) = base();
    let a0 = area(&r0);
    for s in [1e-8, 1e-3, 0.5, 3.0, 1e4, 1e9, 1e15] {
        let mut t = sc.clone();
        for row in t["data"]["y"].as_array_mut().unwrap() {
            row[0] = json!(row[0].as_f64().unwrap() * s);
        }
        for key in ["sigma_v2", "sigma_w2"] {
            t["model"][key] = json!(sc["model"][key].as_f64().unwrap() * s * s);
        }
        let ps: Vec<[f64; 2]> = p.iter().map(|q| [q[0] * s, q[1] * s]).collect();
        let r = report(&with_probes(&t, &ps)).unwrap_or_else(|e| panic!("scale {s}: {e}"));
        let want = a0 * s * s;
        assert!(
            (area(&r) - want).abs() <= AREA_TOL * want,
            "scale {s}: area {} against {want}",
            area(&r)
        );
        assert_eq!(verdicts(&r), verdicts(&r0), "scale {s}: probe verdicts");
    }
}
in_browser!(lscr_scaling_scales_the_region);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn lscr_translation_moves_the_region_until_it_is_refused() {
    let (sc, p, r0) = base();
    let a0 = area(&r0);
    let f = mat(&sc["model"]["F"]);
    let f_b = mat(&r0["lscr"]["f_b"]);
    let h = mat(&sc["model"]["H"]);
    let tau = r0["lscr"]["time"].as_u64().unwrap() as usize;
    let steps = sc["data"]["y"].as_array().unwrap().len();
    for c in [1e-8, 1e-3, 1.0, 1e3, 1e5, 1e6] {
        // x_τ moves by d; the data follow the regression (11), (20), (21): y_t moves by
        // H F^{t−τ} d after τ and by H (F^b)^{τ−t} d up to τ (the backward representation).
        let d = vec![c, -0.5 * c];
        let mut moved = vec![Vec::new(); steps];
        let mut x = d.clone();
        for k in (0..tau.min(steps)).rev() {
            moved[k] = mul(&h, &x);
            x = mul(&f_b, &x);
        }
        let mut x = mul(&f, &d);
        for k in tau..steps {
            moved[k] = mul(&h, &x);
            x = mul(&f, &x);
        }
        let mut t = sc.clone();
        for (k, row) in t["data"]["y"]
            .as_array_mut()
            .unwrap()
            .iter_mut()
            .enumerate()
        {
            row[0] = json!(row[0].as_f64().unwrap() + moved[k][0]);
        }
        let shift = Some(d.clone());
        let shift = shift.expect("the estimated time lies inside the record");
        let ps: Vec<[f64; 2]> = p
            .iter()
            .map(|q| [q[0] + shift[0], q[1] + shift[1]])
            .collect();
        let r = report(&with_probes(&t, &ps)).unwrap_or_else(|e| panic!("shift {c}: {e}"));
        // The area is computed about a vertex of each loop, so a far translation costs only
        // the digits of the vertices themselves: |d|·2⁻⁵² against the region's size.
        let tol = AREA_TOL + 1e-15 * c;
        assert!(
            (area(&r) - a0).abs() <= tol * a0,
            "shift {c}: area {} against {a0}",
            area(&r)
        );
        assert_eq!(verdicts(&r), verdicts(&r0), "shift {c}: probe verdicts");
    }
    // Past the limit the data cannot represent the noise: refused, naming the data.
    for c in [1e12, 1e15] {
        let mut t = sc.clone();
        for row in t["data"]["y"].as_array_mut().unwrap() {
            row[0] = json!(row[0].as_f64().unwrap() + c);
        }
        let e = report(&t).expect_err("a record 1e12 away from its noise scale is refused");
        assert_eq!(e.field, "data.y", "{}", e.message);
        assert!(e.message.contains("spacing of doubles"), "{}", e.message);
    }
}
in_browser!(lscr_translation_moves_the_region_until_it_is_refused);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn lscr_permutation_swaps_the_region() {
    let (sc, p, r0) = base();
    // P swaps the coordinates: F′ = PFP, H′ = HP, G′ = PG.
    let f = mat(&sc["model"]["F"]);
    let h = mat(&sc["model"]["H"]);
    let g = mat(&sc["model"]["G"]);
    let mut t = sc.clone();
    t["model"]["F"] = json!([[f[1][1], f[1][0]], [f[0][1], f[0][0]]]);
    t["model"]["H"] = json!([[h[0][1], h[0][0]]]);
    t["model"]["G"] = json!([g[1].clone(), g[0].clone()]);
    t["plot"] = json!([0, 1]);
    let ps: Vec<[f64; 2]> = p.iter().map(|q| [q[1], q[0]]).collect();
    let r = report(&with_probes(&t, &ps)).unwrap();
    assert!(
        (area(&r) - area(&r0)).abs() <= AREA_TOL * area(&r0),
        "area {} against {}",
        area(&r),
        area(&r0)
    );
    assert_eq!(verdicts(&r), verdicts(&r0), "probe verdicts");
}
in_browser!(lscr_permutation_swaps_the_region);

/// The coverage study of the issue: x̄ = (10¹⁵, 0) is refused before any run; x̄ = (10⁶, 0) runs
/// and counts exactly what x̄ = (0, 0) counts (same draws, translated).
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn lscr_study_far_out_is_refused_and_nearer_counts_do_not_move() {
    let mut sc = preset("lscr-predict");
    sc["lscr"]["coverage"] = json!({ "runs": 60, "seed": 3 });
    let study = |x: f64| {
        let mut s = sc.clone();
        s["simulate"]["condition"] = json!({ "t": 31, "x": [x, 0.0] });
        let mut study = Scenario::from_json(&s.to_string())?.study(None)?;
        confset::study::run_to_end(study.as_mut(), 1000, |_, _| {})
    };
    let e = study(1e15).expect_err("the issue's x̄ = 1e15 is refused");
    assert_eq!(e.field, "simulate.condition.x", "{}", e.message);
    assert!(
        e.message.contains("1.250e-1"),
        "names the spacing 0.125: {}",
        e.message
    );
    let near = study(0.0).unwrap();
    let far = study(1e6).unwrap();
    for key in ["inside", "inside_each", "blue"] {
        assert_eq!(near[key], far[key], "{key}");
    }
}
in_browser!(lscr_study_far_out_is_refused_and_nearer_counts_do_not_move);

/// Tempo's interval hull with explicit data: scaling data and bounds by s scales the hull by s.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn ubb_hull_scales_with_the_problem() {
    let base = preset("ubb-track");
    let r0 = report(&base).unwrap();
    let y = r0["ubb"]["y"].clone();
    let mut sc = base.clone();
    sc.as_object_mut().unwrap().remove("simulate");
    sc["data"] = json!({ "y": y });
    let r0 = report(&sc).unwrap();
    let hull = |r: &Value| -> Vec<f64> {
        let steps = r["ubb"]["track"].as_array().unwrap();
        steps
            .iter()
            .flat_map(|s| {
                ["lo", "hi"]
                    .into_iter()
                    .flat_map(move |k| s[k].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()))
            })
            .collect()
    };
    let h0 = hull(&r0);
    let width = h0.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let mut worst = 0.0_f64;
    for s in [1e-6, 1e-3, 1e3, 1e9] {
        let mut t = sc.clone();
        for row in t["data"]["y"].as_array_mut().unwrap() {
            for v in row.as_array_mut().unwrap() {
                *v = json!(v.as_f64().unwrap() * s);
            }
        }
        // γ: Theorem 5's truncation accuracy, a bound on x like ε and τ.
        for key in ["eps", "tau", "gamma"] {
            t["ubb"][key] = json!(sc["ubb"][key].as_f64().unwrap() * s);
        }
        // δ: the half-widths of x(0)'s box.
        t["ubb"]["delta"] = json!(sc["ubb"]["delta"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap() * s)
            .collect::<Vec<_>>());
        let h = hull(&report(&t).unwrap_or_else(|e| panic!("scale {s}: {e}")));
        for (a, b) in h.iter().zip(&h0) {
            worst = worst.max((a / s - b).abs() / width);
        }
    }
    // The LP's own tolerance is 10⁻⁸ relative to its unit; 6.3·10⁻⁵ before the unit was set.
    assert!(worst <= 1e-8, "worst relative hull error {worst:e}");
}
in_browser!(ubb_hull_scales_with_the_problem);
