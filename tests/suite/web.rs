//! The wasm bindings in a real browser (`wasm-pack test --headless --chrome`): presets, a
//! Session running and drawing a preset, errors thrown as JS Errors naming the field, a
//! chunk of the conditional Monte Carlo; LSCR: a preset's level, the membership raster and the
//! chunked coverage experiment; CSV data (`withCsvData`, `dataShape`) as the core reads it; the
//! figure list the page makes its cards from (`methodPanels`, `Session.usefulPanels`); a study
//! split over workers (`restrict`, `partial`) and merged on the main thread (`merge`).

use confset::web::{
    csv_columns, data_shape, method_panels, presets, with_csv_data, Cursor, Session, Study,
};
use serde_json::Value;
use wasm_bindgen::{JsCast, JsValue};

fn preset(name: &str) -> Value {
    let list: Value = serde_json::from_str(&presets().expect("presets")).expect("preset JSON");
    list.as_array()
        .expect("a list")
        .iter()
        .find(|p| p["name"] == name)
        .unwrap_or_else(|| panic!("preset {name}"))["scenario"]
        .clone()
}

/// (message, field) of a thrown JS Error.
fn thrown(e: JsValue) -> (String, String) {
    let field = js_sys::Reflect::get(&e, &JsValue::from_str("field"))
        .ok()
        .and_then(|f| f.as_string())
        .unwrap_or_default();
    let err: js_sys::Error = e.dyn_into().expect("a JS Error is thrown");
    (String::from(err.message()), field)
}

fn canvas(w: u32, h: u32) -> web_sys::HtmlCanvasElement {
    let doc = web_sys::window()
        .expect("window")
        .document()
        .expect("document");
    let c: web_sys::HtmlCanvasElement = doc
        .create_element("canvas")
        .expect("canvas")
        .dyn_into()
        .expect("a canvas element");
    c.set_width(w);
    c.set_height(h);
    c
}

fn presets_are_listed() {
    let list: Value = serde_json::from_str(&presets().expect("presets")).expect("JSON");
    let names: Vec<&str> = list
        .as_array()
        .expect("list")
        .iter()
        .map(|p| p["name"].as_str().expect("name"))
        .collect();
    for n in ["scf-scalar", "scf-robots", "scf-robots-literal"] {
        assert!(names.contains(&n), "{n} missing from {names:?}");
    }
}
in_browser!(presets_are_listed);

