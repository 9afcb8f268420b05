//! What the speed figures share: the native median of repeated runs, and the uniform-innovation
//! issue's window LP fixture and the LSCR figures' model and options. Used by `tests/suite` (natively and, for the fixture, in wasm)
//! and by the benchmark `tests/bench/speed.rs`, which includes this file by `#[path]`.

use confset::lscr::{Construction, LscrModel, Options, Target};
use confset::uniform::{estimate_states, simulate, StatePrior, Window};
use nalgebra::DVector;

/// The median wall time of `reps` runs of `f`, in milliseconds (native only: the clock is read
/// here, never in the core).
#[cfg(not(target_arch = "wasm32"))]
pub fn median_ms(reps: usize, mut f: impl FnMut()) -> f64 {
    let mut v: Vec<f64> = (0..reps)
        .map(|_| {
            let t = std::time::Instant::now();
            f();
            t.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// One window LP of the uniform paper's example (∂ = 5, 2 states, window 116..=120 of a
/// 120-sample simulation), ready to be timed: the simulation and the prior are built once, here;
/// each call of the closure solves the LP again.
pub fn uniform_window_lp() -> impl FnMut() {
    let (theta, xr, yr) = confset::presets::uniform_paper_model();
    let tr = simulate(&theta, &xr, &yr, &DVector::zeros(2), 0.5, 120, 1);
    let prior = StatePrior {
        x_lo: -5.0,
        x_hi: 5.0,
        x0: None,
        xr_max: DVector::from_element(2, 1.0),
        yr_max: DVector::from_element(1, 1.0),
    };
    move || {
        std::hint::black_box(
            estimate_states(
                &theta,
                &tr.u,
                &tr.y,
                Window {
                    first: 116,
                    last: 120,
                },
                &prior,
            )
            .expect("LP"),
        );
    }
}

/// The LSCR speed figures' model (lscr-predict's) and options: predict, M = 80, q = 2, random
/// construction, seed 1.
pub fn lscr_predict_fixture() -> (LscrModel, Options) {
    let model = LscrModel::from_spec(&confset::presets::get("lscr-predict").expect("preset").model)
        .expect("model");
    let o = Options {
        target: Target::Predict,
        m: 80,
        q: 2,
        construction: Construction::Random,
        seed: 1,
        strings: None,
    };
    (model, o)
}
