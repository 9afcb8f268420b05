//! The papers as a static site (`confset gallery -o DIR`): one entry per figure or table of the
//! five papers that a preset reproduces ([`printed::Catalogue`]), each with the core's figures
//! (SVG, and PNG at 2× for slides), the paper's printed numbers beside ours with a computed verdict, the erratum that
//! explains a difference (quoted from the crate docs' list), the scenario, report and study
//! JSON, a link that opens the same preset in the explorer, and the time the core took.
//!
//! Plain HTML and one stylesheet, relative links only, no script and nothing external: any
//! static host serves the directory as it is. The command line copies the explorer beside it
//! (`explorer/`), which the entries link into with the explorer's `#<panel>/preset/<name>`
//! route. Native only (it times the core with the system clock).

mod notation;
pub mod printed;

use notation::notation;

use crate::error::{Error, Result};
use crate::method::Method;
use crate::plot::{self, Panel, View};
use crate::presets::{self, Preset};
use crate::scenario::Report;
use crate::study;
use printed::{Catalogue, Entry, Printed, Source, Verdict};
use serde_json::Value;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::time::Instant;

/// One file of the site: its path under the site's root and its bytes.
pub struct File {
    pub path: String,
    pub bytes: Vec<u8>,
}

/// The explorer's route of a method's panel (`www/registry.js`).
pub fn explorer_panel(m: Method) -> &'static str {
    m.block().unwrap_or("scf")
}

/// The papers in the order of the index, with their full titles.
const PAPERS: [(&str, &str); 6] = [
    ("scf", "A. Carè, M. C. Campi, E. Weyer — State Conditional Filtering"),
    ("lscr", "E. Weyer, M. C. Campi — Prediction, filtering and smoothing using LSCR"),
    ("glls", "V. Gubarev, M. Mishchenko — Interval state estimator for linear systems with known structure"),
    ("pavelkova", "L. Pavelková — State and parameter estimation for linear models with uniform innovations"),
    ("tempo", "R. Tempo — Robust estimation and filtering with unknown but bounded noise"),
    ("compare", "All five side by side — every method's set on one record, and its promise counted"),
];

/// What one preset gave: its report and study JSON and how long the core took.
struct Computed {
    preset: Preset,
    report: Report,
    report_json: Value,
    report_ms: f64,
    /// Study results by run count (None: the scenario's own).
    studies: BTreeMap<Option<usize>, (Value, f64)>,
}

/// The verdicts of one entry, in the order of its numbers.
pub struct Checked {
    pub entry: Entry,
    pub verdicts: Vec<(Option<f64>, Verdict)>,
}

/// Compute every preset the catalogue names (each once) and the verdict on every number.
fn compute(cat: &Catalogue) -> Result<(BTreeMap<String, Computed>, Vec<Checked>)> {
    let mut done: BTreeMap<String, Computed> = BTreeMap::new();
    for e in &cat.entries {
        if !done.contains_key(&e.preset) {
            let preset = presets::all()
                .into_iter()
                .find(|p| p.name == e.preset)
                .ok_or_else(|| {
                    Error::field(
                        "gallery",
                        format!("entry {} names no preset {}", e.id, e.preset),
                    )
                })?;
            let t0 = Instant::now();
            let report = preset.scenario.run()?;
            let report_ms = t0.elapsed().as_secs_f64() * 1e3;
            let report_json = serde_json::to_value(&report)
                .map_err(|err| Error::field("report", err.to_string()))?;
            done.insert(
                e.preset.clone(),
                Computed {
                    preset,
                    report,
                    report_json,
                    report_ms,
                    studies: BTreeMap::new(),
                },
            );
        }
        let c = done.get_mut(&e.preset).expect("inserted above");
        // A compare's page shows its study's counts beside each method's promise.
        if c.report.compare.is_some() && !c.studies.contains_key(&None) {
            let t0 = Instant::now();
            let s = &c.preset.scenario;
            let v = study::run_sharded(&|| s.study(None), 1000, &|_| {})?;
            c.studies
                .insert(None, (v, t0.elapsed().as_secs_f64() * 1e3));
        }
        for p in e.numbers.iter().filter(|p| p.source == Source::Study) {
            if !c.studies.contains_key(&p.runs) {
                let t0 = Instant::now();
                let s = &c.preset.scenario;
                let v = study::run_sharded(&|| s.study(p.runs), 1000, &|_| {})?;
                c.studies
                    .insert(p.runs, (v, t0.elapsed().as_secs_f64() * 1e3));
            }
        }
    }
    let checked = cat
        .entries
        .iter()
        .map(|e| {
            let c = &done[&e.preset];
            let verdicts = e
                .numbers
                .iter()
                .map(|p| judge(p, &c.report_json, c.studies.get(&p.runs).map(|s| &s.0)))
                .collect();
            Checked {
                entry: e.clone(),
                verdicts,
            }
        })
        .collect();
    Ok((done, checked))
}

