//! The speed comparison's kernels (`confset::bench`): every kernel runs, computes what the
//! README's table says it computes, and is found by its key — natively and in wasm, so the
//! benchmark's two sides run the same, working code.

use confset::bench::Kernel;

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn every_kernel_runs_and_says_what_it_computed() {
    for kernel in Kernel::ALL {
        assert_eq!(Kernel::from_key(kernel.key()).expect("key"), kernel);
        let mut run = kernel.prepare().expect("prepared");
        let what = run().expect("runs");
        let expected = match kernel {
            // The robot counts of scf-robots (tests/suite/scf_paper.rs: paper 0 and 9498).
            Kernel::RobotMc => "10000 runs x 40 steps; inside X^KF 2, X^SCF 9481",
            Kernel::LscrRaster => "512 x 512 pixels",
            Kernel::GllsCurves => "s = 0..500, n = 10, m = 2",
            Kernel::UbbStep => "k = 40, window 30: 92 variables, 184 rows",
            Kernel::UniformReport => "120 steps, window 5",
        };
        assert!(what.starts_with(expected), "{}: {what}", kernel.key());
        // A second run (the benchmark repeats) computes the same.
        assert_eq!(run().expect("runs again"), what, "{}", kernel.key());
    }
    let e = Kernel::from_key("robots").expect_err("no such kernel");
    assert_eq!(e.field, "kernel");
    assert!(e.message.contains("robot_mc, lscr_raster"), "{}", e.message);
}
in_browser!(every_kernel_runs_and_says_what_it_computed);
