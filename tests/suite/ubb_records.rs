//! ubb on users' records: gaps, one state, the filtered set, long records and the budget,
//! and the words of its messages.

use confset::scenario::Scenario;

/// Timings of reports without the work budget (a calibration probe: `UBB_PROBE=files`).
#[test]
#[ignore]
fn probe_timings() {
    let files = std::env::var("UBB_PROBE").unwrap_or_default();
    for path in files.split_whitespace() {
        let text = std::fs::read_to_string(path).unwrap();
        let s = Scenario::from_json(&text).unwrap();
        let est = s.work(confset::scenario::Job::Report).total_operations();
        let t = std::time::Instant::now();
        let r = s.prepare_ubb().and_then(|p| p.report());
        let dt = t.elapsed().as_secs_f64();
        println!(
            "{path}: {dt:.3} s, estimate {est:.2e} ops ({:.2}), {}",
            est / 1e9 / dt.max(1e-9),
            r.map(|_| "ok".to_string()).unwrap_or_else(|e| e.to_string())
        );
    }
}

/// Timings of Theorem 2 at the last step (a calibration probe: `UBB_PROBE=files`).
#[test]
#[ignore]
fn probe_theorem_2() {
    let files = std::env::var("UBB_PROBE").unwrap_or_default();
    for path in files.split_whitespace() {
        let text = std::fs::read_to_string(path).unwrap();
        let s = Scenario::from_json(&text).unwrap();
        let p = s.prepare_ubb().unwrap();
        let run = p.run_data();
        let k = p.steps - 1;
        let t = std::time::Instant::now();
        let step = p.problem.step(&run.y, k).unwrap();
        let t_step = t.elapsed().as_secs_f64();
        let t = std::time::Instant::now();
        let _ = p.problem.theorem_2(&run.y, k, &[0, 1]);
        let t2 = t.elapsed().as_secs_f64();
        println!(
            "{path}: step {t_step:.4} s, theorem 2 {t2:.3} s, polygon vertices {:?}",
            step.planar.as_ref().map(|p| p.vertices().len())
        );
    }
}

/// Timings of one step's build (a calibration probe: `UBB_PROBE=files`).
#[test]
#[ignore]
fn probe_step() {
    let files = std::env::var("UBB_PROBE").unwrap_or_default();
    for path in files.split_whitespace() {
        let text = std::fs::read_to_string(path).unwrap();
        let s = Scenario::from_json(&text).unwrap();
        let p = s.prepare_ubb().unwrap();
        let run = p.run_data();
        let k = p.steps - 1;
        let t = std::time::Instant::now();
        for _ in 0..5 {
            let _ = p.problem.step(&run.y, k).unwrap();
        }
        let t_step = t.elapsed().as_secs_f64() / 5.0;
        let t = std::time::Instant::now();
        for _ in 0..5 {
            let _ = p.problem.step_lp(&run.y, k).unwrap();
        }
        let t_lp = t.elapsed().as_secs_f64() / 5.0;
        println!("{path}: step {t_step:.4} s, LP-path build {t_lp:.4} s");
    }
}
