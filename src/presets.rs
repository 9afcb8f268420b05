//! The paper examples as scenarios: data shipped once and used by the page, the CLI and the
//! tests (`confset presets`, `confset run --preset NAME`, the page's preset menu).

use crate::error::{Error, Result};
use crate::linalg::{self, to_rows};
use crate::lscr::Construction;
use crate::method::Method;
use crate::model::{Inputs, LinearModel, MatrixSpec, ModelSpec};
use crate::scenario::lscr::Estimate;
use crate::scenario::{
    CollisionSpec, Condition, CurveSpec, ExperimentSpec, LscrSpec, Scenario, SimulateSpec,
};
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// A named scenario with a one-line description.
#[derive(Debug, Clone, Serialize)]
pub struct Preset {
    pub name: String,
    pub description: String,
    pub scenario: Scenario,
}

/// Every preset, in menu order.
pub fn all() -> Vec<Preset> {
    vec![
        Preset {
            name: "scf-scalar".into(),
            description: "SCF paper, Example 1: F = √(5/6), H = 1, V = W = 1 (p̄ = 3/5, ratio 0.9, Fig. 1)".into(),
            scenario: scalar(),
        },
        Preset {
            name: "scf-robots".into(),
            description: "SCF paper, Section II: two robots returning to base, a rare realization colliding at t = 40 (V = V_A reading)".into(),
            scenario: robots(NoiseReading::Unscaled),
        },
        Preset {
            name: "scf-robots-literal".into(),
            description: "The same robots with eq. (3) read literally: process noise covariance Δ²·V_A".into(),
            scenario: robots(NoiseReading::Literal),
        },
        Preset {
            name: "lscr-predict".into(),
            description: "LSCR paper, Fig. 1: 90 % confidence set for x₃₁ of the cascade of V-A (t = 30, M = 80, q = 2) with the BLUE ellipse".into(),
            scenario: lscr_cascade(LscrTarget::Predict),
        },
        Preset {
            name: "lscr-smooth".into(),
            description: "LSCR paper, Fig. 2: 90 % confidence set for x₁₅ from y₁..y₃₀ (smoothing, forward + backward representation)".into(),
            scenario: lscr_cascade(LscrTarget::Smooth),
        },
        Preset {
            name: "lscr-ma1".into(),
            description: "LSCR paper, Fig. 3: MA(1) y_t = v_t + v_{t−1}, prediction of x₂₁ — an unbounded LSCR band vs the Kalman ellipse".into(),
            scenario: lscr_ma1(),
        },
        Preset {
            name: "glls-saturate".into(),
            description: "GLLS paper, Fig. 1a/2a kind: a stable mode and a rotation — σ₃(Γ) saturates, so σ_n/√s has a best horizon".into(),
            scenario: glls_preset(GllsKind::Saturate),
        },
        Preset {
            name: "glls-grow".into(),
            description: "GLLS paper, Fig. 1b/2b/3b kind: two unstable modes — every σ grows without bound, ‖x(39)‖ ≈ 10⁷ costs digits".into(),
            scenario: glls_preset(GllsKind::Grow),
        },
        Preset {
            name: "glls-mixed".into(),
            description: "GLLS paper, Fig. 1c kind: stable, neutral and unstable modes (eigenvalues 0.7, 1, 1.05)".into(),
            scenario: glls_preset(GllsKind::Mixed),
        },
        Preset {
            name: "glls-unstable5".into(),
            description: "GLLS paper, Section 5.2: the 5-state unstable system (eigenvalues 3.057, −0.374 ± 1.130i, −0.600, 1.095) with noisy transitions: state-noise estimator vs LLS".into(),
            scenario: glls_preset(GllsKind::Unstable5),
        },
        Preset {
            name: "uniform-paper".into(),
            description: "Pavelková, Section 5: LU model (14)–(15), 120 samples, window ∂ = 5, swapping-based joint estimation of states, Θ and half-widths".into(),
            scenario: uniform_paper(),
        },
        Preset {
            name: "ubb-track".into(),
            description: "Tempo, Section IV: a stable 2-state system tracked with unknown-but-bounded noise (|u| ≤ 0.1, |η| ≤ 0.2), exponentially smoothed bounds α = β = 50, window j + 1 = 30 from Theorem 5 (γ = 0.1)".into(),
            scenario: ubb_preset(UbbKind::Track),
        },
        Preset {
            name: "ubb-series".into(),
            description: "Tempo, Example 1: time-series prediction with basis functions 1 and k — the set of coefficients consistent with |u(k)| ≤ 0.5 and the prediction interval of f(m+1)".into(),
            scenario: ubb_preset(UbbKind::Series),
        },
        Preset {
            name: "ubb-leontief".into(),
            description: "Tempo, Example 3: dynamic Leontief model of 3 industries (nonnegative A, column sums 0.6), known demand, uncertain demand |u| ≤ 0.1, production measured within ±0.3".into(),
            scenario: ubb_preset(UbbKind::Leontief),
        },
        Preset {
            name: "ubb-markov".into(),
            description: "Tempo, Example 4: absorbing Markov chain with an uncertain initial distribution 0 ≤ x_i(0) ≤ δ_i — the set of distributions after k + 1 steps".into(),
            scenario: ubb_preset(UbbKind::Markov),
        },
    ]
}

