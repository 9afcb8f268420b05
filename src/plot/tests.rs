//! Native tests of the figures: every preset draws every useful panel, the legends say what
//! they should, and bad views are errors, not panics.

use super::*;
use crate::presets;

fn preset(name: &str) -> (Scenario, Report) {
    let s = presets::get(name).expect("preset exists");
    let r = s.run().expect("preset runs");
    (s, r)
}

fn svg(s: &Scenario, r: &Report, panel: Panel, time: Option<usize>) -> String {
    let view = View {
        time,
        ..View::new(panel).with_scenario(s)
    };
    report_svg(r, &view, 960, 640).unwrap_or_else(|e| panic!("{}: {e}", panel.name()))
}

#[test]
fn scalar_preset_panels_carry_their_legends() {
    let (s, r) = preset("scf-scalar");
    let state = svg(&s, &r, Panel::State, None);
    for label in [
        "KF interval",
        "SCF interval",
        "true state",
        "measurements",
        "t = 50",
    ] {
        assert!(state.contains(label), "state panel lacks \"{label}\"");
    }
    let series = svg(&s, &r, Panel::Series, Some(10));
    for label in ["KF center", "SCF center", "SCF interval", "t = 10"] {
        assert!(series.contains(label), "series panel lacks \"{label}\"");
    }
    let cov = svg(&s, &r, Panel::Coverage, None);
    for label in ["KF region", "SCF region", "level α = 99 %", "closed form"] {
        assert!(cov.contains(label), "coverage panel lacks \"{label}\"");
    }
}

#[test]
fn robot_preset_shows_both_bodies_and_the_warnings() {
    for name in ["scf-robots", "scf-robots-literal"] {
        let (s, r) = preset(name);
        let state = svg(&s, &r, Panel::State, None);
        for label in [
            "KF Z₄₀|₃₆",
            "SCF Z₄₀|₃₆",
            "true positions at t = 40",
            "Collision warning (d_min = 0.2)",
            "whole run",
            ">\nA\n<",
            ">\nB\n<",
        ] {
            assert!(
                state.contains(label),
                "{name}: state panel lacks \"{label}\""
            );
        }
        assert!(
            state.contains("KF no, SCF YES"),
            "{name}: the warnings are not reported"
        );
        let series = svg(&s, &r, Panel::Series, None);
        assert!(series.contains("KF center") && series.contains("SCF interval"));
    }
}

#[test]
fn early_times_draw_kf_only_and_say_why() {
    let (s, r) = preset("scf-robots");
    // Before t = n = 8 there is no SCF region; ask for the full-state regions (no target).
    let mut s2 = s.clone();
    s2.components = None;
    s2.tau = 0;
    s2.collision = None;
    let r2 = s2.run().expect("runs");
    let out = svg(&s2, &r2, Panel::State, Some(3));
    assert!(out.contains("KF X₃"));
    assert!(!out.contains("SCF X₃"));
    assert!(out.contains("no SCF region at t = 3"));
    // The collision view at an early time still draws.
    let out = svg(&s, &r, Panel::State, Some(2));
    assert!(out.contains("KF Z₆|₂"));
}

#[test]
fn coverage_without_a_curve_is_an_error_naming_the_field() {
    let (s, r) = preset("scf-robots");
    assert!(r.coverage_curve.is_none());
    let e = report_svg(&r, &View::new(Panel::Coverage).with_scenario(&s), 800, 500)
        .expect_err("no coverage curve");
    assert_eq!(e.field, "coverage_curve");
}

#[test]
fn bad_views_are_errors_not_panics() {
    let (s, r) = preset("scf-scalar");
    let view = View {
        time: Some(0),
        ..View::new(Panel::State)
    };
    assert_eq!(report_svg(&r, &view, 800, 500).unwrap_err().field, "time");
    let view = View {
        time: Some(51),
        ..View::new(Panel::Series)
    };
    assert_eq!(report_svg(&r, &view, 800, 500).unwrap_err().field, "time");
    for (w, h) in [(1, 1), (16, 16), (239, 500)] {
        assert_eq!(
            report_svg(&r, &View::new(Panel::State), w, h)
                .unwrap_err()
                .field,
            "size"
        );
    }
    // Small but allowed sizes draw every panel.
    for panel in [Panel::State, Panel::Series, Panel::Coverage] {
        for (w, h) in [(240, 180), (320, 240), (480, 300), (2400, 1600)] {
            let v = View::new(panel).with_scenario(&s);
            if let Err(e) = report_svg(&r, &v, w, h) {
                assert_eq!(e.field, "size", "{} at {w}×{h}: {e}", panel.name());
            }
        }
    }
    let mut broken = r.clone();
    broken.plot = vec![3];
    assert_eq!(
        report_svg(&broken, &View::new(Panel::State), 800, 500)
            .unwrap_err()
            .field,
        "plot"
    );
    let mut empty = r.clone();
    empty.steps.clear();
    assert!(report_svg(&empty, &View::new(Panel::Series), 800, 500).is_err());
}

