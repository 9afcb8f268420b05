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
                // LSCR reports draw the region (whose legend names X̂, shortly on small figures); the
                // others KF/SCF.
                let expect = if r.lscr.is_some() { "X̂ " } else { "KF" };
                assert!(
                    out.contains(expect),
                    "{} {}: no \"{expect}\" in the legend",
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

// ---------------------------------------------------------------- the LSCR region panel

/// SVG polylines drawn in `color` (hatch segments and the legend swatch's lines).
fn strokes(svg: &str, color: &RGBColor) -> usize {
    let hex = format!("stroke=\"#{:02X}{:02X}{:02X}\"", color.0, color.1, color.2);
    svg.matches(hex.as_str()).count()
}

#[test]
fn lscr_presets_use_the_region_panel_only() {
    for name in ["lscr-predict", "lscr-smooth", "lscr-ma1"] {
        let (s, r) = preset(name);
        assert_eq!(useful_panels(&r), vec![Panel::Region], "{name}");
        // The default figure of an LSCR scenario is the region.
        let out = scenario_svg(&s, 800, 600).expect("draws");
        assert!(
            out.contains("X̂ (LSCR, 90 %)"),
            "{name}: not the region figure"
        );
    }
    let (_, r) = preset("scf-scalar");
    assert!(!useful_panels(&r).contains(&Panel::Region));
    assert_eq!(Panel::from_name("region").expect("parses"), Panel::Region);
    assert_eq!(Panel::Region.name(), "region");
    let v: View = serde_json::from_str(r#"{"panel":"region"}"#).expect("parses");
    assert_eq!(v.panel, Panel::Region);
}

#[test]
fn region_panel_draws_the_lscr_presets_at_every_size() {
    for name in ["lscr-predict", "lscr-smooth", "lscr-ma1"] {
        let (s, r) = preset(name);
        let l = r.lscr.as_ref().expect("LSCR report");
        for (w, h) in [
            (240, 180),
            (320, 240),
            (400, 250),
            (800, 600),
            (960, 640),
            (1600, 1200),
        ] {
            let view = View::new(Panel::Region).with_scenario(&s);
            let mut out = String::new();
            let frame = draw(SVGBackend::with_string(&mut out, (w, h)), &r, &view)
                .unwrap_or_else(|e| panic!("{name} {w}×{h}: {e}"));
            // Hatching of the area excluded by X̂₁ (every preset has some in view), beyond the
            // legend swatch's few lines.
            assert!(
                strokes(&out, &style::hatch_color(0)) > 12,
                "{name} {w}×{h}: no hatching of X̂₁"
            );
            let (x, y) = (frame.x_range, frame.y_range);
            assert!(x.0 < x.1 && y.0 < y.1, "{name}: {frame:?}");
            // The window holds the report's (it may grow for equal scales, never shrink).
            assert!(
                x.0 <= l.window.lo[0] + 1e-9 && x.1 >= l.window.hi[0] - 1e-9,
                "{name} {w}×{h}: {frame:?}"
            );
            assert!(
                frame.x_label.starts_with(&format!("x{},₁", sub(l.time))),
                "{}",
                frame.x_label
            );
            if w >= 640 && h >= 400 {
                for label in [
                    "X̂ (LSCR, 90 %)",
                    "excluded by X̂₁ (95 %)",
                    "excluded by X̂₂ (95 %)",
                    "true state",
                ] {
                    assert!(out.contains(label), "{name} {w}×{h}: no \"{label}\"");
                }
            }
        }
    }
}

#[test]
fn region_panel_shows_what_each_figure_of_the_paper_shows() {
    // Fig. 1: prediction, both groups exclude areas in view, BLUE and Kalman ellipses.
    let (s, r) = preset("lscr-predict");
    let out = report_svg(&r, &View::new(Panel::Region).with_scenario(&s), 800, 600).expect("draws");
    assert!(
        strokes(&out, &style::hatch_color(1)) > 12,
        "no hatching of X̂₂"
    );
    for label in [
        "prediction",
        "x₃₁,₁",
        "x₃₁,₂",
        "BLUE estimate",
        "BLUE ellipse 90 %",
        "KF ellipse 90 %",
        "Kalman estimate x̂₃₁|₃₀",
    ] {
        assert!(out.contains(label), "Fig. 1: no \"{label}\"");
    }
    assert!(!out.contains("unbounded"));
    // Fig. 2: smoothing of x₁₅, BLUE only (no Kalman smoother in the report).
    let (s, r) = preset("lscr-smooth");
    let out = report_svg(&r, &View::new(Panel::Region).with_scenario(&s), 800, 600).expect("draws");
    for label in ["smoothing", "x₁₅,₁", "BLUE ellipse 90 %"] {
        assert!(out.contains(label), "Fig. 2: no \"{label}\"");
    }
    assert!(!out.contains("KF ellipse"));
    // Fig. 3: the unbounded band along [1, 1] with the Kalman ellipse and no BLUE.
    let (s, r) = preset("lscr-ma1");
    assert!(!r.lscr.as_ref().expect("LSCR").bounded);
    let out = report_svg(&r, &View::new(Panel::Region).with_scenario(&s), 800, 600).expect("draws");
    for label in [
        "unbounded along ±[0.71, 0.71]",
        "KF ellipse 90 %",
        "no BLUE",
        "x₂₁",
    ] {
        assert!(out.contains(label), "Fig. 3: no \"{label}\"");
    }
    assert!(!out.contains("BLUE ellipse"));
    // Dashed KF ellipse: plotters writes dashes as many short polylines of the KF colour.
    assert!(strokes(&out, &style::KF) > 10);
}

#[test]
fn region_hatching_is_exact() {
    // Every hatch segment of group l lies outside X̂_l (checked at interior points), and points
    // of the hatch lines strictly inside X̂ carry no segment of any group.
    let (_, r) = preset("lscr-smooth");
    let l = r.lscr.as_ref().expect("LSCR");
    let plane = crate::scenario::lscr::plane_region(&l.region, l.plot, None).expect("plane");
    let win = geom::Win::new(
        (l.window.lo[0], l.window.hi[0]),
        (l.window.lo[1], l.window.hi[1]),
    );
    // A 500 × 400 pixel box for the window (y down on screen).
    let (p0, p1) = ((50.0, 450.0), (550.0, 50.0));
    let hatches = region::hatch_segments(&plane, win, p0, p1, 7.0).expect("hatches");
    assert_eq!(hatches.len(), 2);
    let to_chart = |p: (i32, i32)| {
        [
            win.x0 + (p.0 as f64 - p0.0) / (p1.0 - p0.0) * win.width(),
            win.y0 + (p.1 as f64 - p0.1) / (p1.1 - p0.1) * win.height(),
        ]
    };
    let mut checked = 0;
    for (g, segs) in hatches.iter().enumerate() {
        assert!(segs.len() > 20, "group {g}: {} segments", segs.len());
        for &(a, b) in segs {
            let len = ((b.0 - a.0) as f64).hypot((b.1 - a.1) as f64);
            if len < 6.0 {
                continue; // too short to probe away from the rounding of its ends
            }
            for f in [0.3, 0.5, 0.7] {
                let pa = to_chart(a);
                let pb = to_chart(b);
                let x = [pa[0] + f * (pb[0] - pa[0]), pa[1] + f * (pb[1] - pa[1])];
                assert!(
                    plane.excluded(&x) & (1 << g) != 0,
                    "group {g}: hatch point {x:?} is inside X̂{}",
                    g + 1
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 100);
    // The BLUE centre lies inside X̂: no hatch segment of either group passes within 2 px.
    let b = l.blue.as_ref().expect("BLUE");
    assert_eq!(plane.excluded(&b.center), 0);
    let c = (
        p0.0 + (b.center[0] - win.x0) / win.width() * (p1.0 - p0.0),
        p0.1 + (b.center[1] - win.y0) / win.height() * (p1.1 - p0.1),
    );
    for segs in &hatches {
        for &(a, e) in segs {
            let (ax, ay, ex, ey) = (a.0 as f64, a.1 as f64, e.0 as f64, e.1 as f64);
            let (dx, dy) = (ex - ax, ey - ay);
            let t = (((c.0 - ax) * dx + (c.1 - ay) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
            let dist = (ax + t * dx - c.0).hypot(ay + t * dy - c.1);
            assert!(
                dist > 2.0,
                "a hatch segment crosses the BLUE centre inside X̂"
            );
        }
    }
}

#[test]
fn wrong_panel_and_report_pairs_are_errors_naming_the_panel() {
    let (s, r) = preset("lscr-ma1");
    for panel in [Panel::State, Panel::Series, Panel::Coverage] {
        let e = report_svg(&r, &View::new(panel).with_scenario(&s), 800, 600)
            .expect_err("an LSCR report has no time steps");
        assert_eq!(e.field, "panel", "{}: {e}", panel.name());
        assert!(e.message.contains("region"), "{e}");
    }
    let (s, r) = preset("scf-scalar");
    let e = report_svg(&r, &View::new(Panel::Region).with_scenario(&s), 800, 600)
        .expect_err("no LSCR part");
    assert_eq!(e.field, "panel");
    assert!(e.message.contains("scf"), "{e}");
    // Too small is still a size error, and a broken window a clear one.
    let (s, mut r) = preset("lscr-predict");
    assert_eq!(
        report_svg(&r, &View::new(Panel::Region), 200, 100)
            .unwrap_err()
            .field,
        "size"
    );
    if let Some(l) = r.lscr.as_mut() {
        l.window.hi[0] = l.window.lo[0];
    }
    let e = report_svg(&r, &View::new(Panel::Region).with_scenario(&s), 800, 600).unwrap_err();
    assert_eq!(e.field, "report.lscr.window");
}

#[test]
fn region_panel_zoom_choices_draw() {
    let (s, r) = preset("lscr-predict");
    let l = r.lscr.as_ref().expect("LSCR");
    let mut widths = Vec::new();
    for zoom in [Zoom::Regions, Zoom::Auto, Zoom::Full] {
        let v = View {
            zoom,
            ..View::new(Panel::Region).with_scenario(&s)
        };
        let f = draw(
            SVGBackend::with_string(&mut String::new(), (800, 600)),
            &r,
            &v,
        )
        .unwrap_or_else(|e| panic!("{zoom:?}: {e}"));
        widths.push(f.x_range.1 - f.x_range.0);
    }
    // Tight on X̂ is no wider than the report's window, which is no wider than everything.
    assert!(
        widths[0] <= widths[1] + 1e-9 && widths[1] <= widths[2] + 1e-9,
        "{widths:?}"
    );
    assert!(l.bounded);
}

#[test]
fn region_panel_draws_a_slice_of_a_three_dimensional_state() {
    // n = 3: a cascade of three first-order systems; the region is sliced through the BLUE.
    let json = r#"{
        "method": "lscr",
        "model": {"F": [[0.5, 0, 0], [1, 0.7, 0], [0, 0.5, 0.6]], "H": [[0, 0, 1]],
                  "G": [[1], [0], [0]], "sigma_v2": 0.005, "sigma_w2": 0.005},
        "simulate": {"steps": 40, "seed": 2},
        "plot": [0, 2],
        "lscr": {"estimate": "predict", "M": 120, "q": 2, "seed": 4}
    }"#;
    let s = Scenario::from_json(json).expect("scenario");
    let r = s.run().expect("runs");
    let l = r.lscr.as_ref().expect("LSCR");
    assert_eq!(l.region.groups.len(), 3);
    assert!(l.slice_at.is_some());
    assert_eq!(useful_panels(&r), vec![Panel::Region]);
    let out = report_svg(&r, &View::new(Panel::Region).with_scenario(&s), 960, 640)
        .unwrap_or_else(|e| panic!("n = 3: {e}"));
    for label in [
        "excluded by X̂₃",
        "slice of X̂",
        "x₂ = ",
        "x₄₁,₃",
        "(LSCR, 90 %)",
    ] {
        assert!(out.contains(label), "n = 3: no \"{label}\"");
    }
    std::fs::write(std::env::temp_dir().join("confset-lscr-n3.svg"), &out).ok();
    // At least one group excludes something in view, drawn in its own colour.
    assert!((0..3).any(|g| strokes(&out, &style::hatch_color(g)) > 12));
}

#[test]
fn region_panel_is_fast() {
    // The whole 800 × 600 figure in a few ms (release; generous bound for debug builds).
    for name in ["lscr-predict", "lscr-smooth", "lscr-ma1"] {
        let (s, r) = preset(name);
        let v = View::new(Panel::Region).with_scenario(&s);
        report_svg(&r, &v, 800, 600).expect("warm-up");
        let runs = 20;
        let t0 = std::time::Instant::now();
        for _ in 0..runs {
            report_svg(&r, &v, 800, 600).expect("draws");
        }
        let ms = t0.elapsed().as_secs_f64() * 1e3 / runs as f64;
        eprintln!("region panel {name} 800×600: {ms:.2} ms per SVG");
        assert!(ms < 250.0, "{name}: {ms} ms");
    }
}
