//! Tempo's set-membership estimator (`ubb`) on users' records, natively and in the browser:
//!
//! * gaps: a record with missing measurements (first, middle, last rows, one missing output and
//!   a stretch of 20 rows) keeps one step per row; its predicted and filtered sets are those of
//!   an independent box recursion written here (a diagonal model with smoothed bounds and a
//!   sliding window: the window's prior box, the strips of the data present, the map and the
//!   noise), on the planar path and on the LP path, and they contain the sets of the same
//!   record with every measurement present (a gap only removes constraints);
//! * one state: the sets are the intervals of an independent interval recursion, the figures
//!   draw them, and no message asks for two components;
//! * the filtered set X(k | y(0 … k)): with all the data in the window it is the previous
//!   prediction clipped by the strip of y(k), and it maps (by A, plus the noise set) onto the
//!   predicted set of the same step, on the preset's sliding smoothed windows too;
//! * long records: 203 steps run, 1000 are within the budget, 10⁶ are refused by it naming
//!   the steps and the formula, before any work;
//! * the words: the step at which the set became empty (k, row and time), the boundedness of
//!   δ = ∞ by reconstructibility (a singular A with an unobservable but reconstructible pair
//!   gives bounded sets; a non-reconstructible one is named so), the Kalman comparison's
//!   assumption (variances bound²/3), and its diffuse prior in the data's unit (the Kalman
//!   verdicts of a record and its bounds scaled by 10⁴ are the same).

use confset::error::Error;
use confset::plot::{report_svg, Panel, View};
use confset::scenario::{Job, Report, Scenario};
use serde_json::{json, Value};

fn preset(name: &str) -> Value {
    serde_json::to_value(confset::presets::get(name).expect("preset")).expect("json")
}

fn run(v: &Value) -> Result<Report, Error> {
    Scenario::from_json(&v.to_string())?.run()
}

/// The scenario `v` on the data `y` (rows; NaN a gap, written `null`) instead of its simulation.
fn on_data(v: &Value, y: &[Vec<f64>]) -> Value {
    let mut d = v.clone();
    d.as_object_mut().unwrap().remove("simulate");
    let rows: Vec<Value> = y
        .iter()
        .map(|r| {
            Value::Array(
                r.iter()
                    .map(|x| if x.is_nan() { Value::Null } else { json!(x) })
                    .collect(),
            )
        })
        .collect();
    d["data"] = json!({ "y": rows });
    d
}

fn ubb(r: &Report) -> &confset::scenario::UbbReport {
    r.ubb.as_ref().expect("a ubb report")
}

// ---------------------------------------------------------------------------------------------
// Gaps

/// A diagonal 2-state model, two noise inputs and two outputs, each output measuring one state:
/// every constraint of T(h) (3) names one component, so the feasible sets are boxes and each
/// component has an interval recursion of its own.
const A: [f64; 2] = [0.8, -0.5];
const G: [f64; 2] = [1.0, 0.6];
const H: [f64; 2] = [1.0, 2.0];
const EPS: f64 = 0.3;
const TAU: f64 = 0.2;
const DELTA: [f64; 2] = [1.5, 1.0];
const CENTER: [f64; 2] = [0.2, -0.1];
const WINDOW: usize = 8;
const SMOOTH: f64 = 20.0;

fn diagonal(steps: usize) -> Value {
    json!({
        "method": "ubb",
        "model": {"F": [[A[0], 0.0], [0.0, A[1]]], "G": [[G[0], 0.0], [0.0, G[1]]],
                  "H": [[H[0], 0.0], [0.0, H[1]]]},
        "simulate": {"steps": steps, "seed": 11},
        "ubb": {"eps": EPS, "tau": TAU, "delta": DELTA, "x0_center": CENTER, "window": WINDOW,
                "alpha": SMOOTH, "beta": SMOOTH}
    })
}

