//! Exact convex polygons of the plane: the set engine of the planar set-membership paths
//! (Tempo's state estimator with a 2-D state, Pavelková's consistent states for n = 2).
//!
//! With per-sample l∞ bounds, the set of states consistent with the data is a convex polygon,
//! updated exactly by three linear-time operations per sample: clip by the measurement strip,
//! apply the linear map, add the noise box (a Minkowski sum). The interval hull and Tempo's l∞
//! central estimate (31) are then the vertices' min and max. No LP, and no solver tolerance.
//!
//! A [`ConvexPolygon`] is bounded and not empty: one vertex (a point), two (a segment) or at
//! least three, counter-clockwise, with no repeated and no collinear vertices. Operations that
//! can empty a set (the clips) return `None`: the data contradict the bounds.
//!
//! Rounding: every predicate (is a vertex on the line? is it collinear with its neighbours?)
//! is decided with a tolerance of [`REL_TOL`] = 2⁻⁴⁰ times the polygon's scale (its extent, the
//! larger side of its interval hull, or its largest |coordinate| when larger), so that an intersection point computed twice, or a vertex that
//! rounding moved off an edge by 10⁻¹⁶, is merged instead of making a sliver. Cross and dot
//! products are taken on differences divided by a power of two near the extent (an exact
//! division), so sets of size 10⁻¹⁵⁰ or 10¹⁵⁰ neither underflow nor overflow.

/// Relative tolerance of the predicates: 2⁻⁴⁰ of the polygon's extent (≈ 9·10⁻¹³).
pub const REL_TOL: f64 = 1.0 / (1u64 << 40) as f64;

/// A bounded, non-empty convex polygon (possibly a segment or a point).
#[derive(Debug, Clone, PartialEq)]
pub struct ConvexPolygon {
    vertices: Vec<[f64; 2]>,
}

