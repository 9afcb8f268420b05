//! Set types against hand computations and brute force: Ellipsoid membership, bounding box,
//! volume, support function, projection and slice (2-D, 3-D), the distance between planar
//! ellipses (dense boundary sampling), and the χ² quantile (closed forms, tables, round trips).

use crate::common::*;
use confset::sets::{Ellipsoid, PlanarEllipse};
use confset::stats::chi2_quantile;
use nalgebra::{DMatrix, DVector};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

fn ell(c: &[f64], cov: &[&[f64]], r2: f64) -> Ellipsoid {
    Ellipsoid::new(&DVector::from_column_slice(c), &mat(cov), r2)
}

/// E = {x : (x − c)ᵀΣ⁻¹(x − c) ≤ 3}, c = (1, 2), Σ = [[4, 1], [1, 2]]: Σ⁻¹ = [[2, −1], [−1, 4]]/7,
/// det Σ = 7. For d = (1, 1): dᵀΣ⁻¹d = (2 − 1 − 1 + 4)/7 = 4/7. Box half-widths √(3·4), √(3·2).
/// Area π·r²·√det Σ = 3π√7.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn ellipse_2d_by_hand() {
    let e = ell(&[1.0, 2.0], &[&[4.0, 1.0], &[1.0, 2.0]], 3.0);
    assert_eq!(e.dim(), 2);
    assert!(close(e.mahalanobis2(&[2.0, 3.0]), 4.0 / 7.0, 1e-14));
    assert!(e.contains(&[2.0, 3.0]));
    assert!(e.contains(&[1.0, 2.0]));
    // Along d = (1, 1) the boundary is at s = √(3/(4/7)) = √(21/4).
    let s = (21.0f64 / 4.0).sqrt();
    assert!(e.contains(&[1.0 + s * (1.0 - 1e-9), 2.0 + s * (1.0 - 1e-9)]));
    assert!(!e.contains(&[1.0 + s * (1.0 + 1e-9), 2.0 + s * (1.0 + 1e-9)]));
    // (x − c) = (−1.5, 1.5): (2·2.25 + 2·2.25 + 4·2.25)/7 = 18/7 ≤ 3.
    assert!(close(e.mahalanobis2(&[-0.5, 3.5]), 18.0 / 7.0, 1e-14));
    assert!(e.contains(&[-0.5, 3.5]));
    assert!(!e.contains(&[4.5, 2.0]), "(3.5, 0): 2·12.25/7 = 3.5 > 3");

    let b = e.bounding_box();
    assert_slice_rel(
        &b.lo,
        &[1.0 - 12f64.sqrt(), 2.0 - 6f64.sqrt()],
        1e-14,
        "box lo",
    );
    assert_slice_rel(
        &b.hi,
        &[1.0 + 12f64.sqrt(), 2.0 + 6f64.sqrt()],
        1e-14,
        "box hi",
    );
    assert!(
        close(e.volume(), 3.0 * PI * 7f64.sqrt(), 1e-13),
        "area {}",
        e.volume()
    );

    // Boundary points lie on the boundary and touch the box; the support function is the max
    // of ⟨u, x⟩ over them.
    let pts = e.boundary_2d(20_000).unwrap();
    for &(x, y) in pts.iter().step_by(97) {
        assert!(close(e.mahalanobis2(&[x, y]), 3.0, 1e-12));
    }
    let max_x = pts.iter().map(|p| p.0).fold(f64::MIN, f64::max);
    let min_y = pts.iter().map(|p| p.1).fold(f64::MAX, f64::min);
    assert!((max_x - b.hi[0]).abs() < 1e-6 && (min_y - b.lo[1]).abs() < 1e-6);
    for th in [0.0, 0.7, 2.0, 4.0] {
        let (sn, cs) = f64::sin_cos(th);
        let brute = pts
            .iter()
            .map(|p| p.0 * cs + p.1 * sn)
            .fold(f64::MIN, f64::max);
        let h = e.support(&[cs, sn]);
        // By hand: h(u) = cᵀu + √(3 uᵀΣu).
        let hand = cs + 2.0 * sn + (3.0 * (4.0 * cs * cs + 2.0 * cs * sn + 2.0 * sn * sn)).sqrt();
        assert!(close(h, hand, 1e-14));
        assert!(
            brute <= h + 1e-12 && h - brute < 1e-6,
            "support at θ={th}: {h} vs {brute}"
        );
    }
    // Degenerate (singular) shape: only points on its support are inside.
    let flat = ell(&[0.0, 0.0], &[&[1.0, 0.0], &[0.0, 0.0]], 1.0);
    assert!(!flat.contains(&[0.5, 0.1]));
    assert_eq!(flat.volume(), 0.0);
    // 1-D: length 2·√(r2·σ²).
    let seg = ell(&[3.0], &[&[4.0]], 2.25);
    assert!(close(seg.volume(), 2.0 * (2.25f64 * 4.0).sqrt(), 1e-14));
    assert!(seg.contains(&[6.0]) && !seg.contains(&[6.0 + 1e-9]) && seg.contains(&[0.0]));
}
in_browser!(ellipse_2d_by_hand);