/// The verdicts of the compiled catalogue, computed now (what the gallery shows).
pub fn check() -> Result<Vec<Checked>> {
    compute(&printed::catalogue()?).map(|(_, c)| c)
}

/// Our number for `p` (from the report or the study JSON, as the catalogue says) and the
/// verdict on it.
fn judge(p: &Printed, report: &Value, study: Option<&Value>) -> (Option<f64>, Verdict) {
    let json = match p.source {
        Source::Report => Some(report),
        Source::Study => study,
    };
    let at = |path: &str| json.and_then(|j| printed::lookup(j, path)?.as_f64());
    let ours = at(&p.path);
    (
        ours,
        printed::verdict(p, ours, p.runs_path.as_deref().and_then(at)),
    )
}

/// The verdict on each number of one entry of the catalogue, for a preset whose scenario may
/// differ from the shipped one (the tests move a seed): `report` and `study` are its JSON.
pub fn verdicts_of(entry: &Entry, report: &Value, study: Option<&Value>) -> Vec<Verdict> {
    entry
        .numbers
        .iter()
        .map(|p| judge(p, report, study).1)
        .collect()
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The erratum's Markdown as HTML: `code` as code, intra-doc link brackets dropped.
fn markdown_inline(md: &str) -> String {
    let text = esc(&md.replace("[`", "`").replace("`]", "`"));
    let mut out = String::new();
    for (i, part) in text.split('`').enumerate() {
        if i % 2 == 1 {
            let _ = write!(out, "<code>{part}</code>");
        } else {
            out.push_str(part);
        }
    }
    out
}

/// A file-name stem of an id: "LSCR Fig. 1" → "lscr-fig-1".
pub fn slug(id: &str) -> String {
    let mut s = String::new();
    for c in id.chars() {
        // The papers' authors' letters: "Pavelková Fig. 1" → "pavelkova-fig-1".
        let c = match c {
            'á' | 'à' | 'ä' => 'a',
            'é' | 'ě' | 'è' => 'e',
            'í' => 'i',
            'ó' | 'ö' => 'o',
            'ú' | 'ů' | 'ü' => 'u',
            'ý' => 'y',
            'č' => 'c',
            'š' => 's',
            'ž' => 'z',
            'ř' => 'r',
            c => c,
        };
        if c.is_ascii_alphanumeric() {
            s.push(c.to_ascii_lowercase());
        } else if !s.ends_with('-') && !s.is_empty() {
            s.push('-');
        }
    }
    s.trim_end_matches('-').to_string()
}

fn page(title: &str, depth: usize, body: &str) -> Vec<u8> {
    let up = "../".repeat(depth);
    format!(
        "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'self'; script-src 'none'; style-src 'self'\">\n\
         <title>{}</title>\n<link rel=\"stylesheet\" href=\"{up}gallery.css\">\n</head>\n<body>\n{body}</body>\n</html>\n",
        esc(title)
    )
    .into_bytes()
}

fn ms(x: f64) -> String {
    if x < 10.0 {
        format!("{x:.1} ms")
    } else {
        format!("{x:.0} ms")
    }
}

fn number(x: f64) -> String {
    if x == x.trunc() && x.abs() < 1e15 {
        format!("{}", x as i64)
    } else if x != 0.0 && (x.abs() < 1e-3 || x.abs() >= 1e6) {
        format!("{x:.6e}")
    } else {
        format!("{x:.6}")
            .trim_end_matches('0')
            .trim_end_matches('.')
            .to_string()
    }
}

/// The summary of an entry's verdicts: "2 reproduced · 1 within the Monte Carlo band".
fn summary(verdicts: &[(Option<f64>, Verdict)]) -> String {
    let mut counts: Vec<(&str, usize)> = Vec::new();
    for (_, v) in verdicts {
        match counts.iter_mut().find(|(w, _)| *w == v.word()) {
            Some((_, k)) => *k += 1,
            None => counts.push((v.word(), 1)),
        }
    }
    if counts.is_empty() {
        return "figure only".into();
    }
    counts
        .iter()
        .map(|(w, k)| format!("{k} {w}"))
        .collect::<Vec<_>>()
        .join(" · ")
}

fn verdict_cell(p: &Printed, v: &Verdict) -> String {
    match v {
        Verdict::Reproduced => "<td class=\"ok\">reproduced to the printed digits</td>".into(),
        Verdict::WithinTolerance(t) => {
            format!("<td class=\"ok\">within ±{} of the printed value (which the paper gives roughly, or reads off a figure)</td>", number(*t))
        }
        Verdict::WithinBand { lo, hi } => format!(
            "<td class=\"ok\">within the 99.9 % Monte Carlo band: counts {:.0}–{:.0} agree with the paper's {} of {}</td>",
            lo.ceil(),
            hi.floor(),
            esc(&p.printed),
            p.paper_runs.unwrap_or(0)
        ),
        Verdict::Differs { band } => {
            let band = band.map_or(String::new(), |(lo, hi)| {
                format!(" (the 99.9 % band is {:.0}–{:.0})", lo.ceil(), hi.floor())
            });
            let why = match p.erratum.as_deref().and_then(printed::erratum) {
                Some(e) => format!(
                    "<blockquote class=\"erratum\"><p>Erratum (crate docs): {}</p></blockquote>",
                    markdown_inline(&e)
                ),
                None => " — no erratum explains it".into(),
            };
            format!("<td class=\"differs\">differs{band}{why}</td>")
        }
        Verdict::Missing(why) => format!("<td class=\"differs\">not computed: {}</td>", esc(why)),
    }
}

/// The figures of a preset an entry shows (its panels, or the preset's useful ones).
fn panels_of(e: &Entry, report: &Report) -> Result<Vec<Panel>> {
    let useful = plot::useful_panels(report);
    e.panels
        .iter()
        .map(|name| {
            let p = Panel::from_name(name)?;
            if useful.contains(&p) {
                Ok(p)
            } else {
                Err(Error::field(
                    "gallery",
                    format!(
                        "entry {}: {} is not a panel of preset {}",
                        e.id, name, e.preset
                    ),
                ))
            }
        })
        .collect()
}

/// Build the site: every file but the explorer's (which the caller copies into `explorer/`).
/// `size` is the figures' size in pixels.
pub fn build(size: (u32, u32)) -> Result<Vec<File>> {
    let cat = printed::catalogue()?;
    let (computed, checked) = compute(&cat)?;
    let version = env!("CARGO_PKG_VERSION");
    let mut files = vec![File {
        path: "gallery.css".into(),
        bytes: include_bytes!("gallery.css").to_vec(),
    }];
    // The data and figures of every preset named, once.
    let mut drawn: BTreeMap<(String, &'static str), String> = BTreeMap::new();
    for (name, c) in &computed {
        let scenario = serde_json::to_string_pretty(&c.preset.scenario)
            .map_err(|e| Error::field("scenario", e.to_string()))?;
        let report = serde_json::to_string_pretty(&c.report_json)
            .map_err(|e| Error::field("report", e.to_string()))?;
        files.push(File {
            path: format!("data/{name}.scenario.json"),
            bytes: scenario.into_bytes(),
        });
        files.push(File {
            path: format!("data/{name}.report.json"),
            bytes: report.into_bytes(),
        });
        for (runs, (v, _)) in &c.studies {
            let path = match runs {
                None => format!("data/{name}.study.json"),
                Some(r) => format!("data/{name}.study-{r}.json"),
            };
            files.push(File {
                path,
                bytes: serde_json::to_string_pretty(v)
                    .map_err(|e| Error::field("study", e.to_string()))?
                    .into_bytes(),
            });
        }
    }
    for ch in &checked {
        let c = &computed[&ch.entry.preset];
        for panel in panels_of(&ch.entry, &c.report)? {
            let key = (ch.entry.preset.clone(), panel.name());
            if !drawn.contains_key(&key) {
                let path = format!("figures/{}-{}.svg", ch.entry.preset, panel.name());
                let svg = plot::report_svg(&c.report, &View::new(panel), size.0, size.1)?;
                // The PNG at 2× for slides, beside the SVG.
                files.push(File {
                    path: path.replace(".svg", ".png"),
                    bytes: plot::svg_to_png(&svg, 2.0)?,
                });
                files.push(File {
                    path: path.clone(),
                    bytes: svg.into_bytes(),
                });
                drawn.insert(key, path);
            }
        }
    }

    // One page per entry.
    let mut index = String::new();
    let _ = write!(
        index,
        "<header><h1>The papers' figures, rebuilt by confset</h1>\n\
         <p>Every figure and printed number of the five papers that a preset of confset {version} \
         reproduces: the figure as the core draws it, the paper's numbers beside ours with a verdict \
         computed when this site was built, and a link that opens the same configuration live in the \
         <a href=\"explorer/index.html\">explorer</a>.</p></header>\n<main>\n"
    );
    for (paper, title) in PAPERS {
        let entries: Vec<&Checked> = checked.iter().filter(|c| c.entry.paper == paper).collect();
        if entries.is_empty() {
            continue;
        }
        let _ = write!(
            index,
            "<section id=\"{paper}\">\n<h2>{}</h2>\n<div class=\"grid\">\n",
            esc(title)
        );
        for ch in entries {
            let e = &ch.entry;
            let c = &computed[&e.preset];
            let slug = slug(&e.id);
            let thumb = panels_of(e, &c.report)?
                .first()
                .and_then(|p| drawn.get(&(e.preset.clone(), p.name())))
                .map_or(
                    "<div class=\"table-thumb\">table of numbers</div>".to_string(),
                    |f| format!("<img src=\"{f}\" alt=\"\" loading=\"lazy\">"),
                );
            let _ = write!(
                index,
                "<a class=\"card\" href=\"entries/{slug}.html\">{thumb}<span class=\"id\">{}</span>\
                 <span class=\"verdicts\">{}</span></a>\n",
                esc(&e.id),
                esc(&summary(&ch.verdicts))
            );
            files.push(File {
                path: format!("entries/{slug}.html"),
                bytes: entry_page(ch, c, &drawn)?,
            });
        }
        index.push_str("</div>\n</section>\n");
    }
    index.push_str(
        "<section id=\"not-reproduced\">\n<h2>What this site does not reproduce</h2>\n<ul>\n",
    );
    for n in &cat.not_reproduced {
        let _ = writeln!(
            index,
            "<li><strong>{}</strong>: {}</li>",
            esc(&n.id),
            notation(&n.why)
        );
    }
    let differs: Vec<String> = checked
        .iter()
        .flat_map(|c| {
            c.entry
                .numbers
                .iter()
                .zip(&c.verdicts)
                .filter_map(move |(p, (_, v))| {
                    matches!(v, Verdict::Differs { .. } | Verdict::Missing(_)).then(|| {
                        format!(
                            "<li><a href=\"entries/{}.html\">{}</a>: {} — {}</li>",
                            slug(&c.entry.id),
                            esc(&c.entry.id),
                            notation(&p.what),
                            v.word()
                        )
                    })
                })
        })
        .collect();
    if !differs.is_empty() {
        index.push_str(
            "</ul>\n<p>Printed numbers ours differ from (each entry says why):</p>\n<ul>\n",
        );
        index.push_str(&differs.concat());
    }
    index.push_str("</ul>\n</section>\n</main>\n");
    let _ = write!(
        index,
        "<footer>Built by <code>confset gallery</code>, confset {version}. Each entry's numbers \
         are computed by this build; the papers' are as printed.</footer>\n"
    );
    files.push(File {
        path: "index.html".into(),
        bytes: page("The papers' figures — confset gallery", 0, &index),
    });
    Ok(files)
}

/// A compare's table: per method what it assumes (met or why not), what it promises, its set's
/// area, whether it holds the truth, and the study's count with its band and verdict.
fn compare_table(c: &crate::scenario::CompareReport, study: Option<&Value>) -> String {
    let mut b = String::from(
        "<table class=\"numbers counts\">\n<thead><tr><th>method</th><th>assumes</th><th>promises</th><th>area</th><th>holds the truth</th><th>counted at the true state</th><th>verdict</th></tr></thead>\n<tbody>\n",
    );
    let counts = study.and_then(|s| s["methods"].as_array());
    for (row, set) in c.rows.iter().zip(&c.at.sets) {
        let assumes = match &row.violated {
            None => format!("{} <span class=\"ok\">— met</span>", notation(&row.assumes)),
            Some(why) => format!(
                "{}<br><span class=\"bad\">{}</span>",
                notation(&row.assumes),
                notation(why)
            ),
        };
        let level = row.level.map_or(String::new(), |l| {
            format!(
                " ({}{} %)",
                if row.at_least { "≥ " } else { "" },
                number(100.0 * l)
            )
        });
        let area = match (&set.set, set.area) {
            (None, _) => format!(
                "{}: {}{}",
                if set.empty { "empty set" } else { "no set" },
                notation(set.reason.as_deref().unwrap_or("")),
                set.remedy.as_deref().map_or(String::new(), |r| format!(
                    "<br>a set needs: {}",
                    notation(r)
                ))
            ),
            (Some(_), None) => "unbounded".to_string(),
            (Some(_), Some(a)) => number(a),
        };
        let holds = match set.holds {
            Some(true) => "yes",
            Some(false) => "no",
            None => "—",
        };
        let count = counts.and_then(|cs| cs.iter().find(|m| m["method"] == row.method.name()));
        let (counted, verdict) = match (count, study) {
            // Over the runs with a set: a run without one is no miss, counted apart.
            (Some(m), Some(_)) => (
                format!(
                    "{} / {}{}{}",
                    m["holds"],
                    m["with_set"],
                    m["band"].as_array().map_or(String::new(), |b| format!(
                        " <small>(99.9 % band {}–{})</small>",
                        b[0], b[1]
                    )),
                    match m["no_set"].as_u64() {
                        Some(k) if k > 0 => format!(" <small>({k} runs without a set)</small>"),
                        _ => String::new(),
                    }
                ),
                notation(m["verdict"].as_str().unwrap_or("")),
            ),
            _ => ("—".to_string(), String::new()),
        };
        let _ = writeln!(
            b,
            "<tr><td>{}</td><td>{assumes}</td><td>{}{level}</td><td class=\"num\">{area}</td><td>{holds}</td><td class=\"num\">{counted}</td><td>{verdict}</td></tr>",
            row.method,
            notation(&row.promise)
        );
    }
    b.push_str("</tbody>\n</table>\n");
    if let Some(s) = study {
        let _ = writeln!(
            b,
            "<p class=\"caption\">The study: {} runs; {}.</p>",
            s["runs"],
            notation(s["conditioning"].as_str().unwrap_or(""))
        );
    }
    b
}

fn entry_page(
    ch: &Checked,
    c: &Computed,
    drawn: &BTreeMap<(String, &'static str), String>,
) -> Result<Vec<u8>> {
    let e = &ch.entry;
    let version = env!("CARGO_PKG_VERSION");
    let name = &e.preset;
    let route = explorer_panel(c.report.method);
    let mut b = String::new();
    let _ = write!(
        b,
        "<header><a href=\"../index.html\">← all figures</a></header>\n<main class=\"entry\">\n\
         <h1>{}</h1>\n<p class=\"caption\">{}</p>\n\
         <p class=\"preset\">Preset <code>{}</code> — {}</p>\n\
         <p class=\"links\"><a class=\"explorer\" href=\"../explorer/index.html#{route}/preset/{name}\">Open in the explorer</a>\
         <a download href=\"../data/{name}.scenario.json\">scenario JSON</a>\
         <a download href=\"../data/{name}.report.json\">report JSON</a>",
        esc(&e.id),
        notation(&e.caption),
        esc(name),
        notation(&c.preset.description),
    );
    for runs in c.studies.keys() {
        let (path, label) = match runs {
            None => (format!("{name}.study.json"), "study JSON".to_string()),
            Some(r) => (
                format!("{name}.study-{r}.json"),
                format!("study JSON ({r} runs)"),
            ),
        };
        let _ = write!(b, "<a download href=\"../data/{path}\">{label}</a>");
    }
    b.push_str("</p>\n");
    for panel in panels_of(e, &c.report)? {
        if let Some(f) = drawn.get(&(name.clone(), panel.name())) {
            let _ = write!(
                b,
                "<figure><img src=\"../{f}\" alt=\"{}\"><figcaption>{} · <a href=\"../{f}\" download>SVG</a> · <a href=\"../{}\" download>PNG (2×)</a></figcaption></figure>\n",
                esc(panel.alt_text()),
                notation(panel.alt_text()),
                f.replace(".svg", ".png")
            );
        }
    }
    if let Some(cmp) = &c.report.compare {
        b.push_str(&compare_table(cmp, c.studies.get(&None).map(|s| &s.0)));
    }
    if !e.numbers.is_empty() {
        b.push_str(
            "<table class=\"numbers\">\n<thead><tr><th>number</th><th>where</th><th>paper</th><th>confset</th><th>verdict</th></tr></thead>\n<tbody>\n",
        );
        for (p, (ours, v)) in e.numbers.iter().zip(&ch.verdicts) {
            let mine = ours.map_or("—".to_string(), |x| match p.kind {
                printed::Kind::Exact => {
                    format!(
                        "{} <small>({})</small>",
                        printed::at_printed_digits(x, &p.printed),
                        number(x)
                    )
                }
                _ => number(x),
            });
            let _ = writeln!(
                b,
                "<tr><td>{}</td><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td>{}</tr>",
                notation(&p.what),
                notation(&p.place),
                esc(&p.printed),
                mine,
                verdict_cell(p, v)
            );
        }
        b.push_str("</tbody>\n</table>\n");
    }
    let mut timing = format!("The core took {} for the report", ms(c.report_ms));
    for (runs, (_, t)) in &c.studies {
        let _ = write!(
            timing,
            " and {} for the study{}",
            ms(*t),
            runs.map_or(String::new(), |r| format!(" of {r} runs"))
        );
    }
    let _ = write!(
        b,
        "<p class=\"timing\">{timing} (natively, all cores), confset {version}.</p>\n</main>\n"
    );
    Ok(page(&format!("{} — confset gallery", e.id), 1, &b))
}
