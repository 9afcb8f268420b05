//! The limits on what comes in and what a figure lays out (issue 25): one bounded read of
//! every input file, one number range for JSON and CSV, list and text limits checked on the
//! JSON, user text cut and made XML-safe before layout, a pixel budget for PNG, and a study's
//! progress that moves whatever its number of runs.

use confset::error::DISPLAY_CHARS;
use confset::plot::{self, MAX_PNG_PIXELS};
use confset::scenario::{Scenario, LIST_LIMITS, MAX_SCENARIO_BYTES, MAX_TEXT_CHARS};
use confset::{presets, study};
use serde_json::{json, Value};

fn preset(name: &str) -> Value {
    serde_json::to_value(presets::get(name).expect("preset")).expect("preset as JSON")
}

fn refused(v: &Value) -> confset::Error {
    match Scenario::from_json(&v.to_string()).and_then(|s| s.run()) {
        Ok(_) => panic!("accepted: {}", confset::error::cut(&v.to_string(), 300)),
        Err(e) => e,
    }
}

/// `v` is refused with an error on `field` whose message says each of `says`.
fn refused_saying(v: &Value, field: &str, says: &[&str]) {
    let e = refused(v);
    assert_eq!(e.field, field, "{e}");
    assert!(says.iter().all(|w| e.message.contains(w)), "{e}");
}

