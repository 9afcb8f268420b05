//! Geometry of the plane, written once for every set of two state components: the shoelace
//! area, the convex hull, membership in a convex polygon, the corners of a box, the image of a
//! point or an ellipse under a 2×2 map, and the Minkowski sum of convex polygons (with the
//! corners of a noise box G·[−b, b]^p, its usual second term).
//!
//! Points are `[x, y]`; polygons are lists of vertices, counter-clockwise where it matters,
//! not closed (the first vertex is not repeated) unless said. A 2×2 map is the top-left 2×2
//! block of a matrix (the model's F of a two-state system).

use super::Ellipsoid;
use nalgebra::{DMatrix, DVector};

/// Shoelace area, positive counter-clockwise (the polygon closed or not: the closing edge's
/// term is about the first vertex, so it is zero).
///
/// The cross products are taken about the first vertex, not the origin: a small polygon far from
/// the origin (a region around x̄ = 10⁶) would otherwise sum products of size |x̄|² that cancel
/// to its area, losing its digits.
pub fn signed_area(pts: &[[f64; 2]]) -> f64 {
    let Some(&o) = pts.first() else { return 0.0 };
    pts.windows(2)
        .map(|w| {
            let (a, b) = (
                [w[0][0] - o[0], w[0][1] - o[1]],
                [w[1][0] - o[0], w[1][1] - o[1]],
            );
            a[0] * b[1] - b[0] * a[1]
        })
        .sum::<f64>()
        * 0.5
}

/// Area of a simple polygon, either orientation ([`signed_area`]'s magnitude).
pub fn polygon_area(pts: &[[f64; 2]]) -> f64 {
    signed_area(pts).abs()
}

