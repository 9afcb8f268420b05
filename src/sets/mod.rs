//! Set types shared by every method and every plot.
//!
//! [`Ellipsoid`] (KF, SCF, BLUE regions), [`BoxSet`] (interval hulls, plot windows), and in
//! [`sign_region`] the LSCR set type [`SignRegion`] with its exact raster [`GridRegion`],
//! boundary polygons [`Loop`] and line pieces [`Span`]. Polytopes join here with the
//! set-membership methods, so that plots and reports speak one vocabulary of sets: the exact
//! [`SupportPolygon`] of a planar convex set known through its support function (Tempo's
//! feasible set, Pavelková's consistent states, where an LP is still needed), and the exact
//! [`ConvexPolygon`] engine (clip by a half-plane or a strip, 2×2 map, Minkowski sum, hull,
//! area, support) that computes those sets without an LP when the state is 2-D and the bounds
//! are per-sample l∞. The geometry of the plane those sets share
//! (areas, convex hulls, [`point_in_convex`], box corners, 2×2 maps of points and ellipses,
//! Minkowski sums) is written once in [`plane`].

use crate::error::{Error, Result};
use crate::linalg::{self, symmetrize};
use crate::stats::chi2_quantile;
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

pub mod convex_polygon;
pub mod plane;
pub mod sign_region;
pub mod support_polygon;
pub use convex_polygon::ConvexPolygon;
pub(crate) use plane::polygon_scale;
pub use plane::{
    box_corners, box_image_corners, convex_hull, map_ellipse, map_point, minkowski_sum,
    point_in_convex, polygon_area, signed_area,
};
pub use sign_region::{AffineGroup, GridRegion, LineInterval, Loop, SignRegion, Span};
pub use support_polygon::{polygon_from_support, SupportPolygon};

/// {x : (x − c)ᵀ cov⁻¹ (x − c) ≤ radius2}. JSON: `{"center", "cov", "radius2"}`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Ellipsoid {
    pub center: Vec<f64>,
    pub cov: Vec<Vec<f64>>,
    pub radius2: f64,
}

/// An axis-aligned box, `lo[i] ≤ x_i ≤ hi[i]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BoxSet {
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
}

impl BoxSet {
    /// Smallest box containing both.
    pub fn union(&self, other: &BoxSet) -> BoxSet {
        BoxSet {
            lo: linalg::zip_with(&self.lo, &other.lo, f64::min),
            hi: linalg::zip_with(&self.hi, &other.hi, f64::max),
        }
    }
    /// The box grown by `margin` times its width on every side.
    pub fn padded(&self, margin: f64) -> BoxSet {
        let w: Vec<f64> = self
            .lo
            .iter()
            .zip(&self.hi)
            .map(|(l, h)| (h - l).max(1e-12) * margin)
            .collect();
        BoxSet {
            lo: self.lo.iter().zip(&w).map(|(l, w)| l - w).collect(),
            hi: self.hi.iter().zip(&w).map(|(h, w)| h + w).collect(),
        }
    }
    /// A box around one point.
    pub fn point(p: &[f64]) -> BoxSet {
        BoxSet {
            lo: p.to_vec(),
            hi: p.to_vec(),
        }
    }
}

impl Ellipsoid {
    /// E(center, cov) at level α: radius2 = χ²(α, n) — the minimum-volume region holding
    /// probability α of N(center, cov) (SCF notation E^α_Σ(μ)).
    pub fn at_level(center: &DVector<f64>, cov: &DMatrix<f64>, alpha: f64) -> Result<Self> {
        Ok(Self::new(center, cov, chi2_quantile(alpha, center.len())?))
    }

    /// From nalgebra values (cov is symmetrized).
    pub fn new(center: &DVector<f64>, cov: &DMatrix<f64>, radius2: f64) -> Self {
        Ellipsoid {
            center: center.iter().copied().collect(),
            cov: linalg::to_rows(&symmetrize(cov)),
            radius2,
        }
    }

    /// Dimension.
    pub fn dim(&self) -> usize {
        self.center.len()
    }
    /// Center as a vector.
    pub fn center_vec(&self) -> DVector<f64> {
        DVector::from_column_slice(&self.center)
    }
    /// Shape matrix as a matrix.
    pub fn cov_mat(&self) -> DMatrix<f64> {
        let n = self.dim();
        DMatrix::from_fn(n, n, |i, j| self.cov[i][j])
    }

