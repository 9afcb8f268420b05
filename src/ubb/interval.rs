//! The line path of Section IV's state estimator: a 1-D state (r = 1) with per-sample l∞
//! bounds, the planar path's ([`super::planar`]) recursion on intervals.
//!
//! With one state the feasible set of x(t) is an interval, and the recursion of T(h) (3) read
//! at each time is exact with no LP: from e(s) ∈ [−h, h] (the δ bound and the noise before the
//! window, or the whole line with δ = ∞), for t = s … k clip by every measurement strip
//! lo ≤ c_i(t)·e(t) ≤ hi (46) (a row with c = 0 only checks its datum), keep the interval of
//! e(k) after the last strips (the filtered set), map by a and widen by Σ_j |b_j|·τe^{(k−t)/α}
//! (45), the sum of the noise segments. A missing measurement has no strip. An unbounded end
//! stays unbounded under a ≠ 0 and goes to 0 under a = 0 (x(t+1) is then the noise alone: the
//! scalar pair is reconstructible without being observable).

use super::planar::reversed;

/// How the recursion ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Outcome {
    /// The interval of e(k+1) (predicted) and of e(k) after the last strips (filtered;
    /// `None` when unbounded).
    Interval {
        predicted: [f64; 2],
        filtered: Option<[f64; 2]>,
    },
    /// The data contradict the bounds.
    Empty,
    /// The data did not bound the set: the caller keeps the LP path (which says why).
    Open,
}

/// One time of the window: the strips lo ≤ c·e(t) ≤ hi, then the half-width of the noise
/// added by the map to e(t+1) (Σ_j |b_j| times the sample's bound; 0: none).
#[derive(Debug, Clone)]
pub struct Sample {
    pub strips: Vec<(f64, f64, f64)>,
    pub noise: f64,
}

fn bounded(i: [f64; 2]) -> bool {
    i[0].is_finite() && i[1].is_finite()
}

/// [lo, hi] ∩ {e : l ≤ c·e ≤ h}, `None` when empty.
fn clip(i: [f64; 2], c: f64, l: f64, h: f64) -> Option<[f64; 2]> {
    if c == 0.0 {
        return (!reversed(l, 0.0) && !reversed(0.0, h)).then_some(i);
    }
    if reversed(l, h) {
        return None;
    }
    let (a, b) = if c > 0.0 {
        (l / c, h / c)
    } else {
        (h / c, l / c)
    };
    let (lo, hi) = (i[0].max(a), i[1].min(b));
    (!reversed(lo, hi)).then_some([lo, hi.max(lo)])
}

/// The forward recursion from e(s) to e(k+1): `start` the half-width of e(s) (`None`:
/// unbounded), `equal` a value of e(s) (Example 4's Σx(0) with one state), `a` the map,
/// `samples` the times s … k.
pub fn propagate(a: f64, start: Option<f64>, equal: Option<f64>, samples: &[Sample]) -> Outcome {
    let mut set = match start {
        Some(h) => [-h, h],
        None => [f64::NEG_INFINITY, f64::INFINITY],
    };
    if let Some(v) = equal {
        match clip(set, 1.0, v, v) {
            Some(s) => set = s,
            None => return Outcome::Empty,
        }
    }
    let mut filtered = None;
    for (t, sample) in samples.iter().enumerate() {
        for &(c, lo, hi) in &sample.strips {
            match clip(set, c, lo, hi) {
                Some(s) => set = s,
                None => return Outcome::Empty,
            }
        }
        if t + 1 == samples.len() {
            filtered = bounded(set).then_some(set);
        }
        set = if a == 0.0 {
            [0.0, 0.0]
        } else if a > 0.0 {
            [a * set[0], a * set[1]]
        } else {
            [a * set[1], a * set[0]]
        };
        if sample.noise > 0.0 {
            set = [set[0] - sample.noise, set[1] + sample.noise];
        }
    }
    if bounded(set) {
        Outcome::Interval {
            predicted: set,
            filtered,
        }
    } else {
        Outcome::Open
    }
}
