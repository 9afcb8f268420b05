//! `confset` — the command line: scenario file in, report JSON or SVG figures out.
//!
//! ```text
//! confset presets                          list the paper presets
//! confset run SCENARIO.json                report JSON on stdout
//! confset run --preset NAME                the same for a preset
//! confset run (SCENARIO.json | --preset NAME) --data FILE.csv
//!                                          the scenario on measured data from CSV (its
//!                                          `data` replaced, its `simulate` dropped): columns
//!                                          y1 … yq, then optionally u1 … ur, header optional
//! confset experiment SCENARIO.json|--preset NAME [--runs N] [--shard i/N]
//!                                          the method's Monte Carlo study (result JSON):
//!                                          SCF conditional coverage, LSCR coverage, GLLS
//!                                          precision, set-membership guarantee; its shards
//!                                          run on every core (RAYON_NUM_THREADS=1: one),
//!                                          merged. With --shard i/N (0 ≤ i < N) only shard
//!                                          i's runs, printed as a part (one JSON line)
//! confset merge PART.json… | -             the parts of one study (files, or JSON documents
//!                                          on stdin) merged: what `experiment` prints
//! confset figure SCENARIO.json|--preset NAME -o FILE.svg
//!         [--panel state|series|coverage|region|singular|index|plane|precision
//!                 |ustates|uoutput|uparams|upolygon|ubbset|ubbwidth]
//!         [--time T] [--zoom auto|regions|full] [--data FILE.csv]
//!         [--size WxH]                     default panel: the report's first useful one
//!                                          (region for LSCR, singular for GLLS, ustates for
//!                                          uniform_lp, ubbset for ubb, state otherwise)
//! confset figures [-o] DIR [--size WxH]    every useful panel of every preset as SVG
//!                                          (DIR/PRESET-PANEL.svg; LSCR presets: the region;
//!                                          GLLS presets: singular, index, plane, precision;
//!                                          uniform presets: ustates, uoutput, uparams,
//!                                          upolygon; ubb presets: ubbset, ubbwidth)
//! ```

use confset::plot::{self, Panel, View, Zoom};
use confset::scenario::{Report, Scenario};
use confset::{presets, study, Error};
use std::process::ExitCode;

const USAGE: &str = "usage:
  confset presets
  confset run (SCENARIO.json | --preset NAME) [--data FILE.csv]
  confset experiment (SCENARIO.json | --preset NAME) [--runs N] [--shard i/N]
  confset merge (PART.json… | -)
  confset figure (SCENARIO.json | --preset NAME) -o FILE.svg
          [--panel state|series|coverage|region|singular|index|plane|precision
                  |ustates|uoutput|uparams|upolygon|ubbset|ubbwidth]
          [--time T] [--zoom auto|regions|full] [--data FILE.csv]
          [--size WxH]   (default panel: region for LSCR scenarios, singular for GLLS,
                          ustates for uniform_lp, ubbset for ubb, state otherwise)
  confset figures [-o] DIR [--size WxH]";

/// Flags that take a value (so the value is not mistaken for the scenario file).
const VALUED: [&str; 9] = [
    "-o", "--runs", "--preset", "--panel", "--time", "--zoom", "--size", "--data", "--shard",
];

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

/// The value after `flag`, if present.
fn flag<'a>(args: &'a [String], flag: &str) -> Option<&'a str> {
    args.iter()
        .position(|a| a == flag)
        .and_then(|i| args.get(i + 1))
        .map(|s| s.as_str())
}

fn scenario(args: &[String]) -> Result<Scenario, Error> {
    if let Some(name) = flag(args, "--preset") {
        return presets::get(name);
    }
    let path = args
        .iter()
        .enumerate()
        .skip(1)
        .find(|(i, a)| !a.starts_with('-') && !VALUED.contains(&args[i - 1].as_str()))
        .map(|(_, a)| a)
        .ok_or_else(|| {
            Error::field(
                "",
                format!("a scenario file or --preset NAME is needed\n{USAGE}"),
            )
        })?;
    let text = std::fs::read_to_string(path)
        .map_err(|e| Error::field("", format!("cannot read {path}: {e}")))?;
    Scenario::from_json(&text)
}

/// The scenario with `--data FILE.csv` applied (`Scenario::with_csv_data`: its `data` read
/// from the file, its `simulate` dropped), or as it is without the flag.
fn scenario_with_data(args: &[String]) -> Result<Scenario, Error> {
    let s = scenario(args)?;
    if !args.iter().any(|a| a == "--data") {
        return Ok(s);
    }
    let path = flag(args, "--data")
        .ok_or_else(|| Error::field("--data", "needs a file: --data FILE.csv"))?;
    let text = std::fs::read_to_string(path)
        .map_err(|e| Error::field("--data", format!("cannot read {path}: {e}")))?;
    s.with_csv_data(&text).map_err(|e| {
        // Name the file, so "data.y row 7, …" points into it (a model error is the scenario's).
        if e.field.starts_with("data") {
            Error::field(e.field, format!("{} (in {path})", e.message))
        } else {
            e
        }
    })
}

