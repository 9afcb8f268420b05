//! Native tests of the figures: every preset draws every useful panel, the legends say what
//! they should, and bad views are errors, not panics.

use super::*;
use crate::presets;
use crate::scenario::FigureContext;
use style::sub;

/// The panel of that name (every name a test uses is one of the registry's).
fn named(name: &str) -> Panel {
    Panel::from_name(name).expect("a panel of some method's figures")
}

fn preset(name: &str) -> (Scenario, Report) {
    let s = presets::get(name).expect("preset exists");
    let r = s.run().expect("preset runs");
    (s, r)
}

fn svg(r: &Report, panel: Panel, time: Option<usize>) -> String {
    let view = View {
        time,
        ..View::new(panel)
    };
    report_svg(r, &view, 960, 640).unwrap_or_else(|e| panic!("{}: {e}", panel.name()))
}

/// Each of `panels` refused on `r`'s report (at w × h): an error on the field `panel` whose
/// message contains `names` (the panels the report does draw).
fn refuses(r: &Report, panels: &[&str], (w, h): (u32, u32), names: &str) {
    for &name in panels {
        let e = report_svg(r, &View::new(named(name)), w, h)
            .expect_err("a report draws its own method's panels only");
        assert_eq!(e.field, "panel", "{name}: {e}");
        assert!(e.message.contains(names), "{name}: {e}");
    }
}

/// Each of `method`'s panels refused on each of the `others` presets' reports: an error on the
/// field `panel` (they have no part of that method).
fn others_refuse(method: Method, others: &[&str]) {
    for &other in others {
        let (_, r) = preset(other);
        for panel in method_panels(method).iter().copied() {
            let e =
                report_svg(&r, &View::new(panel), 800, 600).expect_err("no part of that method");
            assert_eq!(e.field, "panel", "{other} {}: {e}", panel.name());
        }
    }
}

/// `panel` drawn (at w × h) on a copy of `r` that `edit` broke: a broken report is an error,
/// not a panic.
fn broken(
    r: &Report,
    edit: impl FnOnce(&mut Report),
    panel: &str,
    (w, h): (u32, u32),
) -> Result<String> {
    let mut bad = r.clone();
    edit(&mut bad);
    report_svg(&bad, &View::new(named(panel)), w, h)
}

/// The field of the error of [`broken`].
fn broken_field(
    r: &Report,
    edit: impl FnOnce(&mut Report),
    panel: &str,
    size: (u32, u32),
) -> String {
    broken(r, edit, panel, size)
        .expect_err("a broken report is an error")
        .field
}

#[test]
fn scalar_preset_panels_carry_their_legends() {
    let (_, r) = preset("scf-scalar");
    let state = svg(&r, named("state"), None);
    for label in [
        "KF interval",
        "SCF interval",
        "true state",
        "measurements",
        "t = 50",
    ] {
        assert!(state.contains(label), "state panel lacks \"{label}\"");
    }
    let series = svg(&r, named("series"), Some(10));
    for label in ["KF center", "SCF center", "SCF interval", "t = 10"] {
        assert!(series.contains(label), "series panel lacks \"{label}\"");
    }
    let cov = svg(&r, named("coverage"), None);
    for label in ["KF region", "SCF region", "level α = 99 %", "closed form"] {
        assert!(cov.contains(label), "coverage panel lacks \"{label}\"");
    }
}

#[test]
fn robot_preset_shows_both_bodies_and_the_warnings() {
    for name in ["scf-robots", "scf-robots-literal"] {
        let (_, r) = preset(name);
        let state = svg(&r, named("state"), None);
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
        let series = svg(&r, named("series"), None);
        assert!(series.contains("KF center") && series.contains("SCF interval"));
    }
}

#[test]
fn early_times_draw_kf_only_and_say_why() {
    let (s, r) = preset("scf-robots");
    // Before t = n = 8 there is no SCF region; ask for the full-state regions (no target).
    let mut s2 = s.clone();
    s2.scf = None;
    let r2 = s2.run().expect("runs");
    let out = svg(&r2, named("state"), Some(3));
    assert!(out.contains("KF X₃"));
    assert!(!out.contains("SCF X₃"));
    assert!(out.contains("no SCF region at t = 3"));
    // The collision view at an early time still draws.
    let out = svg(&r, named("state"), Some(2));
    assert!(out.contains("KF Z₆|₂"));
}

#[test]
fn coverage_without_a_curve_is_an_error_naming_the_field() {
    let (_, r) = preset("scf-robots");
    assert!(r.coverage_curve.is_none());
    let e = report_svg(&r, &View::new(named("coverage")), 800, 500).expect_err("no coverage curve");
    assert_eq!(e.field, "coverage_curve");
}

#[test]
fn bad_views_are_errors_not_panics() {
    let (_, r) = preset("scf-scalar");
    let view = View {
        time: Some(0),
        ..View::new(named("state"))
    };
    assert_eq!(report_svg(&r, &view, 800, 500).unwrap_err().field, "time");
    let view = View {
        time: Some(51),
        ..View::new(named("series"))
    };
    assert_eq!(report_svg(&r, &view, 800, 500).unwrap_err().field, "time");
    for (w, h) in [(1, 1), (16, 16), (239, 500)] {
        assert_eq!(
            report_svg(&r, &View::new(named("state")), w, h)
                .unwrap_err()
                .field,
            "size"
        );
    }
    // Small but allowed sizes draw every panel.
    for panel in [named("state"), named("series"), named("coverage")] {
        for (w, h) in [(240, 180), (320, 240), (480, 300), (2400, 1600)] {
            let v = View::new(panel);
            if let Err(e) = report_svg(&r, &v, w, h) {
                assert_eq!(e.field, "size", "{} at {w}×{h}: {e}", panel.name());
            }
        }
    }
    let mut broken = r.clone();
    broken.plot = vec![3];
    assert_eq!(
        report_svg(&broken, &View::new(named("state")), 800, 500)
            .unwrap_err()
            .field,
        "plot"
    );
    let mut empty = r.clone();
    empty.steps.clear();
    assert!(report_svg(&empty, &View::new(named("series")), 800, 500).is_err());
}

