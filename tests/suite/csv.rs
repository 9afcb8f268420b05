//! Measured data from CSV text (`Scenario::with_csv_data`, the parser of the page's upload and
//! of `confset run --data`), driven by the preset registry:
//!
//! * for every preset that simulates, its measurements and the inputs it used, written as CSV
//!   (with and without a header, comma / semicolon / tab / space delimited), read back give
//!   exactly the `data` built directly, and the same report;
//! * `Scenario::data_shape` is the shape of what every method reads (its report's y, its
//!   inputs);
//! * the error cases name the row, the column, both column counts, the unknown header name, the
//!   row limit; empty text is refused;
//! * `confset run --data FILE.csv` prints the core's report (native).

use crate::registry::{first_difference, inputs_used};
use confset::presets;
use confset::scenario::csv::{MAX_CSV_BYTES, MAX_CSV_ROWS};
use confset::scenario::{DataSpec, Report, Scenario};
use serde_json::Value;

const DELIMITERS: [(&str, &str); 4] = [
    ("comma", ","),
    ("semicolon", ";"),
    ("tab", "\t"),
    ("spaces", "   "),
];

/// Natively every variant of every preset runs; in the browser (slower) one variant per preset
/// in turn.
const RUN_EVERY_VARIANT: bool = cfg!(not(target_arch = "wasm32"));

fn report_value(r: &Report) -> Value {
    serde_json::to_value(r).expect("a report serializes")
}

/// A column name in one of the accepted spellings (`y1`, `Y_1`, `y₁`), chosen by `style`.
fn name(kind: char, i: usize, style: usize) -> String {
    let sub: String = i
        .to_string()
        .chars()
        .map(|d| char::from_u32('₀' as u32 + d.to_digit(10).unwrap_or(0)).unwrap_or('₀'))
        .collect();
    match style % 3 {
        0 => format!("{kind}{i}"),
        1 => format!("{}_{i}", kind.to_ascii_uppercase()),
        _ => format!("{kind}{sub}"),
    }
}

/// `data` as CSV text: without header y₁ … y_q then u₁ … u_r; with a header, in the reverse
/// column order (the names decide) and mixed spellings. Numbers are written in their shortest
/// round-trip form (`{}`), or in exponent form (`{:e}`) for the tab variant.
fn write_csv(d: &DataSpec, delimiter: &str, header: bool, exponent: bool) -> String {
    let q = d.y.first().map_or(0, Vec::len);
    let r = d.u.first().map_or(0, Vec::len);
    let mut columns: Vec<(char, usize)> = (0..q)
        .map(|i| ('y', i))
        .chain((0..r).map(|i| ('u', i)))
        .collect();
    // Comments and blank lines only before the header (after it every line is a row).
    let mut text = String::from("# written by tests/suite/csv.rs\n\n# a second comment\n");
    if header {
        columns.reverse();
        let names: Vec<String> = columns
            .iter()
            .enumerate()
            .map(|(k, &(kind, i))| name(kind, i + 1, k))
            .collect();
        text += &names.join(delimiter);
        text += "\r\n";
    }
    for t in 0..d.y.len() {
        let cells: Vec<String> = columns
            .iter()
            .map(|&(kind, i)| {
                let v = if kind == 'y' { d.y[t][i] } else { d.u[t][i] };
                if exponent {
                    format!("{v:e}")
                } else {
                    format!("{v}")
                }
            })
            .collect();
        text += &cells.join(delimiter);
        text += if header { "\r\n" } else { "\n" };
    }
    text
}

/// Every preset that simulates: (name, scenario, the same scenario on its measurements and
/// inputs as `data`, built directly).
fn simulating_presets() -> Vec<(String, Scenario, Scenario)> {
    presets::all()
        .into_iter()
        .filter(|p| p.scenario.simulate.is_some())
        .map(|p| {
            let s = p.scenario;
            let sim = s.run().unwrap_or_else(|e| panic!("{}: {e}", p.name));
            let mut u = inputs_used(&s, &report_value(&sim));
            // One input row is held constant: a CSV file repeats it on every row.
            if u.len() == 1 {
                u = vec![u[0].clone(); sim.y.len()];
            }
            assert!(
                u.is_empty() || u.len() == sim.y.len(),
                "{}: {} input rows for {} measurements",
                p.name,
                u.len(),
                sim.y.len()
            );
            let mut direct = s.clone();
            direct.simulate = None;
            direct.data = Some(DataSpec {
                y: sim.y,
                u,
                t: Vec::new(),
            });
            (p.name, s, direct)
        })
        .collect()
}