/// 3-D: Σ = [[2, 1, 0], [1, 2, 0], [0, 0, 3]], det 9, r² = 2, c = (0, 1, −1).
/// Volume (4/3)π r³ √det = (4/3)π·2√2·3 = 8√2π.
/// Projection on (x₀, x₂): c (0, −1), Σ diag(2, 3), r² 2 (the shadow of a Gaussian level set is the
/// marginal's level set at the same r²).
/// Slice through (·, 2, −1) along x₀: Schur complement: center 0 + (1/2)(2 − 1) = 1/2,
/// var 2 − 1/2 = 3/2, r² 2 − 1/2 = 3/2, i.e. x₀ ∈ [1/2 − 3/2, 1/2 + 3/2] = [−1, 2]; by hand from
/// the quadratic: (2x² − 2x + 2)/3 = 2 ⇔ x² − x − 2 = 0 ⇔ x ∈ {−1, 2}.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn ellipsoid_3d_project_slice_by_hand() {
    let e = ell(
        &[0.0, 1.0, -1.0],
        &[&[2.0, 1.0, 0.0], &[1.0, 2.0, 0.0], &[0.0, 0.0, 3.0]],
        2.0,
    );
    assert!(
        close(e.volume(), 8.0 * 2f64.sqrt() * PI, 1e-13),
        "{}",
        e.volume()
    );
    let b = e.bounding_box();
    assert_slice_rel(&b.hi, &[2.0, 3.0, -1.0 + 6f64.sqrt()], 1e-14, "box hi");

    let p = e.project(&[0, 2]).unwrap();
    assert_eq!(p.center, vec![0.0, -1.0]);
    assert_eq!(p.cov, vec![vec![2.0, 0.0], vec![0.0, 3.0]]);
    assert_eq!(p.radius2, 2.0);
    let p = e.project(&[2, 0]).unwrap();
    assert_eq!(p.center, vec![-1.0, 0.0]);
    assert_eq!(p.cov, vec![vec![3.0, 0.0], vec![0.0, 2.0]]);
    // The shadow is exact: the max of x₀ over the ellipsoid equals the projection's.
    assert!(close(p.bounding_box().hi[1], b.hi[0], 1e-14));

    let s = e.slice(&[0], &[123.0, 2.0, -1.0]).unwrap().unwrap();
    assert!(close(s.center[0], 0.5, 1e-14));
    assert!(close(s.cov[0][0], 1.5, 1e-14));
    assert!(close(s.radius2, 1.5, 1e-14));
    let sb = s.bounding_box();
    assert!(close(sb.lo[0], -1.0, 1e-14) && close(sb.hi[0], 2.0, 1e-14));
    // Brute force on the line: membership of the 3-D ellipsoid.
    for k in 0..=300 {
        let x = -1.5 + 4.0 * k as f64 / 300.0;
        let inside = e.contains(&[x, 2.0, -1.0]);
        let hand = (-1.0..=2.0).contains(&x);
        if (x + 1.0).abs() > 1e-9 && (x - 2.0).abs() > 1e-9 {
            assert_eq!(inside, hand, "x₀ = {x}");
        }
    }
    // Slice along (x₀, x₁) at x₂ = 0: uncoupled, center (0, 1), shape unchanged, r² = 2 − 1/3.
    let s = e.slice(&[0, 1], &[0.0, 0.0, 0.0]).unwrap().unwrap();
    assert_eq!(s.center, vec![0.0, 1.0]);
    assert_eq!(s.cov, vec![vec![2.0, 1.0], vec![1.0, 2.0]]);
    assert!(close(s.radius2, 5.0 / 3.0, 1e-14));
    // A plane that misses the ellipsoid: (x₂ + 1)²/3 > 2.
    assert!(e.slice(&[0, 1], &[0.0, 0.0, 2.0]).unwrap().is_none());
    // Slicing along every coordinate is the ellipsoid itself.
    assert_eq!(e.slice(&[0, 1, 2], &[9.0, 9.0, 9.0]).unwrap().unwrap(), e);
    // Bad requests are errors naming the field.
    assert_eq!(e.slice(&[0], &[0.0, 0.0]).unwrap_err().field, "slice.point");
    for idx in [vec![3], vec![0, 0], vec![]] {
        assert_eq!(e.project(&idx).unwrap_err().field, "components");
        assert_eq!(e.slice(&idx, &[0.0; 3]).unwrap_err().field, "components");
    }
    assert!(e.boundary_2d(10).is_err());
}
in_browser!(ellipsoid_3d_project_slice_by_hand);