/// The set-membership presets (Tempo's paper prints no numbers: these are chosen to show each
/// example).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UbbKind {
    Track,
    Series,
    Leontief,
    Markov,
}

/// A set-membership preset.
pub fn ubb_preset(kind: UbbKind) -> Scenario {
    let v = match kind {
        UbbKind::Track => serde_json::json!({
            "method": "ubb",
            "title": "Set-membership state estimation with smoothed bounds (Tempo, Section IV)",
            "model": {"F": [[0.7, 0.2], [-0.2, 0.7]], "G": [[0.5], [1.0]], "H": [[1.0, 0.0]]},
            "simulate": {"steps": 60, "seed": 1},
            "ubb": {"eps": 0.2, "tau": 0.1, "delta": [2.0], "alpha": 50.0, "beta": 50.0, "gamma": 0.1, "time": 40},
            "notes": "x(k+1) = A x(k) + B u(k), y(k) = C x(k) + η(k) with |u(k)| ≤ τ = 0.1, |η(k)| ≤ ε = 0.2 and |x_i(0)| ≤ δ = 2. \
                      ‖A‖∞ = 0.9 and α = 50 give ‖A‖e^{1/α} = 0.918 < 1, so Theorem 4 bounds the state and Theorem 5 with γ = 0.1 gives j = 29: \
                      each step solves LPs in x(k−29 … k+1) and u(k−29 … k) with the dynamics as equalities, a constant 92 unknowns. The window's initial state is bounded by the Theorem 4 series, \
                      so the set is guaranteed exactly (not only up to γ)."
        }),
        UbbKind::Series => serde_json::json!({
            "method": "ubb",
            "title": "Time-series prediction with basis functions (Tempo, Example 1)",
            "model": {"F": [[1.0, 0.0], [0.0, 1.0]]},
            "simulate": {"steps": 30, "seed": 2, "x0": [1.0, 0.15]},
            "ubb": {"eps": 0.5, "basis": ["1", "k"], "time": 9},
            "notes": "f(k) = a₁ + a₂k + u(k), |u(k)| ≤ 0.5, k = 1 … m: the problem element is (a, u), the information f(1 … m) is exact and partial. \
                      The polygon is the set of coefficients a consistent with the data (the strips |f(k) − a₁ − a₂k| ≤ 0.5 intersected); \
                      the optimal error predictor of f(m+1) is the midpoint of its prediction interval. True a = (1, 0.15)."
        }),
        UbbKind::Leontief => serde_json::json!({
            "method": "ubb",
            "title": "Dynamic Leontief model, 3 industries (Tempo, Example 3)",
            "model": {"F": [[0.2, 0.3, 0.1], [0.1, 0.1, 0.3], [0.3, 0.2, 0.2]],
                      "G": [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                      "H": [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                      "B": [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]},
            "simulate": {"steps": 40, "seed": 3, "u": [[1.0, 0.8, 1.2]]},
            "ubb": {"eps": 0.3, "tau": 0.1, "delta": [1.0], "x0_center": [2.42, 2.14, 2.94], "alpha": 50.0, "beta": 50.0, "gamma": 0.05, "time": 25},
            "notes": "x(k+1) = A x(k) + v(k) + u(k): production x, known demand v = (1, 0.8, 1.2), uncertain demand |u_i| ≤ 0.1, production measured as y = x + η, |η_i| ≤ 0.3. \
                      A is nonnegative with column sums 0.6 < 1 (a feasible Leontief model, σ(A) = 0.6); x(0) within ±1 of the steady state (I − A)⁻¹v. \
                      The polygon shows industries 1 and 2 (a projection of the 3-D set)."
        }),
        UbbKind::Markov => serde_json::json!({
            "method": "ubb",
            "title": "Absorbing Markov chain with uncertain initial distribution (Tempo, Example 4)",
            "model": {"F": [[1.0, 0.2, 0.1], [0.0, 0.5, 0.3], [0.0, 0.3, 0.6]]},
            "simulate": {"steps": 15, "seed": 4, "x0": [0.1, 0.5, 0.4]},
            "ubb": {"eps": 1.0, "delta": [0.15, 0.4, 0.4], "x0_center": [0.15, 0.4, 0.4], "x0_sum": 1.0, "plane": [1, 2], "time": 2},
            "notes": "Transition probabilities (row-stochastic, the paper's form [[I, O], [D, G]]) P = [[1, 0, 0], [0.2, 0.5, 0.3], [0.1, 0.3, 0.6]]; \
                      the distribution evolves as x(k+1) = Pᵀx(k), so model.F = Pᵀ (the paper's x(k+1) = Ax(k) with rows summing to 1 mixes the two conventions). \
                      0 ≤ x_i(0) ≤ δ = (0.3, 0.8, 0.8) and Σx_i(0) = 1; no measurements. The transient probabilities x₂, x₃ shrink to 0 as G^k → 0; \
                      Theorem 4 does not apply (ρ(A) = 1, so ‖A‖ ≥ 1 in every norm) but A^k stays bounded."
        }),
    };
    serde_json::from_value(v).expect("ubb presets are valid scenarios")
}

/// The GLLS presets (the paper prints no matrices: these are built to show each behaviour).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GllsKind {
    Saturate,
    Grow,
    Mixed,
    Unstable5,
}

fn rows(r: &[&[f64]]) -> Option<MatrixSpec> {
    Some(MatrixSpec::Constant(r.iter().map(|x| x.to_vec()).collect()))
}

pub fn glls_preset(kind: GllsKind) -> Scenario {
    use crate::scenario::glls::{
        GllsEstimator, GllsMonteCarloSpec, GllsNoise, GllsSpec, GllsStudyKind,
    };
    let (t, s) = (0.5f64.cos(), 0.5f64.sin());
    let (title, model, steps, spec, notes) = match kind {
        GllsKind::Saturate => (
            "GLLS: a saturating singular value (Figs. 1a, 2a, 3a kind)",
            ModelSpec { f: rows(&[&[0.6, 0.0, 0.0], &[0.0, t, -s], &[0.0, s, t]]), h: rows(&[&[1.0, 1.0, 0.0]]), w: rows(&[&[0.01]]), x1_mean: Some(vec![1.0, 1.0, 0.0]), ..Default::default() },
            40,
            GllsSpec { horizon: None, max_horizon: 60, estimator: GllsEstimator::Lls, p: Some(2), mu: Some(0.1), noise: GllsNoise::Bounded, plane: Some([1, 2]), monte_carlo: Some(GllsMonteCarloSpec { runs: 2000, seed: 1, study: GllsStudyKind::Precision, steps: None, max_horizon: Some(30) }) },
            "A = diag(0.6, rotation by 0.5 rad), C = [1 1 0]: the stable mode's contribution to Γ_{s+1}ᵀΓ_{s+1} converges, so σ₃ saturates while σ₁, σ₂ grow like √s; σ₃/√s peaks at the best horizon. \
             Noise bounded by μ = 0.1 (uniform in the ball): the guaranteed ball and box of x(k) must hold the truth. \
             The paper prints no matrices for its three systems; these are built to show each behaviour.",
        ),
        GllsKind::Grow => (
            "GLLS: every singular value grows (Figs. 1b, 2b, 3b kind)",
            ModelSpec { f: rows(&[&[1.5, 0.2], &[0.0, 1.3]]), h: rows(&[&[1.0, 0.0]]), w: rows(&[&[0.01]]), x1_mean: Some(vec![1.0, 1.0]), ..Default::default() },
            40,
            GllsSpec { horizon: Some(8), max_horizon: 60, estimator: GllsEstimator::Lls, p: None, mu: Some(0.3), noise: GllsNoise::Gaussian, plane: Some([0, 1]), monte_carlo: Some(GllsMonteCarloSpec { runs: 2000, seed: 1, study: GllsStudyKind::Precision, steps: None, max_horizon: Some(30) }) },
            "A = [[1.5, 0.2], [0, 1.3]], C = [1 0]: both modes unstable, every σ_i(Γ_{s+1}) and σ_n/√s grow without bound (Fig. 2b). \
             ‖x(39)‖ ≈ 10⁷, as in the paper's Fig. 3b (1.47·10⁷): the estimates of longer horizons lose to rounding what the condition number promises — the page marks where the estimated rounding error exceeds the bound.",
        ),
        GllsKind::Mixed => (
            "GLLS: stable, neutral and unstable modes (Figs. 1c, 2c, 3c kind)",
            ModelSpec {
                f: rows(&[&[0.697, 0.1515, 0.01], &[-0.006, 1.003, 0.02], &[-0.105, 0.0525, 1.05]]),
                h: rows(&[&[1.0, 0.0, 0.0]]),
                w: rows(&[&[0.01]]),
                x1_mean: Some(vec![1.0, -1.0, 0.5]),
                ..Default::default()
            },
            40,
            GllsSpec { horizon: None, max_horizon: 60, estimator: GllsEstimator::Glls, p: Some(2), mu: Some(0.1), noise: GllsNoise::Gaussian, plane: Some([0, 1]), monte_carlo: Some(GllsMonteCarloSpec { runs: 2000, seed: 1, study: GllsStudyKind::Precision, steps: None, max_horizon: Some(30) }) },
            "A = T diag(0.7, 1, 1.05) T⁻¹ with T = [[1, 0.5, 0.2], [0, 1, 0.4], [0.3, 0, 1]] (rounded to 4 digits), C = [1 0 0]: one σ saturates, one grows like √s, one exponentially. \
             The bound κ·√E‖δ(k,s)‖² becomes conservative for long horizons, as in the paper's Fig. 3c.",
        ),
        GllsKind::Unstable5 => (
            "GLLS: state-noise estimator vs LLS on an unstable 5-state system (Section 5.2, Fig. 4)",
            ModelSpec {
                f: rows(&[
                    &[0.5477, 1.9865, 0.7628, 0.993, 1.007],
                    &[-0.4814, 0.4988, -1.2108, 0.036, -0.4028],
                    &[-1.226, -0.5629, -0.8029, 0.6084, -1.6617],
                    &[0.4885, -0.3119, 0.6064, 3.0772, -0.4143],
                    &[0.4, -0.667, 0.5436, 1.3299, -0.5168],
                ]),
                h: rows(&[&[1.0, 0.0, 0.0, 0.0, 0.0]]),
                w: rows(&[&[0.0]]),
                v: rows(&[&[0.01, 0.0, 0.0, 0.0, 0.0], &[0.0, 0.01, 0.0, 0.0, 0.0], &[0.0, 0.0, 0.01, 0.0, 0.0], &[0.0, 0.0, 0.0, 0.01, 0.0], &[0.0, 0.0, 0.0, 0.0, 0.01]]),
                x1_mean: Some(vec![1.0, 1.0, 1.0, 1.0, 1.0]),
                ..Default::default()
            },
            16,
            GllsSpec { horizon: Some(8), max_horizon: 30, estimator: GllsEstimator::StateNoise, p: None, mu: Some(0.0), noise: GllsNoise::Gaussian, plane: Some([0, 3]), monte_carlo: Some(GllsMonteCarloSpec { runs: 2000, seed: 1, study: GllsStudyKind::StateNoise, steps: None, max_horizon: Some(15) }) },
            "x(k+1) = A x(k) + ξ(k), y = C x exactly (54)–(55), ξ ~ N(0, 0.01·I), 16 steps. A is built (real Schur form, fitted off-diagonal entries, a fixed rotation) to have the paper's eigenvalues 3.057, −0.374 ± 1.130i, −0.600, 1.095 and its singular values 3.735, 3.166, 1.828, 0.636, 0.206 (to 3 digits); the paper prints neither A nor C (C = [1 0 0 0 0] here). \
             The state-noise estimator (63)–(64) is solved in closed form and checked against clarabel's QP.",
        ),
    };
    Scenario {
        method: Method::Glls,
        title: Some(title.into()),
        model,
        data: None,
        simulate: Some(SimulateSpec {
            steps,
            seed: 3,
            u: vec![],
            condition: None,
            x0: None,
        }),
        alpha: 0.9,
        components: None,
        tau: 0,
        asymptotic: false,
        time: None,
        plot: None,
        collision: None,
        coverage_curve: None,
        experiment: None,
        lscr: None,
        glls: Some(spec),
        uniform: None,
        ubb: None,
        notes: Some(notes.into()),
    }
}

/// Which cascade figure of the LSCR paper.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LscrTarget {
    /// Fig. 1: x_31 from y_1..y_30.
    Predict,
    /// Fig. 2: x_15 from y_1..y_30.
    Smooth,
}

