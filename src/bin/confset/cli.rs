//! The command line's arguments (clap) and what each subcommand does with the core.
//!
//! Exit status: 0 done; 1 the core refused the input or could not compute (the message names
//! the field and the limit, as everywhere in confset); 2 a usage error (clap's message).

use clap::{Args, CommandFactory, Parser, Subcommand, ValueEnum};
use confset::method::Method;
use confset::plot::{self, Panel, View, Zoom};
use confset::scenario::csv::MAX_CSV_BYTES;
use confset::scenario::{budget, Scenario, MAX_SCENARIO_BYTES};
use confset::{presets, study, Error};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::{IsTerminal, Read};
use std::path::PathBuf;
use std::process::ExitCode;

const EXIT_STATUS: &str =
    "Exit status: 0 done; 1 the scenario, data or parts were refused or could \
not be computed (the message names the field); 2 a usage error.";

/// Guaranteed-set state estimation from the command line: the five papers' methods on a
/// scenario file, their Monte Carlo studies (on every core, or sharded across machines), their
/// figures, and the gallery site of the papers' figures.
#[derive(Parser)]
#[command(name = "confset", version, after_help = EXIT_STATUS)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// List the paper presets (their names, labels and what they show)
    #[command(after_help = "Example:\n  confset presets")]
    Presets,
    /// Print a preset's scenario JSON: the starting point for a scenario of one's own
    #[command(after_help = "Examples:\n  confset preset scf-scalar > mine.json\n  \
        confset preset ubb-track | confset run -")]
    Preset {
        /// The preset (`confset presets` lists them)
        #[arg(value_parser = preset_names())]
        name: String,
    },
    /// Run a scenario: its report as JSON, or as CSV (one row per time step)
    #[command(after_help = "Examples:\n  confset run --preset scf-scalar\n  \
        confset run my-scenario.json --format csv --out steps.csv\n  \
        confset run --preset ubb-track --data measured.csv\n  \
        confset preset lscr-ma1 | confset run -")]
    Run {
        #[command(flatten)]
        input: Input,
        #[command(flatten)]
        data: DataArg,
        /// json: the whole report; csv: one row per time step of the main estimates and set
        /// sizes (the README lists each method's columns)
        #[arg(long, value_enum, default_value_t = Format::Json)]
        format: Format,
        /// Write to FILE instead of standard output
        #[arg(long, value_name = "FILE")]
        out: Option<PathBuf>,
    },
    /// Run the scenario's Monte Carlo study on every core (or one shard of it): result JSON
    #[command(after_help = "Examples:\n  confset experiment --preset scf-robots\n  \
        confset experiment --preset ubb-track --runs 500\n  \
        confset experiment --preset ubb-track --shard 0/4 > part-0.json\n\n\
        A progress bar goes to standard error when it is a terminal. RAYON_NUM_THREADS=1 runs \
        on one core; the result is the same bit for bit.")]
    Experiment {
        #[command(flatten)]
        input: Input,
        /// Runs of the study (default: the scenario's own count). A scenario without its study
        /// block runs with N runs and seed 0: kf/scf every component, conditioned on
        /// simulate.condition or else on the prior mean at the last step; lscr at
        /// simulate.condition or else x = 0 at the estimated time; glls the estimator's study
        /// (state_noise: Section 5.2, else 5.1's precision); compare at the target's prior
        /// mean; ubb and conformal their own defaults
        #[arg(long, value_name = "N")]
        runs: Option<usize>,
        /// Only shard i of N (0 ≤ i < N), printed as one JSON line for `confset merge`
        #[arg(long, value_name = "i/N", value_parser = parse_shard)]
        shard: Option<(usize, usize)>,
        /// Write to FILE instead of standard output
        #[arg(long, value_name = "FILE")]
        out: Option<PathBuf>,
    },
    /// Every method on one record: the compare report (each method's set, the table) and, when
    /// the scenario has a compare.study, its counts at the true state, as one JSON
    #[command(
        after_help = "Examples:\n  confset compare --preset compare-gaussian\n  \
        confset preset compare-uniform > mine.json && confset compare mine.json --runs 500\n  \
        confset compare --preset compare-uniform --data record.csv --no-study\n\n\
        The scenario's \"method\" must be \"compare\". Each set comes with the method's own \
        scenario (sets[i].scenario): `confset run` on it gives the same set. Each method's run is \
        timed (sets[i].seconds)."
    )]
    Compare {
        #[command(flatten)]
        input: Input,
        #[command(flatten)]
        data: DataArg,
        /// Runs of the study (default: compare.study.runs); without compare.study, the study
        /// at the target's prior mean with seed 0
        #[arg(long, value_name = "N")]
        runs: Option<usize>,
        /// The report only, without the study's counts
        #[arg(long)]
        no_study: bool,
        /// Write to FILE instead of standard output
        #[arg(long, value_name = "FILE")]
        out: Option<PathBuf>,
    },
    /// Merge the parts of one sharded study into what `confset experiment` prints
    #[command(
        after_help = "Examples:\n  confset merge part-*.json > result.json\n  \
        confset merge - < parts.jsonl\n\n\
        The parts must come from the same confset version, scenario, seed and run count, and \
        cover every run exactly once; otherwise the merge says which part is wrong."
    )]
    Merge {
        /// The part files (`-`: JSON documents on standard input)
        #[arg(value_name = "PART", required = true)]
        parts: Vec<String>,
        /// Write to FILE instead of standard output
        #[arg(long, value_name = "FILE")]
        out: Option<PathBuf>,
    },
    /// Draw one figure of a scenario as SVG
    #[command(
        after_help = "Examples:\n  confset figure --preset scf-robots -o robots.svg\n  \
        confset figure --preset glls-saturate --panel singular -o glls-fig1.svg\n  \
        confset figure --preset ubb-track --panel ubbset --time 12 --size 1600x1000 -o set.svg\n\n\
        Without --panel: the report's first useful panel (region for LSCR, singular for GLLS, \
        ustates for uniform_lp, ubbset for ubb, state otherwise)."
    )]
    Figure {
        #[command(flatten)]
        input: Input,
        #[command(flatten)]
        data: DataArg,
        /// The file to write: SVG, or PNG when it ends in .png
        #[arg(short = 'o', long = "out", value_name = "FILE.svg|FILE.png")]
        out: PathBuf,
        /// PNG only: pixels per figure pixel (2 for slides and hi-DPI screens)
        #[arg(long, value_name = "S", default_value_t = 2.0, value_parser = parse_scale)]
        scale: f32,
        #[command(flatten)]
        view: ViewArgs,
        #[command(flatten)]
        size: SizeArg,
    },
    /// Every useful panel of every preset as SVG: DIR/PRESET-PANEL.svg
    #[command(after_help = "Example:\n  confset figures -o figures/")]
    Figures {
        /// The directory to write into
        #[arg(short = 'o', long = "out", value_name = "DIR")]
        out: PathBuf,
        #[command(flatten)]
        size: SizeArg,
    },
    /// Write the gallery site of the papers' figures and numbers, with the explorer copied in
    #[command(
        after_help = "Example:\n  bash .ci/build && confset gallery -o site/\n  \
        python3 -m http.server --directory site 8000\n\n\
        DIR/index.html is a grid of every figure and table of the five papers that a preset \
        reproduces; each entry has the paper's printed numbers beside ours with a verdict, the \
        scenario and report JSON, and a link into the explorer (copied from --explorer into \
        DIR/explorer: it needs the built module, `bash .ci/build`). Relative links only: any \
        static host serves DIR as it is."
    )]
    Gallery {
        /// The directory to write the site into
        #[arg(short = 'o', long = "out", value_name = "DIR")]
        out: PathBuf,
        /// The explorer to copy into DIR/explorer (the repository's www/, built)
        #[arg(long, value_name = "DIR", default_value = "www")]
        explorer: PathBuf,
        #[command(flatten)]
        size: SizeArg,
    },
    /// Print a shell completion script
    #[command(
        after_help = "Example:\n  confset completions bash > ~/.local/share/bash-completion/completions/confset"
    )]
    Completions {
        /// The shell
        shell: clap_complete::Shell,
    },
}

