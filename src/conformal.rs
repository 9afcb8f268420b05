//! Conformal prediction beside the Kalman filter: the distribution-free promise *on average*.
//!
//! Two constructions, both on the Kalman filter's own quantities:
//!
//! * **Split conformal state region** (Vovk, Gammerman & Shafer, *Algorithmic Learning in a
//!   Random World*, 2005; Lei, G'Sell, Rinaldo, Tibshirani & Wasserman, JASA 2018). The score
//!   of a run is the filter's Mahalanobis distance s = (x_t − x̂_t)ᵀ P_t⁻¹ (x_t − x̂_t) at the
//!   target time t. N calibration runs drawn from the *true* noise law (which may differ from
//!   the V, W the filter assumes) give N scores; the radius² is their k-th smallest,
//!   k = ⌈(N + 1)·level⌉ ([`split_rank`]). The region is the Kalman ellipsoid with that radius.
//!   If the N calibration runs and the run at hand are exchangeable, then
//!   level ≤ P(x_t ∈ region) ≤ level + 1/(N + 1) ([`promise`]), the probability taken over the
//!   calibration runs *and* the run at hand: a *marginal* promise, an average over states.
//!   It says nothing about a fixed state: at a state far from the prior mean the region
//!   misses far more often, as the Kalman ellipsoid does. No finite-sample method can promise
//!   conditional coverage for every state without further assumptions (Vovk 2012; Lei &
//!   Wasserman, JRSS-B 2014; Barber, Candès, Ramdas & Tibshirani, *Information and Inference*
//!   2021): the SCF and LSCR papers' regions get theirs from the model (SCF) or from the sign
//!   structure of the noise (LSCR), not from exchangeability.
//! * **Adaptive conformal inference** (Gibbs & Candès, *Adaptive conformal inference under
//!   distribution shift*, NeurIPS 2021) on the filter's one-step output prediction: with the
//!   normalized innovation r_t = ‖S_t^{−1/2}(y_t − H_t x̂_{t|t−1})‖, the set at t is
//!   {y : ‖S_t^{−1/2}(y − ŷ_{t|t−1})‖ ≤ q_t}, q_t the (1 − α_t) empirical quantile of
//!   r_1 … r_{t−1}; then α_{t+1} = α_t + γ(α − err_t) (their (2)). Whatever the record, the
//!   long-run miss rate obeys |(1/T) Σ err_t − α| ≤ (max(α₁, 1 − α₁) + γ)/(γT) (their
//!   Proposition 4.1) — provided a set is empty when α_t ≥ 1 and the whole space when
//!   α_t ≤ 0, which [`aci`] does. It needs no true state, so it runs on measured data.
//!   The bound holds over the T *scored* steps, the whole-line steps of the start included
//!   (their err_t = 0 is part of the recursion the proof sums); the coverage a reader wants is
//!   the one over the steps that have an interval, reported apart from those warm-up steps
//!   ([`AciStep::warmup`]).
//!
//! Gaps (a missing measurement): the filter skips its update there (or makes a partial one,
//! [`crate::kalman::KalmanGains::with_gaps`]). The split conformal region at t uses the
//! filter at t with those updates skipped, and every calibration run is filtered with the
//! same gains (the same skipped updates), so its score has the law of the record's: the runs
//! stay exchangeable with the record. ACI has nothing to score at a step with a missing
//! output: no miss or cover is counted there and α_t is not updated (the step is left out of
//! the sequence (2) runs over; its interval for the missing y is still reported).
//!
//! The heavy-tailed law ([`NoiseLaw::StudentT`]) is the multivariate Student-t with ν > 2
//! degrees of freedom scaled to the same covariance as the Gaussian: z·√((ν − 2)/g) with
//! z ~ N(0, I), g ~ χ²_ν. The filter's χ² radius then loses marginal coverage (its scores
//! are no longer χ²) while the conformal radius, calibrated on that law, keeps it.

use crate::linalg::psd_sqrt;
use crate::model::{normal_vector, Inputs, LinearModel, Trajectory};
use nalgebra::{DMatrix, DVector};
use rand::{Rng, RngExt};
use rand_distr::ChiSquared;

/// The law of the simulated noise (process noise, output noise and the initial state's
/// deviation), each with the covariance the model gives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NoiseLaw {
    Gaussian,
    /// Multivariate Student-t with `nu` > 2 degrees of freedom, scaled to unit covariance.
    StudentT {
        nu: f64,
    },
}