/// For every preset that simulates, every CSV variant reads back to exactly the directly built
/// `data`, and a run on it gives the report of the direct data (its JSON, exactly). The first
/// preset runs every variant, the others one each in turn (the test stays fast); the exact
/// scenario equality of every variant makes the runs not made the same run.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn every_simulating_preset_reads_its_data_back_from_csv() {
    let cases = simulating_presets();
    assert!(!cases.is_empty(), "no preset simulates");
    let mut ran = vec![0usize; 2 * DELIMITERS.len()];
    let mut skipped = Vec::new();
    let mut with_inputs = Vec::new();
    for (k, (name, s, direct)) in cases.iter().enumerate() {
        let data = direct.data.as_ref().expect("direct data");
        // The shape the method reads is the shape of its measurements and inputs.
        let (q, r) = s
            .data_shape()
            .unwrap_or_else(|e| panic!("{name}: data_shape: {e}"));
        assert!(
            data.y.iter().all(|row| row.len() == q),
            "{name}: data_shape gives q = {q}, the report's y has {:?} entries",
            data.y.first().map(Vec::len)
        );
        assert!(
            data.u.iter().all(|row| row.len() == r),
            "{name}: data_shape gives r = {r}, the inputs have {:?} entries",
            data.u.first().map(Vec::len)
        );
        if q == 0 {
            // No outputs (e.g. a Markov chain observed through nothing): a CSV row cannot be
            // empty, so the data are JSON only, and the parser says so.
            let e = s.with_csv_data("1\n").expect_err("no outputs");
            assert_eq!(e.field, "data", "{name}: {e}");
            assert!(e.message.contains("no outputs"), "{name}: {e}");
            skipped.push(name.clone());
            continue;
        }
        if r > 0 && !data.u.is_empty() {
            with_inputs.push(name.clone());
        }
        let want = report_value(
            &direct
                .run()
                .unwrap_or_else(|e| panic!("{name} on direct data: {e}")),
        );
        for (v, (header, (dname, delimiter))) in [false, true]
            .into_iter()
            .flat_map(|h| DELIMITERS.into_iter().map(move |d| (h, d)))
            .enumerate()
        {
            let label = format!(
                "{name}, {dname}, {}",
                if header { "header" } else { "no header" }
            );
            let text = write_csv(data, delimiter, header, dname == "tab");
            let read = s
                .with_csv_data(&text)
                .unwrap_or_else(|e| panic!("{label}: {e}\n{text}"));
            assert!(
                read == *direct,
                "{label}: the scenario read from CSV differs from the direct data"
            );
            if RUN_EVERY_VARIANT || k == 0 || v == k % ran.len() {
                let got = report_value(&read.run().unwrap_or_else(|e| panic!("{label}: {e}")));
                if let Some(d) = first_difference(&got, &want, "") {
                    panic!("{label}: the report differs from the direct data's at {d}");
                }
                assert_eq!(got, want, "{label}");
                ran[v] += 1;
            }
        }
    }
    assert!(
        ran.iter().all(|&n| n > 0),
        "every CSV variant runs at least once: {ran:?}"
    );
    assert!(!with_inputs.is_empty(), "no simulating preset has inputs");
    eprintln!(
        "CSV read back for {} simulating presets (with inputs: {with_inputs:?}; without outputs, so not as CSV: {skipped:?}); runs per variant {ran:?}",
        cases.len()
    );
}
in_browser!(every_simulating_preset_reads_its_data_back_from_csv);

fn error(s: &Scenario, text: &str) -> confset::Error {
    match s.with_csv_data(text) {
        Ok(_) => panic!("{text:?} was accepted"),
        Err(e) => e,
    }
}

