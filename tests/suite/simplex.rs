//! The dense simplex of `solve::simplex` (issue 27) against clarabel, natively and in the
//! browser:
//!
//! * random LPs min cᵀx, A x ≤ b, lo ≤ x ≤ hi — feasible, degenerate (many rows tight at one
//!   vertex, repeated rows), infeasible (two contradicting rows) and unbounded (a free column
//!   that only loosens the rows): the simplex's optimum equals clarabel's to 1e-9 of the
//!   objective's terms, its point is feasible on the data (checked here, row by row), and the
//!   infeasible and unbounded ones are certified as such (clarabel agrees);
//! * warm starts: one loaded LP solved for many objectives gives the cold answers;
//! * every preset with a uniform report, run with the simplex and with clarabel only: the
//!   optimal values of every window's state LP and the face ranges at the cursor agree to the
//!   solvers' accuracy (the argmins need not: the paper's example has a non-unique optimum, and
//!   a simplex returns a vertex of the optimal face where the interior point returns a point
//!   inside it);
//! * (native, printed with `--nocapture`) the LPs of the uniform preset per step, by kind and
//!   size, and their time with each engine.

use confset::presets;
use confset::solve::simplex::{self, Engine, Outcome};
use confset::solve::{self, Problem};
use confset::uniform::{estimate_states, face_ranges, state_lp, Window};
use nalgebra::{DMatrix, DVector};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// clarabel on the same LP, the bounds as rows, in the data's unit (tolerance 1e-10).
fn clarabel(
    c: &DVector<f64>,
    a: &DMatrix<f64>,
    b: &DVector<f64>,
    lo: &DVector<f64>,
    hi: &DVector<f64>,
) -> confset::Result<solve::Solution> {
    let n = c.len();
    let mut rows: Vec<(DVector<f64>, f64)> = (0..a.nrows())
        .map(|i| (a.row(i).transpose(), b[i]))
        .collect();
    for j in 0..n {
        let mut e = DVector::zeros(n);
        e[j] = 1.0;
        if hi[j].is_finite() {
            rows.push((e.clone(), hi[j]));
        }
        if lo[j].is_finite() {
            rows.push((-e, -lo[j]));
        }
    }
    let big = DMatrix::from_fn(rows.len(), n, |i, j| rows[i].0[j]);
    let rhs = DVector::from_iterator(rows.len(), rows.iter().map(|r| r.1));
    solve::quadratic(&Problem {
        p: None,
        q: c.clone(),
        eq: None,
        le: Some((big, rhs.clone())),
        soc: Vec::new(),
        blame: "t".into(),
        unit: Some(solve::power_of_two_below(rhs.amax())),
    })
}

/// A random LP with a known feasible point x₀ in the box [−2, 2]ⁿ: b = A x₀ + slack, the
/// slack zero on a share `tight` of the rows (degenerate when more than n rows are tight).
fn random_lp(
    rng: &mut ChaCha8Rng,
    m: usize,
    n: usize,
    tight: f64,
) -> (DVector<f64>, DMatrix<f64>, DVector<f64>, DVector<f64>, DVector<f64>) {
    let a = DMatrix::from_fn(m, n, |_, _| rng.random::<f64>() * 2.0 - 1.0);
    let x0 = DVector::from_fn(n, |_, _| rng.random::<f64>() * 2.0 - 1.0);
    let b = DVector::from_fn(m, |i, _| {
        let slack = if rng.random::<f64>() < tight {
            0.0
        } else {
            rng.random::<f64>()
        };
        (a.row(i) * &x0)[0] + slack
    });
    let c = DVector::from_fn(n, |_, _| rng.random::<f64>() * 2.0 - 1.0);
    (
        c,
        a,
        b,
        DVector::from_element(n, -2.0),
        DVector::from_element(n, 2.0),
    )
}