    /// (x − c)ᵀ cov⁻¹ (x − c), or +∞ off a degenerate ellipsoid's support.
    pub fn mahalanobis2(&self, x: &[f64]) -> f64 {
        let d = DVector::from_column_slice(x) - self.center_vec();
        match self.cov_mat().cholesky() {
            Some(c) => d.dot(&c.solve(&d)),
            None => f64::INFINITY,
        }
    }

    /// Membership test.
    pub fn contains(&self, x: &[f64]) -> bool {
        self.mahalanobis2(x) <= self.radius2
    }

    /// Support function h(u) = cᵀu + √(radius2 · uᵀ cov u).
    pub fn support(&self, u: &[f64]) -> f64 {
        let uv = DVector::from_column_slice(u);
        self.center_vec().dot(&uv)
            + (self.radius2 * uv.dot(&(self.cov_mat() * &uv)))
                .max(0.0)
                .sqrt()
    }

    /// Bounding box: c_i ± √(radius2 · cov_ii).
    pub fn bounding_box(&self) -> BoxSet {
        let half: Vec<f64> = (0..self.dim())
            .map(|i| (self.radius2 * self.cov[i][i]).max(0.0).sqrt())
            .collect();
        BoxSet {
            lo: self.center.iter().zip(&half).map(|(c, h)| c - h).collect(),
            hi: self.center.iter().zip(&half).map(|(c, h)| c + h).collect(),
        }
    }

    /// Volume (area for n = 2, length for n = 1): V_n · radius^n · √det(cov).
    pub fn volume(&self) -> f64 {
        let n = self.dim() as f64;
        let unit_ball =
            std::f64::consts::PI.powf(n / 2.0) / statrs::function::gamma::gamma(n / 2.0 + 1.0);
        unit_ball * self.radius2.powf(n / 2.0) * self.cov_mat().determinant().max(0.0).sqrt()
    }

    /// Projection onto coordinates `idx` (the shadow: a marginal of the Gaussian keeps the same
    /// radius2, so this is the set of projections of the ellipsoid's points).
    pub fn project(&self, idx: &[usize]) -> Result<Ellipsoid> {
        self.check_indices(idx)?;
        let c = linalg::sub_vector(&self.center_vec(), idx);
        let s = linalg::sub_matrix(&self.cov_mat(), idx);
        Ok(Ellipsoid::new(&c, &s, self.radius2))
    }

    /// Slice through `point` along coordinates `idx` (the other coordinates fixed at `point`):
    /// conditional-Gaussian algebra; empty (None) if the plane misses the ellipsoid.
    pub fn slice(&self, idx: &[usize], point: &[f64]) -> Result<Option<Ellipsoid>> {
        self.check_indices(idx)?;
        let n = self.dim();
        if point.len() != n {
            return Err(Error::field(
                "slice.point",
                format!(
                    "must have {n_entries}",
                    n_entries = crate::error::counted(n, "entry", "entries")
                ),
            ));
        }
        let rest: Vec<usize> = (0..n).filter(|i| !idx.contains(i)).collect();
        let s = self.cov_mat();
        let c = self.center_vec();
        if rest.is_empty() {
            return Ok(Some(self.project(idx)?));
        }
        let s_aa = linalg::sub_matrix(&s, idx);
        let s_bb = linalg::sub_matrix(&s, &rest);
        let s_ab = DMatrix::from_fn(idx.len(), rest.len(), |i, j| s[(idx[i], rest[j])]);
        let s_bb_inv = linalg::inverse("ellipsoid shape", &s_bb)?;
        let db = DVector::from_fn(rest.len(), |i, _| point[rest[i]] - c[rest[i]]);
        let center = linalg::sub_vector(&c, idx) + &s_ab * &s_bb_inv * &db;
        let cov = &s_aa - &s_ab * &s_bb_inv * s_ab.transpose();
        let r2 = self.radius2 - db.dot(&(&s_bb_inv * &db));
        Ok(if r2 < 0.0 {
            None
        } else {
            Some(Ellipsoid::new(&center, &cov, r2))
        })
    }