fn lscr_scenario(
    title: &str,
    model: ModelSpec,
    simulate: SimulateSpec,
    lscr: LscrSpec,
    notes: &str,
) -> Scenario {
    Scenario {
        method: Method::Lscr,
        title: Some(title.into()),
        model,
        data: None,
        simulate: Some(simulate),
        alpha: 0.9,
        components: None,
        tau: 0,
        asymptotic: false,
        time: None,
        plot: Some(vec![0, 1]),
        collision: None,
        coverage_curve: None,
        experiment: None,
        lscr: Some(lscr),
        glls: None,
        uniform: None,
        ubb: None,
        notes: Some(notes.into()),
    }
}

fn lscr_spec(estimate: Estimate, index: Option<usize>) -> LscrSpec {
    LscrSpec {
        estimate,
        index,
        m: Some(80),
        q: Some(2),
        level: None,
        construction: Construction::Random,
        seed: 1,
        strings: None,
        window: None,
        resolution: None,
        probes: vec![],
        slice_at: None,
        coverage: None,
    }
}

/// Section V-A of the LSCR paper: x_{t+1} = [[0.5, 0], [1, 0.7]] x_t + [1, 0]ᵀ v_t, y_t = [0 1] x_t + w_t.
pub fn lscr_cascade(target: LscrTarget) -> Scenario {
    let model = ModelSpec {
        f: Some(MatrixSpec::Constant(vec![vec![0.5, 0.0], vec![1.0, 0.7]])),
        h: Some(MatrixSpec::Constant(vec![vec![0.0, 1.0]])),
        g: Some(vec![vec![1.0], vec![0.0]]),
        sigma_v2: Some(0.005),
        sigma_w2: Some(0.005),
        ..Default::default()
    };
    let (title, spec) = match target {
        LscrTarget::Predict => (
            "Confidence set for x₃₁ (LSCR paper, Fig. 1)",
            lscr_spec(Estimate::Predict, None),
        ),
        LscrTarget::Smooth => (
            "Confidence set for x₁₅ (LSCR paper, Fig. 2)",
            lscr_spec(Estimate::Smooth, Some(15)),
        ),
    };
    lscr_scenario(
        title,
        model,
        SimulateSpec { steps: 30, seed: 5, u: vec![], condition: None, x0: None },
        spec,
        "Cascade of two first-order systems, σ_v² = σ_w² = 0.005 (used only to simulate and for the BLUE).          F^b = [[0.2450, 0.3315], [−0.3500, 0.9550]], Q′ = [[0.49, −0.70], [−0.70, 1.00]] (Q′ = Π′ − F^bΠ′F^bᵀ; the printed (7) is a typo).          M = 80 strings, q = 2: each X̂_l holds the true state with probability 1 − 2q/M = 0.95, X̂ with ≥ 1 − 2qn/M = 0.90 — the paper's 90 %.          (The text says q = 4 but computes 1 − 2·2·2/80; Theorem 3.2 needs q = 2 for 90 %.)          For smoothing the Karhunen–Loève eigenvalues come in exact pairs; the basis is fixed block by block          (data after, at and before the estimated time), before seeing the data.",
    )
}