/// Where the scenario comes from.
#[derive(Args)]
struct Input {
    /// The scenario file (JSON); `-` reads it from standard input
    #[arg(
        value_name = "SCENARIO",
        required_unless_present = "preset",
        conflicts_with = "preset"
    )]
    scenario: Option<String>,
    /// A paper preset instead of a file (`confset presets` lists them)
    #[arg(long, value_name = "NAME", value_parser = preset_names())]
    preset: Option<String>,
}

#[derive(Args)]
struct DataArg {
    /// Measured data from CSV, replacing the scenario's data or simulation: columns y1 … yq,
    /// then optionally u1 … ur, header optional (a column named t, time, year or date is the
    /// record's time; empty, NA, nan and #N/A cells are gaps)
    #[arg(long, value_name = "FILE.csv")]
    data: Option<PathBuf>,
    /// The header's columns to read as y1 … yq, then optionally u1 … ur, in that order (other
    /// columns are not used; the time column is found among them)
    #[arg(long, value_name = "NAME,…", value_delimiter = ',', requires = "data")]
    columns: Vec<String>,
}

#[derive(Args)]
struct ViewArgs {
    /// The panel to draw (one of the scenario's method)
    #[arg(long, value_parser = panel_names())]
    panel: Option<String>,
    /// The time step shown (1, 2, …)
    #[arg(long, value_name = "T", value_parser = clap::value_parser!(u64).range(1..))]
    time: Option<u64>,
    /// How the state plane is framed
    #[arg(long, value_enum)]
    zoom: Option<ZoomArg>,
}

