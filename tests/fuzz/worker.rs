//! The worker: runs cases in this process (as the CLI calls the library) and through the real
//! binary, classifies each, writes the reproducer of each failure. It tells the supervisor
//! `start i` before case i and `end i CLASS` after it, each line flushed, so the case that
//! kills it (abort, hang) is known.

use crate::cases::{self, Bases, Case, File, Job, STUDY_RUNS};
use crate::contract::{check_report_json, null_paths, rust_word};
use crate::tally::{write_repro, Class};
use crate::Args;
use confset::plot::{self, View};
use confset::scenario::Scenario;
use serde_json::Value;
use std::io::Write;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;
use std::process::ExitCode;
use std::time::{Duration, Instant};

pub fn main(args: &Args) -> ExitCode {
    cap_memory(args.memory_gb);
    // A panic is a class, caught and counted: no backtrace on stderr for each.
    std::panic::set_hook(Box::new(|_| {}));
    let mut bases = Bases::load(&args.out);
    let dir = args.out.join(format!("work-{}", std::process::id()));
    let mut out = std::io::stdout().lock();
    for i in args.from..args.from + args.cases {
        let kind = cases::kind_of(&args.kinds, i);
        let _ = writeln!(out, "start {i}").and_then(|_| out.flush());
        let started = Instant::now();
        let (class, line) =
            match catch_unwind(AssertUnwindSafe(|| cases::make(&mut bases, kind, i))) {
                Ok(case) => {
                    let (class, detail) = execute(&case, args, &dir);
                    let line = if class.is_failure() {
                        write_repro(&args.out, &case, class, &detail)
                    } else {
                        case.id
                    };
                    (class, line)
                }
                Err(p) => {
                    let case = Case {
                        id: format!("{kind}:{i}"),
                        kind: kind.into(),
                        what: "(the generator panicked)".into(),
                        job: Job::Cli {
                            args: vec![],
                            files: vec![],
                        },
                    };
                    (
                        Class::Panic,
                        write_repro(&args.out, &case, Class::Panic, &panic_text(p)),
                    )
                }
            };
        // One line: the description may hold newlines.
        let line = line.replace('\n', " ");
        let ms = started.elapsed().as_secs_f64() * 1e3;
        let _ = writeln!(out, "end {i} {} {ms:.3} {line}", class.name()).and_then(|_| out.flush());
    }
    let _ = std::fs::remove_dir_all(&dir);
    ExitCode::SUCCESS
}

