//! The exact planar set engine (`sets::ConvexPolygon`) and the planar paths it runs (issue 27),
//! natively and in the browser:
//!
//! * the engine against brute force: hulls of random points (every point inside, the area of
//!   the plane module's independent hull), clips against membership of sampled points in the
//!   polygon and the half-plane, Minkowski sums against the hull of all pairwise sums, maps
//!   against the hull of the mapped vertices, supports against the best point;
//! * degenerate cases: an empty clip, a strip parallel to an edge, segments and points,
//!   singular maps, sets of size 10⁻¹⁵⁰ and 10¹⁵⁰;
//! * Tempo's state estimator: the planar path against the LP path (clarabel, the oracle) on
//!   every step of the 2-D presets and on 60 seeded random problems (with and without δ,
//!   smoothing, process noise of 0 … 3 columns, 1 or 2 outputs), support functions in 32
//!   directions and interval hulls equal to 1e-9 of the problem's scale (the largest of the
//!   set's coordinates, the data and ε: the LP oracle is accurate to ~10⁻¹⁰ of its data);
//! * Pavelková's consistent polygon for n = 2 against the LP path's polygon (its vertices
//!   inside) and support LPs in 32 directions.

use confset::presets::{self, UbbKind};
use confset::sets::{convex_hull, minkowski_sum, point_in_convex, polygon_area, ConvexPolygon};
use confset::solve::Family;
use confset::ubb::{Bounds, L1Form, NoiseMode, Norm, StateProblem, System};
use confset::uniform::{
    consistent_polygon, consistent_polygon_lp, simulate, state_lp, Lp, StatePrior, Theta, Window,
};
use nalgebra::{DMatrix, DVector};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn rand_pts(rng: &mut ChaCha8Rng, n: usize, scale: f64) -> Vec<[f64; 2]> {
    (0..n)
        .map(|_| {
            [
                (rng.random::<f64>() * 2.0 - 1.0) * scale,
                (rng.random::<f64>() * 2.0 - 1.0) * scale,
            ]
        })
        .collect()
}

fn support(pts: &[[f64; 2]], d: [f64; 2]) -> f64 {
    pts.iter()
        .map(|p| p[0] * d[0] + p[1] * d[1])
        .fold(f64::NEG_INFINITY, f64::max)
}

fn directions(count: usize) -> Vec<[f64; 2]> {
    (0..count)
        .map(|i| {
            let t = 2.0 * std::f64::consts::PI * (i as f64 + 0.37) / count as f64;
            [t.cos(), t.sin()]
        })
        .collect()
}

/// Largest difference of the support functions of two vertex lists over 64 directions,
/// relative to `scale`.
fn support_gap(a: &[[f64; 2]], b: &[[f64; 2]], scale: f64) -> f64 {
    directions(64)
        .into_iter()
        .map(|d| (support(a, d) - support(b, d)).abs() / scale)
        .fold(0.0, f64::max)
}

/// The set's scale: its largest |coordinate| (the LP's unit is the data's magnitude).
fn scale_of(pts: &[[f64; 2]]) -> f64 {
    pts.iter()
        .flatten()
        .fold(f64::MIN_POSITIVE, |m, v| m.max(v.abs()))
}