/// Section V-B of the LSCR paper: the MA(1) process y_t = v_t + v_{t−1}, σ_v² = 0.1, σ_w² = 0.
pub fn lscr_ma1() -> Scenario {
    let model = ModelSpec {
        f: Some(MatrixSpec::Constant(vec![vec![0.0, 0.0], vec![1.0, 0.0]])),
        h: Some(MatrixSpec::Constant(vec![vec![0.0, 1.0]])),
        g: Some(vec![vec![1.0], vec![1.0]]),
        sigma_v2: Some(0.1),
        sigma_w2: Some(0.0),
        ..Default::default()
    };
    lscr_scenario(
        "MA(1): LSCR vs Kalman prediction of x₂₁ (LSCR paper, Fig. 3)",
        model,
        SimulateSpec { steps: 20, seed: 3, u: vec![], condition: Some(Condition { t: 21, x: vec![1.0, 1.2] }), x0: None },
        lscr_spec(Estimate::Predict, None),
        "x_t = [[0, 0], [1, 0]] x_{t−1} + [1, 1]ᵀ v_t, y_t = [0 1] x_t, no measurement noise. F^b = [[−1, 1], [−1, 1]] is singular,          so X̂ is invariant along [1, 1]ᵀ: an unbounded band. The first state is white noise (σ_v² = 0.1); the true x₂₁ is placed at          x₁ = 1.0 (3.2 σ): the Kalman ellipse, always centred at x₁ = 0, misses it, while the LSCR band holds it with probability ≥ 0.9          whatever its value. (The paper's caption says x₂₀; the text and the data say x₂₁.)",
    )
}