/// The convex hull of points, counter-clockwise from the lowest-leftmost (Andrew's monotone
/// chain; collinear points dropped). Fewer than three distinct points come back as they are,
/// sorted.
pub fn convex_hull(mut pts: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    pts.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut hull: Vec<[f64; 2]> = Vec::with_capacity(2 * pts.len());
    // The lower chain left to right, then the upper chain right to left.
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &[f64; 2]>> = if pass == 0 {
            Box::new(pts.iter())
        } else {
            Box::new(pts.iter().rev())
        };
        for &p in iter {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

/// Whether p lies in the convex counter-clockwise polygon `poly` (the vertices of a
/// [`super::SupportPolygon`], or any convex polygon) within `tol`, relative to its size (scale =
/// max(1, largest |coordinate| of the vertices)): for every edge a → b the cross product
/// (b − a) × (p − a) is ≥ −tol·scale², i.e. p is at most about tol·scale outside an edge of
/// length ~scale, and edges much shorter than the polygon (near-duplicate vertices of a
/// sampled outline, whose direction is noise) cannot exclude it. A polygon of one or two
/// vertices (a point, a segment) is checked by the distance tol·scale to it; an empty one
/// holds nothing.
pub fn point_in_convex(poly: &[[f64; 2]], p: [f64; 2], tol: f64) -> bool {
    let scale = polygon_scale(poly);
    let slack = tol * scale;
    let dist = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    match poly {
        [] => false,
        [a] => dist(*a, p) <= slack,
        [a, b] => {
            let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
            let len2 = ex * ex + ey * ey;
            let s = if len2 > 0.0 {
                (((p[0] - a[0]) * ex + (p[1] - a[1]) * ey) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            dist([a[0] + s * ex, a[1] + s * ey], p) <= slack
        }
        _ => (0..poly.len()).all(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            let cross = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
            cross >= -slack * scale
        }),
    }
}

/// max(1, largest |coordinate| of the vertices): the scale of [`point_in_convex`]'s tolerance.
pub(crate) fn polygon_scale(poly: &[[f64; 2]]) -> f64 {
    poly.iter()
        .map(|q| q[0].abs().max(q[1].abs()))
        .fold(1.0, f64::max)
}

/// The corners of the box [lo₀, hi₀] × [lo₁, hi₁], counter-clockwise from lo (the first two
/// entries of `lo` and `hi`).
pub fn box_corners(lo: &[f64], hi: &[f64]) -> Vec<[f64; 2]> {
    vec![
        [lo[0], lo[1]],
        [hi[0], lo[1]],
        [hi[0], hi[1]],
        [lo[0], hi[1]],
    ]
}

/// F·p for the 2×2 map F.
pub fn map_point(f: &DMatrix<f64>, p: [f64; 2]) -> [f64; 2] {
    [
        f[(0, 0)] * p[0] + f[(0, 1)] * p[1],
        f[(1, 0)] * p[0] + f[(1, 1)] * p[1],
    ]
}

/// The image F·E of a planar ellipse E = {x : (x − c)ᵀ C⁻¹ (x − c) ≤ r²} under the 2×2 map F:
/// centre F·c, shape F·C·Fᵀ, the same r² (exact for any F; degenerate when F is singular).
pub fn map_ellipse(f: &DMatrix<f64>, e: &Ellipsoid) -> Ellipsoid {
    let c = DMatrix::from_fn(2, 2, |i, j| e.cov[i][j]);
    let fc = f * c * f.transpose();
    let center = map_point(f, [e.center[0], e.center[1]]);
    Ellipsoid::new(&DVector::from_column_slice(&center), &fc, e.radius2)
}

/// Most noise components whose box corners [`box_image_corners`] enumerates (2^p corners).
pub const MAX_BOX_COMPONENTS: usize = 12;

/// The corners' images G·s of the box s ∈ [−b, b]^p under the 2×p map G (its first two rows):
/// 2^p points whose hull is G·[−b, b]^p. Only the first [`MAX_BOX_COMPONENTS`] columns count,
/// so the enumeration stays at most 4,096 points.
pub fn box_image_corners(g: &DMatrix<f64>, b: f64) -> Vec<[f64; 2]> {
    let p = g.ncols().min(MAX_BOX_COMPONENTS);
    (0..(1usize << p))
        .map(|mask| {
            let mut shift = [0.0; 2];
            for j in 0..p {
                let s = if mask >> j & 1 == 1 { b } else { -b };
                shift[0] += g[(0, j)] * s;
                shift[1] += g[(1, j)] * s;
            }
            shift
        })
        .collect()
}

/// The Minkowski sum A ⊕ B of two convex polygons (or point sets), as the convex hull of every
/// sum a + b: exact, counter-clockwise.
pub fn minkowski_sum(a: &[[f64; 2]], b: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut pts = Vec::with_capacity(a.len() * b.len());
    for s in b {
        for v in a {
            pts.push([v[0] + s[0], v[1] + s[1]]);
        }
    }
    convex_hull(pts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hull_of_a_square_with_inner_and_collinear_points() {
        let pts = vec![
            [1.0, 1.0],
            [0.0, 0.0],
            [2.0, 0.0],
            [1.0, 0.0],
            [2.0, 2.0],
            [0.0, 2.0],
            [0.5, 1.5],
        ];
        let h = convex_hull(pts);
        assert_eq!(h, vec![[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]);
        assert_eq!(signed_area(&h), 4.0);
        assert_eq!(
            polygon_area(&h.iter().rev().copied().collect::<Vec<_>>()),
            4.0
        );
    }

    #[test]
    fn minkowski_sum_of_a_square_and_a_noise_segment() {
        let square = box_corners(&[0.0, 0.0], &[1.0, 1.0]);
        // G = (1, 0)ᵀ, b = 0.5: the segment [−0.5, 0.5] × {0}.
        let g = DMatrix::from_row_slice(2, 1, &[1.0, 0.0]);
        let noise = box_image_corners(&g, 0.5);
        assert_eq!(noise, vec![[-0.5, 0.0], [0.5, 0.0]]);
        let sum = minkowski_sum(&square, &noise);
        assert_eq!(polygon_area(&sum), 2.0);
        assert!(point_in_convex(&sum, [1.4, 0.5], 0.0));
        assert!(!point_in_convex(&sum, [1.6, 0.5], 1e-9));
    }

    #[test]
    fn an_ellipse_mapped_keeps_its_radius_and_scales_its_area() {
        let e = Ellipsoid::new(
            &DVector::from_column_slice(&[1.0, 0.0]),
            &DMatrix::identity(2, 2),
            4.0,
        );
        let f = DMatrix::from_row_slice(2, 2, &[2.0, 0.0, 0.0, 3.0]);
        let m = map_ellipse(&f, &e);
        assert_eq!(m.center, vec![2.0, 0.0]);
        assert_eq!(m.radius2, 4.0);
        assert!((m.volume() - 6.0 * e.volume()).abs() < 1e-12 * e.volume());
        assert_eq!(map_point(&f, [1.0, 1.0]), [2.0, 3.0]);
    }
}