fn is_ccw_strictly_convex(v: &[[f64; 2]]) -> bool {
    let n = v.len();
    n < 3
        || (0..n).all(|i| {
            let (a, b, c) = (v[i], v[(i + 1) % n], v[(i + 2) % n]);
            (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) > 0.0
        })
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn hull_area_and_support_against_brute_force() {
    let mut rng = ChaCha8Rng::seed_from_u64(27);
    for trial in 0..200 {
        let pts = rand_pts(&mut rng, 3 + trial % 40, 1.0 + trial as f64);
        let h = ConvexPolygon::hull(&pts).unwrap();
        let v = h.vertices();
        assert!(is_ccw_strictly_convex(v), "trial {trial}: {v:?}");
        assert!(
            v.iter().all(|q| pts.contains(q)),
            "vertices are input points"
        );
        for p in &pts {
            assert!(
                point_in_convex(v, *p, 1e-12),
                "trial {trial}: {p:?} outside"
            );
        }
        let brute = convex_hull(pts.clone());
        let area = polygon_area(&brute);
        assert!((h.area() - area).abs() <= 1e-12 * area, "trial {trial}");
        for d in directions(16) {
            let (val, at) = h.support(d);
            assert_eq!(val, support(&pts, d));
            assert_eq!(val, at[0] * d[0] + at[1] * d[1]);
        }
        let ih = h.interval_hull();
        assert_eq!(
            ih[0],
            pts.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min)
        );
        assert_eq!(
            ih[3],
            pts.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max)
        );
    }
}
in_browser!(hull_area_and_support_against_brute_force);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn clips_agree_with_membership_of_sampled_points() {
    let mut rng = ChaCha8Rng::seed_from_u64(2727);
    for trial in 0..100 {
        let poly = ConvexPolygon::hull(&rand_pts(&mut rng, 12, 1.0)).unwrap();
        let t = rng.random::<f64>() * std::f64::consts::TAU;
        let a = [t.cos() * 3.0, t.sin() * 3.0];
        let (lo, hi) = (rng.random::<f64>() * 2.0 - 1.5, rng.random::<f64>() * 2.0);
        let Some(cut) = poly.clip_strip(a, lo, hi) else {
            // Empty: no vertex may be in the strip.
            assert!(
                poly.vertices().iter().all(|v| {
                    let s = a[0] * v[0] + a[1] * v[1];
                    s < lo || s > hi
                }) || lo > hi
            );
            continue;
        };
        assert!(is_ccw_strictly_convex(cut.vertices()), "trial {trial}");
        for p in rand_pts(&mut rng, 400, 1.2) {
            let s = a[0] * p[0] + a[1] * p[1];
            let brute_in = point_in_convex(poly.vertices(), p, 0.0) && s >= lo && s <= hi;
            let brute_far =
                !point_in_convex(poly.vertices(), p, 1e-6) || s < lo - 1e-6 || s > hi + 1e-6;
            let got = point_in_convex(cut.vertices(), p, 1e-12);
            if brute_in {
                assert!(got, "trial {trial}: {p:?} lost");
            }
            if brute_far {
                assert!(
                    !point_in_convex(cut.vertices(), p, 0.0),
                    "trial {trial}: {p:?} kept"
                );
            }
        }
        // The cut is the polygon's part: its area is at most the polygon's.
        assert!(cut.area() <= poly.area() * (1.0 + 1e-12));
    }
}
in_browser!(clips_agree_with_membership_of_sampled_points);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn minkowski_sums_and_maps_agree_with_the_hull_of_all_points() {
    let mut rng = ChaCha8Rng::seed_from_u64(270);
    for trial in 0..150 {
        let p = ConvexPolygon::hull(&rand_pts(&mut rng, 3 + trial % 9, 2.0)).unwrap();
        let q = match trial % 3 {
            0 => ConvexPolygon::hull(&rand_pts(&mut rng, 2 + trial % 7, 1.0)).unwrap(),
            1 => {
                let s = rand_pts(&mut rng, 2, 1.0);
                ConvexPolygon::segment(s[0], s[1])
            }
            _ => ConvexPolygon::point(rand_pts(&mut rng, 1, 1.0)[0]),
        };
        let sum = p.minkowski(&q);
        assert!(is_ccw_strictly_convex(sum.vertices()), "trial {trial}");
        let brute = minkowski_sum(p.vertices(), q.vertices());
        assert!(
            support_gap(sum.vertices(), &brute, 1.0) < 1e-14,
            "trial {trial}"
        );
        assert!((sum.area() - polygon_area(&brute)).abs() < 1e-12);
        // A box and a segment through their own entry points.
        let v = [rng.random::<f64>() - 0.5, rng.random::<f64>() - 0.5];
        let seg = p.add_segment(v);
        let brute = minkowski_sum(p.vertices(), &[[-v[0], -v[1]], v]);
        assert!(support_gap(seg.vertices(), &brute, 1.0) < 1e-14);
        let bx = p.add_box([0.3, 0.1]);
        let brute = minkowski_sum(
            p.vertices(),
            &[[-0.3, -0.1], [0.3, -0.1], [0.3, 0.1], [-0.3, 0.1]],
        );
        assert!(support_gap(bx.vertices(), &brute, 1.0) < 1e-14);
        // A map, either orientation.
        let m = [
            [rng.random::<f64>() - 0.5, rng.random::<f64>() - 0.5],
            [rng.random::<f64>() - 0.5, rng.random::<f64>() - 0.5],
        ];
        let img = p.map(m);
        let pts: Vec<[f64; 2]> = p
            .vertices()
            .iter()
            .map(|v| {
                [
                    m[0][0] * v[0] + m[0][1] * v[1],
                    m[1][0] * v[0] + m[1][1] * v[1],
                ]
            })
            .collect();
        assert!(is_ccw_strictly_convex(img.vertices()), "trial {trial}");
        assert!(support_gap(img.vertices(), &pts, 1.0) < 1e-14);
        let det = (m[0][0] * m[1][1] - m[0][1] * m[1][0]).abs();
        assert!((img.area() - det * p.area()).abs() < 1e-12);
        let moved = p.translate([1.0, -2.0]);
        assert_eq!(
            moved.vertices()[0],
            [p.vertices()[0][0] + 1.0, p.vertices()[0][1] - 2.0]
        );
    }
}
in_browser!(minkowski_sums_and_maps_agree_with_the_hull_of_all_points);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn degenerate_sets_empty_parallel_segment_point_and_extreme_scales() {
    let sq = ConvexPolygon::rectangle([0.0, 0.0], [1.0, 1.0]);
    // Empty: the strip misses the square; a reversed strip.
    assert!(sq.clip_strip([1.0, 0.0], 2.0, 3.0).is_none());
    assert!(sq.clip_strip([1.0, 1.0], 1.0, 0.5).is_none());
    // A strip parallel to an edge, exactly on it: the edge; covering the square: unchanged.
    let edge = sq.clip_strip([0.0, 1.0], 1.0, 5.0).unwrap();
    assert_eq!(edge.vertices().len(), 2);
    assert_eq!(edge.area(), 0.0);
    assert_eq!(sq.clip_strip([0.0, 2.0], 0.0, 2.0).unwrap(), sq);
    // Touching at a corner: a point.
    let corner = sq.clip([1.0, 1.0], 0.0).unwrap();
    assert_eq!(corner.vertices(), &[[0.0, 0.0]]);
    // A segment clipped across, and along itself.
    let seg = ConvexPolygon::segment([0.0, 0.0], [2.0, 2.0]);
    let half = seg.clip([1.0, 0.0], 1.0).unwrap();
    assert_eq!(half.vertices().len(), 2);
    assert!((half.support([1.0, 1.0]).0 - 2.0).abs() < 1e-15);
    assert_eq!(seg.clip_strip([1.0, -1.0], -1.0, 1.0).unwrap(), seg);
    assert!(seg.clip_strip([1.0, -1.0], 0.5, 1.0).is_none());
    // A point: kept or not.
    let pt = ConvexPolygon::point([0.5, 0.5]);
    assert_eq!(pt.clip([1.0, 0.0], 0.5).unwrap(), pt);
    assert!(pt.clip([1.0, 0.0], 0.4).is_none());
    assert_eq!(pt.area(), 0.0);
    // Sums of degenerate sets: segment ⊕ segment is a parallelogram, point ⊕ segment a segment.
    let para = seg.add_segment([1.0, 0.0]);
    assert_eq!(para.vertices().len(), 4);
    assert!((para.area() - 4.0).abs() < 1e-15);
    assert_eq!(pt.minkowski(&seg).vertices().len(), 2);
    // Singular maps: onto a segment, onto a point.
    let line = sq.map([[1.0, 2.0], [2.0, 4.0]]);
    assert_eq!(line.vertices().len(), 2);
    assert!((line.support([1.0, 0.0]).0 - 3.0).abs() < 1e-15);
    assert_eq!(sq.map([[0.0, 0.0], [0.0, 0.0]]).vertices(), &[[0.0, 0.0]]);
    // A box with a zero side is a segment; with two, a point.
    assert_eq!(
        ConvexPolygon::rectangle([0.0, 1.0], [2.0, 1.0])
            .vertices()
            .len(),
        2
    );
    assert_eq!(
        ConvexPolygon::rectangle([3.0, 1.0], [3.0, 1.0])
            .vertices()
            .len(),
        1
    );
    // Huge and tiny scales: the same operations on the set scaled by s give the set scaled by s.
    let base = ConvexPolygon::hull(&[[0.0, 0.0], [3.0, 1.0], [2.0, 4.0], [-1.0, 2.0]]).unwrap();
    let run = |p: &ConvexPolygon, s: f64| {
        p.clip_strip([1.0, 1.0], 0.5 * s, 5.0 * s)
            .unwrap()
            .map([[0.9, 0.3], [-0.2, 0.8]])
            .add_segment([0.5 * s, 0.25 * s])
            .add_box([0.1 * s, 0.2 * s])
    };
    let reference = run(&base, 1.0);
    for s in [1e150, 1e-150, 2f64.powi(-1000), 1e300 / 1e10] {
        let pts: Vec<[f64; 2]> = base
            .vertices()
            .iter()
            .map(|v| [v[0] * s, v[1] * s])
            .collect();
        let scaled = run(&ConvexPolygon::hull(&pts).unwrap(), s);
        assert_eq!(
            scaled.vertices().len(),
            reference.vertices().len(),
            "scale {s}"
        );
        let back: Vec<[f64; 2]> = scaled
            .vertices()
            .iter()
            .map(|v| [v[0] / s, v[1] / s])
            .collect();
        assert!(
            support_gap(&back, reference.vertices(), 1.0) < 1e-13,
            "scale {s}"
        );
        let area = scaled.area();
        if (s * s).is_finite() && s * s > 0.0 {
            assert!(
                (area / (s * s) - reference.area()).abs() < 1e-12,
                "scale {s}: {area}"
            );
        }
        assert!(area >= 0.0);
    }
}
in_browser!(degenerate_sets_empty_parallel_segment_point_and_extreme_scales);