/// Look a preset up by name.
pub fn get(name: &str) -> Result<Scenario> {
    all()
        .into_iter()
        .find(|p| p.name == name)
        .map(|p| p.scenario)
        .ok_or_else(|| {
            let names: Vec<String> = all().into_iter().map(|p| p.name).collect();
            Error::field(
                "preset",
                format!("\"{name}\" is unknown; presets: {}", names.join(", ")),
            )
        })
}

/// Example 1 of the SCF paper.
pub fn scalar() -> Scenario {
    let one = DMatrix::from_element(1, 1, 1.0);
    Scenario {
        method: Method::Scf,
        title: Some("Scalar example (SCF paper, Example 1)".into()),
        model: ModelSpec {
            f: Some(MatrixSpec::of(&DMatrix::from_element(1, 1, (5.0f64 / 6.0).sqrt()))),
            h: Some(MatrixSpec::of(&one)),
            v: Some(MatrixSpec::of(&one)),
            w: Some(MatrixSpec::of(&one)),
            ..Default::default()
        },
        data: None,
        simulate: Some(SimulateSpec { steps: 50, seed: 1, u: vec![], condition: None, x0: None }),
        alpha: 0.99,
        components: None,
        tau: 0,
        asymptotic: false,
        time: None,
        plot: None,
        collision: None,
        coverage_curve: Some(CurveSpec { component: 0, from: -50.0, to: 50.0, points: 201 }),
        experiment: None,
        lscr: None,
        glls: None,
        uniform: None,
        ubb: None,
        notes: Some(
            "Γ = 6, p̄ = 3/5, ratio U_tA_t → 0.9: the SCF interval is the KF center / 0.9 with half-width ρ·√(1/0.9). \
             The paper's ρ-integral should read exp(−x²/(2p̄)); with it ρ ≈ 2.00 as printed."
                .into(),
        ),
    }
}