/// The sets of step k by hand, component i: (filtered [lo, hi] of x_i(k), predicted of
/// x_i(k+1)). Section IV with smoothed bounds (45)–(46) on the window s … k, len = min(j + 1,
/// k + 1): x(s) lies in the a-priori box moved by A^s plus the noise before the window, each
/// sample bounded by τe^{(k−l)/α}; then for t = s … k the strip |y_i(t) − h_i x_i(t)| ≤
/// εe^{(k−t)/β} of a measurement present (none at a gap), and x_i(t+1) = a_i x_i(t) + g_i u_i(t)
/// with |u_i(t)| ≤ τe^{(k−t)/α}.
fn boxes(y: &[Vec<f64>], k: usize, i: usize) -> ([f64; 2], [f64; 2]) {
    let grow = |age: usize| (age as f64 / SMOOTH).exp();
    let len = WINDOW.min(k + 1);
    let s = k + 1 - len;
    let mut centre = CENTER[i];
    for _ in 0..s {
        centre *= A[i];
    }
    let mut half = DELTA[i] * A[i].abs().powi(s as i32);
    for l in 0..s {
        half += A[i].abs().powi((s - 1 - l) as i32) * G[i].abs() * TAU * grow(k - l);
    }
    let (mut lo, mut hi) = (centre - half, centre + half);
    let mut filtered = [lo, hi];
    for t in s..=k {
        let v = y[t][i];
        if !v.is_nan() {
            let e = EPS * grow(k - t);
            lo = lo.max((v - e) / H[i]);
            hi = hi.min((v + e) / H[i]);
            assert!(
                lo <= hi + 1e-12,
                "the data contradict the bounds at t = {t}"
            );
        }
        if t == k {
            filtered = [lo, hi];
        }
        let (a, b) = (A[i] * lo, A[i] * hi);
        let w = G[i].abs() * TAU * grow(k - t);
        lo = a.min(b) - w;
        hi = a.max(b) + w;
    }
    (filtered, [lo, hi])
}