#[derive(Args)]
struct SizeArg {
    /// The figure's size in pixels, 16 to 8192 per side
    #[arg(long, value_name = "WxH", value_parser = parse_size, default_value = "960x640")]
    size: (u32, u32),
}

#[derive(Clone, Copy, ValueEnum)]
enum Format {
    Json,
    Csv,
}

#[derive(Clone, Copy, ValueEnum)]
enum ZoomArg {
    Auto,
    Regions,
    Full,
}

fn preset_names() -> clap::builder::PossibleValuesParser {
    clap::builder::PossibleValuesParser::new(presets::all().into_iter().map(|p| p.name))
}

fn panel_names() -> clap::builder::PossibleValuesParser {
    let mut names: Vec<&'static str> = Vec::new();
    for m in Method::ALL {
        for p in plot::method_panels(m) {
            if !names.contains(&p.name()) {
                names.push(p.name());
            }
        }
    }
    clap::builder::PossibleValuesParser::new(names)
}

/// `WxH` in pixels, 16 to 8192 per side.
fn parse_size(v: &str) -> Result<(u32, u32), String> {
    let bad = || format!("must read WIDTHxHEIGHT in pixels, e.g. 960x640, found {v:?}");
    let (w, h) = v.split_once(['x', 'X']).ok_or_else(bad)?;
    let (w, h): (u32, u32) = (w.parse().map_err(|_| bad())?, h.parse().map_err(|_| bad())?);
    if !(16..=8192).contains(&w) || !(16..=8192).contains(&h) {
        return Err("must be a whole number from 16 to 8192 pixels per side".into());
    }
    Ok((w, h))
}

/// A PNG scale from 0.25 to 8.
fn parse_scale(v: &str) -> Result<f32, String> {
    match v.parse::<f32>() {
        Ok(s) if s.is_finite() && (0.25..=8.0).contains(&s) => Ok(s),
        _ => Err(format!("must be a number from 0.25 to 8, found {v:?}")),
    }
}

/// `i/N` with 0 ≤ i < N.
fn parse_shard(v: &str) -> Result<(usize, usize), String> {
    let bad = || {
        format!("must read i/N with 0 ≤ i < N, e.g. 0/4 (shards are counted from 0), found {v:?}")
    };
    let (i, n) = v.split_once('/').ok_or_else(bad)?;
    let (i, n): (usize, usize) = (i.parse().map_err(|_| bad())?, n.parse().map_err(|_| bad())?);
    if i >= n {
        return Err(bad());
    }
    Ok((i, n))
}