/// Which reading of the robot noise scaling of eq. (3) to use (crate docs: errata).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoiseReading {
    /// v_{A,t} enters with covariance V_A (the preset: regions ≈ 2× KF, the paper's "moderate
    /// enlargement").
    Unscaled,
    /// v_{A,t}·Δ as printed: covariance Δ²V_A (SCF prediction region ≈ 84× the KF one).
    Literal,
}

/// Robot constants of Section II.
pub const DELTA: f64 = 1.0 / 20.0;
pub const KP: f64 = 5.0;
pub const KU: f64 = 5.0;
pub const D_MIN: f64 = 0.2;
/// The collision time of the Monte Carlo experiment.
pub const COLLISION_T: usize = 40;

/// One robot's transition matrix, eq. (3) with the erratum fixed: row 4 is (0, −K_pΔ, 0,
/// 1 − K_uΔ) like row 3, since the two axes are identical and decoupled.
pub fn robot_f() -> DMatrix<f64> {
    DMatrix::from_row_slice(
        4,
        4,
        &[
            1.0,
            0.0,
            DELTA,
            0.0,
            0.0,
            1.0,
            0.0,
            DELTA,
            -KP * DELTA,
            0.0,
            1.0 - KU * DELTA,
            0.0,
            0.0,
            -KP * DELTA,
            0.0,
            1.0 - KU * DELTA,
        ],
    )
}

fn block_diag(a: &DMatrix<f64>, b: &DMatrix<f64>) -> DMatrix<f64> {
    let mut m = DMatrix::zeros(a.nrows() + b.nrows(), a.ncols() + b.ncols());
    m.view_mut((0, 0), a.shape()).copy_from(a);
    m.view_mut(a.shape(), b.shape()).copy_from(b);
    m
}