/// Points of a planar ellipse's boundary at angles θ: c + L(cos θ, sin θ), LLᵀ = S (S = r²Σ),
/// L from a hand-written 2×2 Cholesky.
fn boundary(e: &PlanarEllipse, th: f64) -> (f64, f64) {
    let l11 = e.s[0].sqrt();
    let l21 = e.s[1] / l11;
    let l22 = (e.s[2] - l21 * l21).max(0.0).sqrt();
    let (sn, cs) = th.sin_cos();
    (e.c[0] + l11 * cs, e.c[1] + l21 * cs + l22 * sn)
}

fn inside(e: &PlanarEllipse, p: (f64, f64)) -> bool {
    let det = e.s[0] * e.s[2] - e.s[1] * e.s[1];
    let (dx, dy) = (p.0 - e.c[0], p.1 - e.c[1]);
    (e.s[2] * dx * dx - 2.0 * e.s[1] * dx * dy + e.s[0] * dy * dy) / det <= 1.0
}

/// Distance by brute force: `k` points on each boundary, the best pair refined on a finer grid
/// around it; 0 when a sampled boundary point of one ellipse lies inside the other (for convex
/// sets that meet, one boundary crosses or lies inside the other). An upper bound of the true
/// distance when the sets are disjoint (every sample pair is a feasible pair of points).
fn brute_distance(a: &PlanarEllipse, b: &PlanarEllipse, k: usize) -> f64 {
    let step = std::f64::consts::TAU / k as f64;
    let pa: Vec<_> = (0..k).map(|i| boundary(a, i as f64 * step)).collect();
    let pb: Vec<_> = (0..k).map(|i| boundary(b, i as f64 * step)).collect();
    if pa.iter().any(|&p| inside(b, p)) || pb.iter().any(|&p| inside(a, p)) {
        return 0.0;
    }
    let d2 = |p: (f64, f64), q: (f64, f64)| (p.0 - q.0).powi(2) + (p.1 - q.1).powi(2);
    let (mut best, mut bi, mut bj) = (f64::MAX, 0, 0);
    for (i, &p) in pa.iter().enumerate() {
        for (j, &q) in pb.iter().enumerate() {
            let d = d2(p, q);
            if d < best {
                (best, bi, bj) = (d, i, j);
            }
        }
    }
    // Refine: a grid over a window around the best pair, re-centered and shrunk each round
    // (the distance is flat along a flat stretch of boundary, so the window starts wide).
    let (mut ta, mut tb, mut w) = (bi as f64 * step, bj as f64 * step, 8.0 * step);
    let fine = 80;
    for _ in 0..6 {
        let (ca, cb) = (ta, tb);
        for u in 0..=fine {
            let sa = ca - w + 2.0 * w * u as f64 / fine as f64;
            let p = boundary(a, sa);
            for v in 0..=fine {
                let sb = cb - w + 2.0 * w * v as f64 / fine as f64;
                let d = d2(p, boundary(b, sb));
                if d < best {
                    (best, ta, tb) = (d, sa, sb);
                }
            }
        }
        w /= 8.0;
    }
    best.sqrt()
}

