//! The planar path of Section IV's state estimator: a 2-D state with per-sample l∞ bounds.
//!
//! The feasible set of the state on the window, T(h) (3) read at time k + 1, is then a convex
//! polygon computed exactly by forward recursion on the deviations e = x − x̄ from the nominal
//! trajectory (which keeps the coordinates near the set, not near x̄): start from the box of
//! e(s) (the δ bound and the noise before the window, as in the LP), and for t = s … k clip by
//! every measurement strip |C_i(t) e(t) − h_i(t)| ≤ ε·e^{(k−t)/β} (46), map by A and add the
//! process-noise zonotope B·[−τe^{(k−t)/α}, τe^{(k−t)/α}]^p (45), one segment per column of B.
//! Each operation is exact on convex polygons and linear in their vertices, so a step costs
//! microseconds instead of an interior-point LP per support direction.
//!
//! Without a bound on e(s) (δ = ∞) the set starts as the whole plane; a strip stays a strip
//! under an invertible map and a noise sum (it widens by |a·v|), and two independent strips
//! close it into a parallelogram, after which the polygon engine takes over. A singular map
//! can close it too: A = v wᵀ of rank 1 takes the strip lo ≤ a·e ≤ hi to a segment when w is
//! parallel to a (the strip's unbounded direction is A's kernel: the pair is reconstructible
//! though not observable), and A = 0 takes anything to the origin. When the data never close
//! it (or a singular map meets an unbounded set along another direction) the recursion says so
//! and the caller keeps the LP path.
//!
//! A missing measurement (a gap of the record) has no strip: the caller leaves it out of its
//! [`Sample`], and that time is only the map and the noise (the set can only grow).
//!
//! The recursion keeps the set of e(k) after the last time's strips, before the map: the
//! filtered set X(k | y(s … k)) beside the predicted X(k+1 | y(s … k)), which is its image
//! under A plus the noise zonotope.

use crate::sets::convex_polygon::REL_TOL;
use crate::sets::ConvexPolygon;

/// The set of e(t) during the recursion.
#[derive(Debug, Clone)]
enum Region {
    /// Every e(t) (no bound yet).
    Plane,
    /// lo ≤ a·e ≤ hi.
    Strip {
        a: [f64; 2],
        lo: f64,
        hi: f64,
    },
    Polygon(ConvexPolygon),
}

/// How the recursion ended.
#[derive(Debug, Clone)]
pub enum Outcome {
    /// The exact polygon of e(k+1) (the predicted set) and of e(k) after the last strips (the
    /// filtered set; `None` when it is not a bounded polygon: a strip or the plane that a
    /// singular A closed into the predicted one).
    Polygon {
        predicted: ConvexPolygon,
        filtered: Option<ConvexPolygon>,
    },
    /// The data contradict the bounds.
    Empty,
    /// The data did not close the set (or a singular map met an unbounded one): use the LP.
    Open,
}

/// One time of the window: the measurement strips lo ≤ a·e(t) ≤ hi, then the map and noise
/// that take e(t) to e(t+1).
#[derive(Debug, Clone)]
pub struct Sample {
    pub strips: Vec<([f64; 2], f64, f64)>,
    /// Half-width of every process-noise sample u_j(t) (0: none).
    pub tau: f64,
}

fn cross(u: [f64; 2], w: [f64; 2]) -> f64 {
    u[0] * w[1] - u[1] * w[0]
}

fn dot(u: [f64; 2], w: [f64; 2]) -> f64 {
    u[0] * w[0] + u[1] * w[1]
}

/// Whether [lo, hi] is empty beyond rounding.
pub(super) fn reversed(lo: f64, hi: f64) -> bool {
    lo > hi + REL_TOL * (lo.abs() + hi.abs())
}

impl Region {
    fn clip(self, a: [f64; 2], lo: f64, hi: f64) -> Option<Region> {
        if a == [0.0, 0.0] {
            // A row of C that sees nothing: only its datum can contradict.
            return (!reversed(lo, 0.0) && !reversed(0.0, hi)).then_some(self);
        }
        if reversed(lo, hi) {
            return None;
        }
        match self {
            Region::Plane => Some(Region::Strip { a, lo, hi }),
            Region::Strip { a: b, lo: l, hi: h } => {
                let na = a[0].hypot(a[1]);
                let nb = b[0].hypot(b[1]);
                if cross(a, b).abs() <= REL_TOL * na * nb {
                    // Parallel: a = λ b, the intersection of two intervals of b·e.
                    let lam = dot(a, b) / dot(b, b);
                    let (l2, h2) = if lam > 0.0 {
                        (lo / lam, hi / lam)
                    } else {
                        (hi / lam, lo / lam)
                    };
                    let (nl, nh) = (l.max(l2), h.min(h2));
                    if reversed(nl, nh) {
                        return None;
                    }
                    return Some(Region::Strip {
                        a: b,
                        lo: nl,
                        hi: nh.max(nl),
                    });
                }
                // Two independent strips: the parallelogram of the four corners
                // b·e ∈ {l, h}, a·e ∈ {lo, hi} (Cramer's rule).
                let det = cross(b, a);
                let corner =
                    |u: f64, v: f64| [(u * a[1] - v * b[1]) / det, (b[0] * v - a[0] * u) / det];
                let pts = [corner(l, lo), corner(h, lo), corner(h, hi), corner(l, hi)];
                if pts.iter().flatten().any(|c| !c.is_finite()) {
                    return Some(Region::Strip { a: b, lo: l, hi: h });
                }
                ConvexPolygon::hull(&pts).map(Region::Polygon)
            }
            Region::Polygon(p) => p.clip_strip(a, lo, hi).map(Region::Polygon),
        }
    }

