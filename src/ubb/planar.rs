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
//! close it into a parallelogram, after which the polygon engine takes over. When the data
//! never close it (or a singular map meets an unbounded set) the recursion says so and the
//! caller keeps the LP path.

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
    /// The exact polygon of e(k+1).
    Polygon(ConvexPolygon),
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
fn reversed(lo: f64, hi: f64) -> bool {
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

    /// The image under A; `None` when A is singular and the set unbounded (left to the LP).
    fn map(self, m: [[f64; 2]; 2]) -> Option<Region> {
        let det = cross(m[0], m[1]);
        let scale = m.iter().flatten().fold(0.0f64, |s, v| s.max(v.abs()));
        let invertible = det.abs() > REL_TOL * scale * scale && det.is_finite();
        match self {
            Region::Polygon(p) => Some(Region::Polygon(p.map(m))),
            Region::Plane => invertible.then_some(Region::Plane),
            Region::Strip { a, lo, hi } => {
                if !invertible {
                    return None;
                }
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
    for sample in samples {
        for &(row, lo, hi) in &sample.strips {
            match region.clip(row, lo, hi) {
                Some(r) => region = r,
                None => return Outcome::Empty,
            }
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
            Outcome::Polygon(p)
        }
        _ => Outcome::Open,
    }
}