impl NoiseLaw {
    /// n draws with zero mean and identity covariance.
    pub fn draw<R: Rng>(&self, n: usize, rng: &mut R) -> DVector<f64> {
        let z = normal_vector(n, rng);
        match *self {
            NoiseLaw::Gaussian => z,
            NoiseLaw::StudentT { nu } => {
                // χ²_ν with ν > 2 is a valid law (checked by the scenario layer); a draw of 0
                // has probability 0, and is kept off the division anyway.
                let g: f64 = ChiSquared::new(nu).map_or(nu, |d| rng.sample(d));
                z * ((nu - 2.0) / g.max(f64::MIN_POSITIVE)).sqrt()
            }
        }
    }
}

/// Forward simulation with the square roots of Γ₁, V_t, W_t computed once, drawing in
/// [`LinearModel::simulate`]'s order: for the Gaussian law it gives that record bit for bit.
pub struct Simulator {
    law: NoiseLaw,
    x1_root: DMatrix<f64>,
    /// sqrt V_t and sqrt W_t, t = 1..=steps (index t − 1).
    roots: Vec<(DMatrix<f64>, DMatrix<f64>)>,
    inputs: Vec<DVector<f64>>,
}

impl Simulator {
    pub fn new(model: &LinearModel, steps: usize, u: &Inputs, law: NoiseLaw) -> Simulator {
        Simulator {
            law,
            x1_root: psd_sqrt(&model.x1_cov),
            roots: (1..=steps)
                .map(|t| (psd_sqrt(model.v(t)), psd_sqrt(model.w(t))))
                .collect(),
            inputs: (1..=steps).map(|t| model.input_term(t, u)).collect(),
        }
    }

    /// x_1..x_T and y_1..y_T.
    pub fn draw<R: Rng>(&self, model: &LinearModel, rng: &mut R) -> Trajectory {
        let (n, q) = (model.n(), model.q());
        let mut x = &model.x1_mean + &self.x1_root * self.law.draw(n, rng);
        let steps = self.roots.len();
        let mut traj = Trajectory {
            x: Vec::with_capacity(steps),
            y: Vec::with_capacity(steps),
        };
        for (i, (v_root, w_root)) in self.roots.iter().enumerate() {
            let t = i + 1;
            traj.y
                .push(model.h(t) * &x + w_root * self.law.draw(q, rng));
            traj.x.push(x.clone());
            x = model.f(t) * &x + &self.inputs[i] + v_root * self.law.draw(n, rng);
        }
        traj
    }
}

/// The rank k = ⌈(N + 1)·level⌉ of split conformal's radius among N calibration scores, or
/// `None` when k > N (too few runs: the region would be the whole space).
pub fn split_rank(calibration: usize, level: f64) -> Option<usize> {
    let k = ((calibration as f64 + 1.0) * level).ceil();
    // (N + 1)·level is exact enough: N ≤ 10⁶ and level has 53 bits; a product that lands a
    // rounding above a whole number would only make the region one score larger (safe side).
    let k = k.max(1.0) as usize;
    (k <= calibration).then_some(k)
}

/// The fewest calibration runs with a finite radius at `level`: the smallest N with
/// ⌈(N + 1)·level⌉ ≤ N.
pub fn min_calibration(level: f64) -> usize {
    let mut n = (level / (1.0 - level)).floor().max(1.0) as usize;
    while split_rank(n, level).is_none() {
        n += 1;
    }
    n
}

/// The k-th smallest (1-based) of `scores`; reorders them.
pub fn order_statistic(scores: &mut [f64], k: usize) -> f64 {
    let (_, kth, _) = scores.select_nth_unstable_by(k - 1, f64::total_cmp);
    *kth
}

/// The promise of the split conformal region with N calibration runs at `level`: the exact
/// marginal coverage k/(N + 1) for continuous scores, and the published bounds
/// [level, level + 1/(N + 1)] it lies in.
pub fn promise(calibration: usize, level: f64) -> Option<(f64, f64, f64)> {
    let k = split_rank(calibration, level)?;
    let n1 = calibration as f64 + 1.0;
    Some((k as f64 / n1, level, level + 1.0 / n1))
}