/// The power of two at or below v (1 for 0, non-finite or subnormal-free fallback), so that
/// dividing by it is exact.
fn pow2_below(v: f64) -> f64 {
    if !(v > 0.0 && v.is_finite()) {
        return 1.0;
    }
    let e = (v.log2().floor() as i32).clamp(-1022, 1023);
    2f64.powi(e)
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

fn cross(u: [f64; 2], w: [f64; 2]) -> f64 {
    u[0] * w[1] - u[1] * w[0]
}

fn dot(u: [f64; 2], w: [f64; 2]) -> f64 {
    u[0] * w[0] + u[1] * w[1]
}

fn scaled(u: [f64; 2], s: f64) -> [f64; 2] {
    [u[0] / s, u[1] / s]
}

/// Extent (the larger side of the interval hull) of a point list.
fn extent(pts: &[[f64; 2]]) -> f64 {
    let h = interval_hull_of(pts);
    (h[1] - h[0]).max(h[3] - h[2])
}

/// The scale of the predicates' tolerance: the extent, or the largest |coordinate| when that
/// is larger (a set far smaller than its distance from the origin carries rounding errors of
/// its coordinates' size, not of its own: a set the data pin to a point must stay a point,
/// not become empty).
fn tol_scale(pts: &[[f64; 2]]) -> f64 {
    let big = pts
        .iter()
        .fold(0.0f64, |m, v| m.max(v[0].abs()).max(v[1].abs()));
    extent(pts).max(big)
}

fn interval_hull_of(pts: &[[f64; 2]]) -> [f64; 4] {
    let mut h = [
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ];
    for p in pts {
        h[0] = h[0].min(p[0]);
        h[1] = h[1].max(p[0]);
        h[2] = h[2].min(p[1]);
        h[3] = h[3].max(p[1]);
    }
    h
}

/// The sign of u × w without overflow or underflow: each vector is first divided by a power
/// of two near its own size (the sign does not change).
fn cross_sign(u: [f64; 2], w: [f64; 2]) -> f64 {
    let su = pow2_below(u[0].abs().max(u[1].abs()));
    let sw = pow2_below(w[0].abs().max(w[1].abs()));
    cross(scaled(u, su), scaled(w, sw))
}

/// Index of the lowest vertex (least y, then least x): the start of the edges' angle order.
fn lowest(v: &[[f64; 2]]) -> usize {
    (0..v.len())
        .min_by(|&i, &j| {
            v[i][1]
                .total_cmp(&v[j][1])
                .then(v[i][0].total_cmp(&v[j][0]))
        })
        .unwrap_or(0)
}

impl ConvexPolygon {
    /// The polygon of points already in counter-clockwise convex position up to rounding (the
    /// output of a clip, a map or an edge merge): repeated and collinear vertices are merged
    /// in one linear scan from the lowest vertex. Anything the scan cannot certify convex
    /// (a sequence that folds back) goes through the convex hull instead.
    fn cleaned(pts: Vec<[f64; 2]>) -> ConvexPolygon {
        if pts.len() <= 1 {
            return ConvexPolygon { vertices: pts };
        }
        let ext = extent(&pts);
        if ext == 0.0 || !ext.is_finite() {
            return ConvexPolygon {
                vertices: vec![pts[0]],
            };
        }
        let s = pow2_below(ext);
        let tol = REL_TOL * tol_scale(&pts) / s;
        let start = lowest(&pts);
        let n = pts.len();
        let mut st: Vec<[f64; 2]> = Vec::with_capacity(n + 1);
        st.push(pts[start]);
        for k in 1..=n {
            let p = pts[(start + k) % n];
            let top = st[st.len() - 1];
            if scaled(sub(p, top), 1.0)
                .iter()
                .all(|c| (c / s).abs() <= tol)
            {
                continue;
            }
            while st.len() >= 2 {
                let (a, b) = (st[st.len() - 2], st[st.len() - 1]);
                let u = scaled(sub(b, a), s);
                let w = scaled(sub(p, a), s);
                let c = cross(u, w);
                let len = w[0].hypot(w[1]);
                // b is on the line a → p (within tol) and between them, or a reflex turn.
                let drop =
                    c < -tol * len || (c <= tol * len && dot(u, scaled(sub(p, b), s)) >= 0.0);
                if drop {
                    st.pop();
                } else {
                    break;
                }
            }
            st.push(p);
        }
        // The scan closed on the start vertex.
        if st.len() > 1 {
            let (a, b) = (st[0], st[st.len() - 1]);
            if sub(a, b).iter().all(|c| (c / s).abs() <= tol) {
                st.pop();
            }
        }
        // A certified polygon turns left at every vertex; a segment has two distinct ends.
        let ok = match st.len() {
            0 | 1 => true,
            2 => true,
            m => (0..m).all(|i| {
                let (a, b, c) = (st[(i + m - 1) % m], st[i], st[(i + 1) % m]);
                let w = scaled(sub(c, a), s);
                cross(scaled(sub(b, a), s), w) > tol * w[0].hypot(w[1])
            }),
        };
        if ok && !st.is_empty() {
            ConvexPolygon { vertices: st }
        } else {
            ConvexPolygon::hull(&pts).expect("points are not empty")
        }
    }

    /// The convex hull of points (Andrew's monotone chain, collinear and repeated points merged
    /// within [`REL_TOL`] of the points' extent); `None` for no points.
    pub fn hull(points: &[[f64; 2]]) -> Option<ConvexPolygon> {
        let mut pts: Vec<[f64; 2]> = points.to_vec();
        if pts.is_empty() {
            return None;
        }
        pts.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
        let ext = extent(&pts);
        if ext == 0.0 || !ext.is_finite() {
            return Some(ConvexPolygon {
                vertices: vec![pts[0]],
            });
        }
        let s = pow2_below(ext);
        let tol = REL_TOL * tol_scale(&pts) / s;
        let mut hull: Vec<[f64; 2]> = Vec::with_capacity(2 * pts.len());
        for pass in 0..2 {
            let begin = hull.len();
            for k in 0..pts.len() {
                let p = if pass == 0 {
                    pts[k]
                } else {
                    pts[pts.len() - 1 - k]
                };
                while hull.len() >= begin + 2 {
                    let (a, b) = (hull[hull.len() - 2], hull[hull.len() - 1]);
                    let w = scaled(sub(p, a), s);
                    if cross(scaled(sub(b, a), s), w) <= tol * w[0].hypot(w[1]) {
                        hull.pop();
                    } else {
                        break;
                    }
                }
                hull.push(p);
            }
            hull.pop();
        }
        // Merge ends closer than the tolerance (near-duplicate points).
        let mut out: Vec<[f64; 2]> = Vec::with_capacity(hull.len());
        for p in hull {
            if out
                .last()
                .is_none_or(|q| sub(p, *q).iter().any(|c| (c / s).abs() > tol))
            {
                out.push(p);
            }
        }
        while out.len() > 1
            && sub(out[0], out[out.len() - 1])
                .iter()
                .all(|c| (c / s).abs() <= tol)
        {
            out.pop();
        }
        if out.is_empty() {
            out.push(pts[0]);
        }
        Some(ConvexPolygon { vertices: out })
    }

    /// A point.
    pub fn point(p: [f64; 2]) -> ConvexPolygon {
        ConvexPolygon { vertices: vec![p] }
    }

    /// The segment from a to b (a point when they coincide).
    pub fn segment(a: [f64; 2], b: [f64; 2]) -> ConvexPolygon {
        ConvexPolygon::cleaned(vec![a, b])
    }

    /// The box [lo₀, hi₀] × [lo₁, hi₁] (lo ≤ hi; a side of width 0 makes a segment or a point).
    pub fn rectangle(lo: [f64; 2], hi: [f64; 2]) -> ConvexPolygon {
        ConvexPolygon::cleaned(vec![
            [lo[0], lo[1]],
            [hi[0], lo[1]],
            [hi[0], hi[1]],
            [lo[0], hi[1]],
        ])
    }

    /// The vertices, counter-clockwise (one for a point, two for a segment).
    pub fn vertices(&self) -> &[[f64; 2]] {
        &self.vertices
    }

    /// The polygon's extent: the larger side of its interval hull.
    pub fn extent(&self) -> f64 {
        extent(&self.vertices)
    }

    /// The intersection with the half-plane a·x ≤ b (Sutherland–Hodgman against one line, linear
    /// time for a convex polygon); `None` when it is empty. A vertex within the tolerance of
    /// the line counts as on it: a polygon touching the line keeps its vertex or edge there.
    pub fn clip(&self, a: [f64; 2], b: f64) -> Option<ConvexPolygon> {
        // Scale the constraint by a power of two (exact): a·x with |a| and |x| both huge must
        // not overflow.
        let sa = pow2_below(a[0].abs().max(a[1].abs()));
        if a[0] == 0.0 && a[1] == 0.0 {
            return (0.0 <= b).then(|| self.clone());
        }
        let (a, b) = (scaled(a, sa), b / sa);
        let big = self
            .vertices
            .iter()
            .fold(0.0f64, |m, v| m.max(v[0].abs()).max(v[1].abs()));
        let an = a[0].abs() + a[1].abs();
        // The polygon's own tolerance along a, plus the rounding of a·v − b itself.
        let tol =
            REL_TOL * an * tol_scale(&self.vertices) + 8.0 * f64::EPSILON * (an * big + b.abs());
        let val: Vec<f64> = self.vertices.iter().map(|v| dot(a, *v) - b).collect();
        if val.iter().all(|&s| s > tol) {
            return None;
        }
        if val.iter().all(|&s| s <= tol) {
            return Some(self.clone());
        }
        let n = self.vertices.len();
        let mut out = Vec::with_capacity(n + 1);
        for i in 0..n {
            let j = (i + 1) % n;
            let (p, q) = (self.vertices[i], self.vertices[j]);
            let (sp, sq) = (val[i], val[j]);
            if sp <= tol {
                out.push(p);
            }
            if (sp < -tol && sq > tol) || (sp > tol && sq < -tol) {
                let t = sp / (sp - sq);
                out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
            }
        }
        Some(ConvexPolygon::cleaned(out))
    }

    /// The intersection with the strip lo ≤ a·x ≤ hi (two half-planes); `None` when empty.
    pub fn clip_strip(&self, a: [f64; 2], lo: f64, hi: f64) -> Option<ConvexPolygon> {
        self.clip(a, hi)?.clip([-a[0], -a[1]], -lo)
    }

    /// The image M·P under the 2×2 map `m` (rows): counter-clockwise order kept when
    /// det M > 0, reversed when det M < 0; a (nearly) singular map collapses the polygon onto
    /// a segment or a point, taken as the hull of the images.
    pub fn map(&self, m: [[f64; 2]; 2]) -> ConvexPolygon {
        let img: Vec<[f64; 2]> = self
            .vertices
            .iter()
            .map(|v| [dot(m[0], *v), dot(m[1], *v)])
            .collect();
        let sm = pow2_below(m.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs())));
        let det = cross(scaled(m[0], sm), scaled(m[1], sm));
        if det.abs() <= REL_TOL {
            return ConvexPolygon::hull(&img).expect("a polygon has vertices");
        }
        let mut img = img;
        if det < 0.0 {
            img.reverse();
        }
        ConvexPolygon::cleaned(img)
    }

    /// The polygon moved by t.
    pub fn translate(&self, t: [f64; 2]) -> ConvexPolygon {
        ConvexPolygon {
            vertices: self
                .vertices
                .iter()
                .map(|v| [v[0] + t[0], v[1] + t[1]])
                .collect(),
        }
    }

    /// The Minkowski sum P ⊕ Q by merging the two edge sequences by angle from their lowest
    /// vertices (linear time). Points and segments are polygons of one and two vertices.
    pub fn minkowski(&self, other: &ConvexPolygon) -> ConvexPolygon {
        let (p, q) = (&self.vertices, &other.vertices);
        if q.len() == 1 {
            return self.translate(q[0]);
        }
        if p.len() == 1 {
            return other.translate(p[0]);
        }
        let (n, m) = (p.len(), q.len());
        let (pi0, qi0) = (lowest(p), lowest(q));
        let pv = |i: usize| p[(pi0 + i) % n];
        let qv = |j: usize| q[(qi0 + j) % m];
        let mut out = Vec::with_capacity(n + m);
        let (mut i, mut j) = (0, 0);
        while i < n || j < m {
            let (a, b) = (pv(i), qv(j));
            out.push([a[0] + b[0], a[1] + b[1]]);
            let turn = if i == n {
                -1.0
            } else if j == m {
                1.0
            } else {
                cross_sign(sub(pv(i + 1), a), sub(qv(j + 1), b))
            };
            if turn >= 0.0 && i < n {
                i += 1;
            }
            if turn <= 0.0 && j < m {
                j += 1;
            }
        }
        ConvexPolygon::cleaned(out)
    }

    /// P ⊕ [−v, v]: the sum with a centred segment (a noise component B_j·[−τ, τ]).
    pub fn add_segment(&self, v: [f64; 2]) -> ConvexPolygon {
        if v[0] == 0.0 && v[1] == 0.0 {
            return self.clone();
        }
        self.minkowski(&ConvexPolygon::segment([-v[0], -v[1]], v))
    }

    /// P ⊕ [−h₀, h₀] × [−h₁, h₁].
    pub fn add_box(&self, half: [f64; 2]) -> ConvexPolygon {
        self.minkowski(&ConvexPolygon::rectangle(
            [-half[0], -half[1]],
            [half[0], half[1]],
        ))
    }

    /// The area (shoelace about the first vertex, on coordinates divided by a power of two
    /// near the extent); 0 for a point or a segment, never negative.
    pub fn area(&self) -> f64 {
        if self.vertices.len() < 3 {
            return 0.0;
        }
        let s = pow2_below(self.extent());
        let o = self.vertices[0];
        let rel: Vec<[f64; 2]> = self
            .vertices
            .iter()
            .map(|v| scaled(sub(*v, o), s))
            .collect();
        let a: f64 = rel.windows(2).map(|w| cross(w[0], w[1])).sum::<f64>() * 0.5;
        (a.max(0.0) * s) * s
    }

    /// The support function h(d) = max over the set of d·x, and a vertex attaining it.
    pub fn support(&self, d: [f64; 2]) -> (f64, [f64; 2]) {
        let mut best = (f64::NEG_INFINITY, self.vertices[0]);
        for v in &self.vertices {
            let h = dot(d, *v);
            if h > best.0 {
                best = (h, *v);
            }
        }
        best
    }

    /// The interval hull [min x, max x, min y, max y] (the order of
    /// [`super::SupportPolygon::hull`]).
    pub fn interval_hull(&self) -> [f64; 4] {
        interval_hull_of(&self.vertices)
    }

    /// The polygon with its two coordinates exchanged (counter-clockwise kept).
    pub fn swapped(&self) -> ConvexPolygon {
        let mut v: Vec<[f64; 2]> = self.vertices.iter().map(|p| [p[1], p[0]]).collect();
        v.reverse();
        ConvexPolygon::cleaned(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_clipped_mapped_and_summed() {
        let sq = ConvexPolygon::rectangle([0.0, 0.0], [2.0, 2.0]);
        assert_eq!(sq.area(), 4.0);
        let half = sq.clip([1.0, 1.0], 2.0).unwrap();
        assert_eq!(half.vertices().len(), 3);
        assert!((half.area() - 2.0).abs() < 1e-15);
        assert!(sq.clip([1.0, 0.0], -1.0).is_none());
        // A strip of width 0 along an edge leaves the edge.
        let edge = sq.clip_strip([0.0, 1.0], 2.0, 2.0).unwrap();
        assert_eq!(edge.vertices().len(), 2);
        let flipped = sq.map([[0.0, 1.0], [1.0, 0.0]]);
        assert_eq!(flipped.area(), 4.0);
        let line = sq.map([[1.0, 1.0], [2.0, 2.0]]);
        assert_eq!(line.vertices().len(), 2);
        let sum = sq.add_segment([1.0, 0.0]);
        assert_eq!(sum.area(), 8.0);
        assert_eq!(sum.vertices().len(), 4);
        assert_eq!(sq.support([1.0, 1.0]).0, 4.0);
    }
}