/// Joint model of robots A and B: state (p_xA, p_yA, u_xA, u_yA, p_xB, p_yB, u_xB, u_yB).
/// Returns the model spec and the constant input u = K_p·p̄·Δ on the velocity rows (B = I).
pub fn robot_model(reading: NoiseReading) -> (ModelSpec, Vec<f64>) {
    let f = block_diag(&robot_f(), &robot_f());
    let s = match reading {
        NoiseReading::Unscaled => 1.0,
        NoiseReading::Literal => DELTA * DELTA,
    };
    let va = DMatrix::from_diagonal(&DVector::from_vec(vec![
        0.01f64.powi(2),
        0.01f64.powi(2),
        0.04f64.powi(2),
        0.04f64.powi(2),
    ]));
    let vb = DMatrix::from_diagonal(&DVector::from_vec(vec![
        0.01f64.powi(2),
        0.01f64.powi(2),
        0.1f64.powi(2),
        0.04f64.powi(2),
    ]));
    let v = block_diag(&va, &vb) * s;
    let h1 = DMatrix::from_row_slice(2, 4, &[1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
    let h = block_diag(&h1, &h1);
    let w = DMatrix::identity(4, 4) * 0.05f64.powi(2);
    let base_a = [-1.0, 0.0];
    let base_b = [1.0, 0.0];
    let u = vec![
        0.0,
        0.0,
        KP * base_a[0] * DELTA,
        KP * base_a[1] * DELTA,
        0.0,
        0.0,
        KP * base_b[0] * DELTA,
        KP * base_b[1] * DELTA,
    ];
    let spec = ModelSpec {
        f: Some(MatrixSpec::of(&f)),
        h: Some(MatrixSpec::of(&h)),
        v: Some(MatrixSpec::of(&v)),
        w: Some(MatrixSpec::of(&w)),
        b: Some(MatrixSpec::of(&DMatrix::identity(8, 8))),
        x1_mean: Some(vec![-1.0, 20.0, 0.0, 0.0, 1.0, 20.0, 0.0, 0.0]),
        x1_cov: Some(to_rows(&DMatrix::zeros(8, 8))),
        ..Default::default()
    };
    (spec, u)
}

/// The most probable state at time `t` among those where the two bodies' positions (components
/// `a`, `b`) are exactly `distance` apart: minimise the prior Mahalanobis distance of the
/// relative position δ = p_a − p_b on the circle ‖δ‖ = distance, then take the conditional
/// mean of the whole state given δ. This is how the robot presets pick their colliding state.
pub fn most_probable_collision_state(
    model: &LinearModel,
    u: &Inputs,
    t: usize,
    a: &[usize],
    b: &[usize],
    distance: f64,
) -> Result<DVector<f64>> {
    let n = model.n();
    let mo = model.moments(t, u);
    let (m, g) = (&mo.mean[t - 1], &mo.cov[t - 1]);
    let mut c = DMatrix::zeros(2, n);
    for k in 0..2 {
        c[(k, a[k])] += 1.0;
        c[(k, b[k])] -= 1.0;
    }
    let mu = &c * m;
    let sigma = &c * g * c.transpose();
    let s_inv = linalg::inverse("covariance of the relative position", &sigma)?;
    let cost = |th: f64| {
        let d = DVector::from_vec(vec![distance * th.cos(), distance * th.sin()]) - &mu;
        d.dot(&(&s_inv * &d))
    };
    let grid = 3600;
    let best = (0..grid)
        .map(|i| std::f64::consts::TAU * i as f64 / grid as f64)
        .fold((f64::INFINITY, 0.0), |acc, th| {
            let v = cost(th);
            if v < acc.0 {
                (v, th)
            } else {
                acc
            }
        });
    let delta = DVector::from_vec(vec![distance * best.1.cos(), distance * best.1.sin()]);
    Ok(m + g * c.transpose() * s_inv * (delta - mu))
}

/// Section II of the SCF paper: two robots, a realization drawn backwards from a collision.
pub fn robots(reading: NoiseReading) -> Scenario {
    let (spec, u) = robot_model(reading);
    let model = LinearModel::from_spec(&spec).expect("robot model is valid");
    let inputs = Inputs(vec![DVector::from_vec(u.clone())]);
    let xc =
        most_probable_collision_state(&model, &inputs, COLLISION_T, &[0, 1], &[4, 5], D_MIN / 2.0)
            .expect("robot prior is non-singular at t = 40");
    let literal = reading == NoiseReading::Literal;
    Scenario {
        method: Method::Scf,
        title: Some(format!("Two robots returning to base (SCF paper, Section II{})", if literal { ", Δ²V_A" } else { "" })),
        model: spec,
        data: None,
        simulate: Some(SimulateSpec {
            steps: 60,
            seed: 7,
            u: vec![u],
            condition: Some(Condition { t: COLLISION_T, x: xc.iter().copied().collect() }),
            x0: None,
        }),
        alpha: 0.95,
        components: Some(vec![0, 1]),
        tau: 4,
        asymptotic: false,
        time: Some(36),
        plot: Some(vec![0, 1]),
        collision: Some(CollisionSpec { a: vec![0, 1], b: vec![4, 5], d_min: D_MIN }),
        coverage_curve: None,
        experiment: Some(ExperimentSpec { runs: 10_000, seed: 2021, components: vec![0, 1, 2, 3], warning_t: Some(36) }),
        lscr: None,
        glls: None,
        uniform: None,
        ubb: None,
        notes: Some(format!(
            "Robots start at rest at (∓1, 20) and return to bases (∓1, 0); Δ = 1/20, K_p = K_u = 5, W = 0.05²I, \
             d_min = 0.2. Row 4 of eq. (3) is read as 1 − K_uΔ (erratum). Process-noise covariance: {}. \
             The realization is drawn backwards from the most probable state at t = 40 with the robots' centers \
             0.1 apart (half of d_min), velocities at their conditional mean (eq. (45), footnote 2). \
             Regions: robot A's position at t + τ given y_1..y_t (V-C).",
            if literal { "Δ²·V_A as printed (SCF regions far larger than KF)" } else { "V_A (the reading that matches the paper's \"moderate enlargement\")" }
        )),
    }
}

/// Pavelková's example (14)–(15): A = [[1, 0.5], [−0.5, 0]], B = [1, 3]ᵀ, C = [1 1], D = 0,
/// x_r = 0.3·1, y_r = 0.3, inputs uniform with half-width 0.5, 120 samples, ∂ = 5, Θ's prior ±30 %
/// (A₂₂ ∈ [−0.3, 0.3]), x̄_r = ȳ_r = 1, ±5 on the window's states.
/// Θ, x_r and y_r of Pavelková's example (14)–(15), for code that works on the core directly
/// (tests, benchmarks); [`uniform_paper`] is the same model as a scenario.
pub fn uniform_paper_model() -> (crate::uniform::Theta, DVector<f64>, DVector<f64>) {
    let theta = crate::uniform::Theta {
        a: DMatrix::from_row_slice(2, 2, &[1.0, 0.5, -0.5, 0.0]),
        b: DMatrix::from_row_slice(2, 1, &[1.0, 3.0]),
        c: DMatrix::from_row_slice(1, 2, &[1.0, 1.0]),
        d: DMatrix::zeros(1, 1),
    };
    (
        theta,
        DVector::from_element(2, 0.3),
        DVector::from_element(1, 0.3),
    )
}

pub fn uniform_paper() -> Scenario {
    use crate::scenario::uniform::{PriorOverride, UniformSpec};
    let (theta, xr, yr) = uniform_paper_model();
    Scenario {
        method: Method::UniformLp,
        title: Some("Uniform innovations: swapping-based joint estimation (Pavelková, Figs. 1–3)".into()),
        model: ModelSpec { f: Some(MatrixSpec::of(&theta.a)), h: Some(MatrixSpec::of(&theta.c)), b: Some(MatrixSpec::of(&theta.b)), ..Default::default() },
        data: None,
        simulate: Some(SimulateSpec { steps: 120, seed: 1, u: vec![], condition: None, x0: None }),
        alpha: 0.9,
        components: None,
        tau: 0,
        asymptotic: false,
        time: None,
        plot: None,
        collision: None,
        coverage_curve: None,
        experiment: None,
        lscr: None,
        glls: None,
        uniform: Some(UniformSpec {
            d: Some(to_rows(&theta.d)),
            xr: Some(xr.iter().copied().collect()),
            yr: Some(yr.iter().copied().collect()),
            u_half: 0.5,
            estimator: crate::uniform::Joint::Swapping,
            window: 5,
            prior_rel: 0.3,
            prior_overrides: vec![PriorOverride { matrix: "A".into(), row: 1, col: 1, lo: -0.3, hi: 0.3 }],
            xr_max: Some(vec![1.0, 1.0]),
            yr_max: Some(vec![1.0]),
            x_bound: 5.0,
            time: None,
            plane: Some([0, 1]),
            directions: 64,
        }),
        ubb: None,
        notes: Some(
            "The paper's example is not observable: C·A = 0.5·C, so rank [C; CA] = 1 and only x₁ + x₂ is fixed by the data; \
             along x₁ − x₂ the LP optimum is a whole face bounded by the prior box (±5). The report gives each state's range over the optimal face; \
             the estimate drawn is the LP solver's optimal point (an interior-point method returns a point near the face's centre). \
             The polygon is the set of x_t consistent with the window at the half-width bounds x̄_r = ȳ_r = 1 and the Θ in use."
                .into(),
        ),
    }
}