pub fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}

/// Most bytes of a `merge` part, derived from what a part can hold: the scenario (at most
/// [`MAX_SCENARIO_BYTES`] as given, at most twice that as written back: `1` becomes `1.0`)
/// and the study's partial counts, whose per-run numbers (the GLLS errors) the work budget
/// holds to [`budget::MAX_BYTES`] at 8 bytes each, written as at most 25 characters each
/// (`-2.2250738585072014e-308,`), with 1 MB for the rest: about 666 MB.
const MAX_PART_BYTES: usize =
    (budget::MAX_BYTES as usize / 8) * 25 + 2 * MAX_SCENARIO_BYTES + 1_000_000;

/// An input's text, read through one bounded reader: at most `limit` bytes of `path` (`-`:
/// standard input) are read, and one byte more means the input is refused, naming `field`, the
/// file and the limit. `/dev/zero` given as a scenario was read until memory ran out.
fn read_bounded(path: &str, limit: usize, what: &str, field: &str) -> Result<String, Error> {
    let name = if path == "-" {
        "standard input".to_string()
    } else {
        path.to_string()
    };
    let fail = |e: std::io::Error| Error::field(field, format!("cannot read {what} {name}: {e}"));
    let too_large = || {
        Error::field(
            field,
            format!(
                "{what} {name} is larger than {limit} bytes ({} MB), the most {what} may hold",
                limit / 1_000_000
            ),
        )
    };
    // A file that says it is too large is refused unread; devices and pipes (`/dev/zero`)
    // say nothing, so every read stops one byte past the limit.
    if path != "-" && std::fs::metadata(path).is_ok_and(|m| m.is_file() && m.len() > limit as u64) {
        return Err(too_large());
    }
    let mut bytes = Vec::new();
    if path == "-" {
        std::io::stdin()
            .lock()
            .take(limit as u64 + 1)
            .read_to_end(&mut bytes)
    } else {
        std::fs::File::open(path)
            .map_err(fail)?
            .take(limit as u64 + 1)
            .read_to_end(&mut bytes)
    }
    .map_err(fail)?;
    if bytes.len() > limit {
        return Err(too_large());
    }
    String::from_utf8(bytes).map_err(|e| {
        Error::field(
            field,
            format!(
                "{what} {name} is not UTF-8 text (byte {} is not)",
                e.utf8_error().valid_up_to()
            ),
        )
    })
}

fn scenario(input: &Input) -> Result<Scenario, Error> {
    match (&input.preset, &input.scenario) {
        (Some(name), _) => presets::get(name),
        (None, Some(path)) => {
            let s =
                Scenario::from_json(&read_bounded(path, MAX_SCENARIO_BYTES, "the scenario", "")?)?;
            // Keys where an older version wrote them (the report's `notices` says it too).
            for notice in s.notices() {
                eprintln!("note: {}: {notice}", path);
            }
            Ok(s)
        }
        // clap requires one of the two.
        (None, None) => Err(Error::field(
            "",
            "a scenario file or --preset NAME is needed",
        )),
    }
}

/// The scenario with `--data FILE.csv [--columns NAME,…]` applied
/// (`Scenario::read_csv_file`: its `data` read from the file, its `simulate` dropped, its
/// title naming the file), or as it is without the flag. The reader's notes (columns not used,
/// blank lines at the end that are not rows) go to standard error as `note: FILE: …`.
fn scenario_with_data(input: &Input, data: &DataArg) -> Result<Scenario, Error> {
    let s = scenario(input)?;
    let Some(path) = &data.data else {
        return Ok(s);
    };
    let name = path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    let path = path.display().to_string();
    let text = read_bounded(&path, MAX_CSV_BYTES, "the CSV data", "--data")?;
    let (s, notes) = s.read_csv_file(&text, &name, &data.columns).map_err(|e| {
        // Name the file, so "data.y row 7, …" points into it (a model error is the scenario's);
        // a name chosen is the flag's.
        if e.field == "columns" {
            Error::field("--columns", format!("{} (in {path})", e.message))
        } else if e.field.starts_with("data") {
            Error::field(e.field, format!("{} (in {path})", e.message))
        } else {
            e
        }
    })?;
    for note in notes {
        eprintln!("note: {path}: {note}");
    }
    Ok(s)
}