    /// The image under A; `None` when A is singular and the image unbounded (left to the LP).
    fn map(self, m: [[f64; 2]; 2]) -> Option<Region> {
        let det = cross(m[0], m[1]);
        let scale = m.iter().flatten().fold(0.0f64, |s, v| s.max(v.abs()));
        let invertible = det.abs() > REL_TOL * scale * scale && det.is_finite();
        if scale == 0.0 {
            // A = 0: every set goes to the origin.
            return Some(Region::Polygon(ConvexPolygon::point([0.0, 0.0])));
        }
        match self {
            Region::Polygon(p) => Some(Region::Polygon(p.map(m))),
            Region::Plane => invertible.then_some(Region::Plane),
            Region::Strip { a, lo, hi } if !invertible => {
                // A = v wᵀ (rank 1; w the longer row, v the rows' coefficients on it): A e =
                // v (w·e). When w = λ a, w·e runs over λ[lo, hi] and the image is a segment
                // along v; otherwise w·e is unbounded on the strip, and so is the image.
                let w = if m[0][0].hypot(m[0][1]) >= m[1][0].hypot(m[1][1]) {
                    m[0]
                } else {
                    m[1]
                };
                let (ww, na) = (dot(w, w), a[0].hypot(a[1]));
                if cross(a, w).abs() > REL_TOL * na * ww.sqrt() {
                    return None;
                }
                let v = [dot(m[0], w) / ww, dot(m[1], w) / ww];
                let lam = dot(w, a) / dot(a, a);
                let (t0, t1) = (lam * lo, lam * hi);
                let ends = [[v[0] * t0, v[1] * t0], [v[0] * t1, v[1] * t1]];
                ends.iter()
                    .flatten()
                    .all(|c| c.is_finite())
                    .then(|| Region::Polygon(ConvexPolygon::segment(ends[0], ends[1])))
            }
            Region::Strip { a, lo, hi } => {
                // {A e : lo ≤ a·e ≤ hi} = {x : lo ≤ (A⁻ᵀa)·x ≤ hi}.
                let na = [
                    (m[1][1] * a[0] - m[1][0] * a[1]) / det,
                    (-m[0][1] * a[0] + m[0][0] * a[1]) / det,
                ];
                Some(Region::Strip { a: na, lo, hi })
            }
        }
    }

    /// The sum with the centred segment [−v, v].
    fn add_segment(self, v: [f64; 2]) -> Region {
        match self {
            Region::Plane => Region::Plane,
            Region::Strip { a, lo, hi } => {
                let w = dot(a, v).abs();
                Region::Strip {
                    a,
                    lo: lo - w,
                    hi: hi + w,
                }
            }
            Region::Polygon(p) => Region::Polygon(p.add_segment(v)),
        }
    }
}

/// The forward recursion from e(s) to e(k+1): `start` the half-widths of the box of e(s)
/// (`None`: unbounded), `equal` an equality a·e(s) = v (Example 4's Σx(0)), `a` the map,
/// `noise` the columns of B, `samples` the times s … k.
pub fn propagate(
    a: [[f64; 2]; 2],
    noise: &[[f64; 2]],
    start: Option<[f64; 2]>,
    equal: Option<([f64; 2], f64)>,
    samples: &[Sample],
) -> Outcome {
    let mut region = match start {
        Some(h) => Region::Polygon(ConvexPolygon::rectangle([-h[0], -h[1]], h)),
        None => Region::Plane,
    };
    if let Some((e, v)) = equal {
        match region.clip(e, v, v) {
            Some(r) => region = r,
            None => return Outcome::Empty,
        }
    }
    let mut filtered = None;
    for (i, sample) in samples.iter().enumerate() {
        for &(row, lo, hi) in &sample.strips {
            match region.clip(row, lo, hi) {
                Some(r) => region = r,
                None => return Outcome::Empty,
            }
        }
        if i + 1 == samples.len() {
            // e(k) given y(s … k): the filtered set, before the last map.
            filtered = match &region {
                Region::Polygon(p) if p.vertices().iter().flatten().all(|c| c.is_finite()) => {
                    Some(p.clone())
                }
                _ => None,
            };
        }
        match region.map(a) {
            Some(r) => region = r,
            None => return Outcome::Open,
        }
        if sample.tau > 0.0 {
            for col in noise {
                region = region.add_segment([col[0] * sample.tau, col[1] * sample.tau]);
            }
        }
    }
    match region {
        Region::Polygon(p) if p.vertices().iter().flatten().all(|c| c.is_finite()) => {
            Outcome::Polygon {
                predicted: p,
                filtered,
            }
        }
        _ => Outcome::Open,
    }
}
