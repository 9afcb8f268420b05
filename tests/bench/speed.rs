//! `cargo bench` — speed figures for the targets (native). The wasm figures are taken
//! in Chromium by the end-to-end test (tests/e2e), which prints them.
//!
//! Each figure is the median of several repetitions, in milliseconds.
//!
//! `cargo bench --bench speed -- kernels` prints only the comparison's kernels
//! ([`confset::bench::Kernel`]), one `BENCH <key> <median ms> <what ran>` line each, for
//! `.ci/bench`'s table beside wasm and NumPy.

use confset::lscr::{self, Estimator};
use confset::presets;
use confset::scenario::lscr::LscrStudy;
use confset::study::{Chunked, Study as _};
use std::time::Instant;

#[path = "../suite/common/timing.rs"]
mod timing;
use timing::median_ms;

/// The comparison's kernels (those named after `kernels`, or all): one warm-up, then the
/// median of 11 repetitions each.
fn kernels(only: &[String]) {
    for kernel in confset::bench::Kernel::ALL {
        if !only.is_empty() && !only.iter().any(|k| k == kernel.key()) {
            continue;
        }
        let mut run = kernel.prepare().expect("kernel");
        let mut what = run().expect("kernel runs");
        let ms = median_ms(11, || {
            what = run().expect("kernel runs");
        });
        println!("BENCH {} {ms:.3} {what}", kernel.key());
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let Some(i) = args.iter().position(|a| a == "kernels") {
        let only: Vec<String> = args[i + 1..]
            .iter()
            .filter(|a| !a.starts_with('-'))
            .cloned()
            .collect();
        kernels(&only);
        return;
    }
    if std::env::var("SPEED_GLLS_CURVES_REPS").is_ok() {
        glls_figures();
    }
    let robots = presets::get("scf-robots").expect("preset");
    let prepared = robots.prepare_scf().expect("valid");
    let setup = median_ms(11, || {
        prepared.conditional_experiment().expect("experiment");
    });
    let mut last = None;
    let runs = median_ms(11, || {
        let mut e = Chunked::new(prepared.conditional_experiment().expect("experiment"));
        while !e.finished() {
            e.step(10_000).expect("runs");
        }
        last = Some(e.report());
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
    lscr_figures();
    glls_figures();
    uniform_figures();
    ubb_figures();
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

/// The LSCR issue's targets: region raster 512², the data-independent build (s, A, U_A) for
/// t = 30 and t = 200, and 2,000 coverage runs (membership of the true state only).
fn lscr_figures() {
    let l = presets::get("lscr-predict")
        .expect("preset")
        .run()
        .expect("runs")
        .lscr
        .expect("lscr");
    let raster = median_ms(31, || {
        std::hint::black_box(l.region.raster(&l.window, 512, 512).expect("raster"));
    });
    let brute = median_ms(3, || {
        std::hint::black_box(l.region.raster_brute(&l.window, 512, 512).expect("raster"));
    });
    let boundary = median_ms(31, || {
        std::hint::black_box(l.region.boundary(&l.window).expect("boundary"));
    });
    println!(
        "LSCR lscr-predict (t = 30, M = 80, n = 2): raster 512x512 {raster:.2} ms (brute force {brute:.1} ms), boundary polygons {boundary:.2} ms"
    );
    let (model, o) = timing::lscr_predict_fixture();
    for t in [30, 200] {
        let build = median_ms(if t > 100 { 5 } else { 31 }, || {
            std::hint::black_box(Estimator::new(&model, t, &o).expect("estimator"));
        });
        println!("LSCR build (regression, Karhunen-Loeve, SVD of A, strings, BLUE, KF gains) t = {t}: {build:.2} ms");
    }
    let est = Estimator::new(&model, 30, &o).expect("estimator");
    let mut counts = None;
    let cov = median_ms(5, || {
        let mut e = Chunked::new(LscrStudy(
            lscr::Experiment::new(est.clone(), &[0.3, -0.4], 2000, 7).expect("experiment"),
        ));
        while !e.finished() {
            e.step(500).expect("runs");
        }
        counts = Some(e.counts().clone());
    });
    let c = counts.expect("ran");
    println!(
        "LSCR coverage experiment, 2000 runs at x = [0.3, -0.4]: {cov:.1} ms; X^_1 {} X^_2 {} X^ {} BLUE {:?} KF {:?} (levels 0.95, 0.95, 0.90)",
        c.inside_each[0], c.inside_each[1], c.inside, c.blue, c.kf
    );
}

/// The GLLS issue's targets: singular-value curves s = 0..500 for n = 10 (and the 5-state
/// unstable preset), and the Monte Carlo of Section 5.1: 100,000 runs × horizons 0..20, n = 5.
fn glls_figures() {
    use confset::glls::{Curves, GllsModel, Precision, Study, Weighting};
    use nalgebra::DMatrix;
    let ten = confset::bench::ten_state_model();
    if let Ok(reps) = std::env::var("SPEED_GLLS_CURVES_REPS") {
        // Profiling aid: only the n = 10 curves, repeated.
        for _ in 0..reps.parse().unwrap_or(1000) {
            std::hint::black_box(Curves::new(&ten, 500).expect("curves"));
        }
        std::process::exit(0);
    }
    let curves = median_ms(11, || {
        std::hint::black_box(Curves::new(&ten, 500).expect("curves"));
    });
    let five = GllsModel::from_spec(&presets::get("glls-unstable5").expect("preset").model)
        .expect("model");
    let curves5 = median_ms(11, || {
        std::hint::black_box(Curves::new(&five, 500).expect("curves"));
    });
    println!("GLLS curves s = 0..500 (σ(Γ), σ(Γ A^-s), κ LLS/GLLS): n = 10, m = 2: {curves:.2} ms; n = 5 (unstable preset): {curves5:.2} ms");
    let noisy = GllsModel {
        omega: DMatrix::identity(1, 1) * 0.01,
        xi: DMatrix::zeros(5, 5),
        ..five
    };
    let t = Instant::now();
    let mut mc = Chunked::new(
        Precision::new(
            &noisy,
            Study::Precision,
            Weighting::Lls,
            40,
            (0, 20),
            vec![],
            100_000,
            1,
        )
        .expect("study"),
    );
    while !mc.finished() {
        mc.step(10_000).expect("runs");
    }
    let ms = t.elapsed().as_secs_f64() * 1e3;
    let r = mc.report();
    println!(
        "GLLS Monte Carlo (Section 5.1), 100000 runs x horizons {}..{} (n = 5, 40 steps): {ms:.0} ms; median error at s = {}: {:.3e}, at s = {}: {:.3e}",
        r.horizons[0],
        r.horizons[r.horizons.len() - 1],
        r.horizons[0],
        r.first[0].as_ref().map_or(f64::NAN, |s| s.median),
        r.horizons[r.horizons.len() - 1],
        r.first[r.first.len() - 1].as_ref().map_or(f64::NAN, |s| s.median)
    );
}

/// Tempo: one state-estimation step of ubb-track (2-D, window 30: 92 variables, 184 rows, as it prints).
fn ubb_figures() {
    let prep = presets::get("ubb-track")
        .expect("preset")
        .prepare_ubb()
        .expect("valid");
    let run = prep.run_data();
    let k = 40;
    let mut calls = 0;
    let mut size = confset::ubb::LpSize::default();
    let exact = median_ms(21, || {
        let step = prep.problem.step(&run.y, k).expect("step");
        let (_, poly, _) = step.hull_and_polygon([0, 1], 64).expect("LPs");
        calls = poly.calls;
        size = step.set.program().expect("LP").1;
    });
    let fan = median_ms(21, || {
        let step = prep.problem.step(&run.y, k).expect("step");
        let mut solver = step.set.support_solver().expect("LP");
        std::hint::black_box(
            solver
                .support_fan(&step.plane_map([0, 1]), 64)
                .expect("LPs"),
        );
    });
    let report = median_ms(5, || {
        std::hint::black_box(prep.report().expect("report"));
    });
    println!("ubb: one step, window 30 ({} variables, {} rows): hull + exact polygon ({calls} LPs) {exact:.2} ms; support in 64 directions {fan:.2} ms; ubb-track report (60 steps: 4 hull LPs each + polygon + prediction) {report:.0} ms", size.variables, size.rows);
}

/// The uniform-innovation issue's targets: one window LP (∂ = 5, 2 states) and the full
/// 120-sample on-line run of the paper's example with the swapping method.
fn uniform_figures() {
    let window = median_ms(101, timing::uniform_window_lp());
    let s = presets::get("uniform-paper").expect("preset");
    let online = median_ms(5, || {
        std::hint::black_box(s.run().expect("runs"));
    });
    println!("uniform: one window LP (∂ = 5, 2 states, 15 variables, 30 rows): {window:.3} ms; uniform-paper report (120 samples, swapping, + face LPs, exact polygon, KF): {online:.1} ms");
}
