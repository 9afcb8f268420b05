//! A planar convex set known only through its support function (an LP per direction), turned
//! into its exact polygon.
//!
//! Sampling h(d) in fixed directions gives an outer polygon whose corners are not points of the
//! set. Here each support call also returns the optimal point, and the gap between two
//! consecutive points a, b is closed by asking for the support in the direction normal to ab:
//! if nothing of the set lies beyond ab, ab is an edge (exact); otherwise the new point is a
//! new boundary point and both halves are examined. Every vertex and every edge costs about one
//! call, so a polygon with V vertices is exact after about 2V calls; a budget caps the calls and
//! the result says whether every edge was confirmed, and how far the outer bound can still be.

use crate::error::Result;
use serde::{Deserialize, Serialize};

/// The polygon of a planar convex set.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct SupportPolygon {
    /// Counter-clockwise vertices (points of the set).
    pub vertices: Vec<[f64; 2]>,
    /// Every edge was confirmed by a support call: the polygon is the set, up to `tol`.
    pub exact: bool,
    /// Largest distance from an unconfirmed edge to the outer corner of its two supporting
    /// lines (0 when exact): the set lies within this distance of the polygon.
    pub gap: f64,
    /// Support calls made.
    pub calls: usize,
    /// Interval hull [min x, max x, min y, max y] (from the four axis directions).
    pub hull: [f64; 4],
}

impl SupportPolygon {
    /// Whether p may lie in the set: within `rel_tol`·scale of the polygon (see
    /// [`super::point_in_convex`]) plus the `gap` an unfinished budget leaves (the set lies
    /// within `gap` of the polygon). Exact polygons: an exact test up to the tolerance.
    pub fn contains(&self, p: [f64; 2], rel_tol: f64) -> bool {
        let scale = super::polygon_scale(&self.vertices);
        super::point_in_convex(&self.vertices, p, rel_tol + self.gap / scale)
    }
}

struct Probe {
    angle: f64,
    dir: [f64; 2],
    value: f64,
    point: [f64; 2],
}

/// Build the polygon with at most `budget` calls of `support(d) = (h(d), argmax point)`.
/// `rel_tol` is the tolerance of the edge test relative to the set's scale (its largest
/// coordinate, read from the four axis calls): the solver's relative accuracy.
pub fn polygon_from_support<F>(
    mut support: F,
    budget: usize,
    rel_tol: f64,
) -> Result<SupportPolygon>
where
    F: FnMut([f64; 2]) -> Result<(f64, [f64; 2])>,
{
    let mut calls = 0;
    let mut probe = |angle: f64, calls: &mut usize| -> Result<Probe> {
        let dir = [angle.cos(), angle.sin()];
        let (value, point) = support(dir)?;
        *calls += 1;
        Ok(Probe {
            angle,
            dir,
            value,
            point,
        })
    };
    let quarter = std::f64::consts::FRAC_PI_2;
    let mut probes = Vec::new();
    for i in 0..4 {
        probes.push(probe(i as f64 * quarter, &mut calls)?);
    }
    let hull = [
        -probes[2].value,
        probes[0].value,
        -probes[3].value,
        probes[1].value,
    ];
    // Relative to the set's own scale, with no absolute floor: a floor of 1 merged every
    // vertex of a set 10⁻⁸ wide into one point (issue 25).
    let tol = rel_tol * hull.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let dot = |d: [f64; 2], p: [f64; 2]| d[0] * p[0] + d[1] * p[1];
    let close =
        |a: [f64; 2], b: [f64; 2]| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt() <= tol;
    // confirmed[i]: the stretch from probes[i] to probes[i+1] is settled.
    let mut confirmed = vec![false; probes.len()];
    loop {
        // The longest unsettled stretch first, so that a budget leaves the smallest gap.
        let next = (0..probes.len())
            .filter(|&i| !confirmed[i])
            .map(|i| {
                let (a, b) = (probes[i].point, probes[(i + 1) % probes.len()].point);
                (i, (a[0] - b[0]).hypot(a[1] - b[1]))
            })
            .max_by(|x, y| x.1.total_cmp(&y.1));
        let Some((i, _)) = next else { break };
        let j = (i + 1) % probes.len();
        let (a, b) = (probes[i].point, probes[j].point);
        if close(a, b) {
            confirmed[i] = true;
            continue;
        }
        if calls >= budget {
            break;
        }
        // Outward normal of a → b (counter-clockwise order), kept between the two directions.
        let (lo, mut hi) = (probes[i].angle, probes[j].angle);
        if hi <= lo {
            hi += 2.0 * std::f64::consts::PI;
        }
        let mut angle = (b[1] - a[1]).atan2(b[0] - a[0]) - quarter;
        while angle < lo {
            angle += 2.0 * std::f64::consts::PI;
        }
        if angle > hi {
            angle = 0.5 * (lo + hi);
        }
        let p = probe(angle, &mut calls)?;
        if p.value <= dot(p.dir, a).max(dot(p.dir, b)) + tol {
            confirmed[i] = true;
        } else {
            probes.insert(i + 1, p);
            confirmed.insert(i + 1, false);
        }
    }
    // Gap of each unsettled stretch: the corner of its two supporting lines.
    let mut gap: f64 = 0.0;
    for i in 0..probes.len() {
        if confirmed[i] {
            continue;
        }
        let (p, q) = (&probes[i], &probes[(i + 1) % probes.len()]);
        let det = p.dir[0] * q.dir[1] - p.dir[1] * q.dir[0];
        let (a, b) = (p.point, q.point);
        if det.abs() < 1e-12 {
            gap = f64::INFINITY;
            continue;
        }
        let corner = [
            (p.value * q.dir[1] - q.value * p.dir[1]) / det,
            (p.dir[0] * q.value - q.dir[0] * p.value) / det,
        ];
        let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
        let len = ex.hypot(ey).max(f64::MIN_POSITIVE);
        gap = gap.max(((corner[0] - a[0]) * ey - (corner[1] - a[1]) * ex).abs() / len);
    }
    Ok(SupportPolygon {
        vertices: simplify(probes.iter().map(|p| p.point).collect(), tol),
        exact: gap == 0.0,
        gap,
        calls,
        hull,
    })
}