/// (x − m)ᵀ P⁻¹ (x − m) with P's Cholesky factor; `None` when P is not positive definite.
pub fn mahalanobis2(
    x: &DVector<f64>,
    mean: &DVector<f64>,
    chol: &nalgebra::Cholesky<f64, nalgebra::Dyn>,
) -> f64 {
    let d = x - mean;
    let z = chol.l().solve_lower_triangular(&d).unwrap_or(d);
    z.norm_squared()
}

/// One step of adaptive conformal inference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AciStep {
    /// α_t before the step's update.
    pub alpha_t: f64,
    /// q_t: the set's radius in normalized units (+∞: the whole space, α_t ≤ 0 or too few
    /// past scores; `None`-like emptiness is `empty`).
    pub q: f64,
    /// The set is empty (α_t ≥ 1): ACI's own answer, which misses (Gibbs & Candès's rule
    /// that keeps α_t bounded).
    pub empty: bool,
    /// err_t: the score left the set; `None` at a step with no score (a gap: nothing to
    /// count, α_t not updated).
    pub err: Option<bool>,
    /// A warm-up step: before the first finite (or empty) set, the past holds too few scores
    /// for the ⌈(1 − α_t)·t⌉-th smallest, so the set is the whole space and cannot miss.
    pub warmup: bool,
}

/// Adaptive conformal inference over `scores` r_1 … r_T with target miss rate `miss` (α),
/// step size `gamma` and α₁ = `miss`. q_t is the ⌈(1 − α_t)(t)⌉-th smallest of the t − 1 past
/// scores (the split conformal rank with the past as calibration), +∞ when that rank exceeds
/// t − 1 (α_t ≤ 0 included); the set is empty when α_t ≥ 1. A `None` score (a gap) gives the
/// step's set from the past as it stands, counts nothing and leaves α_t and the past as they
/// are: the recursion (2) runs over the scored steps only.
pub fn aci(scores: &[Option<f64>], miss: f64, gamma: f64) -> Vec<AciStep> {
    let mut past: Vec<f64> = Vec::with_capacity(scores.len());
    let mut alpha_t = miss;
    let mut out = Vec::with_capacity(scores.len());
    let mut warming = true;
    for &r in scores {
        let (q, empty) = if alpha_t >= 1.0 {
            (0.0, true)
        } else {
            let level = 1.0 - alpha_t;
            match split_rank(past.len(), level.min(1.0)) {
                Some(k) if alpha_t > 0.0 => (past[k - 1], false),
                _ => (f64::INFINITY, false),
            }
        };
        warming &= q.is_infinite() && !empty;
        let err = r.map(|r| empty || r > q);
        out.push(AciStep {
            alpha_t,
            q,
            empty,
            err,
            warmup: warming,
        });
        if let (Some(r), Some(err)) = (r, err) {
            alpha_t += gamma * (miss - f64::from(u8::from(err)));
            let at = past.partition_point(|p| *p <= r);
            past.insert(at, r);
        }
    }
    out
}

/// Where Proposition 4.1's bound stops saying anything: the coverage lies in [0, 1], so its
/// distance from 1 − α is at most max(α, 1 − α), and a bound at or above that rules out no
/// coverage at all. Returns that largest possible distance.
pub fn aci_largest_gap(miss: f64) -> f64 {
    miss.max(1.0 - miss)
}

/// The fewest scored steps T at which Proposition 4.1's bound rules out some coverage:
/// the smallest T with (max(α₁, 1 − α₁) + γ)/(γT) < max(α, 1 − α), α₁ = α.
pub fn aci_informative_steps(miss: f64, gamma: f64) -> usize {
    let m = aci_largest_gap(miss);
    let t = (miss.max(1.0 - miss) + gamma) / (gamma * m);
    let mut steps = t.floor().max(1.0) as usize;
    while aci_bound(miss, gamma, steps) >= m {
        steps += 1;
    }
    steps
}

/// The theoretical bound on ACI's long-run miss rate over T steps (Gibbs & Candès,
/// Proposition 4.1): |(1/T) Σ err_t − α| ≤ (max(α₁, 1 − α₁) + γ)/(γT), α₁ = α.
pub fn aci_bound(miss: f64, gamma: f64, steps: usize) -> f64 {
    (miss.max(1.0 - miss) + gamma) / (gamma * steps as f64)
}