/// A report's warnings (assumptions not met, gaps and what was done with them, …) on standard
/// error, one `warning: …` line each: standard output stays the JSON or CSV (which hold them
/// too, as `warnings` and `# warning:` lines).
fn print_warnings(warnings: &[String]) {
    for w in warnings {
        eprintln!("warning: {}", w.replace(['\n', '\r'], " "));
    }
}

/// A progress bar on standard error when it is a terminal; hidden otherwise (pipes, CI logs).
fn progress_bar(total: usize) -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(total as u64);
    if let Ok(style) =
        ProgressStyle::with_template("{elapsed_precise} [{wide_bar}] {pos}/{len} runs, {eta} left")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    bar
}

/// A whole study on every core with its progress bar: the one runner of `experiment` and
/// `compare`. Chunks of [`study::progress_chunk`] runs, so the bar moves about every 0.5 %
/// of the runs, whatever their number.
fn run_study(s: &Scenario, runs: Option<usize>) -> Result<serde_json::Value, Error> {
    let total = s.study(runs)?.total();
    let bar = progress_bar(total);
    let result = study::run_sharded(&|| s.study(runs), study::progress_chunk(total), &|k| {
        bar.inc(k as u64)
    });
    bar.finish_and_clear();
    result
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
            // All parts on standard input together are held to one part's limit (the runs'
            // numbers split between the shards); larger parts go as files.
            let text = read_bounded(path, MAX_PART_BYTES, "the parts' text on", "")?;
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
            let text = read_bounded(path, MAX_PART_BYTES, "the part", "")?;
            texts.push((path.clone(), text));
        }
    }
    if texts.is_empty() {
        return Err(Error::field(
            "",
            "merge needs the part files (or - for parts on standard input)",
        ));
    }
    // Each part is named by its number and file in every message: "part 2 (b.json)".
    let names: Vec<String> = texts
        .iter()
        .enumerate()
        .map(|(k, (name, _))| format!("part {} ({name})", k + 1))
        .collect();
    let mut parts = Vec::new();
    for (name, (_, text)) in names.iter().zip(&texts) {
        let p: Part = confset::scenario::parse::from_json(text, "")
            .map_err(|e| Error::field("", format!("{name} is not a part file: {e}")))?;
        if p.confset != env!("CARGO_PKG_VERSION") {
            return Err(Error::field(
                "",
                format!(
                    "{name} was written by confset {}, this is confset {}: runs may differ between versions",
                    p.confset,
                    env!("CARGO_PKG_VERSION")
                ),
            ));
        }
        parts.push(p);
    }
    let first = &parts[0];
    let s = Scenario::from_json(&first.scenario.to_string()).map_err(|e| {
        Error::field(
            e.field,
            format!("{} (in {}'s scenario)", e.message, names[0]),
        )
    })?;
    if s.digest()? != first.scenario_digest {
        return Err(Error::field(
            "",
            format!(
                "{}'s scenario does not match its scenario_digest: the file was edited",
                names[0]
            ),
        ));
    }
    for (name, p) in names.iter().zip(&parts) {
        check_part_fields(name, p, first)?;
    }
    let mut st = s.study(Some(first.runs))?;
    let named: Vec<(&str, &serde_json::Value)> = names
        .iter()
        .map(String::as_str)
        .zip(parts.iter().map(|p| &p.partial))
        .collect();
    st.merge_named(&named)?;
    st.complete().map_err(|e| {
        Error::field(
            e.field,
            format!("{} (the parts: {})", e.message, names.join(", ")),
        )
    })?;
    st.result()
}

