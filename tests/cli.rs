//! The command line draws the figure the page draws: for every preset, `confset figures` and
//! `confset figure` write byte for byte the SVG of the page's path — the preset as JSON (as the
//! page gets it from `presets()`) → `Scenario::from_json` → `run`, then a view parsed from the
//! JSON the page sends (`{"panel": …, "time": …}`). The scenario's part of the figure (title,
//! axis names, …) comes with the report, so nothing else is needed.
#![cfg(not(target_arch = "wasm32"))]

use confset::plot::{self, View};
use confset::presets;
use confset::scenario::Scenario;
use std::path::{Path, PathBuf};
use std::process::Command;

/// What the page draws: the scenario JSON run, the view JSON parsed, `w` × `h` pixels.
fn page_svg(scenario_json: &str, view_json: &str, (w, h): (u32, u32)) -> String {
    let report = Scenario::from_json(scenario_json)
        .and_then(|s| s.run())
        .expect("the page's scenario runs");
    let view: View = serde_json::from_str(view_json).expect("the page's view JSON parses");
    plot::report_svg(&report, &view, w, h).expect("draws")
}

fn preset_json(name: &str) -> String {
    serde_json::to_string(&presets::get(name).expect("preset")).expect("json")
}

/// A fresh directory for this test's files.
fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("confset-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("scratch directory");
    d
}

fn confset(args: &[&str]) {
    let out = Command::new(env!("CARGO_BIN_EXE_confset"))
        .args(args)
        .output()
        .expect("confset runs");
    assert!(
        out.status.success(),
        "confset {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn figures_command_writes_the_page_figures_of_every_preset() {
    let dir = scratch("figures");
    let size = (800, 500);
    confset(&[
        "figures",
        "-o",
        dir.to_str().expect("utf-8"),
        "--size",
        "800x500",
    ]);
    for p in presets::all() {
        let json = serde_json::to_string(&p.scenario).expect("json");
        let report = Scenario::from_json(&json)
            .and_then(|s| s.run())
            .expect("runs");
        for panel in plot::useful_panels(&report) {
            let file = dir.join(format!("{}-{}.svg", p.name, panel.name()));
            let page = page_svg(&json, &format!(r#"{{"panel":"{}"}}"#, panel.name()), size);
            assert!(
                read(&file) == page,
                "{} {}: the CLI figure differs from the page's",
                p.name,
                panel.name()
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn figure_command_draws_the_page_robot_figure_with_its_position_axes() {
    let dir = scratch("figure");
    let json = preset_json("scf-robots");
    // The default panel (state) at the report's time, and the state and series at t = 20 as
    // the page's time slider asks for them.
    let cases = [
        (vec![], r#"{"panel":"state"}"#),
        (
            vec!["--panel", "state", "--time", "20"],
            r#"{"panel":"state","time":20}"#,
        ),
        (
            vec!["--panel", "series", "--time", "20"],
            r#"{"panel":"series","time":20}"#,
        ),
    ];
    for (k, (flags, view)) in cases.iter().enumerate() {
        let file = dir.join(format!("{k}.svg"));
        let mut args = vec![
            "figure",
            "--preset",
            "scf-robots",
            "-o",
            file.to_str().expect("utf-8"),
        ];
        args.extend(flags);
        confset(&args);
        let cli = read(&file);
        assert!(
            cli == page_svg(&json, view, (960, 640)),
            "{flags:?}: CLI and page differ"
        );
        assert!(
            cli.contains("position p_"),
            "{flags:?}: no robot position axis"
        );
        assert!(
            !cli.contains("state component"),
            "{flags:?}: a generic axis name"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
