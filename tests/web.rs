//! The wasm bindings in a real browser (`wasm-pack test --headless --chrome`): presets, a
//! Session running and drawing a preset, errors thrown as JS Errors naming the field, and a
//! chunk of the conditional Monte Carlo.
#![cfg(target_arch = "wasm32")]

use confset::web::{presets, Experiment, Session};
use serde_json::Value;
use wasm_bindgen::{JsCast, JsValue};
use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

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

#[wasm_bindgen_test]
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

#[wasm_bindgen_test]
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
    assert_eq!(field, "view", "{msg}");
    let (_, field) = thrown(s.svg("{}", 0, 300).expect_err("zero width is refused"));
    assert_eq!(field, "size");
}

#[wasm_bindgen_test]
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
        let svg = s.svg(&view, 600, 400).expect("svg");
        assert!(svg.contains("<svg"), "{panel}: not SVG");
    }
}

#[wasm_bindgen_test]
fn experiment_runs_in_chunks() {
    let mut robots = preset("scf-robots");
    robots["experiment"]["runs"] = serde_json::json!(300);
    let mut e = Experiment::new(&robots.to_string()).expect("experiment");
    assert!(!e.finished());
    // Chunks are whole batches of 8 runs (so counts do not depend on the chunking).
    let first: Value = serde_json::from_str(&e.step(96).expect("step")).expect("counts");
    assert_eq!(first["runs_done"], 96);
    while !e.finished() {
        e.step(128).expect("step");
    }
    let c: Value = serde_json::from_str(&e.counts().expect("counts")).expect("counts");
    assert_eq!(c["runs_done"], 300);
    let scf = c["scf_inside"].as_u64().expect("scf_inside");
    let kf = c["kf_inside"].as_u64().expect("kf_inside");
    // At α = 0.95 SCF covers the colliding state about 285 times in 300; KF almost never.
    assert!(scf >= 260, "SCF inside {scf}/300");
    assert!(kf <= 30, "KF inside {kf}/300");
    assert!(c["scf_warnings"].as_u64().expect("warnings") >= 250);

    // The scalar preset has no experiment block: a thrown error naming it.
    let (msg, field) = thrown(
        Experiment::new(&preset("scf-scalar").to_string())
            .err()
            .expect("no experiment in the scalar preset"),
    );
    assert_eq!(field, "experiment", "{msg}");
}