/// The lowest coverage (1 − mean miss) over every window of `window` consecutive steps, and
/// the window's first step (1-based); `None` when the record is shorter than the window.
pub fn worst_window(err: &[bool], window: usize) -> Option<(f64, usize)> {
    if window == 0 || err.len() < window {
        return None;
    }
    let mut misses: usize = err[..window].iter().filter(|e| **e).count();
    let mut worst = (misses, 0);
    for start in 1..=err.len() - window {
        misses += usize::from(err[start + window - 1]);
        misses -= usize::from(err[start - 1]);
        if misses > worst.0 {
            worst = (misses, start);
        }
    }
    Some((1.0 - worst.0 as f64 / window as f64, worst.1 + 1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_rank_is_the_ceiling_of_n_plus_one_times_the_level() {
        assert_eq!(split_rank(99, 0.9), Some(90));
        assert_eq!(split_rank(199, 0.9), Some(180));
        assert_eq!(split_rank(19, 0.95), Some(19));
        assert_eq!(split_rank(18, 0.95), None);
        assert_eq!(min_calibration(0.95), 19);
        assert_eq!(min_calibration(0.9), 9);
        assert_eq!(min_calibration(0.99), 99);
    }

    #[test]
    fn worst_window_finds_the_densest_misses() {
        let err = [false, true, true, false, false, false];
        assert_eq!(worst_window(&err, 2), Some((0.0, 2)));
        assert_eq!(worst_window(&err, 3), Some((1.0 - 2.0 / 3.0, 1)));
        assert_eq!(worst_window(&err, 7), None);
    }

    #[test]
    fn aci_empties_above_one_and_opens_below_zero() {
        // All-equal scores: q = the score, so no non-empty set misses; with no misses α_t
        // rises by γα a step until α_t ≥ 1 empties the set, which then misses.
        let steps = aci(&[Some(1.0); 50], 0.5, 0.5);
        assert!(steps.iter().all(|s| s.empty || s.err == Some(false)));
        assert!(steps
            .iter()
            .any(|s| s.empty && s.err == Some(true) && s.alpha_t >= 1.0));
        // Rising scores: each exceeds every past one, so every finite set misses; α_t falls
        // until α_t ≤ 0 opens the whole space, which holds it.
        let rising: Vec<Option<f64>> = (0..50).map(|i| Some(f64::from(i))).collect();
        let steps = aci(&rising, 0.1, 0.5);
        assert!(steps
            .iter()
            .all(|s| s.q.is_infinite() || s.err == Some(true)));
        assert!(steps
            .iter()
            .skip(1)
            .any(|s| s.alpha_t <= 0.0 && s.q.is_infinite() && s.err == Some(false) && !s.warmup));
    }

    #[test]
    fn aci_skips_a_gap_and_marks_the_warm_up() {
        // α = 0.5: the first set needs ⌈(N + 1)·0.5⌉ ≤ N past scores, N = 1; step 1 is the
        // whole line (warm-up, covered), and α_t rises by γα to 0.75 before step 2.
        let scores = [Some(1.0), None, Some(2.0), Some(0.5)];
        let steps = aci(&scores, 0.5, 0.5);
        assert!(steps[0].warmup && steps[0].q.is_infinite() && steps[0].err == Some(false));
        // The gap: no count, α_t unchanged after it, its set still from the past.
        assert_eq!(steps[1].err, None);
        assert_eq!(steps[1].alpha_t, 0.75);
        assert_eq!(steps[2].alpha_t, 0.75);
        assert!(!steps[1].warmup && steps[1].q == 1.0);
        // Step 3: q = the ⌈2·0.25⌉ = 1st smallest of {1}: 2 > 1 misses, α falls by γ(1 − α).
        assert_eq!(steps[2].err, Some(true));
        assert_eq!(steps[3].alpha_t, 0.75 + 0.5 * (0.5 - 1.0));
        assert!(!steps[3].warmup);
    }

    #[test]
    fn aci_bound_says_something_from_the_informative_length_on() {
        for (miss, gamma) in [(0.1, 0.01), (0.05, 0.005), (0.5, 0.1), (0.2, 1.0)] {
            let t = aci_informative_steps(miss, gamma);
            let m = aci_largest_gap(miss);
            assert!(aci_bound(miss, gamma, t) < m, "{miss} {gamma}");
            assert!(
                t == 1 || aci_bound(miss, gamma, t - 1) >= m,
                "{miss} {gamma}"
            );
        }
    }
}
