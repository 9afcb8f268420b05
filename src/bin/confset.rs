//! `confset` — the command line: scenario file in, report JSON or SVG figures out.
//!
//! ```text
//! confset presets                          list the paper presets
//! confset run SCENARIO.json                report JSON on stdout
//! confset run --preset NAME                the same for a preset
//! confset experiment SCENARIO.json|--preset NAME [--runs N]
//!                                          conditional Monte Carlo (counts JSON)
//! confset figure SCENARIO.json|--preset NAME -o FILE.svg
//! confset figures -o DIR                   every preset's figures as SVG
//! ```

use confset::scenario::Scenario;
use confset::{presets, Error};
use std::process::ExitCode;

const USAGE: &str = "usage:
  confset presets
  confset run (SCENARIO.json | --preset NAME)
  confset experiment (SCENARIO.json | --preset NAME) [--runs N]
  confset figure (SCENARIO.json | --preset NAME) -o FILE.svg
  confset figures -o DIR";

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
        .skip(1)
        .find(|a| {
            !a.starts_with('-')
                && Some(a.as_str()) != flag(args, "-o")
                && Some(a.as_str()) != flag(args, "--runs")
        })
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
                println!("{:<22} {}", p.name, p.description);
            }
            Ok(())
        }
        Some("run") => json(&scenario(args)?.run()?),
        Some("experiment") => {
            let mut s = scenario(args)?;
            if let (Some(r), Some(e)) = (flag(args, "--runs"), s.experiment.as_mut()) {
                e.runs = r
                    .parse()
                    .map_err(|_| Error::field("--runs", "must be a positive integer"))?;
            }
            let prepared = s.prepare()?;
            let mut exp = confset::experiment::ConditionalExperiment::new(&prepared)?;
            while !exp.finished() {
                exp.step(1000);
            }
            json(exp.result())
        }
        Some("figure") => {
            let out = flag(args, "-o")
                .ok_or_else(|| Error::field("-o", "is needed: the SVG file to write"))?;
            let svg = confset::plot::scenario_svg(&scenario(args)?, 960, 640)?;
            write(out, &svg)
        }
        Some("figures") => {
            let dir = flag(args, "-o")
                .ok_or_else(|| Error::field("-o", "is needed: the directory to write into"))?;
            std::fs::create_dir_all(dir)
                .map_err(|e| Error::field("-o", format!("cannot create {dir}: {e}")))?;
            for p in presets::all() {
                let path = format!("{dir}/{}.svg", p.name);
                write(&path, &confset::plot::scenario_svg(&p.scenario, 960, 640)?)?;
                eprintln!("wrote {path}");
            }
            Ok(())
        }
        _ => Err(Error::field("", USAGE)),
    }
}