/// A preset of `q` outputs and `r` inputs, found in the registry.
fn preset_of_shape(q: usize, r: usize) -> (String, Scenario) {
    presets::all()
        .into_iter()
        .find(|p| p.scenario.data_shape().ok() == Some((q, r)))
        .map(|p| (p.name, p.scenario))
        .unwrap_or_else(|| panic!("no preset has q = {q}, r = {r}"))
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn csv_errors_name_the_row_the_column_and_the_counts() {
    let (name, s) = presets::all()
        .into_iter()
        .filter_map(|p| Some((p.scenario.data_shape().ok()?, p)))
        .find(|((q, _), _)| *q >= 2)
        .map(|(_, p)| (p.name, p.scenario))
        .expect("a preset with two outputs");
    let (q, r) = s.data_shape().expect("shape");
    let row = |v: f64| vec![format!("{v}"); q].join(",");
    // Line 7 of the file (header on line 1, a blank line, a row of gaps, on line 3) holds the
    // bad cell in y2.
    let mut lines: Vec<String> = vec![(1..=q)
        .map(|i| format!("y{i}"))
        .collect::<Vec<_>>()
        .join(",")];
    lines.push(row(0.5));
    lines.push(String::new());
    for t in 0..3 {
        lines.push(row(t as f64));
    }
    let mut bad: Vec<String> = vec!["1".into(); q];
    bad[1] = "abc".into();
    lines.push(bad.join(","));
    lines.push(row(2.0));
    let e = error(&s, &lines.join("\n"));
    assert_eq!(e.field, "data.y", "{name}: {e}");
    assert_eq!(
        e.message, "row 7, column y2: 'abc' is not a number",
        "{name}"
    );

    // Too many columns: both counts named.
    let e = error(&s, &vec!["1"; q + r + 1].join(","));
    assert_eq!(e.field, "data", "{name}: {e}");
    assert!(
        e.message.starts_with(&format!(
            "row 1 has {} columns, but the model has q = {q} outputs",
            q + r + 1
        )),
        "{name}: {e}"
    );
    // Ragged rows.
    let e = error(&s, &format!("{}\n{}\n1\n", row(1.0), row(2.0)));
    assert_eq!(
        (e.field.as_str(), e.message.as_str()),
        (
            "data",
            format!("row 3 has 1 column, row 1 has {q}").as_str()
        ),
        "{name}"
    );
    // An unknown header name.
    let e = error(&s, &format!("y1,flow\n{}\n", row(1.0)));
    assert_eq!(e.field, "data");
    assert!(
        e.message
            .starts_with("header (row 1), column 2: 'flow' is not a column name"),
        "{name}: {e}"
    );
    // Empty text.
    for text in ["", "\n \n", "# nothing but comments\n"] {
        let e = error(&s, text);
        assert_eq!(e.field, "data");
        assert!(e.message.starts_with("is empty"), "{name}: {e}");
    }

    // The row limit, checked before any cell is read (the last row is not a number).
    let (name, one) = preset_of_shape(1, 0);
    let text = format!("{}x\n", "1\n".repeat(MAX_CSV_ROWS));
    let e = error(&one, &text);
    assert_eq!(
        (e.field.as_str(), e.message.as_str()),
        (
            "data",
            format!("has {} rows, at most {MAX_CSV_ROWS}", MAX_CSV_ROWS + 1).as_str()
        ),
        "{name}"
    );
    // At the limit the rows are read; the method's own step limit then decides.
    let at_limit = one
        .with_csv_data(&"1\n".repeat(MAX_CSV_ROWS))
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    assert_eq!(
        at_limit.data.as_ref().map(|d| d.y.len()),
        Some(MAX_CSV_ROWS)
    );
    assert!(at_limit.simulate.is_none());
    let e = at_limit
        .run()
        .expect_err("more steps than any method takes");
    assert_eq!(e.field, "data.y", "{name}: {e}");
    // The byte limit.
    let e = error(&one, &" ".repeat(MAX_CSV_BYTES + 1));
    assert_eq!(e.field, "data");
    assert!(
        e.message.starts_with(&format!(
            "is {} bytes of text, at most {MAX_CSV_BYTES}",
            MAX_CSV_BYTES + 1
        )),
        "{e}"
    );
}
in_browser!(csv_errors_name_the_row_the_column_and_the_counts);

/// `confset run --preset NAME --data FILE.csv` prints the report of the core's
/// `with_csv_file` (titled after the file), for the first simulating preset with inputs (or any, if none has them).
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn cli_run_with_data_prints_the_core_report() {
    let cases = simulating_presets();
    let (name, s, direct) = cases
        .iter()
        .find(|(_, _, d)| d.data.as_ref().is_some_and(|d| !d.u.is_empty()))
        .or(cases.first())
        .expect("a simulating preset");
    let data = direct.data.as_ref().expect("data");
    let path = std::env::temp_dir().join(format!("confset-csv-{}-{name}.csv", std::process::id()));
    std::fs::write(&path, write_csv(data, ";", true, false)).expect("write the CSV file");
    let path_text = path.to_string_lossy().to_string();
    let got = crate::registry::cli(&["run", "--preset", name, "--data", &path_text]);
    let _ = std::fs::remove_file(&path);
    let file = path.file_name().unwrap().to_string_lossy().to_string();
    let want = report_value(
        &s.with_csv_file(&write_csv(data, ";", true, false), &file)
            .and_then(|s| s.run())
            .unwrap_or_else(|e| panic!("{name}: {e}")),
    );
    if let Some(d) = first_difference(&got, &want, "") {
        panic!("confset run --preset {name} --data: differs from the core at {d}");
    }
    // The figures' title names the file, not the preset's paper figure (issue 29).
    assert_eq!(
        got["figure"]["title"],
        serde_json::json!(format!("measured data: {file}")),
        "{name}"
    );
}