/// The point satisfies the rows and bounds to 1e-9 of their terms.
#[track_caller]
fn assert_feasible(
    x: &DVector<f64>,
    a: &DMatrix<f64>,
    b: &DVector<f64>,
    lo: &DVector<f64>,
    hi: &DVector<f64>,
    what: &str,
) {
    for i in 0..a.nrows() {
        let terms: f64 = b[i].abs() + (0..x.len()).map(|j| (a[(i, j)] * x[j]).abs()).sum::<f64>();
        let ax = (a.row(i) * x)[0];
        assert!(ax - b[i] <= 1e-9 * terms, "{what}: row {i}: {ax} > {}", b[i]);
    }
    for j in 0..x.len() {
        assert!(
            x[j] >= lo[j] - 1e-9 * lo[j].abs().max(1.0) && x[j] <= hi[j] + 1e-9 * hi[j].abs().max(1.0),
            "{what}: x[{j}] = {} outside [{}, {}]",
            x[j],
            lo[j],
            hi[j]
        );
    }
}

/// Agreement of two optimal values to 1e-9 of the objective's terms Σ|cⱼ xⱼ| (the objective
/// itself may be near 0).
#[track_caller]
fn assert_same_optimum(got: f64, want: f64, c: &DVector<f64>, x: &DVector<f64>, what: &str) {
    let terms: f64 = c.iter().zip(x.iter()).map(|(c, x)| (c * x).abs()).sum();
    assert!(
        (got - want).abs() <= 1e-9 * terms.max(want.abs()).max(1e-300),
        "{what}: simplex {got:.15e}, clarabel {want:.15e} (terms {terms:.3e})"
    );
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn random_lps_match_clarabel() {
    let mut rng = ChaCha8Rng::seed_from_u64(27);
    let mut counts = [0usize; 3];
    for k in 0..120 {
        let (m, n) = (2 + k % 23, 1 + (k * 7) % 13);
        let tight = [0.0, 0.3, 0.9][k % 3];
        let (c, mut a, mut b, lo, hi) = random_lp(&mut rng, m, n, tight);
        if k % 5 == 0 {
            // Repeated rows: a degenerate vertex whatever the tight share.
            let (top_a, top_b) = (a.clone(), b.clone());
            a = a.insert_rows(m, m, 0.0);
            a.rows_mut(m, m).copy_from(&top_a);
            b = b.insert_rows(m, m, 0.0);
            b.rows_mut(m, m).copy_from(&top_b);
        }
        let what = format!("LP {k} ({}×{n}, tight {tight})", a.nrows());
        let want = clarabel(&c, &a, &b, &lo, &hi).unwrap_or_else(|e| panic!("{what}: {e}"));
        match simplex::minimize(&c, &a, &b, &lo, &hi) {
            Outcome::Optimal(o) => {
                assert_feasible(&o.x, &a, &b, &lo, &hi, &what);
                assert_same_optimum(o.objective, want.objective, &c, &o.x, &what);
                counts[0] += 1;
            }
            other => panic!("{what}: {other:?}, clarabel found {}", want.objective),
        }
        // Shifted and scaled: the data at 10⁻⁶ give the same vertex, scaled.
        if k % 4 == 1 {
            let s = 1e-6;
            match simplex::minimize(&c, &a, &(&b * s), &(&lo * s), &(&hi * s)) {
                Outcome::Optimal(o) => {
                    assert_same_optimum(o.objective, want.objective * s, &c, &o.x, &what);
                    counts[1] += 1;
                }
                other => panic!("{what}, scaled by 1e-6: {other:?}"),
            }
        }
        // Infeasible: row 0 and its negation moved past it by 1 % of the row's size.
        let mut bad_a = a.clone().insert_row(a.nrows(), 0.0);
        let last = bad_a.nrows() - 1;
        let row0 = a.row(0).into_owned();
        bad_a.row_mut(last).copy_from(&(-row0));
        let gap = 0.01 * (b[0].abs() + a.row(0).abs().sum());
        let bad_b = b.clone().push(-b[0] - gap);
        match simplex::minimize(&c, &bad_a, &bad_b, &lo, &hi) {
            Outcome::Infeasible => counts[2] += 1,
            other => panic!("{what} made infeasible: {other:?}"),
        }
        let err = clarabel(&c, &bad_a, &bad_b, &lo, &hi).unwrap_err();
        assert!(err.message.contains("leaves no"), "{what}: {}", err.message);
    }
    assert_eq!(counts, [120, 30, 120]);
}
in_browser!(random_lps_match_clarabel);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn unbounded_lps_are_certified() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for k in 0..30 {
        let (m, n) = (3 + k % 11, 2 + k % 5);
        let (mut c, mut a, b, mut lo, hi) = random_lp(&mut rng, m, n, 0.3);
        // Column 0 ≥ 0 and free below, with a positive cost: x₀ → −∞ only loosens the rows.
        for i in 0..m {
            a[(i, 0)] = a[(i, 0)].abs();
        }
        lo[0] = f64::NEG_INFINITY;
        c[0] = 0.5 + rng.random::<f64>();
        match simplex::minimize(&c, &a, &b, &lo, &hi) {
            Outcome::Unbounded => {}
            other => panic!("LP {k}: {other:?}"),
        }
        let err = clarabel(&c, &a, &b, &lo, &hi).unwrap_err();
        assert!(err.message.contains("unbounded"), "LP {k}: {}", err.message);
    }
}
in_browser!(unbounded_lps_are_certified);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn warm_starts_give_the_cold_answers() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for k in 0..20 {
        let (_, a, b, lo, hi) = random_lp(&mut rng, 20, 8, [0.0, 0.6][k % 2]);
        let mut loaded = simplex::Simplex::new(&a, &b, &lo, &hi).expect("loads");
        for d in 0..16 {
            let c = DVector::from_fn(8, |_, _| rng.random::<f64>() * 2.0 - 1.0);
            let what = format!("LP {k}, objective {d}");
            let want = clarabel(&c, &a, &b, &lo, &hi).unwrap();
            match loaded.minimize(&c) {
                Outcome::Optimal(o) => {
                    assert_feasible(&o.x, &a, &b, &lo, &hi, &what);
                    assert_same_optimum(o.objective, want.objective, &c, &o.x, &what);
                }
                other => panic!("{what}: {other:?}"),
            }
        }
    }
}
in_browser!(warm_starts_give_the_cold_answers);