fn assert_close(a: f64, b: f64, tol: f64, what: &str) {
    assert!(
        (a - b).abs() <= tol * (1.0 + a.abs().max(b.abs())),
        "{what}: {a} vs {b}"
    );
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn gaps_drop_their_strips_and_only_widen_the_sets() {
    const STEPS: usize = 60;
    let sim = diagonal(STEPS);
    let full_y = ubb(&run(&sim).expect("the simulation")).y.clone();
    // Gaps: the first row, one in the middle, one output of row 30, a stretch of 20 rows
    // (36 … 55) and the last row.
    let mut y = full_y.clone();
    let whole: Vec<usize> = std::iter::once(0)
        .chain(std::iter::once(17))
        .chain(36..56)
        .chain(std::iter::once(STEPS - 1))
        .collect();
    for &k in &whole {
        y[k] = vec![f64::NAN, f64::NAN];
    }
    y[30][1] = f64::NAN;
    let gapped = on_data(&sim, &y);
    let report = run(&gapped).expect("a record with gaps runs");
    let full = run(&on_data(&sim, &full_y)).expect("the full record");
    let (u, uf) = (ubb(&report), ubb(&full));

    // One step per row of the record, the gaps kept as null in the report's data.
    assert_eq!(u.steps, STEPS);
    assert_eq!(u.track.len(), STEPS);
    assert_eq!(report.table().expect("the table").rows.len(), STEPS);
    let json = serde_json::to_value(&report).expect("JSON");
    assert!(json["ubb"]["y"][0][0].is_null() && json["ubb"]["y"][30][1].is_null());
    assert!(json["y"][59][1].is_null() && json["ubb"]["y"][30][0].is_number());
    let back: Report = serde_json::from_value(json).expect("a report with gaps reads back");
    assert!(ubb(&back).y[17][0].is_nan());
    // The warnings say where the gaps are and what was done.
    let words = report.warnings.join(" ");
    for needle in [
        "gaps (missing measurements) in 24 of its 60 rows",
        "row 1 (step k = 0)",
        "row 18 (step k = 17)",
        "row 31 (step k = 30)",
        "rows 37–56 (steps k = 36–55)",
        "row 60 (step k = 59)",
        "1 of them miss only some of the 2 outputs",
        "no measurement strip",
        "can only grow",
    ] {
        assert!(words.contains(needle), "{needle:?} in {words}");
    }

    // The independent box recursion, predicted and filtered, at every step.
    for st in &u.track {
        for i in 0..2 {
            let (filt, pred) = boxes(&y, st.k, i);
            let what = format!("k = {}, x{}", st.k, i + 1);
            assert_close(st.lo[i], pred[0], 1e-9, &format!("{what} predicted lo"));
            assert_close(st.hi[i], pred[1], 1e-9, &format!("{what} predicted hi"));
            let f = st.filtered.as_ref().expect("a filtered set");
            assert_close(f.lo[i], filt[0], 1e-9, &format!("{what} filtered lo"));
            assert_close(f.hi[i], filt[1], 1e-9, &format!("{what} filtered hi"));
        }
    }
    // The LP path leaves the same rows out.
    let prepared = Scenario::from_json(&gapped.to_string())
        .unwrap()
        .prepare_ubb()
        .unwrap();
    let data = prepared.data.clone().expect("data");
    for k in [0, 17, 30, 40, 59] {
        let step = prepared.problem.step_lp(&data, k).expect("an LP step");
        assert!(step.planar.is_none());
        let (pred, filt) = step.hulls().expect("the LP hulls");
        let filt = filt.expect("a filtered hull");
        for i in 0..2 {
            let (f, p) = boxes(&y, k, i);
            let what = format!("LP path, k = {k}, x{}", i + 1);
            assert_close(pred.lo[i], p[0], 1e-6, &what);
            assert_close(pred.hi[i], p[1], 1e-6, &what);
            assert_close(filt.lo[i], f[0], 1e-6, &what);
            assert_close(filt.hi[i], f[1], 1e-6, &what);
        }
    }

    // Monotonicity: every set of the record with gaps holds the full record's set of the same
    // step, and where measurements are missing it is strictly wider.
    let width = |lo: &[f64], hi: &[f64]| hi[0] - lo[0] + hi[1] - lo[1];
    let mut wider_at_gaps = 0;
    for (g, f) in u.track.iter().zip(&uf.track) {
        assert_eq!(g.k, f.k);
        let (gf, ff) = (g.filtered.as_ref().unwrap(), f.filtered.as_ref().unwrap());
        for i in 0..2 {
            assert!(
                g.lo[i] <= f.lo[i] + 1e-12 && g.hi[i] >= f.hi[i] - 1e-12,
                "k = {}",
                g.k
            );
            assert!(
                gf.lo[i] <= ff.lo[i] + 1e-12 && gf.hi[i] >= ff.hi[i] - 1e-12,
                "k = {}",
                g.k
            );
        }
        if whole.contains(&g.k) && width(&gf.lo, &gf.hi) > width(&ff.lo, &ff.hi) + 1e-9 {
            wider_at_gaps += 1;
        }
    }
    assert_eq!(
        wider_at_gaps,
        whole.len(),
        "a whole-row gap widens the filtered box"
    );
    // The exact polygons of a gap step (the time cursor's detail): the full record's inside.
    let mut cursor = Scenario::from_json(&gapped.to_string())
        .unwrap()
        .cursor()
        .unwrap()
        .expect("a cursor");
    let mut cursor_full = Scenario::from_json(&on_data(&sim, &full_y).to_string())
        .unwrap()
        .cursor()
        .unwrap()
        .expect("a cursor");
    for k in [0, 45, 59] {
        let (g, f) = (cursor.at(k).unwrap(), cursor_full.at(k).unwrap());
        for path in [&["polygon"][..], &["filtered", "polygon"][..]] {
            let poly = |v: &Value| -> Vec<[f64; 2]> {
                let mut p = v;
                for key in path {
                    p = &p[*key];
                }
                serde_json::from_value(p["vertices"].clone()).unwrap()
            };
            let (outer, inner) = (poly(&g), poly(&f));
            for v in &inner {
                assert!(
                    inside(&outer, *v, 1e-9),
                    "k = {k} {path:?}: {v:?} outside {outer:?}"
                );
            }
        }
    }
}
in_browser!(gaps_drop_their_strips_and_only_widen_the_sets);

/// Whether p lies in the convex polygon `poly` (counter-clockwise vertices), to `tol` times its
/// extent.
fn inside(poly: &[[f64; 2]], p: [f64; 2], tol: f64) -> bool {
    let extent = poly
        .iter()
        .flatten()
        .fold(0.0_f64, |m, v| m.max(v.abs()))
        .max(1e-300);
    let n = poly.len();
    if n < 3 {
        // A segment or a point: p on it.
        let (a, b) = (poly[0], poly[n - 1]);
        let (d, e) = ([b[0] - a[0], b[1] - a[1]], [p[0] - a[0], p[1] - a[1]]);
        let len2 = d[0] * d[0] + d[1] * d[1];
        let t = if len2 > 0.0 {
            ((e[0] * d[0] + e[1] * d[1]) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let q = [a[0] + t * d[0] - p[0], a[1] + t * d[1] - p[1]];
        return q[0].hypot(q[1]) <= tol * extent;
    }
    (0..n).all(|i| {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        let cross = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
        cross >= -tol * extent * (b[0] - a[0]).hypot(b[1] - a[1])
    })
}

// ---------------------------------------------------------------------------------------------
// One state

/// x(k+1) = a x(k) + g u(k), y(k) = h x(k) + η(k): its sets by hand, all the data in the
/// window and no smoothing: from [c − δ, c + δ], clip by |y − h x| ≤ ε (none at a gap), keep
/// the filtered interval, map by a (the ends swap for a < 0), add [−|g|τ, |g|τ].
fn scalar_intervals(
    y: &[f64],
    a: f64,
    g: f64,
    h: f64,
    eps: f64,
    tau: f64,
    c: f64,
    delta: f64,
) -> Vec<([f64; 2], [f64; 2])> {
    let (mut lo, mut hi) = (c - delta, c + delta);
    let mut out = Vec::new();
    for &v in y {
        if !v.is_nan() {
            let (p, q) = ((v - eps) / h, (v + eps) / h);
            lo = lo.max(p.min(q));
            hi = hi.min(p.max(q));
        }
        let filtered = [lo, hi];
        let (p, q) = (a * lo, a * hi);
        lo = p.min(q) - g.abs() * tau;
        hi = p.max(q) + g.abs() * tau;
        out.push((filtered, [lo, hi]));
    }
    out
}

fn scalar(steps: usize) -> Value {
    json!({
        "method": "ubb",
        "model": {"F": [[-0.7]], "G": [[0.5]], "H": [[2.0]]},
        "simulate": {"steps": steps, "seed": 5},
        "ubb": {"eps": 0.3, "tau": 0.2, "delta": [1.0], "x0_center": [0.3], "window": steps}
    })
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn one_state_is_an_interval_recursion() {
    let sim = scalar(40);
    let report = run(&sim).expect("one state runs");
    let u = ubb(&report);
    assert_eq!((u.r, u.plane, u.track.len()), (1, [0, 0], 40));
    let mut y: Vec<f64> = u.y.iter().map(|r| r[0]).collect();
    let want = scalar_intervals(&y, -0.7, 0.5, 2.0, 0.3, 0.2, 0.3, 1.0);
    for (st, (filt, pred)) in u.track.iter().zip(&want) {
        let f = st.filtered.as_ref().expect("filtered");
        for (got, want, what) in [
            (st.lo[0], pred[0], "predicted lo"),
            (st.hi[0], pred[1], "predicted hi"),
            (f.lo[0], filt[0], "filtered lo"),
            (f.hi[0], filt[1], "filtered hi"),
        ] {
            assert_close(got, want, 1e-12, &format!("k = {}: {what}", st.k));
        }
        assert_eq!(
            (st.inside, f.inside),
            (Some(true), Some(true)),
            "k = {}",
            st.k
        );
    }
    // The detail's "polygon" is the interval on the diagonal of the plane (x₁, x₁), its
    // Kalman comparison the 1-D interval.
    let at = &u.at;
    assert_eq!(
        at.polygon.vertices,
        vec![[at.lo[0], at.lo[0]], [at.hi[0], at.hi[0]]]
    );
    assert_eq!(at.kf.dim(), 1);

    // With gaps (the same recursion without their strips), and on the LP path (l2 bounds on
    // single samples are the same intervals: every window norm of one sample is |η|).
    y[3] = f64::NAN;
    y[20] = f64::NAN;
    let rows: Vec<Vec<f64>> = y.iter().map(|v| vec![*v]).collect();
    let gapped = run(&on_data(&sim, &rows)).expect("one state with gaps");
    let want = scalar_intervals(&y, -0.7, 0.5, 2.0, 0.3, 0.2, 0.3, 1.0);
    for (st, (_, pred)) in ubb(&gapped).track.iter().zip(&want) {
        assert_close(st.lo[0], pred[0], 1e-12, "gapped lo");
        assert_close(st.hi[0], pred[1], 1e-12, "gapped hi");
    }

    // Every panel draws it, predicted and filtered.
    for set in ["predicted", "filtered"] {
        let mut v = sim.clone();
        v["ubb"]["set"] = json!(set);
        let r = run(&v).unwrap();
        for panel in ["ubbset", "ubbwidth"] {
            let view = View::new(Panel::from_name(panel).unwrap());
            let svg =
                report_svg(&r, &view, 640, 480).unwrap_or_else(|e| panic!("{panel}, {set}: {e}"));
            assert!(
                svg.contains("<svg") && svg.contains("one state") == (panel == "ubbset"),
                "{panel}"
            );
        }
        let explained = Scenario::from_json(&v.to_string())
            .unwrap()
            .explain(&r, Some(10), None)
            .expect("the step-through");
        assert!(!explained.rows.is_empty());
    }
}
in_browser!(one_state_is_an_interval_recursion);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn one_state_never_asks_for_two_components() {
    let mut v = scalar(10);
    v["ubb"]["plane"] = json!([0, 1]);
    let e = run(&v).expect_err("no second component");
    assert_eq!(e.field, "ubb.plane");
    assert!(
        !e.message
            .contains("must name two different state components")
            && e.message.contains("one component (r = 1)")
            && e.message.contains("an interval"),
        "{e}"
    );
    v["ubb"]["plane"] = json!([0, 0]);
    run(&v).expect("[0, 0] names the one state");
}
in_browser!(one_state_never_asks_for_two_components);

// ---------------------------------------------------------------------------------------------
// The filtered set

/// The support function of a convex polygon in direction d.
fn support(poly: &[[f64; 2]], d: [f64; 2]) -> f64 {
    poly.iter()
        .map(|p| p[0] * d[0] + p[1] * d[1])
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The convex polygon `poly` clipped by lo ≤ x₁ ≤ hi (Sutherland–Hodgman, two half-planes).
fn clip_x1(poly: &[[f64; 2]], lo: f64, hi: f64) -> Vec<[f64; 2]> {
    let half = |pts: Vec<[f64; 2]>, keep: &dyn Fn(f64) -> f64| -> Vec<[f64; 2]> {
        let mut out = Vec::new();
        for i in 0..pts.len() {
            let (a, b) = (pts[i], pts[(i + 1) % pts.len()]);
            let (fa, fb) = (keep(a[0]), keep(b[0]));
            if fa >= 0.0 {
                out.push(a);
            }
            if (fa >= 0.0) != (fb >= 0.0) {
                let t = fa / (fa - fb);
                out.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
            }
        }
        out
    };
    let p = half(poly.to_vec(), &|x| x - lo);
    half(p, &|x| hi - x)
}

fn polygon(v: &Value) -> Vec<[f64; 2]> {
    serde_json::from_value(v["vertices"].clone()).expect("vertices")
}

const DIRECTIONS: usize = 36;

fn direction(i: usize) -> [f64; 2] {
    let t = 2.0 * std::f64::consts::PI * i as f64 / DIRECTIONS as f64;
    [t.cos(), t.sin()]
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn the_filtered_set_is_the_clipped_prediction_and_maps_onto_the_next() {
    // ubb-track's model: A = [[0.7, 0.2], [−0.2, 0.7]], B = [0.5; 1], C = [1, 0].
    let (a, b, eps, tau) = ([[0.7, 0.2], [-0.2, 0.7]], [0.5, 1.0], 0.2, 0.1);
    // All the data in every window, no smoothing: X(k | k) = X(k | k − 1) ∩ {|y(k) − x₁| ≤ ε}.
    let mut full = preset("ubb-track");
    for key in ["alpha", "beta", "time"] {
        full["ubb"].as_object_mut().unwrap().remove(key);
    }
    full["ubb"]["window"] = json!(60);
    // The preset itself: sliding windows of 30 with smoothed bounds (α = β = 50).
    let sliding = preset("ubb-track");
    for (v, clipped) in [(&full, true), (&sliding, false)] {
        let s = Scenario::from_json(&v.to_string()).unwrap();
        let report = s.run().unwrap();
        let y: Vec<f64> = ubb(&report).y.iter().map(|r| r[0]).collect();
        let mut cursor = s.cursor().unwrap().expect("a cursor");
        for k in [10, 25, 40] {
            let (at, before) = (cursor.at(k).unwrap(), cursor.at(k - 1).unwrap());
            let filtered = polygon(&at["filtered"]["polygon"]);
            let predicted = polygon(&at["polygon"]);
            let scale = 1.0 + support(&predicted, [1.0, 0.0]).abs();
            for i in 0..DIRECTIONS {
                let d = direction(i);
                // X(k+1 | k) = A X(k | k) + B[−τ, τ]: h(d) = h_filtered(Aᵀd) + τ|Bᵀd|.
                let at_d = [
                    a[0][0] * d[0] + a[1][0] * d[1],
                    a[0][1] * d[0] + a[1][1] * d[1],
                ];
                let mapped = support(&filtered, at_d) + tau * (b[0] * d[0] + b[1] * d[1]).abs();
                assert_close(
                    support(&predicted, d),
                    mapped,
                    1e-9 * scale,
                    &format!("k = {k}, map, d = {d:?}"),
                );
                if clipped {
                    let clip = clip_x1(&polygon(&before["polygon"]), y[k] - eps, y[k] + eps);
                    assert_close(
                        support(&filtered, d),
                        support(&clip, d),
                        1e-9 * scale,
                        &format!("k = {k}, clip, d = {d:?}"),
                    );
                    // ⊆ beside =: no vertex of the filtered set outside the clipped prediction.
                    for v in &filtered {
                        assert!(inside(&clip, *v, 1e-9), "k = {k}: {v:?}");
                    }
                }
            }
            // The track's filtered hull is the detail's, and holds the true x(k).
            let st = ubb(&report).track.iter().find(|t| t.k == k).unwrap();
            let f = st.filtered.as_ref().unwrap();
            for (i, extreme) in [(0, [1.0, 0.0]), (1, [0.0, 1.0])] {
                assert_close(f.hi[i], support(&filtered, extreme), 1e-9, "hull");
            }
            assert_eq!(f.inside, Some(true));
        }
    }
    // The table carries both sets, the figures draw the one `ubb.set` chooses.
    let table = run(&sliding).unwrap().table().unwrap();
    for c in [
        "lo_1",
        "filtered_lo_1",
        "filtered_radius",
        "filtered_x_2",
        "filtered_holds",
    ] {
        assert!(table.columns.iter().any(|x| x == c), "{c}");
    }
    let mut v = sliding.clone();
    v["ubb"]["set"] = json!("filtered");
    let r = run(&v).unwrap();
    // At the page's desktop size: Firefox measures text wider than Chromium (crate docs), and
    // the width panel's stacked charts under a filtered title leave 105 px at 640 × 480 there.
    let svg = report_svg(
        &r,
        &View::new(Panel::from_name("ubbset").unwrap()),
        960,
        720,
    )
    .unwrap();
    assert!(svg.contains("Filtered set at k = 40") && svg.contains("x(40)"));
    let svg = report_svg(
        &r,
        &View::new(Panel::from_name("ubbwidth").unwrap()),
        960,
        720,
    )
    .unwrap();
    assert!(svg.contains("filtered set of x(k)"));
}
in_browser!(the_filtered_set_is_the_clipped_prediction_and_maps_onto_the_next);

// ---------------------------------------------------------------------------------------------
// Long records and the budget

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn long_records_run_within_the_budget_and_huge_ones_are_refused() {
    let mut v = preset("ubb-track");
    v["ubb"].as_object_mut().unwrap().remove("time");
    // 203 quarters: they run, one step per row.
    v["simulate"]["steps"] = json!(203);
    let r = run(&v).expect("203 steps");
    assert_eq!(ubb(&r).track.len(), 203);
    // 1000 steps are within the budget (they take about half a second natively).
    v["simulate"]["steps"] = json!(1000);
    let s = Scenario::from_json(&v.to_string()).unwrap();
    s.work(Job::Report)
        .check(Job::Report)
        .expect("1000 steps fit the budget");
    // 10⁶ steps: refused by the budget before any work, naming the steps and the formula.
    v["simulate"]["steps"] = json!(1_000_000);
    let s = Scenario::from_json(&v.to_string()).unwrap();
    let refusal = s
        .work(Job::Report)
        .check(Job::Report)
        .expect_err("refused by the budget");
    let e = s.run().expect_err("refused");
    assert_eq!(
        e, refusal,
        "the run is refused by the estimate, before any work"
    );
    assert_eq!(e.field, "simulate.steps");
    for words in [
        "= 1000000 with a window of 30",
        "steps²",
        "operations",
        "limited to about",
        "fewer steps",
    ] {
        assert!(e.message.contains(words), "{words:?} in {e}");
    }
    // The time cursor of such a scenario is refused the same way.
    assert_eq!(s.cursor().err().expect("refused").field, "simulate.steps");
    // The steps' own limit is the general count limit: the budget decides.
    let limits = confset::scenario::limits();
    assert_eq!(limits["simulate.steps"]["ubb"], json!([1, 10_000_000]));
}
in_browser!(long_records_run_within_the_budget_and_huge_ones_are_refused);

// ---------------------------------------------------------------------------------------------
// Messages

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn an_empty_set_says_at_which_step_and_row() {
    let sim = preset("ubb-track");
    let mut y = ubb(&run(&sim).unwrap()).y.clone();
    // An outlier at k = 17 no bounded noise explains.
    y[17][0] += 50.0;
    let mut d = on_data(&sim, &y);
    d["data"]["t"] = json!((0..60).map(|i| 1900 + i).collect::<Vec<_>>());
    let e = run(&d).expect_err("no state fits");
    assert_eq!(e.field, "ubb.eps");
    assert!(
        e.message.starts_with("leaves no state consistent with the data under these bounds")
            && e.message.contains(
                "the set became empty at step k = 17, when y(17) (row 18 (t = 18, time 1917) of the record) joined the window y(0 … 17)"
            ),
        "{e}"
    );
    // The LP path (l1 bounds on the stacked noise of a window of 10: ten times the bounds)
    // says the same.
    d["ubb"]["norm"] = json!("l1");
    d["ubb"]["window"] = json!(10);
    d["ubb"]["eps"] = json!(2.0);
    d["ubb"]["tau"] = json!(1.0);
    let e = run(&d).expect_err("no state fits");
    assert!(
        e.message
            .contains("the set became empty at step k = 17, when y(17) (row 18 (t = 18, time 1917) of the record) joined the window y(8 … 17)"),
        "{e}"
    );
}
in_browser!(an_empty_set_says_at_which_step_and_row);

/// x(k+1) = diag(0.5, a₂) x(k) + [0.3; 1] u(k), y = x₁ + η, δ = ∞: x₂ is never measured.
fn unobservable(a2: f64) -> Value {
    json!({
        "method": "ubb",
        "model": {"F": [[0.5, 0.0], [0.0, a2]], "G": [[0.3], [1.0]], "H": [[1.0, 0.0]]},
        "simulate": {"steps": 30, "seed": 7, "x0": [0.4, -0.6]},
        "ubb": {"eps": 0.2, "tau": 0.1, "window": 10}
    })
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn unbounded_means_not_reconstructible() {
    // a₂ = 0: (A, C) is not observable (rank [C; CA] = 1) but reconstructible: A maps the
    // unmeasured x₂ to 0, so x(k+1) is bounded from the first step: x₂(k+1) = u(k) ∈ [−τ, τ].
    // The filtered x(k) needs one step more (x₂(0) is free).
    let r = run(&unobservable(0.0)).expect("a reconstructible pair has bounded sets");
    let u = ubb(&r);
    assert_eq!(u.track.len(), 30);
    assert!(u.track[0].filtered.is_none() && u.track[1].filtered.is_some());
    for st in &u.track {
        assert_close(st.lo[1], -0.1, 1e-9, "x₂(k+1) low");
        assert_close(st.hi[1], 0.1, 1e-9, "x₂(k+1) high");
        assert_eq!(st.inside, Some(true));
        if let Some(f) = &st.filtered {
            assert_eq!(f.inside, Some(true));
            assert_close(f.hi[1], 0.1, 1e-9, "x₂(k) high");
        }
    }
    // a₂ = 0.9: x₂ is neither measured nor forgotten: unbounded, and said so.
    let e = run(&unobservable(0.9)).expect_err("unbounded");
    assert_eq!(e.field, "ubb.delta");
    for words in [
        "is ∞ (no bound on x(0))",
        "leave x(1) unbounded",
        "they determine 1 of the 2 state directions of x(0)",
        "A^1 does not map the rest to 0",
        "not reconstructible",
        "the feasible set is unbounded",
    ] {
        assert!(e.message.contains(words), "{words:?} in {e}");
    }
    assert!(!e.message.contains("observab"), "{e}");
}
in_browser!(unbounded_means_not_reconstructible);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn the_kalman_comparison_states_its_assumption() {
    let r = preset("ubb-track");
    let words = run(&r).unwrap().warnings.join(" ");
    for w in [
        "is a comparison under a stated assumption, not part of Tempo's method",
        "the uniform law on [−bound, bound], bound²/3",
        "Var u = 0.1²/3 = 0.00333",
        "Var η = 0.2²/3 = 0.0133",
        "δᵢ²/3",
    ] {
        assert!(words.contains(w), "{w:?} in {words}");
    }
    let mut at_bound = r.clone();
    at_bound["ubb"]["noise"] = json!("bound");
    let words = run(&at_bound).unwrap().warnings.join(" ");
    assert!(
        words.contains("noise at ± the bound, bound²") && words.contains("Var η = 0.2² = 0.04"),
        "{words}"
    );
    // The CSV table carries it above its header.
    let table = run(&r).unwrap().table().unwrap();
    assert!(table.warnings.iter().any(|w| w.contains("bound²/3")));
}
in_browser!(the_kalman_comparison_states_its_assumption);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn the_diffuse_kalman_prior_scales_with_the_data() {
    // ubb-series has δ = ∞: the Kalman comparison starts from a diffuse prior. The record and
    // its bounds in other units (×10⁴) give the same Kalman verdicts and the sets scaled.
    let base = preset("ubb-series");
    assert!(base["ubb"].get("delta").is_none());
    let mut scaled = base.clone();
    let x0: Vec<f64> = serde_json::from_value(base["simulate"]["x0"].clone()).unwrap();
    scaled["simulate"]["x0"] = json!(x0.iter().map(|v| v * 1e4).collect::<Vec<_>>());
    scaled["ubb"]["eps"] = json!(base["ubb"]["eps"].as_f64().unwrap() * 1e4);
    let (a, b) = (run(&base).unwrap(), run(&scaled).unwrap());
    let (ua, ub) = (ubb(&a), ubb(&b));
    let verdicts = |u: &confset::scenario::UbbReport| -> Vec<(Option<bool>, Option<bool>)> {
        u.track
            .iter()
            .map(|t| (t.kf_inside, t.filtered.as_ref().and_then(|f| f.kf_inside)))
            .collect()
    };
    assert_eq!(verdicts(ua), verdicts(ub));
    assert_eq!(
        (ua.kf_outside, ua.filtered_kf_outside),
        (ub.kf_outside, ub.filtered_kf_outside)
    );
    for (s, t) in ua.track.iter().zip(&ub.track) {
        for i in 0..2 {
            assert_close(t.lo[i], 1e4 * s.lo[i], 1e-9, "scaled hull");
            // The diffuse prior's first update cancels 10⁸ against 1: the means agree to the
            // digits it leaves (the verdicts above exactly).
            assert_close(t.kf_mean[i], 1e4 * s.kf_mean[i], 1e-4, "scaled Kalman mean");
        }
    }
}
in_browser!(the_diffuse_kalman_prior_scales_with_the_data);
