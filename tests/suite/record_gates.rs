//! A user's record through every method's gates (issue "a researcher's own record"): the
//! record's own times and its gaps, looped over [`Method::ALL`] so a new method cannot skip
//! them. What each method does with a gap is a required item of its descriptor
//! ([`confset::scenario::gaps`]): a method that takes gaps reports every row of the record with
//! the gaps where the record has them and says so in its warnings; one that cannot is refused
//! before any work, naming the first gap's row and its time.

use confset::presets;
use confset::scenario::{self, DataSpec, Gaps, RecordTime, Report, Scenario, TimeIndex};
use confset::Method;

/// The first preset of `m` that simulates, run, as the same scenario on the record it drew
/// (its measurements and inputs as `data`), with years 1871, 1872, … as the record's times.
fn record_of(m: Method) -> Option<(String, Scenario)> {
    let p = presets::all().into_iter().find(|p| {
        let method = if m == Method::Kf { Method::Scf } else { m };
        p.scenario.method == method && p.scenario.simulate.is_some()
    })?;
    let mut s = p.scenario.clone();
    s.method = m;
    let sim = s.run().unwrap_or_else(|e| panic!("{}: {e}", p.name));
    let v = serde_json::to_value(&sim).unwrap();
    let mut d = s.clone();
    d.simulate = None;
    let rows = sim.y.len();
    d.data = Some(DataSpec {
        y: sim.y.clone(),
        u: crate::registry::inputs_used(&s, &v),
        t: (0..rows)
            .map(|k| RecordTime::Number(1871.0 + k as f64))
            .collect(),
    });
    Some((p.name, d))
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn every_method_reads_out_the_records_own_time() {
    let mut checked = 0;
    for m in Method::ALL {
        let Some((name, s)) = record_of(m) else {
            continue;
        };
        let rows = s.data.as_ref().unwrap().y.len();
        let r: Report = s
            .run()
            .unwrap_or_else(|e| panic!("{name} ({m}) with times: {e}"));
        assert_eq!(r.figure.times.len(), rows, "{name} ({m}): figure.times");
        assert_eq!(r.figure.time_label(1), Some("1871"), "{name} ({m})");
        let csv = r.table().unwrap().to_csv();
        let header = csv.lines().find(|l| !l.starts_with('#')).unwrap();
        let has = header.split(',').any(|c| c == "record_time");
        assert_eq!(
            has,
            scenario::time_index(m) != TimeIndex::NotTime,
            "{name} ({m}): record_time column in {header}"
        );
        if has {
            // The record time of each row is the one of the row's own time index.
            let cols: Vec<&str> = header.split(',').collect();
            let first = csv.lines().filter(|l| !l.starts_with('#')).nth(1).unwrap();
            let cells: Vec<&str> = first.split(',').collect();
            let index: f64 = cells[0].parse().unwrap();
            let row = match scenario::time_index(m) {
                TimeIndex::OneBased => index as usize - 1,
                TimeIndex::ZeroBased => index as usize,
                TimeIndex::NotTime => unreachable!(),
            };
            assert_eq!(cols[1], "record_time");
            assert_eq!(cells[1], (1871 + row).to_string(), "{name} ({m}): {first}");
        }
        checked += 1;
    }
    assert!(checked >= 6, "{checked} methods checked");
}
in_browser!(every_method_reads_out_the_records_own_time);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn every_method_takes_a_gap_or_refuses_it_naming_the_row() {
    let mut checked = 0;
    for m in Method::ALL {
        let Some((name, mut s)) = record_of(m) else {
            continue;
        };
        let d = s.data.as_mut().unwrap();
        let rows = d.y.len();
        let gaps = [0, rows / 2, rows - 1];
        for &k in &gaps {
            d.y[k][0] = f64::NAN;
        }
        match (scenario::gaps(m), s.run()) {
            (Gaps::Handled(how), Ok(r)) => {
                assert!(!how.is_empty());
                assert_eq!(r.y.len(), rows, "{name} ({m}): a report has every row");
                for &k in &gaps {
                    assert!(r.y[k][0].is_nan(), "{name} ({m}): gap at row {k} kept");
                }
                assert!(
                    r.warnings.iter().any(|w| w.contains("gap")),
                    "{name} ({m}): no warning names the gaps: {:?}",
                    r.warnings
                );
                // The JSON writes a gap as null and the report passes its finiteness check.
                let v = serde_json::to_value(&r).unwrap();
                assert!(v["y"][gaps[1]][0].is_null(), "{name} ({m})");
            }
            (Gaps::Refused(why), Err(e)) => {
                assert!(!why.is_empty());
                assert_eq!(e.field, "data.y[0]", "{name} ({m}): {e}");
                assert!(
                    e.message.contains("row 1") && e.message.contains("1871"),
                    "{name} ({m}): the row and its time are named: {e}"
                );
                assert!(e.message.contains(why), "{name} ({m}): the reason: {e}");
            }
            (Gaps::Handled(_), Err(e)) => panic!("{name} ({m}) says it takes gaps: {e}"),
            (Gaps::Refused(_), Ok(_)) => panic!("{name} ({m}) says it refuses gaps, but ran"),
        }
        checked += 1;
    }
    assert!(checked >= 6, "{checked} methods checked");
}
in_browser!(every_method_takes_a_gap_or_refuses_it_naming_the_row);

/// `data.t` is checked: one time per row, increasing, numbers or ISO dates, not both.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn record_times_are_checked() {
    let (_, s) = record_of(Method::Kf).unwrap();
    let rows = s.data.as_ref().unwrap().y.len();
    let with = |t: Vec<RecordTime>| {
        let mut s = s.clone();
        s.data.as_mut().unwrap().t = t;
        s.run()
    };
    let e = with(vec![RecordTime::Number(1.0)]).unwrap_err();
    assert_eq!(e.field, "data.t", "{e}");
    assert!(
        e.message.contains(&format!("1 time for {rows} rows")),
        "{e}"
    );
    let mut t: Vec<RecordTime> = (0..rows).map(|k| RecordTime::Number(k as f64)).collect();
    t[5] = RecordTime::Number(3.0);
    let e = with(t).unwrap_err();
    assert_eq!(e.field, "data.t[5]", "{e}");
    assert!(e.message.contains("not after row 5's 4"), "{e}");
    let dates: Vec<RecordTime> = (0..rows)
        .map(|k| RecordTime::Date(format!("{}-{:02}-01", 1959 + k / 12, k % 12 + 1)))
        .collect();
    let r = with(dates).unwrap();
    assert_eq!(r.figure.time_label(2), Some("1959-02-01"));
    let mut bad: Vec<RecordTime> = (0..rows).map(|k| RecordTime::Number(k as f64)).collect();
    bad[2] = RecordTime::Date("yesterday".into());
    let e = with(bad).unwrap_err();
    assert_eq!(e.field, "data.t[2]", "{e}");
    assert!(e.message.contains("ISO date"), "{e}");
    // JSON: numbers, dates and null gaps as a data frame would write them.
    let text = r#"{"method": "kf", "model": {"F": [[1]], "H": [[1]], "V": [[1469.1]], "W": [[15099]], "x1_mean": [1120], "x1_cov": [[1e7]]},
        "data": {"y": [[1120], [null], [963], [1210]], "t": ["1871", "1872", "1873", "1874"]}}"#;
    let s = Scenario::from_json(text).unwrap();
    let d = s.data.as_ref().unwrap();
    assert_eq!(d.gap_rows(), vec![1]);
    assert_eq!(d.row_words(1), "row 2 (t = 2, time 1872)");
}
in_browser!(record_times_are_checked);

/// README's table of what each method does with a gap says what the descriptors say, for
/// every method (a method that learns to take gaps must change its row in the same commit).
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn the_readme_gap_table_is_the_descriptors() {
    const README: &str = include_str!("../../README.md");
    let section = README
        .split("## Your own record")
        .nth(1)
        .and_then(|s| s.split("\n## ").next())
        .expect("README has the section \"Your own record\"");
    for m in Method::ALL {
        let row = section
            .lines()
            .map(str::trim)
            .find(|l| {
                l.starts_with(&format!("| {} | takes it", m.name()))
                    || l.starts_with(&format!("| {} | refuses", m.name()))
            })
            .unwrap_or_else(|| panic!("README's gap table has no row for {m}"));
        let takes = row.starts_with(&format!("| {} | takes it", m.name()));
        assert_eq!(
            takes,
            matches!(scenario::gaps(m), Gaps::Handled(_)),
            "README's gap row for {m} disagrees with its descriptor: {row}"
        );
    }
}
in_browser!(the_readme_gap_table_is_the_descriptors);