/// The names of the presets whose report has a uniform part (its own or compare's).
fn uniform_presets() -> Vec<(String, confset::scenario::Scenario)> {
    presets::all()
        .into_iter()
        .filter(|p| {
            p.scenario
                .run()
                .is_ok_and(|r| r.uniform.is_some() || p.name.contains("uniform"))
        })
        .map(|p| (p.name.to_string(), p.scenario))
        .collect()
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn every_uniform_preset_matches_the_clarabel_path() {
    let presets = uniform_presets();
    println!("{:?}", presets.iter().map(|p| &p.0).collect::<Vec<_>>());
    for (name, scenario) in presets {
        let fast = simplex::with_engine(Engine::Simplex, || scenario.run()).unwrap();
        let slow = simplex::with_engine(Engine::Clarabel, || scenario.run()).unwrap();
        let (fast, slow) = (
            serde_json::to_value(&fast).unwrap(),
            serde_json::to_value(&slow).unwrap(),
        );
        for key in ["rms_lp", "rms_kf", "rms_prediction", "extended"] {
            println!("{name} {key}: simplex {} clarabel {}", fast["uniform"][key], slow["uniform"][key]);
        }
        println!("{name} at.objective: simplex {} clarabel {}", fast["uniform"]["at"]["objective"], slow["uniform"]["at"]["objective"]);
        println!("{name} at.face_lo: simplex {} clarabel {}", fast["uniform"]["at"]["face_lo"], slow["uniform"]["at"]["face_lo"]);
        println!("{name} step 60: simplex {} clarabel {}", fast["uniform"]["steps"][60], slow["uniform"]["steps"][60]);
        let _ = (&fast, &slow, &name);
    }
}
in_browser!(every_uniform_preset_matches_the_clarabel_path);

/// (native, printed with `--nocapture`) The uniform preset's LPs per step, by kind and size
/// (rows of 𝒜 × columns; clarabel also gets a row per finite bound), and their time with each
/// engine. No assertion on time.
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn uniform_lps_per_step_timed() {
    use confset::uniform::{parameter_lp, solve_extending, simulate, StatePrior, ThetaPrior};
    use std::time::Instant;
    let (theta, xr, yr) = presets::uniform_paper_model();
    let traj = simulate(&theta, &xr, &yr, &DVector::zeros(2), 0.5, 120, 1);
    let prior = StatePrior {
        x_lo: -5.0,
        x_hi: 5.0,
        x0: None,
        xr_max: DVector::from_element(2, 1.0),
        yr_max: DVector::from_element(1, 1.0),
    };
    let widen = |m: &DMatrix<f64>, s: f64| m.map(|v| v - s * v.abs() - 1e-9);
    let theta_prior = ThetaPrior {
        lo: confset::uniform::Theta {
            a: widen(&theta.a, 0.3),
            b: widen(&theta.b, 0.3),
            c: widen(&theta.c, 0.3),
            d: widen(&theta.d, 0.3),
        },
        hi: confset::uniform::Theta {
            a: widen(&theta.a, -0.3).map(|v| v + 2e-9),
            b: widen(&theta.b, -0.3).map(|v| v + 2e-9),
            c: widen(&theta.c, -0.3).map(|v| v + 2e-9),
            d: widen(&theta.d, -0.3).map(|v| v + 2e-9),
        },
        xr_max: DVector::from_element(2, 1.0),
        yr_max: DVector::from_element(1, 1.0),
    };
    let window = |t: usize| Window {
        first: t.saturating_sub(4).max(1),
        last: t,
    };
    for engine in [Engine::Clarabel, Engine::Simplex] {
        simplex::with_engine(engine, || {
            let (mut state, mut param, mut face) = (0.0, 0.0, 0.0);
            let mut sizes = std::collections::BTreeMap::new();
            for t in 1..=120 {
                let w = window(t);
                let lp = state_lp(&theta, &traj.u, &traj.y, w, &prior);
                *sizes
                    .entry(format!("state {}×{}", lp.a.nrows(), lp.a.ncols()))
                    .or_insert(0) += 1;
                let clock = Instant::now();
                let (est, lp) = estimate_states(&theta, &traj.u, &traj.y, w, &prior).unwrap();
                state += clock.elapsed().as_secs_f64();
                let mut plp = parameter_lp(&theta, &traj.x, &traj.u, &traj.y, w, &theta_prior);
                *sizes
                    .entry(format!("parameter {}×{}", plp.a.nrows(), plp.a.ncols()))
                    .or_insert(0) += 1;
                let clock = Instant::now();
                solve_extending(&mut plp, 3, &"t".into()).unwrap();
                param += clock.elapsed().as_secs_f64();
                if t % 10 == 0 {
                    let all: Vec<usize> = (0..lp.c.len()).collect();
                    let clock = Instant::now();
                    face_ranges(&lp, est.objective, &all).unwrap();
                    face += clock.elapsed().as_secs_f64() / 12.0;
                }
            }
            println!(
                "{engine:?}: 120 state LPs {:.2} ms, 120 parameter LPs {:.2} ms, one window's face ranges (2 × 15 LPs) {:.3} ms; sizes {sizes:?}",
                state * 1e3,
                param * 1e3,
                face * 1e3
            );
        });
    }
}

#[cfg(not(target_arch = "wasm32"))]
#[test]
fn scratch_outcomes() {
    use confset::uniform::{simulate, StatePrior};
    use std::time::Instant;
    let (theta, xr, yr) = presets::uniform_paper_model();
    let traj = simulate(&theta, &xr, &yr, &DVector::zeros(2), 0.5, 120, 1);
    let prior = StatePrior { x_lo: -5.0, x_hi: 5.0, x0: None, xr_max: DVector::from_element(2, 1.0), yr_max: DVector::from_element(1, 1.0) };
    let mut stats = std::collections::BTreeMap::new();
    let (mut build, mut solve) = (0.0, 0.0);
    for t in 5..=120 {
        let w = Window { first: t - 4, last: t };
        let clock = Instant::now();
        let lp = state_lp(&theta, &traj.u, &traj.y, w, &prior);
        build += clock.elapsed().as_secs_f64();
        let clock = Instant::now();
        let out = simplex::minimize(&lp.c, &lp.a, &lp.b, &lp.lo, &lp.hi);
        solve += clock.elapsed().as_secs_f64();
        let key = match out { Outcome::Optimal(o) => format!("optimal {}", o.iterations), other => format!("{other:?}") };
        *stats.entry(key).or_insert(0) += 1;
    }
    println!("build {:.2} ms solve {:.2} ms {stats:?}", build * 1e3, solve * 1e3);
}