/// Whether `svg` is XML 1.0's character set: no control character but tab, line feed and
/// carriage return, and not U+FFFE or U+FFFF.
fn xml_chars_only(svg: &str) -> bool {
    svg.chars().all(|c| {
        !(c.is_control() && !matches!(c, '\t' | '\n' | '\r')) && c != '\u{FFFE}' && c != '\u{FFFF}'
    })
}

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_title_with_nul_and_controls_gives_well_formed_svg() {
    let mut v = preset("scf-scalar");
    v["title"] = json!("A\u{0}B\u{1}C\u{7}D\u{1b}[31mE\u{7f}F\u{9f}G\u{FFFF} <&> \"x\"\tH\nI");
    let s = Scenario::from_json(&v.to_string()).expect("a title with controls is accepted");
    let svg = plot::scenario_svg(&s, 640, 400).expect("its figure");
    assert!(xml_chars_only(&svg), "the SVG holds a control character");
    assert!(
        svg.contains("ABCD[31mEFG &lt;&amp;&gt;"),
        "the title is shown, escaped"
    );
    // A real XML parser (resvg's) reads it: well-formed.
    #[cfg(not(target_arch = "wasm32"))]
    resvg::usvg::Tree::from_str(&svg, &resvg::usvg::Options::default())
        .expect("the SVG is well-formed XML");
}
in_browser!(a_title_with_nul_and_controls_gives_well_formed_svg);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_long_title_is_cut_before_layout() {
    let mut v = preset("scf-scalar");
    // The longest title accepted: laid out, only its first DISPLAY_CHARS characters are.
    v["title"] = json!("Q".repeat(MAX_TEXT_CHARS));
    let s = Scenario::from_json(&v.to_string()).expect("a title at the limit is accepted");
    let report = s.run().expect("report");
    let title = report.figure.title.as_deref().expect("the report's title");
    assert_eq!(title, format!("{}…", "Q".repeat(DISPLAY_CHARS)));
    let svg = plot::scenario_svg(&s, 640, 400).expect("its figure");
    assert!(
        svg.contains(&format!("{}…", "Q".repeat(DISPLAY_CHARS))),
        "cut with …"
    );
    assert!(
        !svg.contains(&"Q".repeat(DISPLAY_CHARS + 1)),
        "never laid out whole"
    );
    assert!(svg.len() < 100_000, "the SVG is {} bytes", svg.len());
    // The PNG lays out the same cut title (10⁶ characters took 9 min 49 s whole).
    #[cfg(not(target_arch = "wasm32"))]
    plot::svg_to_png(&svg, 1.0).expect("its PNG");
}
in_browser!(a_long_title_is_cut_before_layout);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn text_fields_over_the_limit_are_refused_naming_the_field() {
    let mut v = preset("scf-scalar");
    v["title"] = json!("t".repeat(1_000_000));
    refused_saying(&v, "title", &["1000000 characters", "10000"]);
    let mut v = preset("scf-scalar");
    v["notes"] = json!("é".repeat(MAX_TEXT_CHARS + 1));
    assert_eq!(refused(&v).field, "notes");
    // Characters, not bytes: 10,000 two-byte characters are within the limit.
    let mut v = preset("scf-scalar");
    v["notes"] = json!("é".repeat(MAX_TEXT_CHARS));
    Scenario::from_json(&v.to_string()).expect("10,000 characters are accepted");
}
in_browser!(text_fields_over_the_limit_are_refused_naming_the_field);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn compare_keeps_a_cut_title_in_its_derived_scenarios() {
    let mut v = preset("compare-gaussian");
    v["title"] = json!("Z".repeat(MAX_TEXT_CHARS));
    if let Some(c) = v.get_mut("compare").and_then(Value::as_object_mut) {
        c.remove("study");
    }
    let report = Scenario::from_json(&v.to_string())
        .and_then(|s| s.run())
        .expect("compare report");
    let text = serde_json::to_string(&report).expect("JSON");
    assert!(
        !text.contains(&"Z".repeat(DISPLAY_CHARS + 1)),
        "a title is copied whole into the report"
    );
}
in_browser!(compare_keeps_a_cut_title_in_its_derived_scenarios);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn lists_over_their_limits_are_refused_before_reading() {
    let limit = |path: &str| {
        LIST_LIMITS
            .iter()
            .find(|(p, _)| *p == path)
            .expect("listed")
            .1
    };
    let mut v = preset("lscr-predict");
    v["lscr"]["probes"] = json!(vec![[0.0, 0.0]; limit("lscr.probes") + 1]);
    refused_saying(&v, "lscr.probes", &["10001 entries", "10000"]);
    let mut v = preset("uniform-paper");
    let o = json!({"matrix": "A", "row": 0, "col": 0, "lo": -1.0, "hi": 1.0});
    v["uniform"]["prior_overrides"] = json!(vec![o; limit("uniform.prior_overrides") + 1]);
    assert_eq!(refused(&v).field, "uniform.prior_overrides");
}
in_browser!(lists_over_their_limits_are_refused_before_reading);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn input_rows_past_the_last_step_used_are_refused() {
    let mut v = preset("ubb-leontief");
    let steps = v["simulate"]["steps"].as_u64().expect("steps") as usize;
    let row = v["simulate"]["u"][0].clone();
    // One row per step is what the run uses: accepted.
    v["simulate"]["u"] = json!(vec![row.clone(); steps]);
    Scenario::from_json(&v.to_string())
        .and_then(|s| s.run())
        .expect("one input row per step");
    // One more is never read: refused, as data.u is.
    v["simulate"]["u"] = json!(vec![row; steps + 1]);
    refused_saying(&v, "simulate.u", &[&format!("at most {steps} rows")]);
}
in_browser!(input_rows_past_the_last_step_used_are_refused);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn csv_numbers_have_the_json_range() {
    for (cell, ok) in [
        ("1e308", false),
        ("-1e101", false),
        ("1e-101", false),
        ("5e-324", false),
        ("1e100", true),
        ("-1e-100", true),
        ("0", true),
    ] {
        let text = format!("y1\n0.5\n{cell}\n");
        match confset::scenario::data_from_csv(&text, 1, 0) {
            Ok(d) => assert!(ok, "{cell} accepted: {:?}", d.y),
            Err(e) => {
                assert!(!ok, "{cell} refused: {e}");
                assert_eq!(e.field, "data.y", "{e}");
                assert!(
                    e.message.contains("row 3, column y1") && e.message.contains("1e100"),
                    "{e}"
                );
            }
        }
        // The same number in the JSON's data.y gets the same verdict.
        let mut v = preset("scf-scalar");
        v.as_object_mut().expect("object").remove("simulate");
        v["data"] = json!({"y": [[0.5], [cell.parse::<f64>().expect("a number")]]});
        let json_ok = Scenario::from_json(&v.to_string()).is_ok();
        assert_eq!(json_ok, ok, "{cell}: JSON and CSV disagree");
    }
}
in_browser!(csv_numbers_have_the_json_range);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_scenario_text_over_the_limit_is_refused() {
    let text = format!("{{{}}}", " ".repeat(MAX_SCENARIO_BYTES - 1));
    let e = Scenario::from_json(&text).expect_err("over the limit");
    assert!(e.message.contains("at most 20000000 bytes"), "{e}");
}
in_browser!(a_scenario_text_over_the_limit_is_refused);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn png_pixels_are_budgeted_on_size_times_scale() {
    assert_eq!(MAX_PNG_PIXELS, 8192 * 8192);
    plot::check_png_pixels(8192, 8192, 1.0).expect("8192² at scale 1");
    plot::check_png_pixels(4096, 4096, 2.0).expect("4096² at scale 2");
    for (w, h, scale) in [(8192, 8192, 8.0), (8192, 8192, 1.01), (4096, 4096, 2.01)] {
        let e = plot::check_png_pixels(w, h, scale).expect_err("over the budget");
        assert_eq!(e.field, "scale", "{e}");
        assert!(e.message.contains(&MAX_PNG_PIXELS.to_string()), "{e}");
    }
}
in_browser!(png_pixels_are_budgeted_on_size_times_scale);

