//! Sign-count regions: the set type of LSCR (Weyer & Campi, point 5 and (17)).
//!
//! ```text
//! X = ∩_l X_l,   X_l = { x : #{i : g_{l,i}(x) > 0} ≥ q  and  #{i : g_{l,i}(x) < 0} ≥ q },
//! g_{l,i}(x) = c_{l,i} − d_{l,i}·x          (affine in x)
//! ```
//!
//! Because every g is affine, the region is a union of cells of a hyperplane arrangement, and in
//! the plane everything about it can be computed exactly rather than sampled:
//! * [`SignRegion::raster`]: membership of every pixel centre of a window, by finding along each
//!   pixel row the one column where each g changes sign (floating-point evaluation of an affine
//!   function along a row is monotone, so the answer is bit-for-bit the brute-force one,
//!   [`SignRegion::raster_brute`]) and counting with difference arrays: O(rows·(N + columns))
//!   instead of O(rows·columns·N);
//! * [`SignRegion::spans`]: the exact intervals of any straight line in and out of each X_l
//!   (hatching, probes along a ray);
//! * [`SignRegion::boundary`]: the boundary of X inside a window as closed polygons, from the
//!   segments of the arrangement's lines that separate a member cell from a non-member one;
//! * [`SignRegion::recession_2d`], [`SignRegion::invariant_directions`]: whether and along which
//!   directions the region is unbounded (LSCR Section V-B: a singular F^b makes it a band).
//!
//! Regions of dimension > 2 are drawn through [`SignRegion::slice`] (a 2-D section through a
//! point).

use crate::error::{Error, Result};
/// The shoelace area, kept at this path for the region's callers.
pub use crate::sets::plane::signed_area;
use crate::sets::{box_corners, BoxSet};
use serde::{Deserialize, Serialize};

/// The functions g_{l,·} of one group l (one X_l): `c[i] − d[i]·x`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AffineGroup {
    pub c: Vec<f64>,
    pub d: Vec<Vec<f64>>,
}

/// {x : in every group, at least q functions are > 0 and at least q are < 0}.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SignRegion {
    pub dim: usize,
    pub q: usize,
    pub groups: Vec<AffineGroup>,
}

/// Membership of a window's pixel centres. Row 0 is the top row (largest y), like an image.
/// `excluded[r * width + j]` has bit l set when the pixel centre is outside X_l (bit 31 stands
/// for every l ≥ 31); a pixel is in X when its entry is 0.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GridRegion {
    pub window: BoxSet,
    pub width: usize,
    pub height: usize,
    pub excluded: Vec<u32>,
}

impl GridRegion {
    /// Pixel width and height in state units.
    pub fn pixel(&self) -> (f64, f64) {
        (
            (self.window.hi[0] - self.window.lo[0]) / self.width as f64,
            (self.window.hi[1] - self.window.lo[1]) / self.height as f64,
        )
    }
    /// Centre of pixel (row, column).
    pub fn centre(&self, r: usize, j: usize) -> (f64, f64) {
        let (dx, dy) = self.pixel();
        (
            self.window.lo[0] + (j as f64 + 0.5) * dx,
            self.window.hi[1] - (r as f64 + 0.5) * dy,
        )
    }
    /// Number of pixels whose centre is in X.
    pub fn inside_count(&self) -> usize {
        self.excluded.iter().filter(|&&e| e == 0).count()
    }
    /// Area of X inside the window, to the resolution of the raster.
    pub fn area(&self) -> f64 {
        let (dx, dy) = self.pixel();
        self.inside_count() as f64 * dx * dy
    }
}

/// A piece of a line, s ∈ [s0, s1], with the groups it is outside of (bit l = outside X_l).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Span {
    pub s0: f64,
    pub s1: f64,
    pub excluded: u32,
}

/// A piece of the line of a 1-D region (a scalar state): the open interval (lo, hi), an
/// absent end unbounded ([`SignRegion::intervals_1d`]). JSON has no infinity: an unbounded
/// end is an absent key, never a `null`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LineInterval {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lo: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hi: Option<f64>,
}

impl LineInterval {
    /// The ends with ±∞ for the unbounded ones.
    pub fn ends(&self) -> (f64, f64) {
        (
            self.lo.unwrap_or(f64::NEG_INFINITY),
            self.hi.unwrap_or(f64::INFINITY),
        )
    }
}