/// The fields a part file holds beside the core's partial counts agree with them and with
/// part 1: the same scenario (and digest) and run count, `range` the partial's, and `shard`
/// i/N the runs that `study::shard_range` gives shard i of N. A file whose fields were edited
/// apart is refused, naming the file and the field.
fn check_part_fields(name: &str, p: &Part, first: &Part) -> Result<(), Error> {
    let refuse =
        |field: &str, why: String| Err(Error::field("", format!("{name}'s {field} {why}")));
    let partial = &p.partial;
    if p.scenario_digest != first.scenario_digest || p.scenario != first.scenario {
        return refuse(
            "scenario",
            "is not part 1's: parts of one study come from one scenario".into(),
        );
    }
    if partial.get("scenario_digest") != Some(&serde_json::Value::from(p.scenario_digest.as_str()))
    {
        return refuse(
            "partial.scenario_digest",
            format!(
                "is not the file's scenario_digest {}: the file was edited",
                p.scenario_digest
            ),
        );
    }
    if p.runs != first.runs {
        return refuse(
            "runs",
            format!(
                "is {}, part 1's is {}: the parts of one study have one run count",
                p.runs, first.runs
            ),
        );
    }
    if partial.get("total") != Some(&serde_json::Value::from(p.runs)) {
        return refuse(
            "partial.total",
            format!("is not the file's runs {}: the file was edited", p.runs),
        );
    }
    if partial.get("range") != Some(&serde_json::json!(p.range)) {
        return refuse(
            "range",
            format!(
                "{}..{} is not the partial's range: the file was edited",
                p.range[0], p.range[1]
            ),
        );
    }
    let [i, n] = p.shard;
    // The batch is the partial's (the core checks it is the study's when merging).
    let batch = partial.get("batch").and_then(serde_json::Value::as_u64);
    if let Some(batch) = batch {
        let want = study::shard_range(p.runs, batch as usize, i, n)
            .map_err(|e| Error::field("", format!("{name}'s shard {}", e.message)))?;
        if want != (p.range[0]..p.range[1]) {
            return refuse(
                "shard",
                format!(
                    "{i}/{n} holds runs {}..{} of {}, but the file's range is {}..{}: the file was edited",
                    want.start, want.end, p.runs, p.range[0], p.range[1]
                ),
            );
        }
    }
    Ok(())
}

fn json<T: serde::Serialize>(v: &T) -> Result<String, Error> {
    serde_json::to_string_pretty(v)
        .map(|s| s + "\n")
        .map_err(|e| Error::field("", e.to_string()))
}

/// Write `text` to `out`, or to standard output.
fn emit(out: Option<&PathBuf>, text: &str) -> Result<(), Error> {
    match out {
        Some(path) => std::fs::write(path, text)
            .map_err(|e| Error::field("--out", format!("cannot write {}: {e}", path.display()))),
        None => {
            print!("{text}");
            Ok(())
        }
    }
}