fn session_runs_a_preset_and_keeps_it_on_error() {
    let mut s = Session::new();
    assert!(!s.has_report());
    let scalar = preset("scf-scalar");
    let report: Value =
        serde_json::from_str(&s.run(&scalar.to_string()).expect("the scalar preset runs"))
            .expect("report JSON");
    assert_eq!(report["steps"].as_array().expect("steps").len(), 50);
    let ratio = report["asymptotic"]["ratio"][0][0].as_f64().expect("ratio");
    assert!((ratio - 0.9).abs() < 1e-9, "asymptotic ratio {ratio}");
    assert!(report["coverage_curve"].is_object());

    // A non-symmetric V: thrown as an Error naming model.V; the last report stays.
    let mut bad = scalar.clone();
    bad["model"]["F"] = serde_json::json!([[0.5, 0.0], [0.0, 0.5]]);
    bad["model"]["H"] = serde_json::json!([[1.0, 0.0]]);
    bad["model"]["V"] = serde_json::json!([[1.0, 2.0], [0.0, 1.0]]);
    let (msg, field) = thrown(
        s.run(&bad.to_string())
            .expect_err("non-symmetric V is refused"),
    );
    assert!(msg.starts_with("model.V "), "message: {msg}");
    assert!(msg.contains("symmetric"), "message: {msg}");
    assert_eq!(field, "model.V");
    assert!(s.has_report(), "the last good report is kept");

    // Not JSON at all, and an unknown view.
    let (msg, field) = thrown(s.run("{").expect_err("bad JSON is refused"));
    assert_eq!(field, "scenario", "{msg}");
    let (msg, field) = thrown(
        s.svg(r#"{"panel": "nope"}"#, 400, 300)
            .expect_err("unknown panel is refused"),
    );
    assert_eq!(field, "view.panel", "{msg}");
    let (_, field) = thrown(s.svg("{}", 0, 300).expect_err("zero width is refused"));
    assert_eq!(field, "size");
}
in_browser!(session_runs_a_preset_and_keeps_it_on_error);

/// The first preset of each method (its `method`, "scf" when unnamed), in the list's order.
fn first_preset_of_each_method() -> Vec<(String, Value)> {
    let list: Value = serde_json::from_str(&presets().expect("presets")).expect("preset JSON");
    let mut firsts: Vec<(String, Value)> = Vec::new();
    for p in list.as_array().expect("a list") {
        let method = p["scenario"]["method"].as_str().unwrap_or("scf");
        if !firsts.iter().any(|(m, _)| m == method) {
            firsts.push((method.to_string(), p.clone()));
        }
    }
    firsts
}

/// Steps a study to its end: a first chunk of `first` runs (its counts say so), then chunks of
/// `then`, in fewer than `max_chunks` chunks; returns the counts after the last.
fn step_to_end(study: &mut Study, first: u32, then: u32, max_chunks: usize, what: &str) -> Value {
    let counts: Value = serde_json::from_str(&study.step(first).expect("step")).expect("JSON");
    assert_eq!(counts["runs"], first);
    let mut last = counts;
    let mut chunks = 1;
    while !study.finished() {
        last = serde_json::from_str(&study.step(then).expect("step")).expect("JSON");
        chunks += 1;
        assert!(chunks < max_chunks, "the {what} does not finish");
    }
    last
}

/// The page's compute worker runs a scenario and the main thread draws its report: a Session
/// given the report's JSON (`setReport`) draws what the Session that ran it draws, for the first
/// preset of every method; JSON that is not a report is a `report` error and the kept one stays.
fn a_report_set_from_json_draws_as_the_run_one() {
    let firsts = first_preset_of_each_method();
    let methods: Vec<&String> = firsts.iter().map(|(m, _)| m).collect();
    for (method, p) in &firsts {
        let mut ran = Session::new();
        let json = ran
            .run(&p["scenario"].to_string())
            .expect("the preset runs");
        let mut drawn = Session::new();
        drawn.set_report(&json).expect("the report is read back");
        assert_eq!(drawn.useful_panels(), ran.useful_panels(), "{method}");
        let useful: Vec<String> = serde_json::from_str(&ran.useful_panels()).expect("names");
        // The page's full-width figure size. In wasm the SVG backend measures text with the
        // browser's fonts: at 640 × 480 (no page size) Firefox's wider sans-serif leaves the
        // stacked charts of uniform-paper's output figure no room, a size error in both sessions.
        let (w, h) = (960, 640);
        for panel in useful {
            let view = serde_json::json!({ "panel": panel }).to_string();
            assert_eq!(
                drawn.svg(&view, w, h).expect("svg of the set report"),
                ran.svg(&view, w, h).expect("svg of the run report"),
                "{method}: the {panel} figure"
            );
        }
        let (msg, field) = thrown(
            drawn
                .set_report(r#"{"steps": 3}"#)
                .expect_err("not a report"),
        );
        assert_eq!(field, "report", "{msg}");
        assert!(msg.starts_with("report is not a valid report"), "{msg}");
        assert!(drawn.has_report(), "the kept report stays");
    }
    assert!(methods.len() >= 5, "every method: {methods:?}");
}
in_browser!(a_report_set_from_json_draws_as_the_run_one);

/// The worker's time cursor and the page's `setAt`: for the first preset of every method, a
/// `Cursor` exists exactly when the report keeps an `at`; its detail at another step, set into
/// the kept report, draws every figure as the report run at that step does; a detail of
/// another shape is an `at` error and the kept report stays.
fn a_cursor_detail_set_into_the_report_draws_as_a_run_at_that_step() {
    let mut with_cursor = 0;
    let firsts = first_preset_of_each_method();
    let methods: Vec<&String> = firsts.iter().map(|(m, _)| m).collect();
    for (method, p) in &firsts {
        let mut kept = Session::new();
        let report: Value =
            serde_json::from_str(&kept.run(&p["scenario"].to_string()).expect("runs"))
                .expect("report JSON");
        let block = ["ubb", "uniform", "compare"]
            .into_iter()
            .find(|b| report[*b]["at"].is_object());
        let cursor = Cursor::new(&p["scenario"].to_string());
        let (Some(block), Ok(mut cursor)) = (block, cursor) else {
            assert!(
                block.is_none(),
                "{method}: a report with an `at` has a cursor"
            );
            let (msg, field) = thrown(
                Cursor::new(&p["scenario"].to_string())
                    .err()
                    .expect("no cursor"),
            );
            assert_eq!(field, "method", "{msg}");
            continue;
        };
        with_cursor += 1;
        let t = cursor.first() as u32;
        let mut at_t = p["scenario"].clone();
        at_t[block]["time"] = serde_json::json!(t);
        let mut ran = Session::new();
        let want: Value = serde_json::from_str(&ran.run(&at_t.to_string()).expect("runs at t"))
            .expect("report JSON");
        let at = cursor.at(t).expect("the detail at t");
        assert_eq!(
            serde_json::from_str::<Value>(&at).expect("JSON"),
            want[block]["at"],
            "{method}"
        );
        kept.set_at(&at).expect("the detail is set");
        assert_eq!(kept.shown_time(), ran.shown_time(), "{method}");
        let useful: Vec<String> = serde_json::from_str(&ran.useful_panels()).expect("names");
        for panel in useful {
            let view = serde_json::json!({ "panel": panel, "time": t }).to_string();
            // The page's full-width size: at 640 × 480 Firefox's wider text leaves the uniform
            // output figure no room (as in the set-report test above).
            assert_eq!(
                kept.svg(&view, 960, 640).expect("svg with the detail set"),
                ran.svg(&view, 960, 640).expect("svg of the run at t"),
                "{method}: the {panel} figure at {t}"
            );
        }
        let (msg, field) = thrown(kept.set_at(r#"{"k": "no"}"#).expect_err("not a detail"));
        assert_eq!(field, "at", "{msg}");
        assert_eq!(kept.shown_time(), Some(t as usize), "the kept report stays");
    }
    assert_eq!(
        with_cursor, 3,
        "ubb, uniform_lp and compare have a cursor: {methods:?}"
    );
}
in_browser!(a_cursor_detail_set_into_the_report_draws_as_a_run_at_that_step);

fn session_draws_on_a_canvas_and_as_svg() {
    let mut s = Session::new();
    let robots = preset("scf-robots");
    s.run(&robots.to_string()).expect("the robot preset runs");
    for panel in ["state", "series"] {
        let view = format!(r#"{{"panel": "{panel}", "time": 36}}"#);
        // Backing store 2× the CSS size (devicePixelRatio 2): the frame is in CSS pixels.
        let frame: Value = serde_json::from_str(
            &s.draw(canvas(1200, 800), &view, 2.0)
                .unwrap_or_else(|e| panic!("draw {panel}: {:?}", thrown(e))),
        )
        .expect("frame JSON");
        let area: Vec<f64> = frame["plot_area"]
            .as_array()
            .expect("plot_area")
            .iter()
            .map(|v| v.as_f64().expect("number"))
            .collect();
        assert!(
            area[0] >= 0.0 && area[2] <= 600.0 && area[1] >= 0.0 && area[3] <= 400.0,
            "{panel}: plot area {area:?} is not inside the 600×400 CSS box"
        );
        // The axis names come with the report: the robot's position, as in `confset figure`.
        let x_label = frame["x_label"].as_str().expect("x_label");
        if panel == "state" {
            assert!(
                x_label.starts_with("position p_x"),
                "{panel}: x axis \"{x_label}\""
            );
        }
        let svg = s.svg(&view, 600, 400).expect("svg");
        assert!(svg.contains("<svg"), "{panel}: not SVG");
        assert!(
            svg.contains("position p_"),
            "{panel}: no robot position axis in the SVG"
        );
    }
}
in_browser!(session_draws_on_a_canvas_and_as_svg);

/// `Session.csv` is the kept report's table: the text `confset run --format csv` prints for the
/// scenario (`Report::table` → `to_csv`), for the first preset of each method; none before a run.
fn session_csv_is_the_reports_table() {
    let s = Session::new();
    let (msg, _) = thrown(s.csv().expect_err("no report yet"));
    assert!(msg.contains("no report yet"), "{msg}");
    for (method, p) in first_preset_of_each_method() {
        let json = p["scenario"].to_string();
        let mut s = Session::new();
        s.run(&json)
            .unwrap_or_else(|e| panic!("{method}: {:?}", thrown(e)));
        let want = confset::scenario::Scenario::from_json(&json)
            .and_then(|sc| sc.run())
            .and_then(|r| r.table())
            .unwrap_or_else(|e| panic!("{method}: {e}"))
            .to_csv();
        let got = s
            .csv()
            .unwrap_or_else(|e| panic!("{method} csv: {:?}", thrown(e)));
        assert_eq!(got, want, "{method}: Session.csv is not the report's table");
        assert!(
            got.lines().count() >= 2,
            "{method}: a header and no rows:\n{got}"
        );
    }
}
in_browser!(session_csv_is_the_reports_table);

fn experiment_runs_in_chunks() {
    let mut robots = preset("scf-robots");
    robots["experiment"]["runs"] = serde_json::json!(300);
    let mut e = Study::new(&robots.to_string(), 0).expect("experiment");
    assert!(!e.finished());
    // Chunks are whole batches of 8 runs (so counts do not depend on the chunking).
    let first: Value = serde_json::from_str(&e.step(96).expect("step")).expect("counts");
    assert_eq!(first["runs_done"], 96);
    while !e.finished() {
        e.step(128).expect("step");
    }
    let c: Value = serde_json::from_str(&e.result().expect("counts")).expect("counts");
    assert_eq!(c["runs_done"], 300);
    let scf = c["scf_inside"].as_u64().expect("scf_inside");
    let kf = c["kf_inside"].as_u64().expect("kf_inside");
    // At α = 0.95 SCF covers the colliding state about 285 times in 300; KF almost never.
    assert!(scf >= 260, "SCF inside {scf}/300");
    assert!(kf <= 30, "KF inside {kf}/300");
    assert!(c["scf_warnings"].as_u64().expect("warnings") >= 250);

    // The scalar preset has no experiment block: a thrown error naming it.
    let (msg, field) = thrown(
        Study::new(&preset("scf-scalar").to_string(), 0)
            .err()
            .expect("no experiment in the scalar preset"),
    );
    assert_eq!(field, "experiment", "{msg}");
}
in_browser!(experiment_runs_in_chunks);

fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

fn lscr_session_runs_the_fig1_preset() {
    let mut s = Session::new();
    let report: Value = serde_json::from_str(
        &s.run(&preset("lscr-predict").to_string())
            .unwrap_or_else(|e| panic!("lscr-predict runs: {:?}", thrown(e))),
    )
    .expect("report JSON");
    let l = &report["lscr"];
    assert!(
        (num(&l["level"]) - 0.9).abs() < 1e-12,
        "joint level {}",
        l["level"]
    );
    assert!(
        (num(&l["level_each"]) - 0.95).abs() < 1e-12,
        "level per X̂_l {}",
        l["level_each"]
    );
    assert_eq!(l["M"], 80);
    assert_eq!(l["q"], 2);
    assert_eq!(l["time"], 31);
    assert_eq!(l["guaranteed"], true);
    assert_eq!(l["bounded"], true);
    assert!(num(&l["area"]) > 0.0);
    // The backward representation of Section V-A, to the printed digits.
    let fb = [[0.2450, 0.3315], [-0.3500, 0.9550]];
    for (i, row) in fb.iter().enumerate() {
        for (j, v) in row.iter().enumerate() {
            assert!(
                (num(&l["f_b"][i][j]) - v).abs() < 5e-5,
                "F^b[{i}][{j}] = {}",
                l["f_b"][i][j]
            );
        }
    }
}
in_browser!(lscr_session_runs_the_fig1_preset);

fn lscr_raster_of_the_kept_region() {
    let mut s = Session::new();
    let (_, field) = thrown(s.raster(64, 48).expect_err("no report yet"));
    assert_eq!(field, "");
    s.run(&preset("scf-scalar").to_string())
        .expect("scalar preset");
    let (msg, field) = thrown(
        s.raster(64, 48)
            .expect_err("an SCF report has no LSCR region"),
    );
    assert_eq!(field, "method", "{msg}");

    s.run(&preset("lscr-predict").to_string())
        .expect("lscr-predict");
    let r = s.raster(64, 48).expect("raster");
    assert_eq!(r.len(), 64 * 48);
    let inside = r.iter().filter(|&&e| e == 0).count();
    assert!(
        inside > 0 && inside < r.len(),
        "{inside} of {} pixels inside",
        r.len()
    );
    // Only bits of the two groups X̂_1, X̂_2 are used.
    assert!(r.iter().all(|&e| e & !0b11 == 0));
    assert!(
        r.iter().any(|&e| e == 1) && r.iter().any(|&e| e == 2),
        "both X̂_1 and X̂_2 exclude somewhere"
    );
    // The fitted window holds the whole bounded region: its border pixels are outside.
    assert!((0..64).all(|j| r[j] != 0 && r[47 * 64 + j] != 0));

    let big = s.raster(512, 512).expect("512²");
    assert_eq!(big.len(), 512 * 512);
    let (_, field) = thrown(s.raster(0, 10).expect_err("zero width"));
    assert_eq!(field, "size");
    let (_, field) = thrown(s.raster(10, 5000).expect_err("too tall"));
    assert_eq!(field, "size");

    // The MA(1) band: unbounded, so inside pixels reach the window's border.
    s.run(&preset("lscr-ma1").to_string()).expect("lscr-ma1");
    let r = s.raster(100, 100).expect("raster");
    let inside = r.iter().filter(|&&e| e == 0).count();
    assert!(inside > 0 && inside < r.len());
    let border = (0..100)
        .any(|k| r[k] == 0 || r[99 * 100 + k] == 0 || r[k * 100] == 0 || r[k * 100 + 99] == 0);
    assert!(border, "the band crosses the window's border");
}
in_browser!(lscr_raster_of_the_kept_region);

fn lscr_experiment_steps_to_completion() {
    let mut sc = preset("lscr-predict");
    sc["simulate"]["condition"] = serde_json::json!({"t": 31, "x": [0.1, 0.2]});
    sc["lscr"]["coverage"] = serde_json::json!({"runs": 300, "seed": 4});
    let mut e = Study::new(&sc.to_string(), 0)
        .unwrap_or_else(|err| panic!("experiment: {:?}", thrown(err)));
    assert_eq!(e.total(), 300);
    assert!(!e.finished());
    let last = step_to_end(&mut e, 100, 64, 100, "experiment");
    assert_eq!(last["runs"], 300);
    assert_eq!(
        serde_json::from_str::<Value>(&e.result().expect("counts")).expect("JSON"),
        last
    );
    assert!((num(&last["level_each"]) - 0.95).abs() < 1e-12);
    assert!((num(&last["level"]) - 0.9).abs() < 1e-12);
    assert_eq!(last["truth"], serde_json::json!([0.1, 0.2]));
    let band_each = [num(&last["band_each"][0]), num(&last["band_each"][1])];
    let band = [num(&last["band"][0]), num(&last["band"][1])];
    assert!(
        band_each[0] < 0.95 * 300.0 && band_each[1] > 0.95 * 300.0 && band_each[1] <= 300.0,
        "{band_each:?}"
    );
    assert!(band[0] < 0.9 * 300.0 && band[1] > 0.9 * 300.0, "{band:?}");
    let each: Vec<f64> = last["inside_each"]
        .as_array()
        .expect("inside_each")
        .iter()
        .map(num)
        .collect();
    assert_eq!(each.len(), 2);
    for (l, c) in each.iter().enumerate() {
        assert!(
            *c >= band_each[0] && *c <= band_each[1],
            "X̂_{} holds the truth {c} times of 300, band {band_each:?}",
            l + 1
        );
    }
    let joint = num(&last["inside"]);
    assert!(
        joint <= each[0].min(each[1]) && joint >= band[0],
        "X̂ {joint} of 300, band {band:?}"
    );
    for k in ["blue", "kf"] {
        let c = num(&last[k]);
        assert!((0.0..=300.0).contains(&c), "{k}: {c}");
        // A typical true state: both ellipses hold it most of the time.
        assert!(c >= 200.0, "{k}: {c} of 300");
    }

    // Without a fixed true state, or without the coverage block: errors naming the field.
    let no_condition: fn(&mut Value) = |sc| {
        sc["simulate"]
            .as_object_mut()
            .expect("simulate")
            .remove("condition");
    };
    let no_coverage: fn(&mut Value) = |sc| {
        sc["lscr"].as_object_mut().expect("lscr").remove("coverage");
    };
    let wrong_time: fn(&mut Value) = |sc| {
        sc["simulate"]["condition"]["t"] = serde_json::json!(30);
    };
    for (edit, why, want) in [
        (no_condition, "needs a condition", "simulate.condition"),
        (no_coverage, "needs lscr.coverage", "lscr.coverage"),
        (
            wrong_time,
            "condition at the wrong time",
            "simulate.condition.t",
        ),
    ] {
        let mut bad = sc.clone();
        edit(&mut bad);
        let (msg, field) = thrown(Study::new(&bad.to_string(), 0).err().expect(why));
        assert_eq!(field, want, "{msg}");
    }
}
in_browser!(lscr_experiment_steps_to_completion);

fn lscr_errors_name_the_field() {
    let mut s = Session::new();
    let good = preset("lscr-predict");
    s.run(&good.to_string()).expect("lscr-predict");
    let cases: Vec<(&str, Value)> = vec![
        ("lscr.q", serde_json::json!({"lscr": {"q": 21}})),
        ("lscr.q", serde_json::json!({"lscr": {"q": 0}})),
        ("lscr.M", serde_json::json!({"lscr": {"M": 200000}})),
        (
            "lscr.M",
            serde_json::json!({"simulate": {"steps": 5}, "lscr": {"M": 80}}),
        ),
        (
            "lscr.M",
            serde_json::json!({"lscr": {"construction": "group"}}),
        ),
        (
            "simulate.steps",
            serde_json::json!({"simulate": {"steps": 1}}),
        ),
        (
            "lscr.index",
            serde_json::json!({"lscr": {"estimate": "smooth", "index": 30}}),
        ),
        (
            "lscr.estimate",
            serde_json::json!({"lscr": {"estimate": "guess"}}),
        ),
        (
            "model.F",
            serde_json::json!({"model": {"F": [[1.2, 0.0], [1.0, 0.7]]}}),
        ),
    ];
    for (want, patch) in cases {
        let mut sc = good.clone();
        for (k, v) in patch.as_object().expect("object") {
            for (k2, v2) in v.as_object().expect("object") {
                sc[k][k2] = v2.clone();
            }
        }
        let (msg, field) = thrown(
            s.run(&sc.to_string())
                .expect_err(&format!("{patch} is refused")),
        );
        assert_eq!(field, want, "{patch}: {msg}");
        assert!(msg.starts_with(want), "{patch}: {msg}");
    }
    assert!(s.has_report(), "the last good report is kept");
    assert_eq!(s.raster(8, 8).expect("raster of the kept report").len(), 64);
}
in_browser!(lscr_errors_name_the_field);

/// The LSCR issue's wasm speed figures, printed (not asserted: timings on a shared machine are
/// no test). `wasm-pack test --headless --chrome --release -- --test suite -- --nocapture lscr_wasm`
/// shows them.
fn lscr_wasm_timings() {
    use confset::lscr::Estimator;
    let (model, o) = crate::common::timing::lscr_predict_fixture();
    let mean_ms = |reps: usize, f: &mut dyn FnMut()| {
        let t0 = js_sys::Date::now();
        for _ in 0..reps {
            f();
        }
        (js_sys::Date::now() - t0) / reps as f64
    };
    for (t, reps) in [(30, 20), (200, 2)] {
        let ms = mean_ms(reps, &mut || {
            std::hint::black_box(Estimator::new(&model, t, &o).expect("estimator"));
        });
        wasm_bindgen_test::console_log!("[wasm timing] LSCR build (s, A, U_A, strings, BLUE, KF gains) t = {t}: {ms:.3} ms (mean of {reps})");
        assert!(ms.is_finite());
    }
    let l = confset::presets::get("lscr-predict")
        .expect("preset")
        .run()
        .expect("runs")
        .lscr
        .expect("lscr");
    let ms = mean_ms(10, &mut || {
        std::hint::black_box(l.region.raster(&l.window, 512, 512).expect("raster"));
    });
    wasm_bindgen_test::console_log!("[wasm timing] LSCR raster 512x512: {ms:.3} ms (mean of 10)");
}
in_browser!(lscr_wasm_timings);

/// The GLLS issue's wasm speed figures, printed like the LSCR ones.
fn glls_wasm_timings() {
    use confset::glls::{Curves, GllsModel};
    use nalgebra::DMatrix;
    let ten = GllsModel {
        a: DMatrix::from_fn(10, 10, |i, j| {
            if j == (i + 1) % 10 {
                1.01
            } else if i == j {
                0.05
            } else {
                0.0
            }
        }),
        b: DMatrix::zeros(10, 0),
        c: DMatrix::from_fn(2, 10, |i, j| ((i * 10 + j) as f64 * 0.7).sin()),
        omega: DMatrix::identity(2, 2) * 0.01,
        xi: DMatrix::zeros(10, 10),
        x0: nalgebra::DVector::from_element(10, 1.0),
    };
    let five = GllsModel::from_spec(
        &confset::presets::get("glls-unstable5")
            .expect("preset")
            .model,
    )
    .expect("model");
    for (name, model) in [("n = 10, m = 2", &ten), ("n = 5 (glls-unstable5)", &five)] {
        let reps = 3;
        let t0 = js_sys::Date::now();
        for _ in 0..reps {
            std::hint::black_box(Curves::new(model, 500).expect("curves"));
        }
        let ms = (js_sys::Date::now() - t0) / reps as f64;
        wasm_bindgen_test::console_log!(
            "[wasm timing] GLLS curves s = 0..500, {name}: {ms:.2} ms (mean of {reps})"
        );
        assert!(ms.is_finite());
    }
}
in_browser!(glls_wasm_timings);

/// The uniform-innovation issue's wasm speed figures, printed like the others.
fn uniform_wasm_timings() {
    let mut window_lp = crate::common::timing::uniform_window_lp();
    let reps = 10;
    let t0 = js_sys::Date::now();
    for _ in 0..reps {
        window_lp();
    }
    let window = (js_sys::Date::now() - t0) / reps as f64;
    let s = confset::presets::get("uniform-paper").expect("preset");
    let t0 = js_sys::Date::now();
    let u = s.run().expect("runs").uniform.expect("uniform");
    let run = js_sys::Date::now() - t0;
    wasm_bindgen_test::console_log!("[wasm timing] uniform window LP (∂ = 5, 2 states): {window:.3} ms; uniform-paper report (120 samples, swapping, faces, polygon, KF): {run:.0} ms");
    assert_eq!(u.steps.len(), 120);
}
in_browser!(uniform_wasm_timings);

/// The set-membership issue's wasm speed figures: one step of ubb-track (window 30).
fn ubb_wasm_timings() {
    let prep = confset::presets::get("ubb-track")
        .expect("preset")
        .prepare_ubb()
        .expect("valid");
    let run = prep.run_data();
    let mean_ms = |reps: usize, f: &mut dyn FnMut()| {
        let t0 = js_sys::Date::now();
        for _ in 0..reps {
            f();
        }
        (js_sys::Date::now() - t0) / reps as f64
    };
    let mut calls = 0;
    let mut size = confset::ubb::LpSize::default();
    let exact = mean_ms(5, &mut || {
        let step = prep.problem.step(&run.y, 40).expect("step");
        let (_, poly, sz) = step.hull_and_polygon([0, 1], 64).expect("LPs");
        calls = poly.calls;
        size = sz;
    });
    let fan = mean_ms(5, &mut || {
        let step = prep.problem.step(&run.y, 40).expect("step");
        let mut solver = step.set.support_solver().expect("LP");
        std::hint::black_box(
            solver
                .support_fan(&step.plane_map([0, 1]), 64)
                .expect("LPs"),
        );
    });
    let report = mean_ms(3, &mut || {
        std::hint::black_box(prep.report().expect("report"));
    });
    wasm_bindgen_test::console_log!("[wasm timing] ubb step, window 30 ({} variables, {} rows): hull + exact polygon ({calls} LPs) {exact:.2} ms; support in 64 directions {fan:.2} ms; ubb-track report (60 steps) {report:.0} ms", size.variables, size.rows);
    assert!(exact.is_finite() && fan.is_finite());
}
in_browser!(ubb_wasm_timings);

/// The set-membership guarantee in chunks: every run's truth inside the set, the counts merge.
fn ubb_guarantee_steps_to_completion() {
    let mut sc = preset("ubb-track");
    sc["ubb"]["window"] = serde_json::json!(8);
    sc["ubb"]["time"] = serde_json::json!(11);
    sc["ubb"]["noise"] = serde_json::json!("bound");
    let mut g = Study::new(&sc.to_string(), 120)
        .unwrap_or_else(|err| panic!("guarantee: {:?}", thrown(err)));
    assert!(!g.finished());
    let last = step_to_end(&mut g, 50, 50, 10, "guarantee");
    assert_eq!(last["runs"], 120);
    assert_eq!(last["outside"], 0, "{last}");
    assert!(num(&last["worst_excess"]) <= 1e-5, "{last}");
    // True noise far above the assumed bound: every run's data contradict ε, so no run has a
    // set, and each counts as a miss (`empty` and `outside`), not as an error.
    sc["ubb"]["eps"] = serde_json::json!(0.002);
    sc["ubb"]["sim_eps"] = serde_json::json!(0.2);
    let mut bad = Study::new(&sc.to_string(), 10).expect("the scenario itself is valid");
    let last = step_to_end(&mut bad, 10, 10, 2, "contradicted study");
    assert_eq!(last["runs"], 10, "{last}");
    assert_eq!(last["empty"], 10, "{last}");
    assert_eq!(last["outside"], 10, "{last}");
}
in_browser!(ubb_guarantee_steps_to_completion);

fn csv_data_is_read_as_the_core_reads_it() {
    let scenario = preset("scf-scalar").to_string();
    let shape: Value = serde_json::from_str(&data_shape(&scenario).expect("shape")).expect("JSON");
    assert_eq!(shape, serde_json::json!({"outputs": 1, "inputs": 0}));
    let text = "y1\r\n0.5\r\n-1.25\r\n";
    let got: Value =
        serde_json::from_str(&with_csv_data(&scenario, text, "real.csv", None).expect("CSV read"))
            .expect("JSON");
    let core = confset::scenario::Scenario::from_json(&scenario)
        .and_then(|s| s.with_csv_data(text))
        .expect("core");
    let mut want = serde_json::to_value(&core).expect("JSON");
    // The figures' title names the data, not the preset's paper figure.
    assert_ne!(want["title"], "measured data: real.csv");
    want["title"] = "measured data: real.csv".into();
    assert_eq!(got, want);
    assert_eq!(got["data"]["y"], serde_json::json!([[0.5], [-1.25]]));
    assert!(got.get("simulate").is_none(), "simulate is dropped");
    let (message, field) =
        thrown(with_csv_data(&scenario, "y1\n1\nx\n", "bad.csv", None).expect_err("bad cell"));
    assert_eq!(field, "data.y");
    assert_eq!(message, "data.y row 3, column y1: 'x' is not a number");
    let (_, field) = thrown(data_shape("{}").expect_err("no scenario"));
    assert!(!field.is_empty(), "the error names a field");
    // The column picker: the header's names and its time column, then the file read with the
    // columns chosen, as the core reads it (gaps as null, the times read).
    let river = "year,flow,rain\n1871,1120,3\n1872,,4\n";
    let header: Value = serde_json::from_str(&csv_columns(river).expect("header")).expect("JSON");
    assert_eq!(
        header,
        serde_json::json!({"columns": ["year", "flow", "rain"], "time": 0})
    );
    let none: Value =
        serde_json::from_str(&csv_columns("1\n2\n").expect("no header")).expect("JSON");
    assert_eq!(none, serde_json::json!({"columns": [], "time": null}));
    let (message, field) =
        thrown(with_csv_data(&scenario, river, "river.csv", None).expect_err("two candidates"));
    assert_eq!(field, "data");
    assert!(
        message.ends_with("or the column picker (page)"),
        "{message}"
    );
    let got: Value = serde_json::from_str(
        &with_csv_data(&scenario, river, "river.csv", Some(vec!["rain".into()])).expect("chosen"),
    )
    .expect("JSON");
    let core = confset::scenario::Scenario::from_json(&scenario)
        .and_then(|s| s.with_csv_file_columns(river, "river.csv", &["rain".to_string()]))
        .expect("core");
    assert_eq!(got, serde_json::to_value(&core).expect("JSON"));
    assert_eq!(got["data"]["y"], serde_json::json!([[3.0], [4.0]]));
    assert_eq!(got["data"]["t"], serde_json::json!([1871.0, 1872.0]));
    let flow: Value = serde_json::from_str(
        &with_csv_data(&scenario, river, "river.csv", Some(vec!["flow".into()])).expect("chosen"),
    )
    .expect("JSON");
    assert_eq!(flow["data"]["y"], serde_json::json!([[1120.0], [null]]));
    let (message, field) = thrown(
        with_csv_data(&scenario, river, "river.csv", Some(vec!["flux".into()]))
            .expect_err("unknown"),
    );
    assert_eq!(field, "columns");
    assert!(
        message.contains("'flux' (for y1) is not a column of the header"),
        "{message}"
    );
}
in_browser!(csv_data_is_read_as_the_core_reads_it);

/// The page's figure cards come from `methodPanels`: every figure of every method, named as the
/// core names them, with a text alternative; `usefulPanels` is the core's choice for the kept
/// report; an unknown method is a `method` error.
fn figure_lists_are_the_cores() {
    use confset::method::Method;
    use confset::plot;
    for m in Method::ALL {
        let list: Value =
            serde_json::from_str(&method_panels(&m.to_string()).expect("panels")).expect("JSON");
        let names: Vec<&str> = list
            .as_array()
            .expect("a list")
            .iter()
            .map(|f| {
                assert!(f["alt"].as_str().is_some_and(|a| a.len() > 20), "{m}: {f}");
                f["panel"].as_str().expect("a name")
            })
            .collect();
        let core: Vec<&str> = plot::method_panels(m).iter().map(|p| p.name()).collect();
        assert_eq!(names, core, "{m}");
    }
    let (msg, field) = thrown(method_panels("kalman").expect_err("unknown method"));
    assert_eq!(field, "method", "{msg}");
    let mut s = Session::new();
    assert_eq!(s.useful_panels(), "[]");
    s.run(&preset("scf-scalar").to_string()).expect("run");
    let useful: Vec<String> = serde_json::from_str(&s.useful_panels()).expect("JSON");
    assert_eq!(useful, ["state", "series", "coverage"]);
}
in_browser!(figure_lists_are_the_cores);

/// One `Study` per worker on its shard, the main thread's `Study` merging the latest partials
/// after every slice (each merge replaces its counts): at the end, the unsharded result, the
/// same JSON text. For the first preset of each method that has a study.
fn shards_in_workers_merge_on_the_main_thread() {
    let list: Value = serde_json::from_str(&presets().expect("presets")).expect("preset JSON");
    let mut methods = Vec::new();
    for p in list.as_array().expect("a list") {
        let (name, sc) = (&p["name"], p["scenario"].to_string());
        let method = p["scenario"]["method"].clone();
        if methods.contains(&method) {
            continue;
        }
        let Ok(mut whole) = Study::new(&sc, 21) else {
            continue; // no study for this preset
        };
        methods.push(method);
        while !whole.finished() {
            whole.step(5).expect("step");
        }
        let want = whole.result().expect("result");

        let mut workers: Vec<Study> = (0..3)
            .map(|i| {
                let mut w = Study::new(&sc, 21).expect("study");
                w.restrict(i, 3).expect("restrict");
                w
            })
            .collect();
        let mut main = Study::new(&sc, 21).expect("study");
        let mut latest = vec![String::new(); 3];
        let mut got = String::new();
        while workers.iter().any(|w| !w.finished()) {
            for (w, slot) in workers.iter_mut().zip(&mut latest) {
                if !w.finished() {
                    w.step(3).expect("step");
                }
                *slot = w.partial().expect("partial");
            }
            got = main
                .merge(&format!("[{}]", latest.join(",")))
                .expect("merge");
            let done: usize = workers.iter().map(|w| w.runs()).sum();
            assert_eq!(main.runs(), done, "{name}: merge replaces the counts");
        }
        assert!(main.finished(), "{name}");
        assert_eq!(got, want, "{name}: merged result");
        assert_eq!(main.result().expect("result"), want, "{name}");

        let (message, _) = thrown(
            main.merge(&format!("[{},{}]", latest[0], latest[0]))
                .expect_err("overlap"),
        );
        assert!(
            message.contains("part 2 covers runs 0..")
                && message.contains("which part 1 also covers"),
            "{name}: {message}"
        );
        let (message, field) = thrown(main.merge("[{\"range\": 3}]").expect_err("not a part"));
        assert!(
            message.contains("part 1 is not a study's partial counts"),
            "{name}: {message} ({field})"
        );
        let (message, field) = thrown(main.merge("{").expect_err("not JSON"));
        assert_eq!(field, "parts", "{name}: {message}");
        let mut late = Study::new(&sc, 21).expect("study");
        late.step(1).expect("step");
        let (message, field) = thrown(late.restrict(0, 2).expect_err("after a step"));
        assert_eq!(field, "shard", "{name}: {message}");
    }
    assert!(!methods.is_empty(), "no preset has a study");
}
in_browser!(shards_in_workers_merge_on_the_main_thread);