fn planar(rng: &mut ChaCha8Rng, spread: f64) -> PlanarEllipse {
    // Semi-axes from 0.02 to 3 (eccentricities up to 150), random rotation and center.
    let a1 = 10f64.powf(rng.random_range(-1.7..0.5));
    let a2 = 10f64.powf(rng.random_range(-1.7..0.5));
    let (sn, cs) = rng.random_range(0.0..PI).sin_cos();
    let (l1, l2) = (a1 * a1, a2 * a2);
    PlanarEllipse {
        c: [
            rng.random_range(-spread..spread),
            rng.random_range(-spread..spread),
        ],
        s: [
            l1 * cs * cs + l2 * sn * sn,
            (l1 - l2) * cs * sn,
            l1 * sn * sn + l2 * cs * cs,
        ],
    }
}

#[track_caller]
fn check_distance(a: &PlanarEllipse, b: &PlanarEllipse, k: usize, what: &str) {
    let d = a.distance(b);
    let brute = brute_distance(a, b, k);
    // d is a lower bound by weak duality and brute an upper bound: they must meet.
    let tol = 1e-6 * (1.0 + brute);
    assert!(
        d <= brute + tol && brute - d <= tol,
        "{what}: distance {d} vs brute force {brute}\n A = {a:?}\n B = {b:?}"
    );
    let sym = b.distance(a);
    assert!(
        (sym - d).abs() <= tol,
        "{what}: not symmetric: {d} vs {sym}"
    );
}

/// PlanarEllipse::distance against brute force on random pairs (overlapping, near, far,
/// eccentric), plus hand cases.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn planar_distance_against_brute_force() {
    // Hand: two discs of radius 1 and 2 with centers 5 apart: 2. Nested: 0. Touching: 0.
    let disc = |c: [f64; 2], r: f64| PlanarEllipse {
        c,
        s: [r * r, 0.0, r * r],
    };
    assert!(close(
        disc([0.0, 0.0], 1.0).distance(&disc([3.0, 4.0], 2.0)),
        2.0,
        1e-9
    ));
    assert_eq!(disc([0.0, 0.0], 1.0).distance(&disc([0.1, 0.0], 3.0)), 0.0);
    assert!(disc([0.0, 0.0], 1.0).distance(&disc([2.0, 0.0], 1.0)) < 1e-9);
    // Axis-aligned ellipses along x: semi-axes 3 and 1 at x = 0 and x = 10: gap 10 − 3 − 3 = 4.
    let e1 = PlanarEllipse {
        c: [0.0, 0.0],
        s: [9.0, 0.0, 1.0],
    };
    let e2 = PlanarEllipse {
        c: [10.0, 0.0],
        s: [9.0, 0.0, 1.0],
    };
    assert!(close(e1.distance(&e2), 4.0, 1e-9));
    // Through Ellipsoid::distance (radius2 folded in) and the 1-D case.
    let a = ell(&[0.0, 0.0], &[&[1.0, 0.0], &[0.0, 1.0]], 4.0);
    let b = ell(&[6.0, 8.0], &[&[1.0, 0.0], &[0.0, 1.0]], 9.0);
    assert!(close(a.distance(&b).unwrap(), 10.0 - 2.0 - 3.0, 1e-9));
    let i1 = ell(&[0.0], &[&[1.0]], 1.0);
    let i2 = ell(&[5.0], &[&[4.0]], 1.0);
    assert!(close(i1.distance(&i2).unwrap(), 5.0 - 1.0 - 2.0, 1e-14));
    assert!(a.distance(&i1).is_err());

    let mut rng = ChaCha8Rng::seed_from_u64(31);
    let (pairs, k) = if cfg!(target_arch = "wasm32") {
        (60, 600)
    } else {
        (300, 1200)
    };
    let mut disjoint = 0;
    for i in 0..pairs {
        let spread = [1.0, 3.0, 8.0][i % 3];
        let (a, b) = (planar(&mut rng, spread), planar(&mut rng, spread));
        disjoint += (brute_distance(&a, &b, 64) > 0.0) as usize;
        check_distance(&a, &b, k, &format!("random pair {i}"));
    }
    assert!(
        disjoint > pairs / 4 && disjoint < pairs,
        "{disjoint}/{pairs} disjoint pairs"
    );
}
in_browser!(planar_distance_against_brute_force);