fn run(command: Command) -> Result<(), Error> {
    match command {
        Command::Presets => {
            for p in presets::all() {
                println!("{:<22} {}\n{:<22} {}", p.name, p.label, "", p.description);
            }
            Ok(())
        }
        Command::Preset { name } => emit(None, &json(&presets::get(&name)?)?),
        Command::Run {
            input,
            data,
            format,
            out,
        } => {
            let report = scenario_with_data(&input, &data)?.run()?;
            print_warnings(&report.warnings);
            let text = match format {
                Format::Json => json(&report)?,
                Format::Csv => report.table()?.to_csv(),
            };
            emit(out.as_ref(), &text)
        }
        Command::Experiment {
            input,
            runs,
            shard,
            out,
        } => {
            let s = scenario(&input)?;
            match shard {
                None => emit(out.as_ref(), &json(&run_study(&s, runs)?)?),
                Some((i, n)) => {
                    let mut st = s.study(runs)?;
                    st.restrict(i, n)?;
                    let bar = progress_bar(st.range().len());
                    let chunk = study::progress_chunk(st.range().len());
                    let result = study::run_to_end(st.as_mut(), chunk, |done, _| {
                        bar.set_position(done as u64)
                    });
                    bar.finish_and_clear();
                    result?;
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
                    emit(out.as_ref(), &(line + "\n"))
                }
            }
        }
        Command::Compare {
            input,
            data,
            runs,
            no_study,
            out,
        } => {
            let s = scenario_with_data(&input, &data)?;
            if s.method != confset::Method::Compare {
                return Err(Error::field(
                    "method",
                    format!("is \"{}\": `confset compare` takes a scenario with \"method\": \"compare\" (`confset preset compare-gaussian` is one)", s.method),
                ));
            }
            confset::scenario::compare::set_clock(seconds_since_start);
            let report = s.run()?;
            print_warnings(&report.warnings);
            let study = match (&s.compare, no_study) {
                (Some(c), false) if c.study.is_some() || runs.is_some() => {
                    Some(run_study(&s, runs)?)
                }
                _ => None,
            };
            let mut v = serde_json::Map::new();
            v.insert("report".into(), to_value(&report)?);
            if let Some(st) = study {
                v.insert("study".into(), st);
            }
            emit(out.as_ref(), &json(&serde_json::Value::Object(v))?)
        }
        Command::Merge { parts, out } => emit(out.as_ref(), &json(&merge(&parts)?)?),
        Command::Figure {
            input,
            data,
            out,
            scale,
            view,
            size,
        } => {
            let png = out
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("png"));
            // The PNG's pixels (size × scale) are checked before the scenario is even read.
            if png {
                let (w, h) = size.size;
                plot::check_png_pixels(w, h, scale).map_err(|e| {
                    Error::field(
                        "--scale",
                        format!(
                            "{} (--size {w}x{h}): give a smaller --scale or --size",
                            e.message
                        ),
                    )
                })?;
            }
            let s = scenario_with_data(&input, &data)?;
            // A panel of another method is refused before the report is computed.
            let panel = view.panel.as_deref().map(Panel::from_name).transpose()?;
            if let Some(p) = panel {
                if !plot::method_panels(s.method).contains(&p) {
                    return Err(Error::field(
                        "--panel",
                        format!(
                            "{} is not a panel of the method \"{}\" (its panels: {})",
                            p.name(),
                            s.method,
                            plot::method_panels(s.method)
                                .iter()
                                .map(|p| p.name())
                                .collect::<Vec<_>>()
                                .join(", ")
                        ),
                    ));
                }
            }
            let report = s.run()?;
            print_warnings(&report.warnings);
            let mut v = View::new(panel.unwrap_or_else(|| {
                plot::useful_panels(&report)
                    .first()
                    .copied()
                    .unwrap_or_default()
            }));
            v.time = view.time.map(|t| t as usize);
            if let Some(z) = view.zoom {
                v.zoom = match z {
                    ZoomArg::Auto => Zoom::Auto,
                    ZoomArg::Regions => Zoom::Regions,
                    ZoomArg::Full => Zoom::Full,
                };
            }
            let (w, h) = size.size;
            let svg = plot::report_svg(&report, &v, w, h).map_err(|e| {
                if e.field == "panel" && panel.is_some() {
                    Error::field("--panel", e.message)
                } else {
                    e
                }
            })?;
            let bytes = if png {
                plot::svg_to_png(&svg, scale)?
            } else {
                svg.into_bytes()
            };
            std::fs::write(&out, bytes)
                .map_err(|e| Error::field("-o", format!("cannot write {}: {e}", out.display())))
        }
        Command::Figures { out, size } => {
            std::fs::create_dir_all(&out)
                .map_err(|e| Error::field("-o", format!("cannot create {}: {e}", out.display())))?;
            let (w, h) = size.size;
            for p in presets::all() {
                let report = p.scenario.run()?;
                for panel in plot::useful_panels(&report) {
                    let path = out.join(format!("{}-{}.svg", p.name, panel.name()));
                    std::fs::write(&path, plot::report_svg(&report, &View::new(panel), w, h)?)
                        .map_err(|e| {
                            Error::field("-o", format!("cannot write {}: {e}", path.display()))
                        })?;
                    eprintln!("wrote {}", path.display());
                }
            }
            Ok(())
        }
        Command::Gallery {
            out,
            explorer,
            size,
        } => gallery(&out, &explorer, size.size),
        Command::Completions { shell } => {
            clap_complete::generate(
                shell,
                &mut Cli::command(),
                "confset",
                &mut std::io::stdout(),
            );
            Ok(())
        }
    }
}