/// `--size WxH` (default 960x640).
fn size(args: &[String]) -> Result<(u32, u32), Error> {
    let Some(v) = flag(args, "--size") else {
        return Ok((960, 640));
    };
    let bad = || {
        Error::field(
            "--size",
            format!(
                "must read WIDTHxHEIGHT in pixels, e.g. 960x640, found {}",
                confset::error::quoted(v)
            ),
        )
    };
    let (w, h) = v.split_once(['x', 'X']).ok_or_else(bad)?;
    let (w, h): (u32, u32) = (w.parse().map_err(|_| bad())?, h.parse().map_err(|_| bad())?);
    if !(16..=8192).contains(&w) || !(16..=8192).contains(&h) {
        return Err(Error::field(
            "--size",
            "must be a whole number from 16 to 8192 pixels per side",
        ));
    }
    Ok((w, h))
}

/// The view asked for by `--panel`, `--time`, `--zoom` (the scenario's part of the figure
/// comes with the report); without `--panel`, the report's first useful panel.
fn view(args: &[String], report: &Report) -> Result<View, Error> {
    let mut v = View::new(match flag(args, "--panel") {
        Some(p) => Panel::from_name(p).map_err(|e| Error::field("--panel", e.message))?,
        None => plot::useful_panels(report)
            .first()
            .copied()
            .unwrap_or(Panel::State),
    });
    if let Some(t) = flag(args, "--time") {
        v.time = Some(
            t.parse()
                .map_err(|_| Error::field("--time", "must be a time step 1, 2, …"))?,
        );
    }
    if let Some(z) = flag(args, "--zoom") {
        v.zoom = match z {
            "auto" => Zoom::Auto,
            "regions" => Zoom::Regions,
            "full" => Zoom::Full,
            _ => return Err(Error::field("--zoom", "must be auto, regions or full")),
        };
    }
    Ok(v)
}

/// Runs per chunk of a study on the command line.
const CHUNK: usize = 1000;

/// `--shard i/N` (0 ≤ i < N), if given.
fn shard(args: &[String]) -> Result<Option<(usize, usize)>, Error> {
    if !args.iter().any(|a| a == "--shard") {
        return Ok(None);
    }
    let v = flag(args, "--shard").unwrap_or("");
    let bad = || {
        Error::field(
            "--shard",
            format!(
                "must read i/N with 0 ≤ i < N, e.g. --shard 0/4 (shards are counted from 0), found {}",
                confset::error::quoted(v)
            ),
        )
    };
    let (i, n) = v.split_once('/').ok_or_else(bad)?;
    let (i, n): (usize, usize) = (i.parse().map_err(|_| bad())?, n.parse().map_err(|_| bad())?);
    if i >= n {
        return Err(bad());
    }
    Ok(Some((i, n)))
}

/// What `experiment --shard i/N` prints and `merge` reads: the scenario with its digest, the
/// study's run count, the shard and the core's partial counts.
#[derive(serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Part {
    confset: String,
    scenario: serde_json::Value,
    scenario_digest: String,
    runs: usize,
    shard: [usize; 2],
    range: [usize; 2],
    partial: serde_json::Value,
}

fn to_value<T: serde::Serialize>(v: &T) -> Result<serde_json::Value, Error> {
    serde_json::to_value(v).map_err(|e| Error::field("", e.to_string()))
}

/// `merge PART.json…` or `merge -` (parts as JSON documents on stdin): the parts checked
/// (same version, scenario, seed and run count; every run exactly once) and merged into the
/// result `experiment` prints.
fn merge(paths: &[String]) -> Result<serde_json::Value, Error> {
    let mut texts = Vec::new();
    for path in paths {
        if path == "-" {
            let mut text = String::new();
            std::io::Read::read_to_string(&mut std::io::stdin(), &mut text)
                .map_err(|e| Error::field("", format!("cannot read the parts on stdin: {e}")))?;
            for (k, v) in serde_json::Deserializer::from_str(&text)
                .into_iter::<serde_json::Value>()
                .enumerate()
            {
                let v = v.map_err(|e| {
                    Error::field("", format!("document {} on stdin is not JSON: {e}", k + 1))
                })?;
                texts.push((format!("stdin document {}", k + 1), v.to_string()));
            }
        } else {
            let text = std::fs::read_to_string(path)
                .map_err(|e| Error::field("", format!("cannot read {path}: {e}")))?;
            texts.push((path.clone(), text));
        }
    }
    if texts.is_empty() {
        return Err(Error::field(
            "",
            format!("merge needs the part files\n{USAGE}"),
        ));
    }
    let legend = texts
        .iter()
        .enumerate()
        .map(|(k, (name, _))| format!("part {} = {name}", k + 1))
        .collect::<Vec<_>>()
        .join(", ");
    let with_legend = |e: Error| Error::field(e.field, format!("{} ({legend})", e.message));
    let mut parts = Vec::new();
    for (k, (name, text)) in texts.iter().enumerate() {
        let p: Part = confset::scenario::parse::from_json(text, "").map_err(|e| {
            Error::field(
                "",
                format!("part {} ({name}) is not a part file: {e}", k + 1),
            )
        })?;
        if p.confset != env!("CARGO_PKG_VERSION") {
            return Err(with_legend(Error::field(
                "",
                format!(
                    "part {} was written by confset {}, this is confset {}: runs may differ between versions",
                    k + 1,
                    p.confset,
                    env!("CARGO_PKG_VERSION")
                ),
            )));
        }
        parts.push(p);
    }
    let first = &parts[0];
    let s = Scenario::from_json(&first.scenario.to_string()).map_err(with_legend)?;
    if s.digest()? != first.scenario_digest {
        return Err(with_legend(Error::field(
            "",
            "part 1's scenario does not match its scenario_digest: the file was edited",
        )));
    }
    let mut st = s.study(Some(first.runs)).map_err(with_legend)?;
    let partials: Vec<serde_json::Value> = parts.iter().map(|p| p.partial.clone()).collect();
    st.merge(&partials).map_err(with_legend)?;
    st.complete().map_err(with_legend)?;
    st.result()
}