/// Compare one ubb step's planar answer with the LP oracle (clarabel: one support LP per
/// direction on the LP path's T(h), and its interval hull); returns the largest gap relative to
/// the problem's scale.
fn compare_step(problem: &StateProblem, y: &[DVector<f64>], k: usize, what: &str) -> f64 {
    let step = problem.step(y, k).unwrap();
    assert!(step.planar.is_some(), "{what}: the planar path must run");
    let (hull, poly, _) = step.hull_and_polygon([0, 1], 64).unwrap();
    assert_eq!(poly.calls, 0, "{what}: no LP on the planar path");
    let lp_step = problem.step_lp(y, k).unwrap();
    assert!(lp_step.planar.is_none());
    let lp_hull = lp_step.hull().unwrap();
    let mut solver = lp_step.set.support_solver().unwrap();
    // The LP's accuracy is relative to its data (clarabel's 1e-10 gap tolerance in the unit
    // of the data and bounds): the scale is the largest of the set's coordinates, the data
    // y(0 … k) and ε.
    let data = y[..=k]
        .iter()
        .map(|v| v.amax())
        .fold(problem.bounds.eps, f64::max);
    let scale = scale_of(&poly.vertices).max(data);
    let mut gap: f64 = 0.0;
    for d in directions(32) {
        let dir = lp_step.s_map.row(0).transpose() * d[0] + lp_step.s_map.row(1).transpose() * d[1];
        let lp =
            solver.support(&dir).unwrap().0 + d[0] * lp_step.offset[0] + d[1] * lp_step.offset[1];
        gap = gap.max((support(&poly.vertices, d) - lp).abs() / scale);
    }
    for i in 0..2 {
        gap = gap.max((hull.lo[i] - lp_hull.lo[i]).abs() / scale);
        gap = gap.max((hull.hi[i] - lp_hull.hi[i]).abs() / scale);
    }
    // The other plane order: the same set with its coordinates exchanged.
    let (_, swapped, _) = step.hull_and_polygon([1, 0], 64).unwrap();
    let back: Vec<[f64; 2]> = swapped.vertices.iter().map(|v| [v[1], v[0]]).collect();
    gap = gap.max(support_gap(&back, &poly.vertices, scale));
    assert!(
        gap <= 1e-9,
        "{what}: planar and LP sets differ by {gap:e} of {scale}"
    );
    gap
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn ubb_planar_path_equals_the_lp_on_every_2d_preset_step() {
    let mut checked = 0;
    for kind in [
        UbbKind::Track,
        UbbKind::Series,
        UbbKind::Leontief,
        UbbKind::Markov,
    ] {
        let prep = presets::ubb_preset(kind).prepare_ubb().unwrap();
        let run = prep.run_data();
        let r = prep.problem.system.r();
        for k in 0..run.y.len() {
            let Ok(step) = prep.problem.step(&run.y, k) else {
                continue;
            };
            if r != 2 {
                assert!(step.planar.is_none(), "{kind:?}: a 3-D state keeps the LP");
                continue;
            }
            // Every third step (the LP oracle is slow in the browser).
            if k % 3 == 0 || k + 1 == run.y.len() {
                compare_step(&prep.problem, &run.y, k, &format!("{kind:?} k = {k}"));
                checked += 1;
            }
        }
    }
    assert!(checked >= 20, "{checked} steps checked");
}
in_browser!(ubb_planar_path_equals_the_lp_on_every_2d_preset_step);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn ubb_planar_path_equals_the_lp_on_random_problems() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x27_2727);
    let mut worst: f64 = 0.0;
    let mut open = 0;
    for case in 0..60 {
        let theta = rng.random::<f64>() * std::f64::consts::TAU;
        let rho = 0.5 + 0.45 * rng.random::<f64>();
        let a = DMatrix::from_row_slice(
            2,
            2,
            &[
                rho * theta.cos(),
                rho * theta.sin() + 0.3 * (rng.random::<f64>() - 0.5),
                -rho * theta.sin(),
                rho * theta.cos(),
            ],
        );
        let p = case % 4;
        let b = DMatrix::from_fn(2, p, |_, _| rng.random::<f64>() * 2.0 - 1.0);
        let q = 1 + case % 2;
        let c = DMatrix::from_fn(q, 2, |_, _| rng.random::<f64>() * 2.0 - 1.0);
        let delta = (case % 3 != 0).then(|| DVector::from_element(2, 0.5 + rng.random::<f64>()));
        let smooth = (case % 5 < 2).then(|| 5.0 + 50.0 * rng.random::<f64>());
        let problem = StateProblem {
            system: System {
                a,
                b,
                c: vec![c],
                v: if case % 7 == 0 {
                    vec![DVector::from_column_slice(&[0.3, -0.1])]
                } else {
                    Vec::new()
                },
            },
            bounds: Bounds {
                norm: Norm::Linf,
                l1_form: L1Form::Lifted,
                tau: 0.05 + 0.2 * rng.random::<f64>(),
                eps: 0.05 + 0.3 * rng.random::<f64>(),
                delta,
                x0_center: DVector::from_column_slice(&[0.2, -0.3]),
                x0_sum: None,
                alpha: smooth,
                beta: smooth,
            },
            window: 3 + case % 9,
            sim_levels: (None, None),
        };
        let mode = if case % 2 == 0 {
            NoiseMode::Random
        } else {
            NoiseMode::Bound
        };
        let steps = 8 + case % 10;
        let run = problem.simulate(steps, mode, None, case as u64);
        let k = steps - 1 - case % 3;
        match problem.step(&run.y, k) {
            Ok(step) if step.planar.is_some() => {
                worst = worst.max(compare_step(&problem, &run.y, k, &format!("case {case}")));
                // The truth lies in the exact set.
                let (_, poly, _) = step.hull_and_polygon([0, 1], 0).unwrap();
                let x = &run.x[k + 1];
                assert!(
                    poly.contains([x[0], x[1]], 1e-9),
                    "case {case}: truth outside"
                );
            }
            Ok(_) => open += 1,
            Err(e) => panic!("case {case}: {e}"),
        }
    }
    assert!(open <= 5, "{open} cases left to the LP");
    assert!(worst <= 1e-9);
    println!("ubb random problems: worst planar/LP gap {worst:e} of the problem's scale, {open} left to the LP");
}
in_browser!(ubb_planar_path_equals_the_lp_on_random_problems);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn ubb_contradicting_data_name_the_same_field_as_the_lp() {
    let prep = presets::ubb_preset(UbbKind::Track).prepare_ubb().unwrap();
    let mut run = prep.run_data();
    run.y[5][0] += 50.0;
    let err = prep.problem.step(&run.y, 10).unwrap_err();
    // The LP path on the same data: the same message.
    let lp = prep
        .problem
        .step_lp(&run.y, 10)
        .unwrap()
        .hull()
        .unwrap_err();
    assert_eq!(err.field, "ubb.eps");
    assert_eq!(err.to_string(), lp.to_string());
    assert!(
        err.to_string().contains("consistent with the data"),
        "{err}"
    );
}
in_browser!(ubb_contradicting_data_name_the_same_field_as_the_lp);