#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_small_study_reports_progress_in_many_steps() {
    // Compare's default study has 200 runs: in chunks of 1,000 its bar moved once, at the end.
    for total in [1, 7, 200, 2_000, 100_000, 10_000_000] {
        let chunk = study::progress_chunk(total);
        let steps = total.div_ceil(chunk);
        assert!(
            steps >= total.min(study::PROGRESS_STEPS),
            "{total}: {steps} steps"
        );
        assert!(chunk <= study::MAX_CHUNK);
    }
    let s = presets::get("scf-robots").expect("preset");
    let total = s.study(Some(400)).expect("study").total();
    let ticks = std::sync::atomic::AtomicUsize::new(0);
    let runs = std::sync::atomic::AtomicUsize::new(0);
    study::run_sharded(&|| s.study(Some(400)), study::progress_chunk(total), &|k| {
        ticks.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        runs.fetch_add(k, std::sync::atomic::Ordering::Relaxed);
    })
    .expect("study");
    assert_eq!(runs.into_inner(), total);
    // Batches of 8 runs (SCF) round chunks up: still dozens of moves.
    assert!(ticks.into_inner() >= 40);
}
in_browser!(a_small_study_reports_progress_in_many_steps);

/// The command line's reads: one bounded reader for the scenario, `--data` and merge parts.
#[cfg(not(target_arch = "wasm32"))]
mod cli {
    use crate::cli::{confset, spawn};
    use std::io::Write;

    fn stderr(o: &std::process::Output) -> String {
        String::from_utf8_lossy(&o.stderr).into_owned()
    }

    /// A sparse file of `bytes` bytes (no disk written): larger than a limit, cheaply.
    fn sparse(dir: &std::path::Path, name: &str, bytes: u64) -> String {
        let path = dir.join(name);
        std::fs::File::create(&path)
            .and_then(|f| f.set_len(bytes))
            .expect("sparse file");
        path.display().to_string()
    }

    fn temp_dir(name: &str) -> std::path::PathBuf {
        let dir =
            std::env::temp_dir().join(format!("confset-limits-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        dir
    }

    #[test]
    fn oversize_files_are_refused_naming_the_file_and_the_limit() {
        let dir = temp_dir("files");
        let scenario = sparse(&dir, "big.json", 20_000_001);
        let o = confset(&["run", &scenario], None);
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.contains(&scenario) && e.contains("larger than 20000000 bytes"),
            "{e}"
        );

        let csv = sparse(&dir, "big.csv", 20_000_001);
        let o = confset(&["run", "--preset", "scf-scalar", "--data", &csv], None);
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        let e = stderr(&o);
        assert!(e.starts_with("error: --data") && e.contains(&csv), "{e}");
        assert!(e.contains("larger than 20000000 bytes"), "{e}");

        // A part is bounded too (about 666 MB: the largest a study's part can be).
        let part = sparse(&dir, "part.json", 2_000_000_000);
        let o = confset(&["merge", &part], None);
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        let e = stderr(&o);
        assert!(e.contains(&part) && e.contains("larger than"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }

    /// An endless input on a pipe (as `/dev/zero` is) is read to the limit and one byte more,
    /// then refused: the writer is stopped by the closed pipe, so the test is bounded.
    #[test]
    fn an_endless_scenario_on_stdin_is_read_only_to_the_limit() {
        let mut c = spawn(&["run", "-"]);
        let mut input = c.stdin.take().expect("stdin");
        let writer = std::thread::spawn(move || {
            let block = vec![b' '; 1 << 16];
            let mut written = 0usize;
            // At most 4× the limit: the reader stops long before, or the test fails below.
            while written < 80_000_000 {
                if input.write_all(&block).is_err() {
                    break;
                }
                written += block.len();
            }
            written
        });
        let o = c.wait_with_output().expect("confset finishes");
        let written = writer.join().expect("writer");
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.contains("standard input is larger than 20000000 bytes"),
            "{e}"
        );
        assert!(written < 80_000_000, "the whole endless input was read");
    }

    #[test]
    fn a_png_over_the_pixel_budget_is_refused_before_drawing() {
        let dir = temp_dir("png");
        let out = dir.join("f.png").display().to_string();
        let o = confset(
            &[
                "figure",
                "--preset",
                "scf-scalar",
                "--size",
                "8192x8192",
                "--scale",
                "8",
                "-o",
                &out,
            ],
            None,
        );
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.starts_with("error: --scale is 8") && e.contains("--size 8192x8192"),
            "{e}"
        );
        assert!(e.contains("67108864"), "{e}");
        assert!(!std::path::Path::new(&out).exists());
        std::fs::remove_dir_all(&dir).ok();
    }
}
