//! Plot windows and clipping (plotters draws outside the plotting area if asked to, so every
//! series that may leave the window is clipped here first). Pure geometry: it imports nothing
//! of the plot layer (a chart's window, `Win::of_chart`, is made in `style::axes`).

/// An axis-aligned window [x0, x1] × [y0, y1] in chart coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Win {
    pub x0: f64,
    pub x1: f64,
    pub y0: f64,
    pub y1: f64,
}

impl Win {
    /// Holds nothing yet.
    pub fn empty() -> Win {
        Win {
            x0: f64::INFINITY,
            x1: f64::NEG_INFINITY,
            y0: f64::INFINITY,
            y1: f64::NEG_INFINITY,
        }
    }
    pub fn new(x: (f64, f64), y: (f64, f64)) -> Win {
        Win {
            x0: x.0,
            x1: x.1,
            y0: y.0,
            y1: y.1,
        }
    }
    pub fn is_empty(&self) -> bool {
        !(self.x0 <= self.x1 && self.y0 <= self.y1)
    }
    /// Grow to hold (x, y); non-finite points are ignored.
    pub fn add(&mut self, x: f64, y: f64) {
        if x.is_finite() && y.is_finite() {
            self.x0 = self.x0.min(x);
            self.x1 = self.x1.max(x);
            self.y0 = self.y0.min(y);
            self.y1 = self.y1.max(y);
        }
    }
    /// Grow to hold only x (y unchanged) or only y.
    pub fn add_x(&mut self, x: f64) {
        if x.is_finite() {
            self.x0 = self.x0.min(x);
            self.x1 = self.x1.max(x);
        }
    }
    pub fn add_y(&mut self, y: f64) {
        if y.is_finite() {
            self.y0 = self.y0.min(y);
            self.y1 = self.y1.max(y);
        }
    }
    pub fn add_points(&mut self, pts: &[(f64, f64)]) {
        for &(x, y) in pts {
            self.add(x, y);
        }
    }
    pub fn union(&self, o: &Win) -> Win {
        Win {
            x0: self.x0.min(o.x0),
            x1: self.x1.max(o.x1),
            y0: self.y0.min(o.y0),
            y1: self.y1.max(o.y1),
        }
    }
    pub fn width(&self) -> f64 {
        self.x1 - self.x0
    }
    pub fn height(&self) -> f64 {
        self.y1 - self.y0
    }
    pub fn contains(&self, x: f64, y: f64) -> bool {
        x >= self.x0 && x <= self.x1 && y >= self.y0 && y <= self.y1
    }
    /// Pad by `fx`, `fy` of the width/height on each side; a degenerate side gets a span from
    /// the other side or the magnitude of its values, so the window is never empty or flat.
    pub fn padded(&self, fx: f64, fy: f64) -> Win {
        let mut w = if self.is_empty() {
            Win::new((-1.0, 1.0), (-1.0, 1.0))
        } else {
            *self
        };
        let fallback = |a: f64, b: f64, other: f64| {
            let m = a.abs().max(b.abs());
            if other > 0.0 {
                other
            } else if m > 0.0 {
                0.2 * m
            } else {
                1.0
            }
        };
        let (ww, hh) = (w.width(), w.height());
        if ww <= 0.0 {
            let s = fallback(w.x0, w.x1, hh);
            w.x0 -= 0.5 * s;
            w.x1 += 0.5 * s;
        }
        if hh <= 0.0 {
            let s = fallback(w.y0, w.y1, ww.max(0.0));
            w.y0 -= 0.5 * s;
            w.y1 += 0.5 * s;
        }
        let (dx, dy) = (w.width() * fx, w.height() * fy);
        Win::new((w.x0 - dx, w.x1 + dx), (w.y0 - dy, w.y1 + dy))
    }
    /// The window of a time chart spanning `x` and holding `ys`: the y range padded by 7 % (a
    /// flat range gets a unit span), or [−1, 1] when `ys` is empty.
    pub fn time(x: (f64, f64), ys: impl Iterator<Item = f64>) -> Win {
        let mut w = Win::empty();
        for y in ys {
            w.add_y(y);
        }
        let p = if w.y0 <= w.y1 {
            Win::new((0.0, 1.0), (w.y0, w.y1)).padded(0.0, 0.07)
        } else {
            Win::new((0.0, 1.0), (-1.0, 1.0))
        };
        Win::new(x, (p.y0, p.y1))
    }
    /// Grow the narrower side so one unit has the same length in pixels on both axes.
    pub fn equal_aspect(&self, px_w: f64, px_h: f64) -> Win {
        let (sx, sy) = (self.width() / px_w, self.height() / px_h);
        let s = sx.max(sy);
        let (cx, cy) = (0.5 * (self.x0 + self.x1), 0.5 * (self.y0 + self.y1));
        let (hw, hh) = (0.5 * s * px_w, 0.5 * s * px_h);
        Win::new((cx - hw, cx + hw), (cy - hh, cy + hh))
    }
}

/// Liang–Barsky: the part of segment a→b inside `w`, if any.
fn clip_segment(a: (f64, f64), b: (f64, f64), w: &Win) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0 - w.x0),
        (dx, w.x1 - a.0),
        (-dy, a.1 - w.y0),
        (dy, w.y1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    if t0 > t1 {
        return None;
    }
    Some((
        (a.0 + t0 * dx, a.1 + t0 * dy),
        (a.0 + t1 * dx, a.1 + t1 * dy),
    ))
}

