//! The speed comparison's kernels, written once so that the native benchmark
//! (`cargo bench --bench speed -- kernels`), the wasm one (`BenchKernel` in Chromium,
//! `tests/bench/kernels.mjs`) and the README's table time the same code. Each kernel is
//! prepared once (the preset run, the model built) and then repeated; a repetition returns a
//! short summary of what it computed, so a reader sees that the same work ran everywhere
//! (`tests/bench/numpy_baselines.py` prints the same summaries for its NumPy versions).

use crate::error::{Error, Result};
use crate::glls::{Curves, GllsModel};
use crate::presets;
use crate::study::{Chunked, Study as _};

/// The kernels of the comparison, in the README's order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kernel {
    /// The SCF robot Monte Carlo: 10,000 runs × 40 steps, Kalman and state-conditional
    /// regions (scf-robots, `conditional_experiment`).
    RobotMc,
    /// The LSCR region raster 512 × 512 of lscr-predict.
    LscrRaster,
    /// The GLLS singular-value curves s = 0..500 of a 10-state, 2-output model.
    GllsCurves,
    /// One set-membership step of ubb-track at k = 40 (window 30): the interval hull and the
    /// exact polygon.
    UbbStep,
    /// The uniform-paper report: 120 samples, swapping, window ∂ = 5.
    UniformReport,
}

impl Kernel {
    pub const ALL: [Kernel; 5] = [
        Kernel::RobotMc,
        Kernel::LscrRaster,
        Kernel::GllsCurves,
        Kernel::UbbStep,
        Kernel::UniformReport,
    ];

    /// The key the three benchmarks print (`BENCH <key> <ms> …`).
    pub fn key(self) -> &'static str {
        match self {
            Kernel::RobotMc => "robot_mc",
            Kernel::LscrRaster => "lscr_raster",
            Kernel::GllsCurves => "glls_curves",
            Kernel::UbbStep => "ubb_step",
            Kernel::UniformReport => "uniform_report",
        }
    }

    pub fn from_key(key: &str) -> Result<Kernel> {
        Kernel::ALL
            .into_iter()
            .find(|k| k.key() == key)
            .ok_or_else(|| {
                let keys: Vec<&str> = Kernel::ALL.iter().map(|k| k.key()).collect();
                Error::field(
                    "kernel",
                    format!(
                        "{} is not a kernel; the kernels are {}",
                        crate::error::quoted(key),
                        keys.join(", ")
                    ),
                )
            })
    }

    /// The kernel prepared: a function that runs it once and says what it computed.
    pub fn prepare(self) -> Result<Box<dyn FnMut() -> Result<String>>> {
        Ok(match self {
            Kernel::RobotMc => {
                let prepared = preset("scf-robots")?.prepare_scf()?;
                Box::new(move || {
                    let mut e = Chunked::new(prepared.conditional_experiment()?);
                    while !e.finished() {
                        e.step(10_000)?;
                    }
                    let r = e.report();
                    Ok(format!(
                        "{} runs x {} steps; inside X^KF {}, X^SCF {}",
                        r.runs_total, r.condition_t, r.kf_inside, r.scf_inside
                    ))
                })
            }
            Kernel::LscrRaster => {
                let l = preset("lscr-predict")?
                    .run()?
                    .lscr
                    .ok_or_else(|| Error::field("kernel", "lscr-predict gave no LSCR report"))?;
                Box::new(move || {
                    let g = l.region.raster(&l.window, 512, 512)?;
                    Ok(format!(
                        "512 x 512 pixels, {} inside",
                        g.excluded.iter().filter(|&&e| e == 0).count()
                    ))
                })
            }
            Kernel::GllsCurves => {
                let model = ten_state_model();
                Box::new(move || {
                    let c = Curves::new(&model, 500)?;
                    Ok(format!(
                        "s = 0..500, n = 10, m = 2; log10 sigma_n(Gamma_501) = {:.3}",
                        c.log10_sigma
                            .last()
                            .and_then(|s| s.last())
                            .copied()
                            .unwrap_or(f64::NAN)
                    ))
                })
            }
            Kernel::UbbStep => {
                let prep = preset("ubb-track")?.prepare_ubb()?;
                let run = prep.run_data();
                Box::new(move || {
                    // As the page computes it: the step, then its hull and polygon (the planar
                    // path for this 2-D l∞ preset: no LP).
                    let step = prep.problem.step(&run.y, 40)?;
                    let (_, poly, size) = step.hull_and_polygon([0, 1], 64)?;
                    Ok(format!(
                        "k = 40, window 30: {} variables, {} rows; {} LPs for the polygon ({} path, {} vertices)",
                        size.variables,
                        size.rows,
                        poly.calls,
                        if step.planar.is_some() { "planar" } else { "LP" },
                        poly.vertices.len()
                    ))
                })
            }
            Kernel::UniformReport => {
                let s = preset("uniform-paper")?;
                Box::new(move || {
                    let r = s.run()?;
                    let u = r
                        .uniform
                        .ok_or_else(|| Error::field("kernel", "no uniform report"))?;
                    Ok(format!("{} steps, window {}", u.steps.len(), u.window))
                })
            }
        })
    }
}

fn preset(name: &str) -> Result<crate::scenario::Scenario> {
    presets::get(name)
}

/// A 10-state, 2-output model with spectral radius 1.02 (seeded): the GLLS curves' test bed.
pub fn ten_state_model() -> GllsModel {
    use nalgebra::{DMatrix, DVector};
    use rand::{RngExt, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    let a = DMatrix::from_fn(10, 10, |_, _| rng.random::<f64>() - 0.5);
    let rho = a
        .complex_eigenvalues()
        .iter()
        .map(|z| z.norm())
        .fold(0.0, f64::max);
    GllsModel {
        a: a / rho * 1.02,
        b: DMatrix::zeros(10, 0),
        c: DMatrix::from_fn(2, 10, |_, _| rng.random::<f64>() - 0.5),
        omega: DMatrix::identity(2, 2) * 0.01,
        xi: DMatrix::zeros(10, 10),
        x0: DVector::from_element(10, 1.0),
    }
}