/// `--replay FILE`: the reproducer's case run here, its class and detail printed.
pub fn replay(args: &Args, file: &Path) -> ExitCode {
    let case: Option<Case> = std::fs::read_to_string(file)
        .ok()
        .and_then(|t| serde_json::from_str::<Value>(&t).ok())
        .and_then(|v| serde_json::from_value(v["case"].clone()).ok());
    let Some(case) = case else {
        eprintln!("{}: not a reproducer of the campaign", file.display());
        return ExitCode::from(2);
    };
    std::panic::set_hook(Box::new(|_| {}));
    let started = Instant::now();
    let (class, detail) = execute(&case, args, &args.out.join("replay"));
    println!(
        "{} {} ({:.2} s): {}\n{detail}",
        class.name(),
        case.id,
        started.elapsed().as_secs_f64(),
        case.what
    );
    if class.is_failure() {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

/// The address-space cap (RLIMIT_AS) on this process and the binaries it starts: an
/// allocation past it aborts the worker, which the supervisor records.
fn cap_memory(gb: u64) {
    let bytes = gb << 30;
    let limit = libc::rlimit {
        rlim_cur: bytes,
        rlim_max: bytes,
    };
    // SAFETY: setrlimit reads the struct we pass and touches nothing else of ours.
    if unsafe { libc::setrlimit(libc::RLIMIT_AS, &limit) } != 0 {
        eprintln!("campaign: could not cap the worker's memory at {gb} GB");
    }
}

fn panic_text(p: Box<dyn std::any::Any + Send>) -> String {
    let text = p
        .downcast_ref::<String>()
        .cloned()
        .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_default();
    format!("panicked: {text}")
}

/// Run one case: its class and what it gave.
pub fn execute(case: &Case, args: &Args, dir: &Path) -> (Class, String) {
    match &case.job {
        Job::Cli { args: a, files } => cli(a, files, args, dir),
        job => catch_unwind(AssertUnwindSafe(|| in_process(job)))
            .unwrap_or_else(|p| (Class::Panic, panic_text(p))),
    }
}

/// A word of Rust in a message (backquotes aside: messages quote commands in them).
fn rust_in(text: &str) -> Option<&'static str> {
    rust_word(&text.replace('`', ""))
}

/// The class of an error: refused, or a bad message.
fn refusal(e: &confset::Error) -> (Class, String) {
    let text = e.to_string();
    if e.field.is_empty() || e.message.trim().is_empty() {
        (
            Class::BadMessage,
            format!("an error without a field: {text}"),
        )
    } else if let Some(w) = rust_in(&text) {
        (Class::BadMessage, format!("{w:?} in the message: {text}"))
    } else {
        (Class::Refused, text)
    }
}

/// Null where a number belongs in a study's result, partial or merged result.
fn nulls_in(v: &Value, what: &str) -> (Class, String) {
    let bad: Vec<String> = null_paths(v)
        .into_iter()
        .filter(|(_, nullable)| !nullable)
        .map(|(p, _)| p)
        .collect();
    if bad.is_empty() {
        (Class::Ok, String::new())
    } else {
        let first: Vec<&str> = bad.iter().take(5).map(String::as_str).collect();
        (
            Class::Null,
            format!(
                "null in the {what} at {} of {} paths: {}",
                bad.len(),
                bad.len(),
                first.join(", ")
            ),
        )
    }
}

/// The first cell of CSV text that is not a finite number or a word.
fn non_finite_cell(csv: &str) -> Option<String> {
    csv.lines().enumerate().find_map(|(i, line)| {
        line.split(',').find_map(|cell| {
            let c = cell
                .trim()
                .trim_start_matches(['+', '-'])
                .to_ascii_lowercase();
            matches!(c.as_str(), "inf" | "infinity" | "nan")
                .then(|| format!("line {} has the cell {cell:?}", i + 1))
        })
    })
}

fn in_process(job: &Job) -> (Class, String) {
    let go = || -> Result<(Class, String), confset::Error> {
        Ok(match job {
            Job::Run {
                scenario,
                csv_data,
                figure,
            } => {
                let mut s = Scenario::from_json(scenario)?;
                if let Some(text) = csv_data {
                    s = s.with_csv_data(text)?;
                }
                let report = s.run()?;
                if let Err(e) = check_report_json(&report) {
                    return Ok((Class::Null, format!("report: {e}")));
                }
                // A non-finite cell is refused by the table itself (a field error); one that
                // slipped past it would be written as text here.
                if let Some(cell) = non_finite_cell(&report.table()?.to_csv()) {
                    return Ok((Class::NonFinite, format!("the report's CSV: {cell}")));
                }
                if *figure {
                    let panel = plot::useful_panels(&report)
                        .first()
                        .copied()
                        .unwrap_or_default();
                    plot::report_svg(&report, &View::new(panel), 480, 320)?;
                }
                (Class::Ok, String::new())
            }
            Job::Study {
                scenario,
                runs,
                shard,
            } => {
                let s = Scenario::from_json(scenario)?;
                let mut st = s.study(*runs)?;
                if let Some((i, n)) = shard {
                    st.restrict(*i, *n)?;
                }
                let mut done = 0;
                while !st.finished() && done < STUDY_RUNS {
                    st.step(8)?;
                    done += 8;
                }
                if st.finished() && shard.is_none() {
                    nulls_in(&st.result()?, "study's result")
                } else {
                    nulls_in(&st.partial()?, "study's partial")
                }
            }
            Job::Merge {
                scenario,
                runs,
                parts,
            } => {
                let s = Scenario::from_json(scenario)?;
                let mut st = s.study(*runs)?;
                let mut values = Vec::new();
                for (k, t) in parts.iter().enumerate() {
                    match serde_json::from_str::<Value>(t) {
                        Ok(v) => values.push(v),
                        // The binary refuses a part that is not JSON before the library sees it.
                        Err(e) => {
                            return Ok((Class::Refused, format!("part {k} is not JSON: {e}")))
                        }
                    }
                }
                st.merge(&values)?;
                st.complete()?;
                nulls_in(&st.result()?, "merged result")
            }
            Job::Cli { .. } => unreachable!("command-line cases run the binary"),
        })
    };
    go().unwrap_or_else(|e| refusal(&e))
}

/// A file's bytes: its text, or one byte per character for a raw file.
pub fn file_bytes(f: &File) -> Vec<u8> {
    if f.raw {
        f.text.chars().map(|c| c as u32 as u8).collect()
    } else {
        f.text.clone().into_bytes()
    }
}

/// The binary on the case's files, stopped a second before the supervisor's limit.
fn cli(a: &[String], files: &[File], args: &Args, dir: &Path) -> (Class, String) {
    let _ = std::fs::remove_dir_all(dir);
    if let Err(e) = std::fs::create_dir_all(dir) {
        return (
            Class::Abort,
            format!("the campaign cannot write {}: {e}", dir.display()),
        );
    }
    for f in files {
        let _ = std::fs::write(dir.join(&f.name), file_bytes(f));
    }
    let d = dir.display().to_string();
    let a: Vec<String> = a.iter().map(|s| s.replace("{dir}", &d)).collect();
    let open = |name: &str| std::fs::File::create(dir.join(name));
    let (Ok(stdout), Ok(stderr)) = (open("stdout"), open("stderr")) else {
        return (Class::Abort, "the campaign cannot write the outputs".into());
    };
    let child = std::process::Command::new(args.confset())
        .args(&a)
        .env("RAYON_NUM_THREADS", "1")
        .stdin(std::process::Stdio::null())
        .stdout(stdout)
        .stderr(stderr)
        .spawn();
    let mut child = match child {
        Ok(c) => c,
        Err(e) => {
            return (
                Class::Abort,
                format!("cannot start {}: {e}", args.confset().display()),
            )
        }
    };
    let limit = Duration::from_secs(args.case_seconds.saturating_sub(1).max(1));
    let started = Instant::now();
    let status = loop {
        match child.try_wait() {
            Ok(Some(s)) => break s,
            Ok(None) if started.elapsed() > limit => {
                let _ = child.kill();
                let _ = child.wait();
                return (
                    Class::Hang,
                    format!(
                        "confset {} still running after {} s",
                        a.join(" "),
                        limit.as_secs()
                    ),
                );
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(2)),
            Err(e) => return (Class::Abort, format!("cannot wait for confset: {e}")),
        }
    };
    let read = |name: &str| {
        String::from_utf8_lossy(&std::fs::read(dir.join(name)).unwrap_or_default()).into_owned()
    };
    let err = read("stderr");
    let tail: String = err.chars().take(400).collect();
    use std::os::unix::process::ExitStatusExt;
    if let Some(sig) = status.signal() {
        return (
            Class::Abort,
            format!("confset killed by signal {sig}: {tail}"),
        );
    }
    match status.code() {
        Some(0) => {}
        Some(101) => return (Class::Panic, tail),
        Some(2) => return (Class::Refused, tail),
        Some(1) if !err.starts_with("error: ") => {
            return (Class::BadMessage, format!("not an error line: {tail}"))
        }
        Some(1) => {
            return match rust_in(&err) {
                Some(w) => (Class::BadMessage, format!("{w:?} in the message: {tail}")),
                None => (Class::Refused, tail),
            }
        }
        code => return (Class::Abort, format!("exit code {code:?}: {tail}")),
    }
    if a[0] == "figure" {
        return (Class::Ok, String::new());
    }
    let out = read("stdout");
    match serde_json::from_str::<Value>(&out) {
        // A part file holds the scenario (whose absent options are null): its counts count.
        Ok(v) if a[0] == "experiment" => nulls_in(&v["partial"], "part's partial"),
        Ok(v) => nulls_in(&v, &format!("output of confset {}", a[0])),
        Err(_) => match non_finite_cell(&out) {
            Some(cell) => (Class::NonFinite, format!("confset {}: {cell}", a.join(" "))),
            None => (Class::Ok, String::new()),
        },
    }
}