#[test]
fn frame_maps_the_plotting_area() {
    let (s, r) = preset("scf-scalar");
    let mut text = String::new();
    let f = draw(
        SVGBackend::with_string(&mut text, (900, 600)),
        &r,
        &View::new(Panel::State).with_scenario(&s),
    )
    .expect("draws");
    let (l, t, rt, b) = f.plot_area;
    assert!(
        0 < l && l < rt && rt <= 900 && 0 < t && t < b && b <= 600,
        "{f:?}"
    );
    assert!(f.x_range.0 < 1.0 && f.x_range.1 > 50.0);
    assert!(f.y_range.0 < f.y_range.1);
    assert_eq!(f.x_label, "time t (steps)");
    let (_, r2) = preset("scf-robots");
    let f2 = draw(
        SVGBackend::with_string(&mut String::new(), (900, 600)),
        &r2,
        &View::new(Panel::Series),
    )
    .expect("draws");
    assert_eq!(
        f2.more.len(),
        1,
        "two plotted components: two stacked charts"
    );
    assert!(f2.more[0].plot_area.1 > f2.plot_area.3);
}

#[test]
fn svg_text_uses_css_pixel_sizes() {
    let (s, r) = preset("scf-scalar");
    let out = svg(&s, &r, Panel::State, None);
    // Titles are 17 CSS px: plotters writes font-size = size / 1.24.
    assert!(out.contains("font-size=\"17\""), "title size");
    assert!(out.contains("font-family=\"sans-serif\""));
}

#[test]
fn view_json_accepts_the_short_form_and_the_context() {
    let v: View = serde_json::from_str(r#"{"panel":"series","time":20}"#).expect("parses");
    assert_eq!(
        (v.panel, v.time, v.zoom),
        (Panel::Series, Some(20), Zoom::Auto)
    );
    let s = presets::get("scf-robots").expect("preset");
    let v = View::new(Panel::State).with_scenario(&s);
    assert_eq!(v.measured.as_ref().map(|m| m[0]), Some(Some(0)));
    assert_eq!(v.measured.as_ref().map(|m| m[2]), Some(None));
    assert_eq!(v.measured.as_ref().map(|m| m[5]), Some(Some(3)));
    assert!(v.names[0].contains("robot A"));
    let back: View =
        serde_json::from_str(&serde_json::to_string(&v).expect("json")).expect("parses");
    assert_eq!(back, v);
}

#[test]
fn every_preset_draws_every_useful_panel_at_page_sizes() {
    for p in presets::all() {
        let r = p.scenario.run().expect("preset runs");
        for panel in useful_panels(&r) {
            for (w, h) in [(960, 640), (900, 450), (400, 250)] {
                let v = View::new(panel).with_scenario(&p.scenario);
                let out = report_svg(&r, &v, w, h)
                    .unwrap_or_else(|e| panic!("{} {} {w}×{h}: {e}", p.name, panel.name()));
                assert!(
                    out.contains("KF"),
                    "{} {}: no KF legend",
                    p.name,
                    panel.name()
                );
            }
        }
    }
}

#[test]
fn thinning_keeps_the_envelope_of_dense_columns() {
    let pts: Vec<(i32, i32)> = (0..100).map(|k| (k / 10, (k * 37) % 23)).collect();
    let t = style::thin(&pts);
    assert!(t.len() <= 40, "{}", t.len());
    for x in 0..10 {
        let col: Vec<i32> = pts.iter().filter(|p| p.0 == x).map(|p| p.1).collect();
        let kept: Vec<i32> = t.iter().filter(|p| p.0 == x).map(|p| p.1).collect();
        assert_eq!(kept.iter().min(), col.iter().min());
        assert_eq!(kept.iter().max(), col.iter().max());
        assert_eq!(kept.first(), col.first());
        assert_eq!(kept.last(), col.last());
    }
}

#[test]
fn numbers_read_well() {
    assert_eq!(style::num(-0.0001, 2), "0.00");
    assert_eq!(style::num(-1.5, 1), "−1.5");
    assert_eq!(style::sig(0.2), "0.2");
    assert_eq!(style::sig(0.65654), "0.657");
    assert_eq!(style::sci(2.1664e-5), "2.17 × 10⁻⁵");
    assert_eq!(style::sub(40), "₄₀");
    assert_eq!(style::pct(0.95), "95 %");
}

#[test]
fn one_plotted_component_of_a_larger_state_draws_over_time() {
    let (mut s, _) = preset("scf-robots");
    s.plot = Some(vec![1]);
    let r = s.run().expect("runs");
    let out = svg(&s, &r, Panel::State, None);
    assert!(out.contains("KF interval") && out.contains("projection of the 8-dimensional regions"));
    std::fs::write(std::env::temp_dir().join("confset-one-component.svg"), &out).ok();
}