    /// Boundary of a 2-D ellipsoid as `k` points (closed by the caller).
    pub fn boundary_2d(&self, k: usize) -> Result<Vec<(f64, f64)>> {
        if self.dim() != 2 {
            return Err(Error::field(
                "ellipsoid",
                format!(
                    "boundary needs 2 dimensions, has {} (project or slice first)",
                    self.dim()
                ),
            ));
        }
        let l = linalg::psd_sqrt(&self.cov_mat()) * self.radius2.max(0.0).sqrt();
        Ok((0..k)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / k as f64;
                let (s, c) = a.sin_cos();
                (
                    self.center[0] + l[(0, 0)] * c + l[(0, 1)] * s,
                    self.center[1] + l[(1, 0)] * c + l[(1, 1)] * s,
                )
            })
            .collect())
    }

    /// Euclidean distance between two ellipsoids of the same dimension (0 when they meet).
    ///
    /// dist(A, B) = max over unit u of −h_A(u) − h_B(−u) (separating-hyperplane duality). For
    /// n = 2 the maximum over the circle is found on a grid of angles and refined by golden
    /// section; for n = 1 it is exact.
    pub fn distance(&self, other: &Ellipsoid) -> Result<f64> {
        if self.dim() != other.dim() {
            return Err(Error::field(
                "ellipsoid",
                "distance needs ellipsoids of the same dimension",
            ));
        }
        match self.dim() {
            1 => {
                let (a, b) = (self.bounding_box(), other.bounding_box());
                Ok((b.lo[0] - a.hi[0]).max(a.lo[0] - b.hi[0]).max(0.0))
            }
            2 => {
                let pa = PlanarEllipse::from(self);
                let pb = PlanarEllipse::from(other);
                Ok(pa.distance(&pb))
            }
            n => Err(Error::field(
                "ellipsoid",
                format!("distance is implemented for 1 and 2 dimensions, not {n}"),
            )),
        }
    }

    fn check_indices(&self, idx: &[usize]) -> Result<()> {
        let n = self.dim();
        if idx.is_empty() {
            return Err(Error::field(
                "components",
                "must name at least one state component",
            ));
        }
        for (k, &i) in idx.iter().enumerate() {
            if i >= n {
                return Err(Error::field(
                    "components",
                    format!(
                        "entry {k} is {i}, but the state has {n_components} (0-based)",
                        n_components = crate::error::counted(n, "component", "components")
                    ),
                ));
            }
            if idx[..k].contains(&i) {
                return Err(Error::field(
                    "components",
                    format!("lists component {i} twice"),
                ));
            }
        }
        Ok(())
    }
}

/// A 2-D ellipse in plain numbers, for tight loops (Monte Carlo collision checks).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanarEllipse {
    pub c: [f64; 2],
    /// radius2 · cov, entries (xx, xy, yy).
    pub s: [f64; 3],
}

impl From<&Ellipsoid> for PlanarEllipse {
    fn from(e: &Ellipsoid) -> Self {
        PlanarEllipse {
            c: [e.center[0], e.center[1]],
            s: [
                e.radius2 * e.cov[0][0],
                e.radius2 * e.cov[0][1],
                e.radius2 * e.cov[1][1],
            ],
        }
    }
}

impl PlanarEllipse {
    /// Support function at (cos θ, sin θ).
    #[inline]
    pub fn support(&self, cs: f64, sn: f64) -> f64 {
        let q = self.s[0] * cs * cs + 2.0 * self.s[1] * cs * sn + self.s[2] * sn * sn;
        self.c[0] * cs + self.c[1] * sn + q.max(0.0).sqrt()
    }

    /// Distance to another ellipse (0 when they meet); see [`Ellipsoid::distance`].
    pub fn distance(&self, other: &PlanarEllipse) -> f64 {
        let gap = |th: f64| {
            let (s, c) = th.sin_cos();
            -self.support(c, s) - other.support(-c, -s)
        };
        const GRID: usize = 36;
        let step = std::f64::consts::TAU / GRID as f64;
        let (mut best, mut arg) = (f64::NEG_INFINITY, 0.0);
        for i in 0..GRID {
            let th = i as f64 * step;
            let g = gap(th);
            if g > best {
                best = g;
                arg = th;
            }
        }
        // Golden-section refinement on the bracketing interval.
        let (mut a, mut b) = (arg - step, arg + step);
        let r = 0.5 * (5f64.sqrt() - 1.0);
        let (mut x1, mut x2) = (b - r * (b - a), a + r * (b - a));
        let (mut g1, mut g2) = (gap(x1), gap(x2));
        for _ in 0..32 {
            if g1 > g2 {
                b = x2;
                x2 = x1;
                g2 = g1;
                x1 = b - r * (b - a);
                g1 = gap(x1);
            } else {
                a = x1;
                x1 = x2;
                g1 = g2;
                x2 = a + r * (b - a);
                g2 = gap(x2);
            }
        }
        best.max(g1).max(g2).max(0.0)
    }
}