/// The support function of the consistent set of x_last (components `plane`) by one LP per
/// direction: the state LP (6)–(10) with the half-widths fixed, loaded once.
fn support_lp<'a>(
    theta: &Theta,
    u: &[DVector<f64>],
    y: &[DVector<f64>],
    w: Window,
    prior: &StatePrior,
    hw: &(DVector<f64>, DVector<f64>),
    plane: [usize; 2],
) -> impl FnMut([f64; 2]) -> f64 + 'a {
    let (n, m) = (theta.n(), theta.m());
    let lp = state_lp(theta, u, y, w, prior);
    let nx = w.states() * n;
    let mut fixed = DVector::zeros(n + m);
    fixed.rows_mut(0, n).copy_from(&hw.0);
    fixed.rows_mut(n, m).copy_from(&hw.1);
    let states = Lp {
        c: DVector::zeros(nx),
        a: lp.a.columns(0, nx).into_owned(),
        b: &lp.b - lp.a.columns(nx, n + m) * fixed,
        lo: lp.lo.rows(0, nx).into_owned(),
        hi: lp.hi.rows(0, nx).into_owned(),
        unit: lp.unit,
    };
    let mut family = Family::new(&states.problem(&states.c, None, "uniform.window")).unwrap();
    move |d| {
        let mut c = DVector::zeros(nx);
        c[plane[0]] = -d[0];
        c[plane[1]] = -d[1];
        -family.minimize(Some(&c)).unwrap().objective
    }
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn uniform_consistent_polygon_equals_the_lp_polygon() {
    let (th, xr, yr) = presets::uniform_paper_model();
    let observable = Theta {
        a: DMatrix::from_row_slice(2, 2, &[0.9, 0.2, 0.0, 0.7]),
        b: DMatrix::from_row_slice(2, 1, &[1.0, 0.5]),
        c: DMatrix::from_row_slice(1, 2, &[1.0, 0.0]),
        d: DMatrix::from_row_slice(1, 1, &[0.2]),
    };
    let mut checked = 0;
    for (which, theta) in [&th, &observable].into_iter().enumerate() {
        for seed in 0..12u64 {
            let tr = simulate(theta, &xr, &yr, &DVector::zeros(2), 0.5, 20, seed);
            let prior = StatePrior {
                x_lo: -5.0,
                x_hi: 5.0,
                x0: (seed % 2 == 0).then(|| {
                    (
                        DVector::from_element(2, -1.0),
                        DVector::from_element(2, 1.0),
                    )
                }),
                xr_max: DVector::from_element(2, 1.0),
                yr_max: DVector::from_element(1, 1.0),
            };
            for last in [5usize, 12, 20] {
                let w = Window {
                    first: last.saturating_sub(4).max(1),
                    last,
                };
                let hw = if seed % 3 == 0 {
                    (prior.xr_max.clone(), prior.yr_max.clone())
                } else {
                    (xr.clone(), yr.clone())
                };
                let plane = if seed % 4 == 1 { [1, 0] } else { [0, 1] };
                let exact =
                    consistent_polygon(theta, &tr.u, &tr.y, w, &prior, &hw.0, &hw.1, plane, 64)
                        .unwrap();
                assert_eq!(exact.calls, 0, "the planar path ran");
                // The LP path's polygon (its vertices are points of the set) ...
                let lp =
                    consistent_polygon_lp(theta, &tr.u, &tr.y, w, &prior, &hw.0, &hw.1, plane, 200)
                        .unwrap();
                assert!(lp.exact);
                // Relative to the set and the window's data (the LP's unit, see compare_step).
                let data = tr.y[w.first..=w.last]
                    .iter()
                    .map(|v| v.amax())
                    .fold(0.0, f64::max);
                let scale = scale_of(&lp.vertices).max(data);
                for v in &lp.vertices {
                    assert!(
                        point_in_convex(&exact.vertices, *v, 1e-9),
                        "LP vertex {v:?} outside"
                    );
                }
                // ... and the support function by one LP per direction (the polygon's edges
                // are settled only to 1e-7 of its scale).
                let mut oracle = support_lp(theta, &tr.u, &tr.y, w, &prior, &hw, plane);
                let gap = directions(32)
                    .into_iter()
                    .map(|d| (support(&exact.vertices, d) - oracle(d)).abs() / scale)
                    .fold(0.0, f64::max);
                assert!(
                    gap <= 1e-9,
                    "theta {which}, seed {seed}, t = {last}: gap {gap:e}"
                );
                let truth = [tr.x[last][plane[0]], tr.x[last][plane[1]]];
                assert!(point_in_convex(&exact.vertices, truth, 1e-9));
                checked += 1;
            }
        }
    }
    assert!(checked >= 60);
}
in_browser!(uniform_consistent_polygon_equals_the_lp_polygon);