/// A closed boundary polygon of X inside a window; counter-clockwise around the region
/// (`hole == false`) or clockwise around a hole.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Loop {
    pub points: Vec<[f64; 2]>,
    pub hole: bool,
}

fn bit(l: usize) -> u32 {
    1u32 << l.min(31)
}

/// The affine function of a 2-D region at (x, y). Raster, brute force and membership all use
/// this one expression, so they agree to the last bit.
#[inline(always)]
fn eval2(c: f64, d0: f64, d1: f64, x: f64, y: f64) -> f64 {
    c - (d0 * x + d1 * y)
}

/// Smallest j in 0..=len with `pred(j)` true, for a predicate that is false then true along j
/// (len if never true); starts at `guess` and gallops, so an accurate guess costs two calls.
fn first_true(len: usize, guess: f64, pred: impl Fn(usize) -> bool) -> usize {
    if len == 0 {
        return 0;
    }
    let g = if guess.is_nan() {
        0.0
    } else {
        guess.clamp(0.0, (len - 1) as f64)
    } as usize;
    // Invariant: pred false below lo, pred true at hi.
    let (mut lo, mut hi);
    if pred(g) {
        hi = g;
        let mut step = 1;
        loop {
            if hi == 0 {
                return 0;
            }
            let probe = hi.saturating_sub(step);
            if pred(probe) {
                hi = probe;
                step *= 2;
            } else {
                lo = probe + 1;
                break;
            }
        }
    } else {
        lo = g + 1;
        let mut step = 1;
        loop {
            if lo >= len {
                return len;
            }
            let probe = (lo + step - 1).min(len - 1);
            if pred(probe) {
                hi = probe;
                break;
            }
            lo = probe + 1;
            step *= 2;
        }
    }
    while lo < hi {
        let mid = (lo + hi) / 2;
        if pred(mid) {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    hi
}

impl SignRegion {
    /// Check shapes and finiteness (a region built by a method is always valid; this guards
    /// regions read back from JSON).
    pub fn validate(&self, field: &str) -> Result<()> {
        if self.q == 0 {
            return Err(Error::field(field, "q must be at least 1"));
        }
        for (l, g) in self.groups.iter().enumerate() {
            if g.c.len() != g.d.len()
                || g.d.iter().any(|d| d.len() != self.dim)
                || g.c
                    .iter()
                    .chain(g.d.iter().flatten())
                    .any(|v| !v.is_finite())
            {
                return Err(Error::field(
                    field,
                    format!(
                        "group {l} is not {} finite functions of dimension {}",
                        g.c.len(),
                        self.dim
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The values g_{l,i}(x) of group l at x, evaluated as [`excluded`](Self::excluded) does
    /// (so a step-through's sums give the region's verdict bit for bit).
    pub fn values(&self, l: usize, x: &[f64]) -> Vec<f64> {
        let g = &self.groups[l];
        g.c.iter()
            .zip(&g.d)
            .map(|(c, d)| self.value(*c, d, x))
            .collect()
    }

    fn value(&self, c: f64, d: &[f64], x: &[f64]) -> f64 {
        if self.dim == 2 {
            eval2(c, d[0], d[1], x[0], x[1])
        } else {
            c - d.iter().zip(x).fold(0.0, |a, (di, xi)| a + di * xi)
        }
    }

    /// Bit l set when x ∉ X_l.
    pub fn excluded(&self, x: &[f64]) -> u32 {
        let mut mask = 0;
        for (l, g) in self.groups.iter().enumerate() {
            let (mut pos, mut neg) = (0, 0);
            for (c, d) in g.c.iter().zip(&g.d) {
                let v = self.value(*c, d, x);
                if v > 0.0 {
                    pos += 1;
                } else if v < 0.0 {
                    neg += 1;
                }
            }
            if pos < self.q || neg < self.q {
                mask |= bit(l);
            }
        }
        mask
    }

    /// x ∈ X.
    pub fn contains(&self, x: &[f64]) -> bool {
        self.excluded(x) == 0
    }

    /// The 2-D section {(a, b) : point with components `axes` replaced by (a, b) ∈ X}.
    pub fn slice(&self, point: &[f64], axes: [usize; 2]) -> Result<SignRegion> {
        if point.len() != self.dim
            || axes[0] >= self.dim
            || axes[1] >= self.dim
            || axes[0] == axes[1]
        {
            return Err(Error::field(
                "slice",
                format!(
                    "needs a point of dimension {} and two distinct axes below it",
                    self.dim
                ),
            ));
        }
        let groups = self
            .groups
            .iter()
            .map(|g| {
                let mut c = Vec::with_capacity(g.c.len());
                let mut d = Vec::with_capacity(g.c.len());
                for (ci, di) in g.c.iter().zip(&g.d) {
                    let rest: f64 = (0..self.dim)
                        .filter(|k| !axes.contains(k))
                        .map(|k| di[k] * point[k])
                        .sum();
                    c.push(ci - rest);
                    d.push(vec![di[axes[0]], di[axes[1]]]);
                }
                AffineGroup { c, d }
            })
            .collect();
        Ok(SignRegion {
            dim: 2,
            q: self.q,
            groups,
        })
    }

    fn need_2d(&self) -> Result<()> {
        if self.dim != 2 {
            return Err(Error::field(
                "region",
                format!("is {}-dimensional: take a 2-D slice first", self.dim),
            ));
        }
        Ok(())
    }

    fn check_window(window: &BoxSet, width: usize, height: usize) -> Result<()> {
        let ok = window.lo.len() == 2
            && window.hi.len() == 2
            && (0..2).all(|k| {
                window.lo[k].is_finite() && window.hi[k].is_finite() && window.lo[k] < window.hi[k]
            });
        if !ok {
            return Err(Error::field(
                "window",
                "must be two finite intervals lo < hi",
            ));
        }
        if width == 0 || height == 0 || width > 4096 || height > 4096 {
            return Err(Error::field(
                "resolution",
                "must be between 1 and 4096 pixels per side",
            ));
        }
        Ok(())
    }

    /// The raster of `window` at `width` × `height` pixels with no pixel excluded yet, once the
    /// region is 2-D and the window and size are checked.
    fn empty_grid(&self, window: &BoxSet, width: usize, height: usize) -> Result<GridRegion> {
        self.need_2d()?;
        Self::check_window(window, width, height)?;
        Ok(GridRegion {
            window: window.clone(),
            width,
            height,
            excluded: vec![0; width * height],
        })
    }

    /// Exact membership of every pixel centre (see the module docs for the method).
    pub fn raster(&self, window: &BoxSet, width: usize, height: usize) -> Result<GridRegion> {
        let mut grid = self.empty_grid(window, width, height)?;
        let (dx, dy) = grid.pixel();
        let x0 = window.lo[0];
        let xs: Vec<f64> = (0..width).map(|j| x0 + (j as f64 + 0.5) * dx).collect();
        let (mut pos, mut neg) = (vec![0i32; width + 1], vec![0i32; width + 1]);
        // Per function: the root column at row 0 as a fractional index, its change per row, and
        // a bound (in columns) on every rounding error between that estimate and the sign of
        // the floating-point evaluation at a pixel centre. When the estimate is farther than
        // the bound from every pixel centre, the sign pattern of the row follows without
        // evaluating g; otherwise the exact search decides. Either way the result is the
        // brute-force one.
        let xmax = window.lo[0].abs().max(window.hi[0].abs());
        let ymax = window.lo[1].abs().max(window.hi[1].abs());
        let y0 = window.hi[1] - 0.5 * dy;
        let guides: Vec<Vec<(f64, f64, f64)>> = self
            .groups
            .iter()
            .map(|g| {
                g.c.iter()
                    .zip(&g.d)
                    .map(|(&c, d)| {
                        if d[0] == 0.0 {
                            return (0.0, 0.0, f64::INFINITY);
                        }
                        let g0 = ((c - d[1] * y0) / d[0] - x0) / dx - 0.5;
                        let slope = d[1] * dy / d[0] / dx;
                        let scale = c.abs() + d[0].abs() * xmax + d[1].abs() * ymax;
                        let tol = 256.0
                            * f64::EPSILON
                            * (scale / (d[0].abs() * dx)
                                + xmax / dx
                                + g0.abs()
                                + height as f64 * slope.abs()
                                + width as f64
                                + 4.0);
                        (g0, slope, if tol.is_finite() { tol } else { f64::INFINITY })
                    })
                    .collect()
            })
            .collect();
        for r in 0..height {
            let y = window.hi[1] - (r as f64 + 0.5) * dy;
            let row = &mut grid.excluded[r * width..(r + 1) * width];
            for (l, g) in self.groups.iter().enumerate() {
                pos.iter_mut().for_each(|v| *v = 0);
                neg.iter_mut().for_each(|v| *v = 0);
                for ((&c, d), &(g0, slope, tol)) in g.c.iter().zip(&g.d).zip(&guides[l]) {
                    let (d0, d1) = (d[0], d[1]);
                    let f = |j: usize| eval2(c, d0, d1, xs[j], y);
                    if d0 == 0.0 {
                        let v = f(0);
                        if v > 0.0 {
                            pos[0] += 1;
                            pos[width] -= 1;
                        } else if v < 0.0 {
                            neg[0] += 1;
                            neg[width] -= 1;
                        }
                        continue;
                    }
                    let root = g0 + r as f64 * slope;
                    let near = (root - root.round()).abs() <= tol
                        && root >= -1.0 - tol
                        && root <= width as f64 + tol;
                    if !near && root.is_finite() {
                        // No pixel centre within the error bound of the root: g > 0 on one side
                        // of it and < 0 on the other, at every centre.
                        let k = root.ceil().clamp(0.0, width as f64) as usize;
                        if d0 > 0.0 {
                            pos[0] += 1;
                            pos[k] -= 1;
                            neg[k] += 1;
                            neg[width] -= 1;
                        } else {
                            neg[0] += 1;
                            neg[k] -= 1;
                            pos[k] += 1;
                            pos[width] -= 1;
                        }
                        continue;
                    }
                    let guess = root.ceil();
                    if d0 > 0.0 {
                        // Decreasing along the row: positive on a prefix, negative on a suffix.
                        let p = first_true(width, guess, |j| f(j) <= 0.0);
                        let m = if p < width && f(p) < 0.0 {
                            p
                        } else {
                            first_true(width, p as f64, |j| j >= p && f(j) < 0.0)
                        };
                        pos[0] += 1;
                        pos[p] -= 1;
                        neg[m] += 1;
                        neg[width] -= 1;
                    } else {
                        let m = first_true(width, guess, |j| f(j) >= 0.0);
                        let p = if m < width && f(m) > 0.0 {
                            m
                        } else {
                            first_true(width, m as f64, |j| j >= m && f(j) > 0.0)
                        };
                        neg[0] += 1;
                        neg[m] -= 1;
                        pos[p] += 1;
                        pos[width] -= 1;
                    }
                }
                let (mut cp, mut cn) = (0i32, 0i32);
                let (b, q) = (bit(l), self.q as i32);
                for ((cell, dp), dn) in row.iter_mut().zip(&pos).zip(&neg) {
                    cp += dp;
                    cn += dn;
                    if cp < q || cn < q {
                        *cell |= b;
                    }
                }
            }
        }
        Ok(grid)
    }

    /// Membership of every pixel centre by evaluating every function there: the reference
    /// that [`SignRegion::raster`] must equal.
    pub fn raster_brute(&self, window: &BoxSet, width: usize, height: usize) -> Result<GridRegion> {
        let mut grid = self.empty_grid(window, width, height)?;
        for r in 0..height {
            for j in 0..width {
                let (x, y) = grid.centre(r, j);
                grid.excluded[r * width + j] = self.excluded(&[x, y]);
            }
        }
        Ok(grid)
    }

    /// Sweep the line z(s) = p + s·dir over (s0, s1), calling `visit(sa, sb, pos, neg)` with the
    /// counts of positive and negative functions per group on each piece between crossings.
    /// `skip` leaves one function (group, index) out of the counts.
    fn sweep(
        &self,
        p: [f64; 2],
        dir: [f64; 2],
        (s0, s1): (f64, f64),
        skip: Option<(usize, usize)>,
        mut visit: impl FnMut(f64, f64, &[usize], &[usize]),
    ) {
        let ng = self.groups.len();
        let (mut pos, mut neg) = (vec![0usize; ng], vec![0usize; ng]);
        // (crossing s, group, sign after crossing: +1 positive → negative … encoded as bool)
        let mut events: Vec<(f64, usize, bool)> = Vec::new();
        for (l, g) in self.groups.iter().enumerate() {
            for (i, (&c, d)) in g.c.iter().zip(&g.d).enumerate() {
                if skip == Some((l, i)) {
                    continue;
                }
                // g(z(s)) = α − β s
                let alpha = eval2(c, d[0], d[1], p[0], p[1]);
                let beta = d[0] * dir[0] + d[1] * dir[1];
                let (sign_start, root) = if beta == 0.0 {
                    (alpha.partial_cmp(&0.0), None)
                } else {
                    let root = alpha / beta;
                    // Sign just after s0: positive iff s < root for β > 0.
                    let before = if beta > 0.0 {
                        std::cmp::Ordering::Greater
                    } else {
                        std::cmp::Ordering::Less
                    };
                    if root > s0 {
                        (Some(before), if root < s1 { Some(root) } else { None })
                    } else {
                        (Some(before.reverse()), None)
                    }
                };
                match sign_start {
                    Some(std::cmp::Ordering::Greater) => pos[l] += 1,
                    Some(std::cmp::Ordering::Less) => neg[l] += 1,
                    _ => {}
                }
                if let Some(r) = root {
                    // After the root the sign flips: β > 0 means positive → negative.
                    events.push((r, l, beta > 0.0));
                }
            }
        }
        events.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut sa = s0;
        let mut k = 0;
        while k <= events.len() {
            let sb = if k < events.len() { events[k].0 } else { s1 };
            if sb > sa {
                visit(sa, sb, &pos, &neg);
            }
            if k == events.len() {
                break;
            }
            // Apply every crossing at this parameter before the next piece.
            let here = events[k].0;
            while k < events.len() && events[k].0 == here {
                let (_, l, pos_to_neg) = events[k];
                if pos_to_neg {
                    pos[l] -= 1;
                    neg[l] += 1;
                } else {
                    neg[l] -= 1;
                    pos[l] += 1;
                }
                k += 1;
            }
            sa = here;
        }
    }

    fn mask(&self, pos: &[usize], neg: &[usize]) -> u32 {
        let mut m = 0;
        for l in 0..pos.len() {
            if pos[l] < self.q || neg[l] < self.q {
                m |= bit(l);
            }
        }
        m
    }

    /// The pieces of the line p + s·dir, s ∈ [s0, s1], with the groups each piece is outside of;
    /// neighbouring pieces with the same membership are merged.
    pub fn spans(&self, p: [f64; 2], dir: [f64; 2], s0: f64, s1: f64) -> Result<Vec<Span>> {
        self.need_2d()?;
        let mut out: Vec<Span> = Vec::new();
        self.sweep(p, dir, (s0, s1), None, |sa, sb, pos, neg| {
            let excluded = self.mask(pos, neg);
            match out.last_mut() {
                Some(last) if last.excluded == excluded && last.s1 == sa => last.s1 = sb,
                _ => out.push(Span {
                    s0: sa,
                    s1: sb,
                    excluded,
                }),
            }
        });
        Ok(out)
    }

    /// The boundary of X ∩ window as closed polygons (exact up to rounding of the line
    /// intersections). Pieces of every line g = 0 that separate a member cell from a non-member
    /// one, plus the pieces of the window's edges that lie in X, are chained into loops.
    pub fn boundary(&self, window: &BoxSet) -> Result<Vec<Loop>> {
        self.need_2d()?;
        Self::check_window(window, 1, 1)?;
        let (lo, hi) = ([window.lo[0], window.lo[1]], [window.hi[0], window.hi[1]]);
        // Oriented segments with X on their left.
        let mut segs: Vec<([f64; 2], [f64; 2])> = Vec::new();
        for (l, g) in self.groups.iter().enumerate() {
            for (i, (&c, d)) in g.c.iter().zip(&g.d).enumerate() {
                let nn = d[0] * d[0] + d[1] * d[1];
                if !(nn > 0.0) {
                    continue;
                }
                let norm = nn.sqrt();
                let p = [c * d[0] / nn, c * d[1] / nn];
                // Walking along dir, the left side is −d: where g > 0.
                let dir = [-d[1] / norm, d[0] / norm];
                let Some((s0, s1)) = clip_line(p, dir, lo, hi) else {
                    continue;
                };
                self.sweep(p, dir, (s0, s1), Some((l, i)), |sa, sb, pos, neg| {
                    let mut pp = pos.to_vec();
                    pp[l] += 1;
                    let in_plus = self.mask(&pp, neg) == 0;
                    let mut nn = neg.to_vec();
                    nn[l] += 1;
                    let in_minus = self.mask(pos, &nn) == 0;
                    if in_plus != in_minus {
                        let a = [p[0] + sa * dir[0], p[1] + sa * dir[1]];
                        let b = [p[0] + sb * dir[0], p[1] + sb * dir[1]];
                        segs.push(if in_plus { (a, b) } else { (b, a) });
                    }
                });
            }
        }
        // The window's edges, counter-clockwise: X ∩ window is on their left.
        let corners = box_corners(&lo, &hi);
        for k in 0..4 {
            let (a, b) = (corners[k], corners[(k + 1) % 4]);
            let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
            let dir = [(b[0] - a[0]) / len, (b[1] - a[1]) / len];
            for sp in self.spans(a, dir, 0.0, len)? {
                if sp.excluded == 0 {
                    segs.push((
                        [a[0] + sp.s0 * dir[0], a[1] + sp.s0 * dir[1]],
                        [a[0] + sp.s1 * dir[0], a[1] + sp.s1 * dir[1]],
                    ));
                }
            }
        }
        let scale = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        Ok(chain(segs, 1e-9 * scale))
    }

    /// Exact area of X ∩ window (shoelace over the boundary loops; holes count negative).
    pub fn area(&self, window: &BoxSet) -> Result<f64> {
        Ok(self
            .boundary(window)?
            .iter()
            .map(|lp| signed_area(&lp.points))
            .sum())
    }

    /// Directions v (unit, 2-D) along which X contains rays: for far x = x0 + s v the sign of
    /// g is that of −d·v, so v is a recession direction when every group has ≥ q functions with
    /// d·v < 0 and ≥ q with d·v > 0; on a direction where some d·v = 0 those functions keep a
    /// constant value and the offset across v decides. Checks every critical direction and the
    /// middle of every arc between them, so the answer is exact. Empty: X is bounded.
    pub fn recession_2d(&self) -> Result<Vec<[f64; 2]>> {
        self.need_2d()?;
        let mut angles: Vec<f64> = Vec::new();
        for g in &self.groups {
            for d in &g.d {
                if d[0] != 0.0 || d[1] != 0.0 {
                    let a = d[1].atan2(d[0]) + std::f64::consts::FRAC_PI_2;
                    angles.push(a.rem_euclid(std::f64::consts::PI));
                    angles.push((a + std::f64::consts::PI).rem_euclid(2.0 * std::f64::consts::PI));
                }
            }
        }
        for a in angles.iter_mut() {
            *a = a.rem_euclid(2.0 * std::f64::consts::PI);
        }
        crate::linalg::sort_increasing(&mut angles);
        angles.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
        let mut candidates: Vec<f64> = Vec::new();
        if angles.is_empty() {
            candidates.push(0.0);
        }
        for (k, a) in angles.iter().enumerate() {
            candidates.push(*a);
            let next = if k + 1 < angles.len() {
                angles[k + 1]
            } else {
                angles[0] + 2.0 * std::f64::consts::PI
            };
            candidates.push(0.5 * (a + next));
        }
        let mut out: Vec<[f64; 2]> = Vec::new();
        for a in candidates {
            let v = [a.cos(), a.sin()];
            if self.recedes_along(v) {
                out.push([clean(v[0]), clean(v[1])]);
            }
        }
        Ok(out)
    }

    fn recedes_along(&self, v: [f64; 2]) -> bool {
        let ng = self.groups.len();
        let (mut pos, mut neg) = (vec![0usize; ng], vec![0usize; ng]);
        // Functions constant along v, as (group, c, d·w) with w ⟂ v: g = c − (d·w)·ω.
        let mut flat: Vec<(usize, f64, f64)> = Vec::new();
        let w = [-v[1], v[0]];
        for (l, g) in self.groups.iter().enumerate() {
            for (&c, d) in g.c.iter().zip(&g.d) {
                let norm = d[0].hypot(d[1]);
                let dv = d[0] * v[0] + d[1] * v[1];
                if dv.abs() <= 1e-12 * norm {
                    flat.push((l, c, d[0] * w[0] + d[1] * w[1]));
                } else if dv < 0.0 {
                    pos[l] += 1;
                } else {
                    neg[l] += 1;
                }
            }
        }
        if flat.is_empty() {
            return self.mask(&pos, &neg) == 0;
        }
        // 1-D question: is there an offset ω where the flat functions complete the counts?
        let mut roots: Vec<f64> = flat
            .iter()
            .filter(|f| f.2 != 0.0)
            .map(|f| f.1 / f.2)
            .collect();
        crate::linalg::sort_increasing(&mut roots);
        let mut probes = Vec::new();
        match (roots.first(), roots.last()) {
            (Some(&a), Some(&b)) => {
                probes.push(a - 1.0 - a.abs());
                probes.push(b + 1.0 + b.abs());
                probes.extend(roots.windows(2).map(|p| 0.5 * (p[0] + p[1])));
            }
            _ => probes.push(0.0),
        }
        probes.into_iter().any(|om| {
            let (mut p, mut n) = (pos.clone(), neg.clone());
            for &(l, c, dw) in &flat {
                let val = c - dw * om;
                if val > 0.0 {
                    p[l] += 1;
                } else if val < 0.0 {
                    n[l] += 1;
                }
            }
            self.mask(&p, &n) == 0
        })
    }

    /// X of a 1-D region (dim = 1, a scalar state) exactly: the maximal open intervals of the
    /// line in X, in increasing order. Each g = c − d·x changes sign once, at its root c/d, so X
    /// is constant between consecutive roots; one sweep over the sorted roots updates the
    /// counts (d > 0: positive left of its root, negative right; d < 0 the reverse; d = 0 or a
    /// root beyond double precision: the sign of c everywhere). At a root the functions with that
    /// root are zero and count on neither side, so the root is in X only when both cells beside
    /// it are (then the two cells join into one interval): X has no isolated points, and it is
    /// a union of open intervals. O(N log N) for N functions.
    pub fn intervals_1d(&self) -> Result<Vec<LineInterval>> {
        if self.dim != 1 {
            return Err(Error::field(
                "region",
                format!(
                    "is {}-dimensional: its intervals are for a scalar state",
                    self.dim
                ),
            ));
        }
        let ng = self.groups.len();
        let (mut pos, mut neg) = (vec![0usize; ng], vec![0usize; ng]);
        // (root, group, d > 0): crossing the root left to right turns the function's sign.
        let mut roots: Vec<(f64, usize, bool)> = Vec::new();
        for (l, g) in self.groups.iter().enumerate() {
            for (&c, d) in g.c.iter().zip(&g.d) {
                let d = d[0];
                let root = c / d;
                if d != 0.0 && root.is_finite() {
                    roots.push((root, l, d > 0.0));
                    // Far left (x → −∞): g has the sign of d.
                    if d > 0.0 {
                        pos[l] += 1;
                    } else {
                        neg[l] += 1;
                    }
                } else if c > 0.0 {
                    pos[l] += 1;
                } else if c < 0.0 {
                    neg[l] += 1;
                }
            }
        }
        roots.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut out: Vec<LineInterval> = Vec::new();
        // The left end of the interval being built (None: −∞), when the current cell is in X.
        let mut open: Option<Option<f64>> = (self.mask(&pos, &neg) == 0).then_some(None);
        let mut k = 0;
        while k < roots.len() {
            let r = roots[k].0;
            let mut j = k;
            // At r: the functions with this root are zero.
            let (mut p_at, mut n_at) = (pos.clone(), neg.clone());
            while j < roots.len() && roots[j].0 == r {
                let (_, l, up) = roots[j];
                if up {
                    p_at[l] -= 1;
                    pos[l] -= 1;
                    neg[l] += 1;
                } else {
                    n_at[l] -= 1;
                    neg[l] -= 1;
                    pos[l] += 1;
                }
                j += 1;
            }
            let point_in = self.mask(&p_at, &n_at) == 0;
            let right_in = self.mask(&pos, &neg) == 0;
            match open {
                // The interval goes on through r only when r itself is in X.
                Some(lo) if !(point_in && right_in) => {
                    out.push(LineInterval { lo, hi: Some(r) });
                    open = right_in.then_some(Some(r));
                }
                Some(_) => {}
                None => open = right_in.then_some(Some(r)),
            }
            k = j;
        }
        if let Some(lo) = open {
            out.push(LineInterval { lo, hi: None });
        }
        Ok(out)
    }

    /// Directions along which every g is constant (the null space of the stacked d's): X is
    /// invariant along them, so it is unbounded as soon as it is not empty. Any dimension.
    pub fn invariant_directions(&self) -> Vec<Vec<f64>> {
        let rows: Vec<&Vec<f64>> = self.groups.iter().flat_map(|g| g.d.iter()).collect();
        if rows.is_empty() {
            return (0..self.dim)
                .map(|k| {
                    (0..self.dim)
                        .map(|j| if j == k { 1.0 } else { 0.0 })
                        .collect()
                })
                .collect();
        }
        let m = nalgebra::DMatrix::from_fn(rows.len(), self.dim, |i, j| rows[i][j]);
        let gram = m.transpose() * &m;
        let Some(eig) = crate::linalg::try_symmetric_eigen(gram) else {
            return Vec::new();
        };
        let top = eig.eigenvalues.iter().cloned().fold(0.0, f64::max);
        let mut out = Vec::new();
        for (k, &ev) in eig.eigenvalues.iter().enumerate() {
            if ev <= 1e-20 * top.max(f64::MIN_POSITIVE) * (rows.len() as f64) {
                let mut v: Vec<f64> = eig.eigenvectors.column(k).iter().copied().collect();
                // Sign: first clearly non-zero entry positive, so reports are reproducible.
                if let Some(first) = v.iter().find(|x| x.abs() > 1e-9) {
                    if *first < 0.0 {
                        v.iter_mut().for_each(|x| *x = -*x);
                    }
                }
                out.push(v.into_iter().map(clean).collect());
            }
        }
        out
    }
}

/// Round values within 1e-12 of a "nice" number so reports read [0.707…, 0.707…], not ±1e-17.
fn clean(v: f64) -> f64 {
    if v.abs() < 1e-13 {
        0.0
    } else {
        v
    }
}

/// The parameter range where p + s·dir lies inside the box [lo, hi] (slab clipping).
fn clip_line(p: [f64; 2], dir: [f64; 2], lo: [f64; 2], hi: [f64; 2]) -> Option<(f64, f64)> {
    let (mut s0, mut s1) = (f64::NEG_INFINITY, f64::INFINITY);
    for k in 0..2 {
        if dir[k] == 0.0 {
            if p[k] < lo[k] || p[k] > hi[k] {
                return None;
            }
        } else {
            let (a, b) = ((lo[k] - p[k]) / dir[k], (hi[k] - p[k]) / dir[k]);
            s0 = s0.max(a.min(b));
            s1 = s1.min(a.max(b));
        }
    }
    (s1 > s0).then_some((s0, s1))
}

/// Chain oriented segments (X on the left) into closed loops: each segment is followed by the
/// unused segment starting nearest its end (the ends of neighbouring pieces are computed from
/// different lines and agree only to rounding, hence the tolerance).
fn chain(segs: Vec<([f64; 2], [f64; 2])>, tol: f64) -> Vec<Loop> {
    let mut used = vec![false; segs.len()];
    let mut loops = Vec::new();
    let dist = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs().max((a[1] - b[1]).abs());
    for start in 0..segs.len() {
        if used[start] {
            continue;
        }
        used[start] = true;
        let mut pts = vec![segs[start].0];
        let mut end = segs[start].1;
        loop {
            if dist(end, segs[start].0) <= tol && pts.len() > 1 {
                break;
            }
            let next = (0..segs.len())
                .filter(|&k| !used[k])
                .map(|k| (k, dist(segs[k].0, end)))
                .filter(|&(_, e)| e <= tol)
                .min_by(|a, b| a.1.total_cmp(&b.1));
            match next {
                Some((k, _)) => {
                    used[k] = true;
                    pts.push(segs[k].0);
                    end = segs[k].1;
                }
                None => break, // open chain (degenerate arrangement): keep what we have
            }
        }
        // Merge collinear consecutive points (pieces of one line split by other crossings).
        let pts = simplify(pts);
        if pts.len() >= 3 {
            let hole = signed_area(&pts) < 0.0;
            loops.push(Loop { points: pts, hole });
        }
    }
    loops
}

fn simplify(pts: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    let n = pts.len();
    if n < 4 {
        return pts;
    }
    let mut out = Vec::with_capacity(n);
    for k in 0..n {
        let (a, b, c) = (pts[(k + n - 1) % n], pts[k], pts[(k + 1) % n]);
        let cross = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
        let scale = ((b[0] - a[0]).abs() + (b[1] - a[1]).abs())
            * ((c[0] - b[0]).abs() + (c[1] - b[1]).abs());
        if cross.abs() > 1e-12 * scale {
            out.push(b);
        }
    }
    out
}