#[test]
fn frame_maps_the_plotting_area() {
    let (_, r) = preset("scf-scalar");
    let mut text = String::new();
    let f = draw(
        SVGBackend::with_string(&mut text, (900, 600)),
        &r,
        &View::new(named("state")),
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
        &View::new(named("series")),
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
    let (_, r) = preset("scf-scalar");
    let out = svg(&r, named("state"), None);
    // Titles are 17 CSS px: plotters writes font-size = size / 1.24.
    assert!(out.contains("font-size=\"17\""), "title size");
    assert!(out.contains("font-family=\"sans-serif\""));
}

#[test]
fn view_json_takes_what_the_viewer_chooses_only() {
    let v: View = serde_json::from_str(r#"{"panel":"series","time":20}"#).expect("parses");
    assert_eq!(
        (v.panel, v.time, v.zoom),
        (named("series"), Some(20), Zoom::Auto)
    );
    // What the page's figure.js sends before a time is set.
    let v: View = serde_json::from_str(r#"{"panel":"region","time":null}"#).expect("parses");
    assert_eq!((v.panel, v.time), (named("region"), None));
    let back: View =
        serde_json::from_str(&serde_json::to_string(&v).expect("json")).expect("parses");
    assert_eq!(back, v);
    // The scenario's part of the figure comes with the report, never with the view.
    for field in [r#""names":["a"]"#, r#""title":"t""#, r#""measured":[0]"#] {
        let e = serde_json::from_str::<View>(&format!(r#"{{"panel":"state",{field}}}"#))
            .expect_err("context in a view is refused");
        assert!(e.to_string().contains("unknown field"), "{field}: {e}");
    }
}

#[test]
fn the_report_carries_the_figure_context() {
    let (s, r) = preset("scf-robots");
    let f = &r.figure;
    assert_eq!(f.title, s.title);
    assert_eq!(f.collision, s.scf_options().collision);
    // H measures both robots' positions: components 0, 1 and 4, 5 in rows 0 … 3.
    assert_eq!(f.measured, vec![[0, 0], [1, 1], [4, 2], [5, 3]]);
    assert_eq!(f.names[0], "position p_x of robot A [m]");
    assert_eq!(f.names[5], "position p_y of robot B [m]");
    assert_eq!(
        f.names[2], "",
        "not a body's position: the panel's default name"
    );
    // The report JSON holds it (strings, indices, d_min) and reads back the same.
    let json = serde_json::to_value(&r).expect("json");
    assert_eq!(json["figure"]["names"][0], "position p_x of robot A [m]");
    assert_eq!(json["figure"]["measured"][2], serde_json::json!([4, 2]));
    let back: Report = serde_json::from_value(json).expect("parses");
    assert_eq!(back.figure, r.figure);
    // A scenario without a title or collision check: an empty context, `{}` in JSON.
    let mut plain = s.clone();
    plain.title = None;
    plain.scf = None;
    plain.model.h = None;
    let f = FigureContext::of(&plain);
    assert_eq!(f, FigureContext::default());
    assert_eq!(serde_json::to_string(&f).expect("json"), "{}");
}

/// The page path (the preset as the page gets it, JSON → `Scenario::from_json` → `run`, a view
/// parsed from `{"panel": …}`) and the CLI path (`presets::get` → `run` → `View::new(panel)`,
/// as `confset figure`/`figures` do) draw byte-identical SVG for every useful panel of every
/// preset; `scenario_svg` is the first of them.
/// Issue 28: no text of any figure is cut, at the widths the page and slides use (a 2 × 2 grid
/// cell at 1366 px is about 480 px wide, a phone 390 px at DPR 2 draws 660, a single figure 891,
/// a slide 1280), at the page's figure shapes: no `<text>` of the SVG ends in "…" (titles
/// wrap, notes that do not fit are left out whole, axis labels drop their qualifiers).
#[test]
fn no_text_is_cut_at_any_supported_width() {
    let mut cut = Vec::new();
    let mut drawn = 0;
    for p in presets::all() {
        let r = p.scenario.run().expect("preset runs");
        for panel in useful_panels(&r) {
            for w in [480u32, 660, 891, 1280] {
                // The page's shapes (www/style.css): 16:8 for the time series, else 16:10.
                let h = match panel.name() {
                    "series" | "coverage" => w / 2,
                    _ => w * 5 / 8,
                };
                let svg = report_svg(&r, &View::new(panel), w, h)
                    .unwrap_or_else(|e| panic!("{} {} {w}: {e}", p.name, panel.name()));
                drawn += 1;
                for piece in svg.split("<text").skip(1) {
                    let content = piece
                        .split_once('>')
                        .and_then(|(_, rest)| rest.split_once("</text>"))
                        .map_or("", |(t, _)| t.trim());
                    if content.ends_with('…') {
                        cut.push(format!(
                            "{} {} at {w} px: {content:?}",
                            p.name,
                            panel.name()
                        ));
                    }
                }
            }
        }
    }
    assert!(drawn >= 150, "only {drawn} figures drawn");
    assert!(
        cut.is_empty(),
        "{} cut lines:\n{}",
        cut.len(),
        cut.join("\n")
    );
}

/// A figure's height at width `w` in the page's shapes (www/style.css): 16:8 for the time
/// series, else 16:10.
fn page_height(panel: Panel, w: u32) -> u32 {
    match panel.name() {
        "series" | "coverage" => w / 2,
        _ => w * 5 / 8,
    }
}

/// One `<text>` of an SVG drawn here: its content and the box it takes, in figure pixels.
#[derive(Debug, Clone)]
struct TextBox {
    text: String,
    x0: f64,
    y0: f64,
    x1: f64,
    y1: f64,
}

/// The value of attribute `name` in a tag's attribute text.
fn attr<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let at = tag.find(&key)? + key.len();
    tag[at..].split('"').next()
}

/// Every `<text>` of an SVG written by plotters' SVG backend, with the box it takes: its
/// content measured with the same function and font the figures lay their text out with
/// ([`style::text_size`], the embedded DejaVu subset at the style's size: the SVG's
/// `font-size` is the style's size / 1.24), placed by the element's `x`, `y`, `text-anchor`
/// and `dy` (plotters writes "0.76em" for a top anchor, "0.5ex" for a centred one, "-0.5ex"
/// for a bottom one) and turned by its `rotate(…)` about (x, y).
fn text_boxes(svg: &str) -> Vec<TextBox> {
    ensure_fonts().expect("the embedded font");
    let mut scratch = String::new();
    let backend = SVGBackend::with_string(&mut scratch, (16, 16));
    let area = backend.into_drawing_area();
    let mut out = Vec::new();
    for piece in svg.split("<text").skip(1) {
        let Some((tag, rest)) = piece.split_once('>') else {
            continue;
        };
        let Some((raw, _)) = rest.split_once("</text>") else {
            continue;
        };
        let raw = raw.strip_prefix('\n').unwrap_or(raw);
        let raw = raw.strip_suffix('\n').unwrap_or(raw);
        let text = raw
            .replace("&lt;", "<")
            .replace("&gt;", ">")
            .replace("&quot;", "\"")
            .replace("&apos;", "'")
            .replace("&amp;", "&");
        if text.trim().is_empty() {
            continue;
        }
        let num = |name: &str| attr(tag, name).and_then(|v| v.parse::<f64>().ok());
        let (Some(x), Some(y), Some(size)) = (num("x"), num("y"), num("font-size")) else {
            panic!("a <text> without x, y or font-size: <text{tag}>");
        };
        let style: TextStyle = if attr(tag, "font-weight") == Some("bold") {
            ("sans-serif", size * 1.24, FontStyle::Bold)
                .into_font()
                .into()
        } else {
            ("sans-serif", size * 1.24).into_font().into()
        };
        let (w, h) = style::text_size(&area, &text, &style).expect("measures");
        let (w, h) = (f64::from(w), f64::from(h));
        let dx0 = match attr(tag, "text-anchor") {
            Some("middle") => -w / 2.0,
            Some("end") => -w,
            _ => 0.0,
        };
        let dy0 = match attr(tag, "dy") {
            Some("0.76em") => 0.0,
            Some("0.5ex") => -h / 2.0,
            Some("-0.5ex") => -h,
            other => panic!("a <text> with dy {other:?}"),
        };
        // Rotation about (x, y), clockwise on screen by `deg` (SVG's sense).
        let deg = attr(tag, "transform")
            .and_then(|t| t.strip_prefix("rotate("))
            .and_then(|t| t.split(',').next())
            .and_then(|a| a.trim().parse::<f64>().ok())
            .unwrap_or(0.0);
        let (sin, cos) = deg.to_radians().sin_cos();
        let corners = [
            (dx0, dy0),
            (dx0 + w, dy0),
            (dx0, dy0 + h),
            (dx0 + w, dy0 + h),
        ]
        .map(|(dx, dy)| (x + dx * cos - dy * sin, y + dx * sin + dy * cos));
        let fold = |f: fn(f64, f64) -> f64, k: usize, init: f64| {
            corners
                .iter()
                .map(|c| if k == 0 { c.0 } else { c.1 })
                .fold(init, f)
        };
        out.push(TextBox {
            text,
            x0: fold(f64::min, 0, f64::INFINITY),
            y0: fold(f64::min, 1, f64::INFINITY),
            x1: fold(f64::max, 0, f64::NEG_INFINITY),
            y1: fold(f64::max, 1, f64::NEG_INFINITY),
        });
    }
    out
}

/// How far two boxes overlap: the smaller of the overlaps along x and along y (≤ 0: apart).
fn overlap(a: &TextBox, b: &TextBox) -> f64 {
    let ox = a.x1.min(b.x1) - a.x0.max(b.x0);
    let oy = a.y1.min(b.y1) - a.y0.max(b.y0);
    ox.min(oy)
}

/// Issue 28: labels avoid each other. Every preset × useful panel × {480, 660, 891, 1280} px
/// at the page's shapes (as [`no_text_is_cut_at_any_supported_width`]): no two texts of the
/// figure overlap by more than a pixel (titles, notes, axis names, tick labels, legends,
/// labels on the chart, the cursor's) and none leaves the figure. The boxes are those of the
/// drawn SVG ([`text_boxes`]), so every text counts, whoever drew it (plotters' own tick
/// labels as much as the panels' labels), measured as the layout measured it.
#[test]
fn no_two_texts_overlap_at_any_supported_width() {
    let mut bad = Vec::new();
    let mut drawn = 0;
    let mut texts = 0;
    for p in presets::all() {
        let r = p.scenario.run().expect("preset runs");
        for panel in useful_panels(&r) {
            for w in [480u32, 660, 891, 1280] {
                let h = page_height(panel, w);
                let svg = report_svg(&r, &View::new(panel), w, h)
                    .unwrap_or_else(|e| panic!("{} {} {w}: {e}", p.name, panel.name()));
                drawn += 1;
                let boxes = text_boxes(&svg);
                texts += boxes.len();
                let at = format!("{} {} at {w}×{h}", p.name, panel.name());
                for b in &boxes {
                    if b.x0 < -0.5 || b.y0 < -0.5 || b.x1 > w as f64 + 0.5 || b.y1 > h as f64 + 0.5
                    {
                        bad.push(format!(
                            "{at}: {:?} leaves the figure ({:.0}, {:.0})–({:.0}, {:.0})",
                            b.text, b.x0, b.y0, b.x1, b.y1
                        ));
                    }
                }
                for (i, a) in boxes.iter().enumerate() {
                    for b in &boxes[i + 1..] {
                        let o = overlap(a, b);
                        if o > 1.0 {
                            bad.push(format!(
                                "{at}: {:?} and {:?} overlap by {o:.0} px",
                                a.text, b.text
                            ));
                        }
                    }
                }
            }
        }
    }
    assert!(drawn >= 150, "only {drawn} figures drawn");
    assert!(texts >= 20 * drawn, "only {texts} texts in {drawn} figures");
    assert!(
        bad.is_empty(),
        "{} overlapping or outside texts:\n{}",
        bad.len(),
        bad.join("\n")
    );
}

/// The boxes [`text_boxes`] reads back are where the text is: a title at the top left, a
/// rotated y-axis name tall and narrow at the left edge, and two texts drawn on top of each
/// other are found overlapping (the check above can fail).
#[test]
fn text_boxes_are_where_the_text_is() {
    let mut s = String::new();
    {
        let root = SVGBackend::with_string(&mut s, (300, 200)).into_drawing_area();
        let fonts = Fonts::for_backend::<SVGBackend>((300, 200));
        let st = fonts.title();
        use plotters::style::text_anchor::{HPos, VPos};
        style::text(&root, "Title", (10, 10), &st, (HPos::Left, VPos::Top)).unwrap();
        style::text(&root, "Tit", (12, 14), &st, (HPos::Left, VPos::Top)).unwrap();
        let rot = fonts
            .axis()
            .transform(plotters::style::FontTransform::Rotate270);
        style::text(
            &root,
            "a long axis name",
            (6, 100),
            &rot,
            (HPos::Center, VPos::Top),
        )
        .unwrap();
    }
    let b = text_boxes(&s);
    assert_eq!(b.len(), 3, "{b:?}");
    assert!(
        (b[0].x0 - 10.0).abs() < 0.5 && (b[0].y0 - 10.0).abs() < 0.5,
        "{:?}",
        b[0]
    );
    assert!(
        b[0].x1 - b[0].x0 > 30.0 && b[0].y1 - b[0].y0 > 10.0,
        "{:?}",
        b[0]
    );
    assert!(overlap(&b[0], &b[1]) > 1.0, "{b:?}");
    let r = &b[2];
    assert!(
        r.y1 - r.y0 > 3.0 * (r.x1 - r.x0),
        "rotated: tall and narrow {r:?}"
    );
    assert!(r.x0 >= 5.5 && r.y0 < 100.0 && r.y1 > 100.0, "{r:?}");
    assert!(overlap(&b[0], r) <= 0.0, "{b:?}");
}

/// The boxes [`text_boxes`] measures hold the ink the PNG export renders: for every preset's
/// every useful panel at the smallest and the largest supported width, resvg (with the embedded
/// font the layout measured with) draws each `<text>` inside its box, give or take a pixel. So
/// a figure that passes [`no_two_texts_overlap_at_any_supported_width`] has no glyphs on top of
/// each other in the exported picture.
#[test]
fn text_boxes_hold_what_resvg_renders() {
    use resvg::usvg;
    fn texts(g: &usvg::Group, out: &mut Vec<usvg::Rect>) {
        for n in g.children() {
            match n {
                usvg::Node::Group(g) => texts(g, out),
                // The glyphs' outlines: the ink.
                usvg::Node::Text(t) => out.push(t.flattened().abs_bounding_box()),
                _ => {}
            }
        }
    }
    let mut options = usvg::Options::default();
    options.fontdb_mut().load_font_data(FONT.to_vec());
    options.fontdb_mut().set_sans_serif_family("DejaVu Sans");
    let mut compared = 0;
    for p in presets::all() {
        let r = p.scenario.run().expect("preset runs");
        for panel in useful_panels(&r) {
            for w in [480u32, 1280] {
                let h = page_height(panel, w);
                let svg = report_svg(&r, &View::new(panel), w, h).expect("draws");
                let ours = text_boxes(&svg);
                let tree = usvg::Tree::from_str(&svg, &options).expect("parses");
                let mut ink = Vec::new();
                texts(tree.root(), &mut ink);
                assert_eq!(
                    ours.len(),
                    ink.len(),
                    "{} {} {w}: texts",
                    p.name,
                    panel.name()
                );
                for (b, i) in ours.iter().zip(&ink) {
                    compared += 1;
                    // A pixel of rounding; a combining accent over a capital (x̂, B̂) inks
                    // a little above the line's box (to the left of a rotated one).
                    let (sx, sy) = (3.0, 3.0);
                    assert!(
                        f64::from(i.left()) >= b.x0 - sx
                            && f64::from(i.right()) <= b.x1 + sx
                            && f64::from(i.top()) >= b.y0 - sy
                            && f64::from(i.bottom()) <= b.y1 + sy,
                        "{} {} {w}: {:?} is drawn at {i:?}, outside its box {b:?}",
                        p.name,
                        panel.name(),
                        b.text
                    );
                }
            }
        }
    }
    assert!(compared > 1000, "only {compared} texts compared");
}

#[test]
fn page_and_cli_draw_the_same_figure_for_every_preset() {
    for p in presets::all() {
        let json = serde_json::to_string(&p.scenario).expect("json");
        let page = Scenario::from_json(&json)
            .and_then(|s| s.run())
            .expect("page path runs");
        let cli = presets::get(&p.name)
            .and_then(|s| s.run())
            .expect("CLI path runs");
        assert_eq!(page.figure, cli.figure, "{}: figure context", p.name);
        let panels = useful_panels(&cli);
        for &panel in &panels {
            let view: View = serde_json::from_str(&format!(r#"{{"panel":"{}"}}"#, panel.name()))
                .expect("view JSON");
            let a = report_svg(&page, &view, 960, 640)
                .unwrap_or_else(|e| panic!("{} {}: {e}", p.name, panel.name()));
            let b = report_svg(&cli, &View::new(panel), 960, 640).expect("draws");
            assert!(
                a == b,
                "{} {}: page and CLI figures differ",
                p.name,
                panel.name()
            );
        }
        let first = scenario_svg(&p.scenario, 960, 640).expect("draws");
        let b = report_svg(&cli, &View::new(panels[0]), 960, 640).expect("draws");
        assert!(first == b, "{}: scenario_svg differs", p.name);
    }
}

#[test]
fn robot_state_figure_names_the_robot_position_axes() {
    let (_, r) = preset("scf-robots");
    let view: View = serde_json::from_str(r#"{"panel":"state"}"#).expect("view JSON");
    let out = report_svg(&r, &view, 960, 640).expect("draws");
    assert!(
        out.contains("position p_x"),
        "x axis names robot A's position"
    );
    assert!(!out.contains("state component"), "no generic axis names");
    let mut frame_svg = String::new();
    let frame = draw(
        SVGBackend::with_string(&mut frame_svg, (960, 640)),
        &r,
        &view,
    )
    .expect("draws");
    assert!(
        frame.x_label.starts_with("position p_x"),
        "{}",
        frame.x_label
    );
    assert!(
        frame.y_label.starts_with("position p_y"),
        "{}",
        frame.y_label
    );
}

#[test]
fn every_preset_draws_every_useful_panel_at_page_sizes() {
    for p in presets::all() {
        let r = p.scenario.run().expect("preset runs");
        for panel in useful_panels(&r) {
            for (w, h) in [(960, 640), (900, 450), (400, 250)] {
                let v = View::new(panel);
                let out = report_svg(&r, &v, w, h)
                    .unwrap_or_else(|e| panic!("{} {} {w}×{h}: {e}", p.name, panel.name()));
                // LSCR reports draw the region (whose legend names X̂, shortly on small figures);
                // a compare names every method (Kalman first);
                // GLLS reports mark the horizon in use (the plane: the true state); the others
                // KF/SCF.
                let expect = match (r.lscr.is_some(), r.glls.is_some(), panel.name()) {
                    (_, _, "upolygon") => "true state",
                    // The compare legend names each method's set.
                    (_, _, "compare") => "Kalman",
                    _ if panel.method() == Method::UniformLp => "t = ",
                    _ if panel.method() == Method::Ubb => "k = ",
                    // Conformal's sets beside the filter's own.
                    _ if panel.method() == Method::Conformal => "Kalman",
                    (true, _, _) => "X̂ ",
                    (_, true, "plane") => "true state",
                    (_, true, _) => "in use",
                    _ => "KF",
                };
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

/// Every size a figure is drawn at: the smallest, the page's cards and grids, slides.
const SIZES: [(u32, u32); 7] = [
    (240, 180),
    (320, 240),
    (400, 250),
    (640, 400),
    (800, 600),
    (960, 640),
    (1600, 1200),
];

/// Every method's every panel, drawn from every preset of the method at every size: the
/// plotting area lies inside the figure, the ranges increase and the figure is not empty; each
/// name parses back to its panel, from the CLI and from a view's JSON. The loop is over the
/// registries (methods, their figures, the presets), so a method or a panel that no preset
/// draws fails here. KF has no preset of its own: its reports are the SCF presets run with
/// method "kf".
#[test]
fn every_method_draws_every_panel_at_every_size() {
    let presets = presets::all();
    for m in Method::ALL {
        let mut reports = Vec::new();
        for p in &presets {
            let mut s = p.scenario.clone();
            if m == Method::Kf && s.method == Method::Scf {
                s.method = Method::Kf;
            }
            if s.method == m {
                reports.push((p.name.clone(), s.run().expect("preset runs")));
            }
        }
        assert!(!reports.is_empty(), "no preset draws the figures of {m}");
        for &panel in method_panels(m) {
            assert_eq!(Panel::from_name(panel.name()).expect("parses"), panel);
            let v: View = serde_json::from_str(&format!("{{\"panel\":\"{}\"}}", panel.name()))
                .expect("parses");
            assert_eq!(v.panel, panel);
            let mut drawn = 0;
            for (name, r) in reports
                .iter()
                .filter(|(_, r)| useful_panels(r).contains(&panel))
            {
                for (w, h) in SIZES {
                    let mut out = String::new();
                    let f = draw(
                        SVGBackend::with_string(&mut out, (w, h)),
                        r,
                        &View::new(panel),
                    )
                    .unwrap_or_else(|e| panic!("{name} {} {w}×{h}: {e}", panel.name()));
                    let (l, t, rt, b) = f.plot_area;
                    assert!(
                        0 <= l && l < rt && rt <= w as i32 && 0 <= t && t < b && b <= h as i32,
                        "{name} {} {w}×{h}: {f:?}",
                        panel.name()
                    );
                    assert!(
                        f.x_range.0 < f.x_range.1 && f.y_range.0 < f.y_range.1,
                        "{name} {} {w}×{h}: {f:?}",
                        panel.name()
                    );
                    assert!(
                        out.len() > 2000 && out.contains("<svg"),
                        "{name} {} {w}×{h}: empty",
                        panel.name()
                    );
                }
                drawn += 1;
            }
            assert!(
                drawn > 0,
                "no preset of {m} fills the panel {}",
                panel.name()
            );
        }
    }
}

/// Panel names are unique across methods (a name resolves to one panel), except that KF shares
/// SCF's figures.
#[test]
fn panel_names_resolve_to_their_method() {
    let mut seen: Vec<(&str, Method)> = Vec::new();
    for m in Method::ALL {
        for p in method_panels(m) {
            if let Some((_, other)) = seen.iter().find(|(n, _)| *n == p.name()) {
                assert!(
                    make_figures(*other).panels() == make_figures(m).panels(),
                    "{} is a panel of {other} and of {m}",
                    p.name()
                );
            } else {
                seen.push((p.name(), m));
                assert_eq!(p.method(), m, "{}", p.name());
            }
        }
    }
    let e = Panel::from_name("nope").unwrap_err();
    assert_eq!(e.field, "panel");
    assert!(
        e.message.contains("state, series, coverage, region"),
        "{}",
        e.message
    );
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
    let out = svg(&r, named("state"), None);
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
        assert_eq!(useful_panels(&r), vec![named("region")], "{name}");
        // The default figure of an LSCR scenario is the region.
        let out = scenario_svg(&s, 800, 600).expect("draws");
        assert!(
            out.contains("X̂ (LSCR, 90 %)"),
            "{name}: not the region figure"
        );
    }
    let (_, r) = preset("scf-scalar");
    assert!(!useful_panels(&r).contains(&named("region")));
    assert_eq!(Panel::from_name("region").expect("parses"), named("region"));
    assert_eq!(named("region").name(), "region");
    let v: View = serde_json::from_str(r#"{"panel":"region"}"#).expect("parses");
    assert_eq!(v.panel, named("region"));
}

#[test]
fn region_panel_hatches_and_holds_the_window_small_and_large() {
    for name in ["lscr-predict", "lscr-smooth", "lscr-ma1"] {
        let (_, r) = preset(name);
        let l = r.lscr.as_ref().expect("LSCR report");
        for (w, h) in [(240, 180), (960, 640)] {
            let view = View::new(named("region"));
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
    let (_, r) = preset("lscr-predict");
    let out = report_svg(&r, &View::new(named("region")), 800, 600).expect("draws");
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
    let (_, r) = preset("lscr-smooth");
    let out = report_svg(&r, &View::new(named("region")), 800, 600).expect("draws");
    for label in ["smoothing", "x₁₅,₁", "BLUE ellipse 90 %"] {
        assert!(out.contains(label), "Fig. 2: no \"{label}\"");
    }
    assert!(!out.contains("KF ellipse"));
    // Fig. 3: the unbounded band along [1, 1] with the Kalman ellipse and no BLUE.
    let (_, r) = preset("lscr-ma1");
    assert!(!r.lscr.as_ref().expect("LSCR").bounded);
    let out = report_svg(&r, &View::new(named("region")), 800, 600).expect("draws");
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
    let hatches = lscr::region::hatch_segments(&plane, win, p0, p1, 7.0).expect("hatches");
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
    let (_, r) = preset("lscr-ma1");
    for panel in [named("state"), named("series"), named("coverage")] {
        let e = report_svg(&r, &View::new(panel), 800, 600)
            .expect_err("an LSCR report has no time steps");
        assert_eq!(e.field, "panel", "{}: {e}", panel.name());
        assert!(e.message.contains("region"), "{e}");
    }
    let (_, r) = preset("scf-scalar");
    let e = report_svg(&r, &View::new(named("region")), 800, 600).expect_err("no LSCR part");
    assert_eq!(e.field, "panel");
    assert!(e.message.contains("scf"), "{e}");
    // Too small is still a size error, and a broken window a clear one.
    let (_, mut r) = preset("lscr-predict");
    assert_eq!(
        report_svg(&r, &View::new(named("region")), 200, 100)
            .unwrap_err()
            .field,
        "size"
    );
    if let Some(l) = r.lscr.as_mut() {
        l.window.hi[0] = l.window.lo[0];
    }
    let e = report_svg(&r, &View::new(named("region")), 800, 600).unwrap_err();
    assert_eq!(e.field, "report.lscr.window");
}

#[test]
fn region_panel_zoom_choices_draw() {
    let (_, r) = preset("lscr-predict");
    let l = r.lscr.as_ref().expect("LSCR");
    let mut widths = Vec::new();
    for zoom in [Zoom::Regions, Zoom::Auto, Zoom::Full] {
        let v = View {
            zoom,
            ..View::new(named("region"))
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
    assert_eq!(useful_panels(&r), vec![named("region")]);
    let out = report_svg(&r, &View::new(named("region")), 960, 640)
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

// ---------------------------------------------------------------- the GLLS panels

const GLLS_PRESETS: [&str; 4] = ["glls-saturate", "glls-grow", "glls-mixed", "glls-unstable5"];

/// The SVG `<polyline>` elements drawn in `color` with `width`, as their point counts.
fn polylines(svg: &str, color: &RGBColor, width: u32) -> Vec<usize> {
    let hex = format!("stroke=\"#{:02X}{:02X}{:02X}\"", color.0, color.1, color.2);
    let w = format!("stroke-width=\"{width}\"");
    svg.split("<polyline")
        .skip(1)
        .map(|el| el.split("/>").next().unwrap_or(""))
        .filter(|el| el.contains(hex.as_str()) && el.contains(w.as_str()))
        .map(|el| {
            el.split("points=\"")
                .nth(1)
                .and_then(|p| p.split('"').next())
                .map_or(0, |p| p.split_whitespace().count())
        })
        .collect()
}

/// `<rect` elements filled with `color` (any opacity).
fn rects(svg: &str, color: &RGBColor) -> usize {
    let hex = format!("fill=\"#{:02X}{:02X}{:02X}\"", color.0, color.1, color.2);
    svg.split("<rect")
        .skip(1)
        .filter(|el| el.split("/>").next().unwrap_or("").contains(hex.as_str()))
        .count()
}

#[test]
fn glls_reports_use_the_glls_panels() {
    for name in GLLS_PRESETS {
        let (s, r) = preset(name);
        assert_eq!(
            useful_panels(&r),
            vec![
                named("singular"),
                named("index"),
                named("plane"),
                named("precision")
            ],
            "{name}"
        );
        // The default figure is Fig. 1.
        let out = scenario_svg(&s, 800, 600).expect("draws");
        assert!(
            out.contains("Singular values of Γₛ₊₁"),
            "{name}: not Fig. 1"
        );
    }
    for p in method_panels(Method::Glls).iter().copied() {
        assert_eq!(Panel::from_name(p.name()).expect("parses"), p);
        let v: View =
            serde_json::from_str(&format!("{{\"panel\":\"{}\"}}", p.name())).expect("parses");
        assert_eq!(v.panel, p);
    }
    // Without a Monte Carlo study there is no precision panel (and asking for it says why).
    let (mut s, _) = preset("glls-grow");
    if let Some(g) = s.glls.as_mut() {
        g.monte_carlo = None;
    }
    let r = s.run().expect("runs");
    assert_eq!(
        useful_panels(&r),
        vec![named("singular"), named("index"), named("plane")]
    );
    let e = report_svg(&r, &View::new(named("precision")), 800, 600).unwrap_err();
    assert_eq!(e.field, "glls.monte_carlo");
}

#[test]
fn singular_panel_draws_n_solid_and_n_dashed_curves() {
    for name in GLLS_PRESETS {
        let (_, r) = preset(name);
        let g = r.glls.as_ref().expect("GLLS");
        assert!(g.curves.log10_sigma_prime.is_some(), "{name}: A invertible");
        let out = report_svg(&r, &View::new(named("singular")), 960, 640).expect("draws");
        for i in 0..g.n {
            let c = style::series_color(i);
            // The solid curve: one long polyline (plus the legend swatch of 2 points).
            let lines = polylines(&out, &c, 2);
            assert!(
                lines.iter().any(|&k| k > 10),
                "{name}: no solid curve of σ{}: {lines:?}",
                i + 1
            );
            // The dashed curve: many short pieces of the same colour.
            assert!(
                lines.iter().filter(|&&k| k == 2).count() > 5,
                "{name}: no dashed curve of σ{}",
                i + 1
            );
            assert!(out.contains(&format!("σ{}(Γₛ₊₁)", sub(i + 1))), "{name}");
        }
        assert!(
            !out.contains(&format!("σ{}(Γₛ₊₁)", sub(g.n + 1))),
            "{name}: too many legend entries"
        );
        for label in [
            "σᵢ(Γ A⁻ˢ) — the paper&apos;s remark says equal",
            &format!("s = {} in use", g.s),
            "log scale",
            "10⁰",
        ] {
            assert!(out.contains(label), "{name}: no \"{label}\"");
        }
    }
    // The floor band is drawn where it matters (σ₅ of the unstable system comes within a
    // decade of it) and only noted where it is far below.
    let (_, r) = preset("glls-unstable5");
    let out = report_svg(&r, &View::new(named("singular")), 960, 640).unwrap();
    assert!(out.contains("below: not resolved in double precision"));
    let (_, r) = preset("glls-saturate");
    let out = report_svg(&r, &View::new(named("singular")), 960, 640).unwrap();
    assert!(!out.contains("below: not resolved in double precision"));
    assert!(out.contains("every drawn σ is resolved"));
}

#[test]
fn index_panel_marks_the_best_horizons() {
    let (_, r) = preset("glls-saturate");
    let g = r.glls.as_ref().expect("GLLS");
    let out = report_svg(&r, &View::new(named("index")), 960, 640).unwrap();
    let b = g.best_horizon.expect("a best horizon");
    let bp = g.best_horizon_p.expect("a best regularized horizon");
    assert!(
        out.contains(&format!("best s = {b}")),
        "no best-horizon label"
    );
    assert!(out.contains(&format!("best s = {bp} (p = 2)")));
    assert!(out.contains("σ₃/√s (n = 3)") && out.contains("σ₂/√s (p = 2, regularized)"));
    // Fig. 2b: the index grows over the whole range.
    let (_, r) = preset("glls-grow");
    let out = report_svg(&r, &View::new(named("index")), 960, 640).unwrap();
    assert!(out.contains("largest at S = 60") && out.contains("still grows"));
    // A best horizon beyond the data is said so.
    let (_, r) = preset("glls-mixed");
    let out = report_svg(&r, &View::new(named("index")), 960, 640).unwrap();
    assert!(out.contains("best s = 48") && out.contains("the data hold 40"));
}

#[test]
fn precision_panel_draws_one_box_per_horizon() {
    for name in GLLS_PRESETS {
        let (_, r) = preset(name);
        let p = r
            .glls
            .as_ref()
            .and_then(|g| g.precision.as_ref())
            .expect("a study");
        let drawn = p.first.iter().filter(|x| x.is_some()).count();
        let out = report_svg(&r, &View::new(named("precision")), 960, 640).expect("draws");
        match &p.second {
            None => {
                // One box per horizon, plus the legend swatch.
                assert_eq!(rects(&out, &style::GLLS_EST), drawn + 1, "{name}");
                assert!(out.contains("bound κ·√E‖δ‖² (39)"), "{name}");
                assert!(out.contains("Fig. 3") || out.contains("Precision against"));
            }
            Some(second) => {
                // Fig. 4: paired half-boxes in two colours.
                let lls = second.iter().filter(|x| x.is_some()).count();
                assert_eq!(rects(&out, &style::STATE_NOISE), drawn + 1, "{name}");
                assert_eq!(rects(&out, &style::GLLS_EST), lls + 1, "{name}");
                assert!(
                    out.contains("state-noise estimator (left)") && out.contains("LLS (right)")
                );
                // ‖x(k)‖ ≈ 2.5·10⁷ is far above errors of order 1: a note, not a line.
                assert!(out.contains("far above the axis"), "{name}");
            }
        }
    }
}

#[test]
fn plane_panel_shows_the_sets_and_says_when_the_truth_is_outside() {
    let (_, r) = preset("glls-saturate");
    let out = report_svg(&r, &View::new(named("plane")), 960, 640).unwrap();
    for label in [
        "true state x(39)",
        "LLS estimate x̂(39)",
        "guaranteed ball (35), r = 0.168",
        "interval box (exact hull)",
        "regularized estimate (p = 2)",
        "projected truth",
        "in ball: yes, in box: yes",
        "x₂(39)",
        "x₃(39)",
    ] {
        assert!(out.contains(label), "saturate plane: no \"{label}\"");
    }
    assert!(!out.contains("outside:"));
    // The unstable system has state noise and μ = 0: the truth is outside, the sets are a point.
    let (_, r) = preset("glls-unstable5");
    let out = report_svg(&r, &View::new(named("plane")), 960, 640).unwrap();
    for label in [
        "state-noise estimate (63)–(64)",
        "LLS estimate (centre of ball and box)",
        "outside: the sets cover only measurement noise",
        "μ = 0",
    ] {
        assert!(out.contains(label), "unstable5 plane: no \"{label}\"");
    }
    // Noise beyond μ is named as the reason.
    let (_, mut r) = preset("glls-saturate");
    if let Some(g) = r.glls.as_mut() {
        g.truth_in_ball = Some(false);
        g.noise_max = Some(0.2);
        g.rounding_dominates = true;
    }
    let out = report_svg(&r, &View::new(named("plane")), 960, 640).unwrap();
    assert!(out.contains("outside: the noise exceeded μ"));
    assert!(out.contains("floating point: estimated rounding error"));
    // Huge coordinates get an offset so the ticks stay short.
    let (_, r) = preset("glls-grow");
    let out = report_svg(&r, &View::new(named("plane")), 960, 640).unwrap();
    assert!(out.contains("x₁(39) − 14715"), "no offset on the x axis");
}

#[test]
fn the_horizon_marker_follows_the_horizon_in_use() {
    let (_, r) = preset("glls-saturate");
    let mut r2 = r.clone();
    if let Some(g) = r2.glls.as_mut() {
        g.s = 20;
    }
    for panel in [named("singular"), named("index"), named("precision")] {
        let v = View::new(panel);
        let a = report_svg(&r, &v, 800, 600).unwrap();
        let b = report_svg(&r2, &v, 800, 600).unwrap();
        assert_ne!(a, b, "{}", panel.name());
        assert!(a.contains("s = 8 in use") && b.contains("s = 20 in use"));
    }
}

#[test]
fn glls_and_other_panels_do_not_mix() {
    let (_, r) = preset("glls-mixed");
    let size = (800, 600);
    refuses(
        &r,
        &["state", "series", "coverage", "region"],
        size,
        "singular",
    );
    others_refuse(Method::Glls, &["scf-scalar", "lscr-predict"]);
    // Broken reports are errors, not panics.
    let (_, r) = preset("glls-saturate");
    let curves = |r: &mut Report| {
        if let Some(g) = r.glls.as_mut() {
            g.curves.log10_floor.pop();
        }
    };
    assert_eq!(
        broken_field(&r, curves, "singular", size),
        "report.glls.curves"
    );
    let plane = |r: &mut Report| {
        if let Some(g) = r.glls.as_mut() {
            g.plane = [0, 7];
        }
    };
    assert_eq!(broken_field(&r, plane, "plane", size), "report.glls.plane");
    let index = |r: &mut Report| {
        if let Some(g) = r.glls.as_mut() {
            g.index = vec![-400.0; g.index.len()];
            g.index_p = None;
            if let Some(p) = g.precision.as_mut() {
                p.bound.pop();
            }
        }
    };
    assert!(broken(&r, index, "index", size).is_err());
    assert_eq!(
        broken_field(&r, index, "precision", size),
        "report.glls.precision"
    );
    assert_eq!(broken_field(&r, |_| {}, "plane", (200, 100)), "size");
}

#[test]
fn log_ticks_read_as_powers_of_ten() {
    let t = style::log_ticks(-15.3, 1.2, 400);
    let labels: Vec<&str> = t
        .iter()
        .filter(|t| !t.label.is_empty())
        .map(|t| t.label.as_str())
        .collect();
    assert!(
        labels.contains(&"10⁻¹⁴") && labels.contains(&"10⁰"),
        "{labels:?}"
    );
    let t = style::log_ticks(-1.2, -0.4, 400);
    let labels: Vec<&str> = t
        .iter()
        .filter(|t| !t.label.is_empty())
        .map(|t| t.label.as_str())
        .collect();
    assert!(
        labels.contains(&"0.1") && labels.contains(&"0.2"),
        "{labels:?}"
    );
    assert!(style::log_ticks(1.0, 1.0, 400).is_empty());
    assert_eq!(style::pow10(-5), "10⁻⁵");
}

// ------------------------------------------------------------------ uniform innovations

/// `<polygon` elements filled with `color` (any opacity).
fn polygons(svg: &str, color: &RGBColor) -> usize {
    let hex = format!("fill=\"#{:02X}{:02X}{:02X}\"", color.0, color.1, color.2);
    svg.split("<polygon")
        .skip(1)
        .filter(|el| el.split("/>").next().unwrap_or("").contains(hex.as_str()))
        .count()
}

#[test]
fn uniform_reports_use_the_uniform_panels() {
    let (s, r) = preset("uniform-paper");
    assert_eq!(useful_panels(&r), method_panels(Method::UniformLp).to_vec());
    let out = scenario_svg(&s, 800, 600).expect("draws");
    assert!(out.contains("Fig. 1"), "the default figure is Fig. 1");
}

#[test]
fn uniform_panels_show_what_the_papers_figures_show() {
    let (_, r) = preset("uniform-paper");
    let u = r.uniform.as_ref().expect("uniform");
    let n = u.n;
    // Fig. 1: per component a truth, an LP and a KF curve in the states row and LP/KF errors.
    let states = svg(&r, named("ustates"), None);
    for label in [
        "true state",
        "LP (MAP) estimate",
        "KF with the true Θ",
        "optimal face",
        "t = 120",
    ] {
        assert!(states.contains(label), "ustates: no \"{label}\"");
    }
    // The curves' points (a curve may be split into several polylines): the truth x_0 … x_T
    // once per component; the LP estimate and its error once each per component.
    let points = |svg: &str, c: &RGBColor| polylines(svg, c, 2).into_iter().sum::<usize>();
    let steps = u.steps.len();
    let truth = points(&states, &style::TRUTH);
    assert!(
        truth >= n * (steps - 10) && truth <= n * (steps + 40),
        "one true curve per component: {truth} points"
    );
    let lp = points(&states, &style::UNIFORM_LP);
    assert!(
        lp >= 2 * n * (steps - 10) && lp <= 2 * n * (steps + 40),
        "LP: estimate and error per component: {lp} points"
    );
    // The KF is dashed: many short pieces rather than one polyline; it is there.
    assert!(polylines(&states, &style::KF, 2).len() > 50);
    // The face bars: one I-beam (3 px stem) per state of the window, per component.
    let stems = polylines(&states, &style::FACE, 3).len();
    assert_eq!(
        stems,
        n * u.at.face_lo.len() + 1,
        "bars plus the legend swatch"
    );

    // Fig. 2: output and prediction, and the error.
    let output = svg(&r, named("uoutput"), None);
    for label in ["measured output", "one-step prediction", "t = 120"] {
        assert!(output.contains(label), "uoutput: no \"{label}\"");
    }
    let y = points(&output, &style::TRUTH);
    assert!(
        y >= steps - 10 && y <= steps + 40,
        "one output curve: {y} points"
    );
    let p = points(&output, &style::UNIFORM_LP);
    assert!(
        p >= 2 * (steps - 10) && p <= 2 * (steps + 40),
        "prediction and error: {p} points"
    );

    // Fig. 3: n² entries of Â and n + m half-widths, each with its true value dashed (thin).
    let params = svg(&r, named("uparams"), None);
    for label in ["â₁₁", "â₂₂", "x̂ᵣ,₁", "ŷᵣ", "true value", "Fig. 3"] {
        assert!(params.contains(label), "uparams: no \"{label}\"");
    }
    let m = u.yr_true.as_ref().expect("simulated").len();
    for k in 0..n * n + n + m {
        let c = style::series_color(k);
        assert!(points(&params, &c) >= steps - 10, "curve {k}");
        // The true value: a thin dashed line across the chart (dashes are pieces of width 1).
        assert!(
            polylines(&params, &c, 1).len() >= 10,
            "true value of curve {k}"
        );
    }

    // The polygon: one filled polygon, the markers and the note on Θ.
    let poly = svg(&r, named("upolygon"), None);
    assert_eq!(
        polygons(&poly, &style::POLYGON),
        1,
        "one consistent-state polygon"
    );
    assert_eq!(rects(&poly, &style::POLYGON), 1, "its legend swatch");
    for label in [
        "true state",
        "LP (MAP) estimate",
        "KF estimate",
        "consistent states",
        "optimal face",
    ] {
        assert!(poly.contains(label), "upolygon: no \"{label}\"");
    }
    assert!(!u.at.polygon_theta_true);
    assert!(poly.contains("not guaranteed"));
    assert!(!poly.contains("truth outside"));
    // With the true Θ the note says it is guaranteed; a truth outside is said.
    let mut r2 = r.clone();
    if let Some(u) = r2.uniform.as_mut() {
        u.at.polygon_theta_true = true;
        u.at.truth_in_polygon = Some(false);
    }
    let poly2 = svg(&r2, named("upolygon"), None);
    assert!(
        poly2.contains("guaranteed to hold the true state") && !poly2.contains("not guaranteed")
    );
    assert!(poly2.contains("truth outside"));
}

#[test]
fn the_uniform_cursor_follows_the_window_time() {
    let (_, r) = preset("uniform-paper");
    let mut moved = r.clone();
    if let Some(u) = moved.uniform.as_mut() {
        u.at.time = 60;
        u.at.first = 56;
    }
    for p in [named("ustates"), named("uoutput"), named("uparams")] {
        let a = svg(&r, p, None);
        let b = svg(&moved, p, None);
        assert!(
            a.contains("t = 120") && !a.contains("t = 60"),
            "{}",
            p.name()
        );
        assert!(
            b.contains("t = 60"),
            "{}: the cursor did not move",
            p.name()
        );
        assert_ne!(a, b);
    }
    // A view time other than the window's: the time charts move the cursor; the polygon panel
    // draws the estimates at that time without the window's polygon and face (which belong to
    // the report's time), and says so.
    let a = svg(&r, named("uoutput"), Some(30));
    assert!(a.contains("t = 30"));
    let at = r.uniform.as_ref().expect("uniform").at.time;
    let p = svg(&r, named("upolygon"), Some(30));
    assert!(
        p.contains(&format!("not in this report (it holds t = {at})")),
        "the polygon panel at another time says what it lacks"
    );
    assert!(p.contains("States consistent with the window at t = 30"));
    assert_ne!(p, svg(&r, named("upolygon"), None), "no polygon at t = 30");
    let e = report_svg(
        &r,
        &View {
            time: Some(500),
            ..View::new(named("ustates"))
        },
        800,
        600,
    )
    .unwrap_err();
    assert_eq!(e.field, "time");
}

#[test]
fn uniform_and_other_panels_do_not_mix() {
    let (_, r) = preset("uniform-paper");
    let size = (800, 600);
    let others = ["state", "series", "coverage", "region", "singular", "plane"];
    refuses(&r, &others, size, "ustates");
    others_refuse(
        Method::UniformLp,
        &["scf-scalar", "lscr-predict", "glls-mixed"],
    );
    // Broken reports are errors, not panics.
    let kf = |r: &mut Report| {
        if let Some(u) = r.uniform.as_mut() {
            u.kf.as_mut().expect("simulated").pop();
        }
    };
    assert_eq!(broken_field(&r, kf, "ustates", size), "report.uniform");
    let face = |r: &mut Report| {
        if let Some(u) = r.uniform.as_mut() {
            u.at.face_lo.pop();
        }
    };
    assert_eq!(
        broken_field(&r, face, "upolygon", size),
        "report.uniform.at"
    );
    let step = |r: &mut Report| {
        if let Some(u) = r.uniform.as_mut() {
            u.steps[3].a[1].pop();
        }
    };
    assert!(broken(&r, step, "uparams", size).is_err());
    let plane = |r: &mut Report| {
        if let Some(u) = r.uniform.as_mut() {
            u.plane = Some([0, 0]);
        }
    };
    assert_eq!(
        broken_field(&r, plane, "upolygon", size),
        "report.uniform.plane"
    );
    assert_eq!(broken_field(&r, |_| {}, "ustates", (200, 100)), "size");
}

/// The uniform-paper scenario on its own y and u as `data` (no truth), and a scalar model.
fn uniform_without_truth() -> (Scenario, Report, Scenario, Report) {
    let (s, r) = preset("uniform-paper");
    let u = r.uniform.as_ref().expect("uniform");
    let mut d = s.clone();
    d.simulate = None;
    d.data = Some(crate::scenario::DataSpec {
        y: u.y[1..].to_vec(),
        u: u.u[1..].to_vec(),
        t: Vec::new(),
    });
    let rd = d.run().expect("data run");
    let mut one = s.clone();
    one.model.f = Some(crate::model::MatrixSpec::Constant(vec![vec![0.8]]));
    one.model.h = Some(crate::model::MatrixSpec::Constant(vec![vec![1.0]]));
    one.model.b = Some(crate::model::MatrixSpec::Constant(vec![vec![1.0]]));
    if let Some(spec) = one.uniform.as_mut() {
        spec.xr = Some(vec![0.2]);
        spec.xr_max = Some(vec![1.0]);
        spec.plane = None;
        spec.prior_overrides.clear();
    }
    let r1 = one.run().expect("n = 1 runs");
    (d, rd, one, r1)
}

#[test]
fn uniform_panels_draw_data_and_scalar_reports_without_inventing_a_truth() {
    let (_d, rd, _one, r1) = uniform_without_truth();
    assert_eq!(
        useful_panels(&rd),
        method_panels(Method::UniformLp).to_vec()
    );
    // Data: no truth curve, no KF, no true values; the error charts say why.
    let states = svg(&rd, named("ustates"), None);
    assert!(!states.contains("true state xₜ") && !states.contains("KF with"));
    assert!(
        states.contains("no true states"),
        "the error charts explain"
    );
    assert!(polylines(&states, &style::TRUTH, 2).is_empty());
    assert!(polylines(&states, &style::KF, 2).is_empty());
    assert!(!polylines(&states, &style::UNIFORM_LP, 2).is_empty());
    let output = svg(&rd, named("uoutput"), None);
    assert!(output.contains("measured output") && !output.contains("noise bound"));
    let params = svg(&rd, named("uparams"), None);
    assert!(!params.contains("true value (same colour)") && params.contains("your data"));
    let poly = svg(&rd, named("upolygon"), None);
    assert_eq!(polygons(&poly, &style::POLYGON), 1);
    assert!(!poly.contains("true state x") && !poly.contains("KF"));
    // n = 1: no polygon panel; the others draw a scalar state; asking for it says why.
    assert_eq!(
        useful_panels(&r1),
        vec![named("ustates"), named("uoutput"), named("uparams")]
    );
    for p in [named("ustates"), named("uoutput"), named("uparams")] {
        for (w, h) in [(320, 240), (800, 600)] {
            let v = View::new(p);
            let mut out = String::new();
            draw(SVGBackend::with_string(&mut out, (w, h)), &r1, &v)
                .unwrap_or_else(|e| panic!("{} {w}×{h}: {e}", p.name()));
        }
    }
    assert!(svg(&r1, named("ustates"), None).contains("state x"));
    assert!(svg(&r1, named("uparams"), None).contains("â"));
    let e = report_svg(&r1, &View::new(named("upolygon")), 800, 600).unwrap_err();
    assert_eq!(e.field, "report.uniform.at.polygon");
    assert!(e.message.contains("n = 1"), "{e}");
}

// ------------------------------------------------------------------ set-membership (ubb)

const UBB_PRESETS: [&str; 4] = ["ubb-track", "ubb-series", "ubb-leontief", "ubb-markov"];

#[test]
fn ubb_reports_use_both_panels_and_show_their_step() {
    for name in UBB_PRESETS {
        let (_, r) = preset(name);
        assert_eq!(
            useful_panels(&r),
            vec![named("ubbset"), named("ubbwidth")],
            "{name}"
        );
        let k = r.ubb.as_ref().expect("ubb").at.k;
        for p in [named("ubbset"), named("ubbwidth")] {
            for (w, h) in [(240, 180), (960, 640)] {
                let out = report_svg(&r, &View::new(p), w, h).expect("draws");
                assert!(
                    out.contains(&format!("k = {k}")),
                    "{name} {} {w}×{h}: no k = {k}",
                    p.name()
                );
            }
        }
    }
}

#[test]
fn ubb_panels_say_what_they_show() {
    let (_, r) = preset("ubb-track");
    let set = svg(&r, named("ubbset"), None);
    for label in [
        "Feasible set at k = 40: x(41)",
        "l∞ bounds",
        "true state x(41)",
        "central estimate",
        "interval hull",
        "Kalman 99 % ellipse",
        "x₁(k+1)",
        "x₂(k+1)",
        "truth inside the set",
        "(exact)",
    ] {
        assert!(set.contains(label), "ubbset lacks \"{label}\"");
    }
    let width = svg(&r, named("ubbwidth"), None);
    for label in [
        "Width of the interval hull",
        "width of x₁(k+1)",
        "width of x₂(k+1)",
        "Theorem 4 bound on lim sup (2·τ‖B‖/(1−‖A‖·exp(1/α)))",
        "k = 40",
        "truth in its hull band",
    ] {
        assert!(width.contains(label), "ubbwidth lacks \"{label}\"");
    }
    let f: Frame = {
        let mut out = String::new();
        draw(
            SVGBackend::with_string(&mut out, (960, 640)),
            &r,
            &View::new(named("ubbwidth")),
        )
        .expect("draws")
    };
    assert_eq!(f.more.len(), 1, "the truth bands below the widths");
    // Without process noise there is no Theorem 4 bound, and the panel says why.
    let (_, r) = preset("ubb-series");
    let width = svg(&r, named("ubbwidth"), None);
    assert!(width.contains("no Theorem 4 bound"));
    assert!(!width.contains("Theorem 4 bound on lim sup (2"));
    // An l1 norm is named; a projection of r = 3 says so; a polygon within a gap says so.
    let (s, r) = preset("ubb-leontief");
    let set = svg(&r, named("ubbset"), None);
    assert!(set.contains("r = 3: the projection on x₁, x₂"));
    assert!(r.ubb.as_ref().expect("ubb").at.polygon.exact && !set.contains("within gap"));
    // With a budget of 16 LPs its 47 vertices cannot all be found: the figure says how close.
    let mut few = s.clone();
    if let Some(u) = few.ubb.as_mut() {
        u.budget = 16;
    }
    let few_report = few.run().expect("runs");
    assert!(!few_report.ubb.as_ref().expect("ubb").at.polygon.exact);
    assert!(svg(&few_report, named("ubbset"), None).contains("within gap"));
    let mut s1 = s.clone();
    if let Some(u) = s1.ubb.as_mut() {
        u.norm = crate::ubb::Norm::L1;
        u.eps *= 3.0;
    }
    let r1 = s1.run().expect("l1 runs");
    assert!(svg(&r1, named("ubbset"), None).contains("l₁ bounds"));
}

#[test]
fn ubb_and_other_panels_do_not_mix() {
    let (_, r) = preset("ubb-track");
    let size = (640, 400);
    let others = ["state", "series", "region", "plane", "upolygon"];
    refuses(&r, &others, size, "ubbset or ubbwidth");
    let (_, other) = preset("uniform-paper");
    refuses(&other, &["ubbset"], size, "no ubb part");
    // The set panel draws the polygon of step k only: at another step of the track, its hull
    // and markers without the polygon and the Kalman ellipse, saying so; past the track, an
    // error naming the time.
    let u = r.ubb.as_ref().expect("ubb");
    let k = u.at.k;
    let other = |t: usize| View {
        time: Some(t),
        ..View::new(named("ubbset"))
    };
    let drawn = report_svg(&r, &other(k + 1), 640, 400).expect("another step of the track");
    assert!(
        drawn.contains(&format!("not in this report (it holds k = {k})")),
        "the set panel at another step says what it lacks"
    );
    assert_ne!(drawn, report_svg(&r, &other(k), 640, 400).expect("step k"));
    assert_eq!(
        report_svg(&r, &other(u.steps + 3), 640, 400)
            .expect_err("past the track")
            .field,
        "time"
    );
    // Broken reports are errors, not panics.
    let short = |r: &mut Report| {
        if let Some(u) = r.ubb.as_mut() {
            u.at.lo.pop();
        }
    };
    assert_eq!(broken_field(&r, short, "ubbset", size), "report.ubb.at");
    let plane = |r: &mut Report| {
        if let Some(u) = r.ubb.as_mut() {
            u.plane = [0, 0];
        }
    };
    assert_eq!(broken_field(&r, plane, "ubbwidth", size), "report.ubb");
    let empty = |r: &mut Report| {
        if let Some(u) = r.ubb.as_mut() {
            u.track.clear();
        }
    };
    assert_eq!(broken_field(&r, empty, "ubbwidth", size), "report.ubb");
    let nan = |r: &mut Report| {
        if let Some(u) = r.ubb.as_mut() {
            u.at.polygon.vertices.push([f64::NAN, 0.0]);
        }
    };
    assert_eq!(
        broken_field(&r, nan, "ubbset", size),
        "report.ubb.at.polygon"
    );
}

// ------------------------------------------------------------------ the record's own time

/// A figure context whose record has `times` (as the report carries them, `data.t` shown).
fn with_times(times: &[String]) -> FigureContext {
    FigureContext {
        times: times.to_vec(),
        ..FigureContext::default()
    }
}

fn years(from: i64, count: i64) -> Vec<String> {
    (from..from + count).map(|y| y.to_string()).collect()
}

/// The labelled ticks of a time axis as (position, label).
fn labelled(ticks: &[style::TimeTick]) -> Vec<(f64, String)> {
    ticks
        .iter()
        .filter(|t| t.major)
        .map(|t| (t.at, t.label.clone()))
        .collect()
}

/// Years 1871 … 1970 over 100 steps: the labels at round years (every 20th with room for 6
/// labels, every 10th with room for 10), each at the step of its year (t = year − 1870 for
/// t = 1, 2, …; k = year − 1871 for ubb's k = 0, 1, …), with light lines between.
#[test]
fn a_time_axis_reads_the_record_years_at_round_years() {
    let fig = with_times(&years(1871, 100));
    let t = style::RecordTimes::of(&fig, crate::scenario::TimeIndex::OneBased);
    let ticks = t.ticks(0.0, 101.0, 6);
    let want: Vec<(f64, String)> = (1880..=1960)
        .step_by(20)
        .map(|y| ((y - 1870) as f64, y.to_string()))
        .collect();
    assert_eq!(labelled(&ticks), want);
    // Light lines every 10 years between them (1870 lies before the record: no line).
    let light: Vec<f64> = ticks.iter().filter(|t| !t.major).map(|t| t.at).collect();
    assert_eq!(light, vec![20.0, 40.0, 60.0, 80.0, 100.0]);
    let ten: Vec<String> = labelled(&t.ticks(0.0, 101.0, 10))
        .into_iter()
        .map(|p| p.1)
        .collect();
    assert_eq!(
        ten,
        years(1880, 91).into_iter().step_by(10).collect::<Vec<_>>()
    );
    // A window on part of the record: only its years.
    assert_eq!(
        labelled(&t.ticks(35.0, 62.0, 3)),
        vec![
            (40.0, "1910".to_string()),
            (50.0, "1920".to_string()),
            (60.0, "1930".to_string())
        ]
    );
    // ubb counts k from 0: k = 19 is row 20, 1890.
    let k = style::RecordTimes::of(&fig, crate::scenario::TimeIndex::ZeroBased);
    assert_eq!(k.at("k", 19), "k = 19 (1890)");
    assert_eq!(t.at("t", 40), "t = 40 (1910)");
    assert_eq!(
        labelled(&k.ticks(0.0, 99.0, 6))[0],
        (9.0, "1880".to_string())
    );
    assert_eq!(t.axis_name("time t"), style::RECORD_TIME_AXIS);
    // A GLLS-like axis that does not count time has no record time.
    let none = style::RecordTimes::of(&fig, crate::scenario::TimeIndex::NotTime);
    assert!(none.is_empty() && none.ticks(0.0, 101.0, 6).is_empty());
}

/// Numbers that are not evenly spaced: a round value between two rows sits between their steps
/// in proportion (1900 halfway from 1890 at t = 2 to 1910 at t = 3); fractional times get
/// decimals.
#[test]
fn a_time_axis_places_round_times_between_uneven_rows() {
    let fig = with_times(&["1880", "1890", "1910", "1911", "1950"].map(String::from));
    let t = style::RecordTimes::of(&fig, crate::scenario::TimeIndex::OneBased);
    let ticks = labelled(&t.ticks(0.0, 6.0, 4));
    let want = [
        (1.0, "1880"),
        (2.5, "1900"),
        (4.0 + 9.0 / 39.0, "1920"),
        (4.0 + 29.0 / 39.0, "1940"),
    ];
    assert_eq!(ticks.len(), want.len(), "{ticks:?}");
    for ((at, label), (want_at, want_label)) in ticks.iter().zip(want) {
        assert!(
            (at - want_at).abs() < 1e-12 && label == want_label,
            "{ticks:?}"
        );
    }
    let fig = with_times(&["0.05", "0.1", "0.15", "0.2", "0.25"].map(String::from));
    let t = style::RecordTimes::of(&fig, crate::scenario::TimeIndex::OneBased);
    let labels: Vec<String> = labelled(&t.ticks(0.0, 6.0, 3))
        .into_iter()
        .map(|p| p.1)
        .collect();
    assert_eq!(labels, vec!["0.1", "0.2"]);
}

/// Dates: ticks at every 1st, 2nd, 5th, 10th, … row from the first shown, labelled with the
/// row's date as the record writes it; no times: no ticks, and the words are the steps alone.
#[test]
fn a_time_axis_labels_dates_at_rows_and_nothing_without_times() {
    let months: Vec<String> = (0..36)
        .map(|m| format!("{}-{:02}", 2001 + m / 12, m % 12 + 1))
        .collect();
    let fig = with_times(&months);
    let t = style::RecordTimes::of(&fig, crate::scenario::TimeIndex::OneBased);
    let ticks = labelled(&t.ticks(0.0, 37.0, 4));
    // 36 rows, at most 4 labels: every 10th row from the first.
    assert_eq!(
        ticks,
        vec![
            (1.0, "2001-01".to_string()),
            (11.0, "2001-11".to_string()),
            (21.0, "2002-09".to_string()),
            (31.0, "2003-07".to_string()),
        ]
    );
    assert_eq!(t.at("t", 14), "t = 14 (2002-02)");
    let fig = with_times(&[]);
    let t = style::RecordTimes::of(&fig, crate::scenario::TimeIndex::OneBased);
    assert!(t.is_empty() && t.ticks(0.0, 37.0, 4).is_empty());
    assert_eq!(t.at("t", 14), "t = 14");
    assert_eq!(t.axis_name("time t"), "time t");
    // Times out of order (a report edited by hand) are labelled at rows, never a panic.
    let fig = with_times(&["1900", "1890", "1910"].map(String::from));
    let t = style::RecordTimes::of(&fig, crate::scenario::TimeIndex::OneBased);
    assert_eq!(labelled(&t.ticks(0.0, 4.0, 3)).len(), 3);
}

/// Every time axis of every method reads the record's years when the report has them: the
/// labelled years are in the SVG, the step numbers of the axis are not, the axis says it is
/// the record's time and the cursor names the step with its year.
#[test]
fn every_time_panel_labels_its_axis_with_the_record_years() {
    let cases: [(&str, &str, crate::scenario::TimeIndex); 6] = [
        ("scf-scalar", "series", crate::scenario::TimeIndex::OneBased),
        ("scf-scalar", "state", crate::scenario::TimeIndex::OneBased),
        (
            "uniform-paper",
            "ustates",
            crate::scenario::TimeIndex::OneBased,
        ),
        (
            "uniform-paper",
            "uparams",
            crate::scenario::TimeIndex::OneBased,
        ),
        (
            "ubb-track",
            "ubbwidth",
            crate::scenario::TimeIndex::ZeroBased,
        ),
        (
            "conformal-gaussian",
            "aciband",
            crate::scenario::TimeIndex::OneBased,
        ),
    ];
    for (name, panel, index) in cases {
        let (_, mut r) = preset(name);
        let rows = if r.method == Method::Ubb {
            r.ubb.as_ref().expect("ubb").y.len()
        } else {
            r.y.len()
        };
        r.figure.times = years(1801, rows as i64);
        let before = svg(&r, named(panel), None);
        let step = match index {
            crate::scenario::TimeIndex::ZeroBased => r.ubb.as_ref().expect("ubb").at.k,
            _ if r.method == Method::UniformLp => r.uniform.as_ref().expect("uniform").at.time,
            _ => r.time,
        };
        let year = style::RecordTimes::of(&r.figure, index)
            .label(step)
            .expect("a year at the shown step")
            .to_string();
        // The axis name (its apostrophe escaped in the SVG) and the cursor or title's step.
        assert!(
            before.contains("data.t)"),
            "{name} {panel}: no record time axis"
        );
        // The shown step with its year, where the panel names it (aciband shows every step).
        let shown = format!("{step} ({year})");
        assert!(
            panel == "aciband" || before.contains(&shown),
            "{name} {panel}: no \"{shown}\""
        );
        let round = (1810..1801 + rows as i64)
            .step_by(10)
            .any(|y| before.contains(&format!("\n{y}\n</text>")));
        assert!(round, "{name} {panel}: no round year on the axis");
        if panel == "aciband" {
            // The conformal region's title names its time with the year.
            let c = r.conformal.as_ref().expect("conformal");
            let t = c.time + c.tau;
            let set = svg(&r, named("conformalset"), None);
            let want = format!("State region at t = {t} ({})", 1800 + t);
            assert!(
                c.tau != 0 || set.contains(&want),
                "conformalset: no \"{want}\""
            );
        }
    }
}

// ------------------------------------------------------------------ gaps of a user's record

/// The report `r` with gaps (NaN, JSON `null`: not measured) in its measurements `y` and
/// `ubb.y` at the first, a middle and the last rows' first component; the number of gaps made.
fn with_gaps(r: &Report) -> (Report, usize) {
    let mut r = r.clone();
    let mut made = 0;
    let ubb_y = r.ubb.as_mut().map(|u| &mut u.y);
    for rows in [Some(&mut r.y), ubb_y].into_iter().flatten() {
        let n = rows.len();
        for k in [0, n / 2, n.saturating_sub(1)] {
            if let Some(v) = rows.get_mut(k).and_then(|row| row.first_mut()) {
                if !v.is_nan() {
                    *v = f64::NAN;
                    made += 1;
                }
            }
        }
    }
    (r, made)
}

/// Gaps of a user's record (a NaN in the report's `y` or `ubb.y`) in every preset's report:
/// every useful panel of every method draws, at a page size and a small one and at the shown
/// time's neighbours, an SVG that parses (usvg) and holds no "NaN" (a gap is no marker, never a
/// point at NaN); and every method's presets put gaps somewhere.
#[test]
fn gaps_in_the_measurements_draw_no_nan_in_any_panel() {
    let mut gapped_methods = std::collections::BTreeSet::new();
    for p in presets::all() {
        let r = p.scenario.run().expect("preset runs");
        let (r, made) = with_gaps(&r);
        if made > 0 {
            gapped_methods.insert(r.method.to_string());
        }
        for panel in useful_panels(&r) {
            for (w, h) in [(960, 640), (400, 250)] {
                let out = report_svg(&r, &View::new(panel), w, h)
                    .unwrap_or_else(|e| panic!("{} {} with gaps: {e}", p.name, panel.name()));
                assert!(
                    !out.contains("NaN"),
                    "{} {} {w}×{h}: NaN in the SVG",
                    p.name,
                    panel.name()
                );
                resvg::usvg::Tree::from_str(&out, &resvg::usvg::Options::default())
                    .unwrap_or_else(|e| panic!("{} {}: not an SVG: {e}", p.name, panel.name()));
            }
        }
    }
    // Every method whose report carries its measurements gets gaps (GLLS and LSCR keep theirs
    // in their own blocks, which a gap never reaches: those methods refuse one).
    for m in ["scf", "uniform_lp", "ubb", "conformal", "compare"] {
        assert!(
            gapped_methods.contains(m),
            "no preset of {m} had a gap put in: {gapped_methods:?}"
        );
    }
}

/// A gap is simply no marker: the measurement dots of SCF's over-time chart lose one for each
/// gap at a measured component, and the rest stay where they were.
#[test]
fn a_gap_removes_its_measurement_marker_only() {
    let (_, r) = preset("scf-scalar");
    let dots = |svg: &str| {
        let hex = format!(
            "fill=\"#{:02X}{:02X}{:02X}\"",
            style::MEASURE.0,
            style::MEASURE.1,
            style::MEASURE.2
        );
        svg.split("<circle")
            .skip(1)
            .filter(|el| el.split("/>").next().unwrap_or("").contains(hex.as_str()))
            .count()
    };
    for panel in ["state", "series"] {
        let whole = dots(&svg(&r, named(panel), None));
        let mut g = r.clone();
        g.y[3][0] = f64::NAN;
        g.y[7][0] = f64::NAN;
        let gapped = svg(&g, named(panel), None);
        assert!(whole > 10, "{panel}: {whole} dots");
        assert_eq!(
            dots(&gapped),
            whole - 2,
            "{panel}: two gaps, two dots fewer"
        );
        assert!(!gapped.contains("NaN"));
    }
}