/// Files of the explorer's directory that a static site does not serve.
fn not_served(name: &str) -> bool {
    matches!(
        name,
        "node_modules" | "package.json" | "package-lock.json" | ".gitignore" | "README.md"
            // A gallery written into www/ by .ci/serve: the site's gallery is its root.
            | "gallery"
    ) || name.starts_with("screenshot")
        || name.ends_with(".d.ts")
}

/// Copy the explorer's served files from `from` into `to`.
fn copy_explorer(from: &std::path::Path, to: &std::path::Path) -> Result<usize, Error> {
    let fail = |p: &std::path::Path, e: std::io::Error| {
        Error::field("--explorer", format!("cannot copy {}: {e}", p.display()))
    };
    std::fs::create_dir_all(to).map_err(|e| fail(to, e))?;
    let mut copied = 0;
    for item in std::fs::read_dir(from).map_err(|e| fail(from, e))? {
        let item = item.map_err(|e| fail(from, e))?;
        let name = item.file_name().to_string_lossy().into_owned();
        if not_served(&name) {
            continue;
        }
        let path = item.path();
        if path.is_dir() {
            copied += copy_explorer(&path, &to.join(&name))?;
        } else {
            std::fs::copy(&path, to.join(&name)).map_err(|e| fail(&path, e))?;
            copied += 1;
        }
    }
    Ok(copied)
}

/// `confset gallery -o DIR`: the core's site, then the explorer beside it.
fn gallery(
    out: &std::path::Path,
    explorer: &std::path::Path,
    size: (u32, u32),
) -> Result<(), Error> {
    let module = explorer.join("pkg").join("confset_bg.wasm");
    if !module.is_file() {
        return Err(Error::field(
            "--explorer",
            format!(
                "{} has no built module ({} is missing): run `bash .ci/build` first, or point \
                 --explorer at a built copy of www/",
                explorer.display(),
                module.display()
            ),
        ));
    }
    let t0 = std::time::Instant::now();
    let files = confset::gallery::build(size)?;
    for f in &files {
        let path = out.join(&f.path);
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir)
                .map_err(|e| Error::field("-o", format!("cannot create {}: {e}", dir.display())))?;
        }
        std::fs::write(&path, &f.bytes)
            .map_err(|e| Error::field("-o", format!("cannot write {}: {e}", path.display())))?;
    }
    let copied = copy_explorer(explorer, &out.join("explorer"))?;
    // The explorer links to its gallery as gallery/index.html (beside it when .ci/serve wrote
    // one into www/); inside the site, the gallery is the site's root: a redirect, no script
    // (the gallery's pages run none).
    let redirect = out.join("explorer").join("gallery");
    std::fs::create_dir_all(&redirect)
        .map_err(|e| Error::field("-o", format!("cannot create {}: {e}", redirect.display())))?;
    std::fs::write(
        redirect.join("index.html"),
        "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta http-equiv=\"refresh\" content=\"0; url=../../index.html\">\n\
         <title>The gallery</title>\n</head>\n<body>\n\
         <p><a href=\"../../index.html\">The gallery of the papers' figures</a></p>\n</body>\n</html>\n",
    )
    .map_err(|e| Error::field("-o", format!("cannot write {}: {e}", redirect.display())))?;
    eprintln!(
        "wrote {} gallery files and {copied} explorer files into {} in {:.1} s",
        files.len(),
        out.display(),
        t0.elapsed().as_secs_f64()
    );
    Ok(())
}

/// Seconds since the first call: the compare's clock (the core never reads one).
fn seconds_since_start() -> f64 {
    static START: std::sync::OnceLock<std::time::Instant> = std::sync::OnceLock::new();
    START
        .get_or_init(std::time::Instant::now)
        .elapsed()
        .as_secs_f64()
}
