//! `cargo bench` — speed figures for the targets (native). The wasm figures are taken
//! in Chromium by the end-to-end test (tests/e2e), which prints them.
//!
//! Each figure is the median of several repetitions, in milliseconds.

use confset::experiment::ConditionalExperiment;
use confset::presets;
use std::time::Instant;

fn median_ms(reps: usize, mut f: impl FnMut()) -> f64 {
    let mut v: Vec<f64> = (0..reps)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

fn main() {
    let robots = presets::get("scf-robots").expect("preset");
    let prepared = robots.prepare().expect("valid");
    let setup = median_ms(11, || {
        ConditionalExperiment::new(&prepared).expect("experiment");
    });
    let mut last = None;
    let runs = median_ms(11, || {
        let mut e = ConditionalExperiment::new(&prepared).expect("experiment");
        while !e.finished() {
            e.step(10_000);
        }
        last = Some(e.result().clone());
    });
    let r = last.expect("ran");
    println!(
        "robot Monte Carlo, {} runs x {} steps, KF+SCF: {:.1} ms total ({:.1} ms setup)",
        r.runs_total, r.condition_t, runs, setup
    );
    println!(
        "  counts: A's state inside X^KF {}/{} and X^SCF {}/{} (paper 0 and 9498); warnings at t=36: KF {} SCF {} (paper 2 and 10000)",
        r.kf_inside, r.runs_total, r.scf_inside, r.runs_total, r.kf_warnings, r.scf_warnings
    );
    for p in presets::all() {
        let s = p.scenario.clone();
        let ms = median_ms(21, || {
            s.run().expect("runs");
        });
        let svg = median_ms(11, || {
            confset::plot::scenario_svg(&s, 960, 640).ok();
        });
        println!(
            "{:<20} report {:.2} ms, report + SVG figure {:.2} ms",
            p.name, ms, svg
        );
    }
}