/// Long thin ellipses side by side with a small gap: the directions that separate them form an
/// arc narrower than a 5° grid. Two copies of the same ellipse translated across their long
/// axis by `off` are off − 2·(short semi-axis) apart, whatever the rotation: semi-axes 10 and
/// 0.1 shifted by 0.3 → 0.1; semi-axes 100 and 0.01 shifted by 0.021 → 0.001.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn planar_distance_thin_parallel_ellipses() {
    // (semi-axes², offset across, expected distance): 10 × 0.1 with gap 0.1, and 100 × 0.01
    // with gap 0.001 (separating directions within ≈ 1e-5 rad).
    for (l1, l2, off, want) in [(100.0, 0.01, 0.3, 0.1), (1e4, 1e-4, 0.021, 0.001)] {
        for deg in [0.0, 2.5, 17.0, 33.3, 90.0, 122.0] {
            let th = deg * PI / 180.0;
            let (sn, cs) = f64::sin_cos(th);
            let s = [
                l1 * cs * cs + l2 * sn * sn,
                (l1 - l2) * cs * sn,
                l1 * sn * sn + l2 * cs * cs,
            ];
            let a = PlanarEllipse { c: [1.0, -2.0], s };
            // Offset along the short axis (−sin θ, cos θ).
            let b = PlanarEllipse {
                c: [1.0 - off * sn, -2.0 + off * cs],
                s,
            };
            let d = a.distance(&b);
            assert!(
                (d - want).abs() < 1e-9,
                "rotation {deg}°, axes² {l1}/{l2}: distance {d}, expected {want}"
            );
        }
    }
}
in_browser!(planar_distance_thin_parallel_ellipses);

/// χ²(α, k): tables; the closed form for k = 2 (−2 ln(1 − α)); even k by the closed-form CDF
/// 1 − e^{−x/2} Σ_{j<k/2} (x/2)^j / j! solved here by bisection; round trips; α ∉ (0, 1) rejected.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn chi2_quantiles() {
    let table = [
        (0.95, 1, 3.841_458_820_694_124),
        (0.99, 1, 6.634_896_601_021_214),
        (0.9, 1, 2.705_543_454_095_404),
        (0.95, 2, 5.991_464_547_107_979),
        (0.95, 3, 7.814_727_903_251_178),
        (0.95, 4, 9.487_729_036_781_154),
        (0.99, 4, 13.276_704_135_987_622),
        (0.5, 1, 0.454_936_423_119_572_8),
    ];
    for (a, k, q) in table {
        let got = chi2_quantile(a, k).unwrap();
        assert!(rel_close(got, q, 1e-12), "χ²({a}, {k}) = {got}, table {q}");
    }
    let cdf_even = |x: f64, k: usize| {
        let (mut term, mut sum) = (1.0, 0.0);
        for j in 0..k / 2 {
            if j > 0 {
                term *= x / 2.0 / j as f64;
            }
            sum += term;
        }
        1.0 - (-x / 2.0).exp() * sum
    };
    for &a in &[1e-4, 0.01, 0.05, 0.3, 0.5, 0.683, 0.9, 0.95, 0.99, 0.999] {
        let q2 = chi2_quantile(a, 2).unwrap();
        assert!(
            rel_close(q2, -2.0 * (1.0 - a).ln(), 1e-11),
            "k=2, α={a}: {q2}"
        );
        for k in [4, 6, 8] {
            let (mut lo, mut hi) = (0.0, 200.0);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if cdf_even(mid, k) < a {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let q = chi2_quantile(a, k).unwrap();
            assert!(
                rel_close(q, lo, 1e-10),
                "k={k}, α={a}: {q} vs bisection {lo}"
            );
            assert!((cdf_even(q, k) - a).abs() < 1e-12);
        }
        // Monotone in α and k.
        for k in 1..=5 {
            assert!(chi2_quantile(a, k).unwrap() < chi2_quantile(a, k + 1).unwrap());
        }
    }
    for bad in [
        0.0,
        1.0,
        -0.1,
        1.1,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ] {
        let e = chi2_quantile(bad, 2).unwrap_err();
        assert_eq!(e.field, "alpha");
        assert!(e.to_string().contains("strictly between 0 and 1"), "{e}");
        assert!(Ellipsoid::at_level(&DVector::zeros(2), &DMatrix::identity(2, 2), bad).is_err());
    }
    assert!(chi2_quantile(0.5, 0).is_err());
    let e = Ellipsoid::at_level(&DVector::zeros(2), &DMatrix::identity(2, 2), 0.95).unwrap();
    assert!(rel_close(e.radius2, -2.0 * 0.05f64.ln(), 1e-12));
}
in_browser!(chi2_quantiles);