/// The pieces of a polyline inside `w`. Non-finite points break the line.
pub fn clip_polyline(pts: &[(f64, f64)], w: &Win) -> Vec<Vec<(f64, f64)>> {
    let mut out: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut cur: Vec<(f64, f64)> = Vec::new();
    let finite = |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite();
    for pair in pts.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        if !(finite(&a) && finite(&b)) {
            if cur.len() > 1 {
                out.push(std::mem::take(&mut cur));
            }
            cur.clear();
            continue;
        }
        match clip_segment(a, b, w) {
            Some((p, q)) => {
                if cur.last() != Some(&p) {
                    if cur.len() > 1 {
                        out.push(std::mem::take(&mut cur));
                    }
                    cur.clear();
                    cur.push(p);
                }
                cur.push(q);
                if q != b {
                    out.push(std::mem::take(&mut cur));
                }
            }
            None => {
                if cur.len() > 1 {
                    out.push(std::mem::take(&mut cur));
                }
                cur.clear();
            }
        }
    }
    if cur.len() > 1 {
        out.push(cur);
    }
    out
}

/// A closed polygon cut to `w` (Sutherland–Hodgman against the four edges): the filled area
/// inside the window. A non-convex polygon stays one polygon, with edges along the window
/// where it left it.
pub fn clip_polygon(pts: &[(f64, f64)], w: &Win) -> Vec<(f64, f64)> {
    type Inside = fn(&(f64, f64), &Win) -> bool;
    type Cross = fn((f64, f64), (f64, f64), &Win) -> (f64, f64);
    fn at_x(a: (f64, f64), b: (f64, f64), x: f64) -> (f64, f64) {
        (x, a.1 + (b.1 - a.1) * (x - a.0) / (b.0 - a.0))
    }
    fn at_y(a: (f64, f64), b: (f64, f64), y: f64) -> (f64, f64) {
        (a.0 + (b.0 - a.0) * (y - a.1) / (b.1 - a.1), y)
    }
    let edges: [(Inside, Cross); 4] = [
        (|p, w| p.0 >= w.x0, |a, b, w| at_x(a, b, w.x0)),
        (|p, w| p.0 <= w.x1, |a, b, w| at_x(a, b, w.x1)),
        (|p, w| p.1 >= w.y0, |a, b, w| at_y(a, b, w.y0)),
        (|p, w| p.1 <= w.y1, |a, b, w| at_y(a, b, w.y1)),
    ];
    let mut poly: Vec<(f64, f64)> = pts
        .iter()
        .copied()
        .filter(|p| p.0.is_finite() && p.1.is_finite())
        .collect();
    for (inside, cross) in edges {
        let n = poly.len();
        let mut out = Vec::with_capacity(n + 4);
        for i in 0..n {
            let (a, b) = (poly[(i + n - 1) % n], poly[i]);
            match (inside(&a, w), inside(&b, w)) {
                (true, true) => out.push(b),
                (true, false) => out.push(cross(a, b, w)),
                (false, true) => {
                    out.push(cross(a, b, w));
                    out.push(b);
                }
                (false, false) => {}
            }
        }
        poly = out;
    }
    poly
}

#[cfg(all(test, not(target_arch = "wasm32")))]
mod tests {
    use super::*;

    #[test]
    fn polygon_clipping_keeps_the_area_inside() {
        let w = Win::new((0.0, 1.0), (0.0, 1.0));
        // A square from (0.5, 0.5) to (1.5, 1.5): its quarter inside the window.
        let cut = clip_polygon(&[(0.5, 0.5), (1.5, 0.5), (1.5, 1.5), (0.5, 1.5)], &w);
        let area = |p: &[(f64, f64)]| {
            (0..p.len())
                .map(|i| {
                    let (a, b) = (p[i], p[(i + 1) % p.len()]);
                    a.0 * b.1 - b.0 * a.1
                })
                .sum::<f64>()
                .abs()
                / 2.0
        };
        assert!((area(&cut) - 0.25).abs() < 1e-12, "{cut:?}");
        assert!(cut.iter().all(|p| w.contains(p.0, p.1)));
        assert!(clip_polygon(&[(2.0, 2.0), (3.0, 2.0), (3.0, 3.0)], &w).is_empty());
    }

    #[test]
    fn clipping_keeps_inside_and_cuts_at_the_edges() {
        let w = Win::new((0.0, 1.0), (0.0, 1.0));
        let pieces = clip_polyline(&[(-1.0, 0.5), (0.5, 0.5), (0.5, 2.0), (0.6, 3.0)], &w);
        assert_eq!(pieces.len(), 1);
        assert_eq!(pieces[0], vec![(0.0, 0.5), (0.5, 0.5), (0.5, 1.0)]);
        let back = clip_polyline(&[(0.2, 0.2), (0.2, 2.0), (0.8, 2.0), (0.8, 0.2)], &w);
        assert_eq!(back.len(), 2);
        assert!(clip_polyline(&[(2.0, 2.0), (3.0, 3.0)], &w).is_empty());
    }

    #[test]
    fn equal_aspect_grows_the_narrow_side() {
        let w = Win::new((0.0, 1.0), (0.0, 4.0)).equal_aspect(400.0, 400.0);
        assert!((w.width() - 4.0).abs() < 1e-12 && (w.height() - 4.0).abs() < 1e-12);
        let p = Win::new((3.0, 3.0), (1.0, 1.0)).padded(0.1, 0.1);
        assert!(p.width() > 0.0 && p.height() > 0.0);
    }
}
