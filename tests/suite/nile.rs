//! The Nile (Durbin & Koopman's local level example, 100 annual flows 1871–1970, a data frame's
//! `year,volume` CSV) with their missing stretches (observations 21–40 and 61–80 blank), read
//! by the one CSV reader and filtered by the Kalman filter, against an independent
//! implementation: statsmodels 0.15's `UnobservedComponents(level='local level')` with
//! σ²_ε = 15099, σ²_η = 1469.1 (Durbin & Koopman's estimates) and a known prior a₁ = 0,
//! P₁ = 10⁷, whose filtered means and variances are pinned below (computed once by
//! `mod.filter([15099, 1469.1]).filtered_state`, `filtered_state_cov`).

use confset::model::{MatrixSpec, ModelSpec};
use confset::scenario::Scenario;
use confset::Method;

const NILE: &str = include_str!("../data/nile.csv");
const NILE_GAPS: &str = include_str!("../data/nile-gaps.csv");

fn local_level() -> Scenario {
    let c = |x: f64| Some(MatrixSpec::Constant(vec![vec![x]]));
    let mut model = ModelSpec {
        f: c(1.0),
        h: c(1.0),
        v: c(1469.1),
        w: c(15099.0),
        ..ModelSpec::default()
    };
    model.x1_mean = Some(vec![0.0]);
    model.x1_cov = Some(vec![vec![1e7]]);
    Scenario::new(Method::Kf, model)
}

/// (t, filtered mean x̂_{t|t}, filtered variance P_{t|t}) from statsmodels.
const FULL: [(usize, f64, f64); 5] = [
    (1, 1118.3114615242446, 15076.236390674487),
    (20, 1026.1394343959414, 4032.1961236867182),
    (21, 1045.8638519873812, 4032.1784537862386),
    (41, 903.8110596948877, 4032.157941890706),
    (100, 798.3702926083578, 4032.157941808782),
];
const GAPS: [(usize, f64, f64); 6] = [
    (20, 1026.1394343959414, 4032.1961236867182),
    (21, 1026.1394343959414, 5501.296123686718),
    (40, 1026.1394343959414, 33414.19612368671),
    (41, 889.9490789429342, 10537.78895767736),
    (60, 834.2614167747446, 4032.186797450499),
    (100, 798.3151146175683, 4032.1867974482548),
];

fn check(csv: &str, name: &str, pinned: &[(usize, f64, f64)]) -> confset::scenario::Report {
    let s = local_level()
        .with_csv_file(csv, name)
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    let d = s.data.as_ref().unwrap();
    assert_eq!(d.y.len(), 100, "{name}: every row kept");
    assert_eq!(
        d.t.len(),
        100,
        "{name}: the year column is the record's time"
    );
    let r = s.run().unwrap_or_else(|e| panic!("{name}: {e}"));
    assert_eq!(r.steps.len(), 100, "{name}: one step per row");
    assert_eq!(r.figure.time_label(20), Some("1890"));
    for &(t, mean, var) in pinned {
        let kf = &r.steps[t - 1].kf;
        let (m, p) = (kf.center[0], kf.cov[0][0]);
        assert!(
            (m - mean).abs() <= 1e-9 * mean.abs(),
            "{name} t = {t}: mean {m} vs statsmodels {mean}"
        );
        assert!(
            (p - var).abs() <= 1e-9 * var,
            "{name} t = {t}: variance {p} vs statsmodels {var}"
        );
    }
    r
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn the_nile_equals_statsmodels() {
    check(NILE, "nile.csv", &FULL);
}
in_browser!(the_nile_equals_statsmodels);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn the_nile_with_its_missing_stretches_equals_statsmodels() {
    let r = check(NILE_GAPS, "nile-gaps.csv", &GAPS);
    let d = r.y.iter().filter(|y| y[0].is_nan()).count();
    assert_eq!(d, 40, "the two stretches of 20 are gaps");
    // Through each gap the variance grows step by step (no update: P⁻ = P + V).
    for stretch in [21..=40, 61..=80] {
        let vars: Vec<f64> = stretch.map(|t| r.steps[t - 1].kf.cov[0][0]).collect();
        assert!(vars.windows(2).all(|w| w[1] > w[0]), "{vars:?}");
    }
    assert!(
        r.warnings.iter().any(|w| w.contains("gap")),
        "{:?}",
        r.warnings
    );
    // The CSV table reads out the years.
    let csv = r.table().unwrap().to_csv();
    assert!(csv.lines().any(|l| l.starts_with("21,1891,")), "{csv}");
}
in_browser!(the_nile_with_its_missing_stretches_equals_statsmodels);
