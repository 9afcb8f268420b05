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
//!   size, and their time with each engine, and the time of the preset's whole report.

use confset::presets;
use confset::solve::simplex::{self, Engine, Outcome};
use confset::solve::{self, Problem};
#[cfg(not(target_arch = "wasm32"))]
use confset::uniform::state_lp;
use confset::uniform::{estimate_states, face_ranges, Window};
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

/// c, A, b, lo, hi of min cᵀx, A x ≤ b, lo ≤ x ≤ hi.
type Lp = (
    DVector<f64>,
    DMatrix<f64>,
    DVector<f64>,
    DVector<f64>,
    DVector<f64>,
);

/// A random LP with a known feasible point x₀ in the box [−2, 2]ⁿ: b = A x₀ + slack, the
/// slack zero on a share `tight` of the rows (degenerate when more than n rows are tight).
fn random_lp(rng: &mut ChaCha8Rng, m: usize, n: usize, tight: f64) -> Lp {
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
        assert!(
            ax - b[i] <= 1e-9 * terms,
            "{what}: row {i}: {ax} > {}",
            b[i]
        );
    }
    for j in 0..x.len() {
        assert!(
            x[j] >= lo[j] - 1e-9 * lo[j].abs().max(1.0)
                && x[j] <= hi[j] + 1e-9 * hi[j].abs().max(1.0),
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

/// Rows of a report's matrix.
fn matrix(v: &serde_json::Value) -> DMatrix<f64> {
    let rows: Vec<Vec<f64>> = serde_json::from_value(v.clone()).unwrap();
    let cols = rows.first().map_or(0, |r| r.len());
    DMatrix::from_fn(rows.len(), cols, |i, j| rows[i][j])
}

/// Every preset with a uniform report, run with the simplex and with clarabel only. The
/// paper's optimum is not unique (C·A = 0.5·C): the simplex returns a vertex of the optimal
/// face, clarabel a point inside it, so the swapping estimator's Θ̂ (fitted to those states)
/// and everything after differ between the two runs; what is unique is compared instead:
/// * at every step of the simplex run, the state LP with the Θ̂ that step used has the same
///   optimal value with either engine (1e-9 of the objective's terms);
/// * at the cursor, the report's optimum and face ranges equal clarabel's on the same window
///   and Θ̂ (1e-9 of the optimum; the ranges to 1e-7 of the prior box, the face's own
///   tolerance);
/// * the verdicts (truth in the polygon, bound extensions) are the same in both runs.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn every_uniform_preset_matches_the_clarabel_path() {
    let mut seen = 0;
    for p in presets::all() {
        let Some(spec) = p.scenario.uniform.clone() else {
            continue;
        };
        let name = &p.name;
        let fast = simplex::with_engine(Engine::Simplex, || p.scenario.run()).unwrap();
        let slow = simplex::with_engine(Engine::Clarabel, || p.scenario.run()).unwrap();
        let (Some(fast), Some(slow)) = (fast.uniform, slow.uniform) else {
            continue;
        };
        seen += 1;
        assert_eq!(fast.at.truth_in_polygon, slow.at.truth_in_polygon, "{name}");
        assert_eq!(fast.extended, slow.extended, "{name}");
        let report = serde_json::to_value(&fast).unwrap();
        let rows = |key: &str| -> Vec<DVector<f64>> {
            serde_json::from_value::<Vec<Vec<f64>>>(report[key].clone())
                .unwrap()
                .into_iter()
                .map(DVector::from_vec)
                .collect()
        };
        let (u, y) = (rows("u"), rows("y"));
        let prior = confset::uniform::StatePrior {
            x_lo: -fast.x_bound,
            x_hi: fast.x_bound,
            x0: None,
            xr_max: DVector::from_vec(spec.xr_max.clone().expect("xr_max")),
            yr_max: DVector::from_vec(spec.yr_max.clone().expect("yr_max")),
        };
        let theta_after = |k: usize| confset::uniform::Theta {
            a: matrix(&report["steps"][k]["a"]),
            b: matrix(&report["steps"][k]["b"]),
            c: matrix(&report["steps"][k]["c"]),
            d: matrix(&report["steps"][k]["d"]),
        };
        let steps = fast.steps.len();
        let window = |t: usize| Window {
            first: t.saturating_sub(spec.window - 1).max(1),
            last: t,
        };
        for t in 2..=steps {
            let (theta, w) = (theta_after(t - 2), window(t));
            let solve = |engine| {
                simplex::with_engine(engine, || estimate_states(&theta, &u, &y, w, &prior)).unwrap()
            };
            let ((a, lp), (b, _)) = (solve(Engine::Simplex), solve(Engine::Clarabel));
            let x = DVector::from_iterator(
                lp.c.len(),
                a.x.iter()
                    .flat_map(|v| v.iter().copied())
                    .chain(a.xr.iter().copied())
                    .chain(a.yr.iter().copied()),
            );
            assert_same_optimum(
                a.objective,
                b.objective,
                &lp.c,
                &x,
                &format!("{name}, t = {t}"),
            );
        }
        // The cursor's window, with the Θ̂ after its step.
        let (theta, w) = (theta_after(fast.at.time - 1), window(fast.at.time));
        let (est, lp) = simplex::with_engine(Engine::Clarabel, || {
            estimate_states(&theta, &u, &y, w, &prior)
        })
        .unwrap();
        assert!(
            (fast.at.objective - est.objective).abs() <= 1e-9 * est.objective.abs().max(1e-300),
            "{name}: optimum {} at the cursor, clarabel {}",
            fast.at.objective,
            est.objective
        );
        let all: Vec<usize> = (0..lp.c.len()).collect();
        let ranges =
            simplex::with_engine(Engine::Clarabel, || face_ranges(&lp, est.objective, &all))
                .unwrap();
        let n = theta.n();
        let got: Vec<(f64, f64)> = fast
            .at
            .face_lo
            .iter()
            .flatten()
            .zip(fast.at.face_hi.iter().flatten())
            .map(|(l, h)| (*l, *h))
            .chain(
                fast.at
                    .face_xr
                    .iter()
                    .chain(&fast.at.face_yr)
                    .map(|r| (r[0], r[1])),
            )
            .collect();
        assert_eq!(got.len(), ranges.len(), "{name}: {n} states");
        for (k, (g, want)) in got.iter().zip(&ranges).enumerate() {
            assert!(
                (g.0 - want.0).abs() <= 1e-7 * fast.x_bound
                    && (g.1 - want.1).abs() <= 1e-7 * fast.x_bound,
                "{name}: range {k} over the face: simplex {g:?}, clarabel {want:?}"
            );
        }
    }
    assert!(seen >= 1, "no uniform preset");
}
in_browser!(every_uniform_preset_matches_the_clarabel_path);

/// (native, printed with `--nocapture`) The uniform preset's LPs per step, by kind and size
/// (rows of 𝒜 × columns; clarabel also gets a row per finite bound), and their time with each
/// engine. No assertion on time.
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn uniform_lps_per_step_timed() {
    use confset::uniform::{parameter_lp, simulate, solve_extending, StatePrior, ThetaPrior};
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
    let scenario = presets::get("uniform-paper").unwrap();
    for engine in [Engine::Clarabel, Engine::Simplex] {
        let mut times: Vec<f64> = (0..5)
            .map(|_| {
                let clock = Instant::now();
                simplex::with_engine(engine, || scenario.run()).unwrap();
                clock.elapsed().as_secs_f64() * 1e3
            })
            .collect();
        times.sort_by(f64::total_cmp);
        println!(
            "{engine:?}: the uniform-paper report {:.1} ms (median of 5)",
            times[2]
        );
    }
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