/// Drop repeated points and points on the segment between their neighbours.
fn simplify(points: Vec<[f64; 2]>, tol: f64) -> Vec<[f64; 2]> {
    let mut v: Vec<[f64; 2]> = Vec::with_capacity(points.len());
    for p in points {
        if v.last()
            .is_none_or(|q: &[f64; 2]| (p[0] - q[0]).hypot(p[1] - q[1]) > tol)
        {
            v.push(p);
        }
    }
    while v.len() > 1 && (v[0][0] - v[v.len() - 1][0]).hypot(v[0][1] - v[v.len() - 1][1]) <= tol {
        v.pop();
    }
    let mut changed = true;
    while changed && v.len() > 2 {
        changed = false;
        for i in 0..v.len() {
            let (a, b, c) = (v[(i + v.len() - 1) % v.len()], v[i], v[(i + 1) % v.len()]);
            let (ex, ey) = (c[0] - a[0], c[1] - a[1]);
            let len = ex.hypot(ey);
            if len > 0.0 && ((b[0] - a[0]) * ey - (b[1] - a[1]) * ex).abs() / len <= tol {
                v.remove(i);
                changed = true;
                break;
            }
        }
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Support of a polygon given by its vertices: the best vertex.
    fn oracle(vertices: &[[f64; 2]]) -> impl FnMut([f64; 2]) -> Result<(f64, [f64; 2])> + '_ {
        move |d| {
            let best = vertices
                .iter()
                .copied()
                .max_by(|a, b| (d[0] * a[0] + d[1] * a[1]).total_cmp(&(d[0] * b[0] + d[1] * b[1])))
                .unwrap();
            Ok((d[0] * best[0] + d[1] * best[1], best))
        }
    }

    #[test]
    fn recovers_a_polygon_exactly() {
        let hexagon: Vec<[f64; 2]> = (0..7)
            .map(|i| {
                let t = 0.3 + i as f64 * 0.9;
                [2.0 * t.cos() + 1.0, t.sin() - 0.5]
            })
            .collect();
        let p = polygon_from_support(oracle(&hexagon), 100, 1e-9).unwrap();
        assert!(p.exact);
        assert_eq!(p.vertices.len(), 7, "{:?}", p.vertices);
        for v in &hexagon {
            assert!(p
                .vertices
                .iter()
                .any(|w| (w[0] - v[0]).hypot(w[1] - v[1]) < 1e-12));
        }
        assert!(p.calls <= 4 + 2 * 7, "{} calls", p.calls);
        // A budget too small leaves a gap that bounds the error.
        let q = polygon_from_support(oracle(&hexagon), 5, 1e-9).unwrap();
        assert!(!q.exact && q.gap > 0.0 && q.gap.is_finite());
    }

    #[test]
    fn segments_and_points() {
        let seg = [[0.0, 0.0], [1.0, 2.0]];
        let p = polygon_from_support(oracle(&seg), 50, 1e-9).unwrap();
        assert!(p.exact);
        assert_eq!(p.vertices.len(), 2);
        let pt = [[3.0, -1.0]];
        let p = polygon_from_support(oracle(&pt), 50, 1e-9).unwrap();
        assert_eq!(p.vertices, vec![[3.0, -1.0]]);
        let want = [3.0, 3.0, -1.0, -1.0];
        assert!(
            p.hull.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-12),
            "{:?}",
            p.hull
        );
    }
}
