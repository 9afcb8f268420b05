//! What the page reads from a kept report through the core instead of re-deriving it
//! (`web.rs`: `Session.cursorSteps`, `Session.setStudy`, `ellipsoidLevel`), asked of every
//! method through its scenario file (`Report::cursor_steps`, `Report::set_study`).

use confset::presets;
use confset::scenario::Report;
use serde_json::{json, Value};

/// Every preset of a method with a time cursor: the steps its report says the cursor moves over
/// are the cursor's own (`Cursor::steps`, the range the worker computes details for); a preset
/// without one has none.
#[test]
fn a_reports_cursor_steps_are_its_cursors() {
    let mut with_cursor = 0;
    for p in presets::all() {
        let Some(cursor) = p.scenario.cursor().expect(&p.name) else {
            continue;
        };
        with_cursor += 1;
        let report = p.scenario.run().expect(&p.name);
        assert_eq!(report.cursor_steps(), Some(cursor.steps()), "{}", p.name);
        // The report's own time is one of them.
        assert!(cursor.steps().contains(&report.time), "{}", p.name);
    }
    assert!(
        with_cursor >= 3,
        "ubb, uniform_lp and compare presets have a cursor"
    );
    let scf = presets::get("scf-scalar").expect("preset scf-scalar");
    assert_eq!(scf.run().expect("scf-scalar").cursor_steps(), None);
}
in_browser!(a_reports_cursor_steps_are_its_cursors);

/// A study's result enters a report through one path: GLLS's becomes `glls.precision` (as a
/// run with `glls.monte_carlo` holds it), `null` removes it; a method whose report holds no
/// study result refuses with the `study` field, and the report stays as it was.
#[test]
fn a_study_result_enters_the_report_through_one_path() {
    // The page's way: the scenario runs without its Monte Carlo, the study apart.
    let glls = presets::get("glls-saturate").expect("preset glls-saturate");
    let mut alone = glls.clone();
    alone.glls.as_mut().expect("glls block").monte_carlo = None;
    let mut report: Report = alone.run().expect("glls-saturate");
    assert!(report
        .glls
        .as_ref()
        .expect("glls block")
        .precision
        .is_none());
    let mut study = glls.study(Some(40)).expect("the GLLS study");
    study.step(40).expect("40 runs");
    let result: Value = study.result().expect("the study's result");
    report
        .set_study(result.clone())
        .expect("GLLS takes its study");
    let held = serde_json::to_value(&report).expect("report JSON");
    assert_eq!(held["glls"]["precision"], result);
    report.set_study(Value::Null).expect("null removes it");
    assert!(report
        .glls
        .as_ref()
        .expect("glls block")
        .precision
        .is_none());
    let err = report
        .set_study(json!({"runs": "many"}))
        .expect_err("not a precision study");
    assert!(err.field.starts_with("glls.precision"), "{err}");

    let ubb = presets::get("ubb-track").expect("preset ubb-track");
    let mut report = ubb.run().expect("ubb-track");
    let before = report.clone();
    let err = report
        .set_study(json!({"runs": 1}))
        .expect_err("ubb keeps its study apart");
    assert_eq!(err.field, "study", "{err}");
    assert!(err.message.contains("\"ubb\""), "{err}");
    assert_eq!(report, before);
}
in_browser!(a_study_result_enters_the_report_through_one_path);