fn json<T: serde::Serialize>(v: &T) -> Result<(), Error> {
    let s = serde_json::to_string_pretty(v).map_err(|e| Error::field("", e.to_string()))?;
    println!("{s}");
    Ok(())
}

fn write(path: &str, text: &str) -> Result<(), Error> {
    std::fs::write(path, text).map_err(|e| Error::field("-o", format!("cannot write {path}: {e}")))
}

fn run(args: &[String]) -> Result<(), Error> {
    match args.first().map(|s| s.as_str()) {
        Some("presets") => {
            for p in presets::all() {
                println!("{:<22} {}\n{:<22} {}", p.name, p.label, "", p.description);
            }
            Ok(())
        }
        Some("run") => json(&scenario_with_data(args)?.run()?),
        Some("experiment") => {
            let s = scenario(args)?;
            let runs = match flag(args, "--runs") {
                Some(r) => Some(
                    r.parse()
                        .map_err(|_| Error::field("--runs", "must be a positive integer"))?,
                ),
                None => None,
            };
            match shard(args)? {
                None => json(&study::run_sharded(&|| s.study(runs), CHUNK)?),
                Some((i, n)) => {
                    let mut st = s.study(runs)?;
                    st.restrict(i, n)?;
                    study::run_to_end(st.as_mut(), CHUNK, |_, _| {})?;
                    let range = st.range();
                    let part = Part {
                        confset: env!("CARGO_PKG_VERSION").into(),
                        scenario: to_value(&s)?,
                        scenario_digest: s.digest()?,
                        runs: st.total(),
                        shard: [i, n],
                        range: [range.start, range.end],
                        partial: st.partial()?,
                    };
                    let line = serde_json::to_string(&part)
                        .map_err(|e| Error::field("", e.to_string()))?;
                    println!("{line}");
                    Ok(())
                }
            }
        }
        Some("merge") => json(&merge(&args[1..])?),
        Some("figure") => {
            let out = flag(args, "-o")
                .ok_or_else(|| Error::field("-o", "is needed: the SVG file to write"))?;
            let report = scenario_with_data(args)?.run()?;
            let (w, h) = size(args)?;
            let v = view(args, &report)?;
            // A panel that does not fit the report (e.g. state for LSCR) names the flag.
            let svg = plot::report_svg(&report, &v, w, h).map_err(|e| {
                if e.field == "panel" && flag(args, "--panel").is_some() {
                    Error::field("--panel", e.message)
                } else {
                    e
                }
            })?;
            write(out, &svg)
        }
        Some("figures") => {
            // `figures -o DIR` or `figures DIR`.
            let dir = flag(args, "-o")
                .or_else(|| {
                    args.iter()
                        .enumerate()
                        .skip(1)
                        .find(|(i, a)| {
                            !a.starts_with('-') && !VALUED.contains(&args[i - 1].as_str())
                        })
                        .map(|(_, a)| a.as_str())
                })
                .ok_or_else(|| Error::field("-o", "is needed: the directory to write into"))?;
            std::fs::create_dir_all(dir)
                .map_err(|e| Error::field("-o", format!("cannot create {dir}: {e}")))?;
            let (w, h) = size(args)?;
            for p in presets::all() {
                let report = p.scenario.run()?;
                for panel in plot::useful_panels(&report) {
                    let path = format!("{dir}/{}-{}.svg", p.name, panel.name());
                    write(&path, &plot::report_svg(&report, &View::new(panel), w, h)?)?;
                    eprintln!("wrote {path}");
                }
            }
            Ok(())
        }
        _ => Err(Error::field("", USAGE)),
    }
}
