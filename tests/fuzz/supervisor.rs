//! The supervisor: one worker process at a time over the case range; a worker that dies
//! (a signal, a panic that escaped) or stays on one case past the limit (killed) is charged
//! with its case in flight, which gets a reproducer, and a new worker goes on from the next
//! case. At the end (or at --minutes) it prints the counts table and writes `<out>/table.md`.

use crate::cases::{self, Bases};
use crate::tally::{write_repro, Class, Tally};
use crate::Args;
use std::io::BufRead;
use std::process::{Child, Command, ExitCode, Stdio};
use std::sync::mpsc::{channel, Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

/// A running worker and the lines it writes.
struct Worker {
    child: Child,
    lines: Receiver<String>,
}

/// The CPU seconds (user + system) process `pid` has used so far, from /proc (0 where there
/// is no /proc).
fn cpu_seconds(pid: u32) -> f64 {
    let Ok(stat) = std::fs::read_to_string(format!("/proc/{pid}/stat")) else {
        return 0.0;
    };
    // Fields after the command name (which may hold spaces, so split after its ')'): utime and
    // stime are fields 14 and 15 of the line, 12 and 13 after the ')'.
    let rest = stat.rsplit_once(')').map_or("", |(_, r)| r);
    let ticks: f64 = rest
        .split_whitespace()
        .skip(11)
        .take(2)
        .filter_map(|v| v.parse::<f64>().ok())
        .sum();
    let per_second = unsafe { libc::sysconf(libc::_SC_CLK_TCK) }.max(1) as f64;
    ticks / per_second
}

fn start(args: &Args, from: u64, to: u64) -> Worker {
    let exe = std::env::current_exe().expect("the campaign's own path");
    let mut child = Command::new(exe)
        .args([
            "--worker",
            "--from",
            &from.to_string(),
            "--cases",
            &(to - from).to_string(),
        ])
        .args(["--kinds", &args.kinds.join(",")])
        .arg("--out")
        .arg(&args.out)
        .args(["--case-seconds", &args.case_seconds.to_string()])
        .args(["--memory-gb", &args.memory_gb.to_string()])
        .arg("--confset")
        .arg(args.confset())
        .stdout(Stdio::piped())
        .spawn()
        .expect("the worker starts");
    let stdout = child.stdout.take().expect("the worker's stdout");
    let (send, lines) = channel();
    std::thread::spawn(move || {
        for line in std::io::BufReader::new(stdout)
            .lines()
            .map_while(Result::ok)
        {
            if send.send(line).is_err() {
                break;
            }
        }
    });
    Worker { child, lines }
}

pub fn main(args: &Args) -> ExitCode {
    if !args.confset().exists() {
        eprintln!(
            "campaign: no confset binary at {} (cargo build --profile bench --bin confset, or --confset PATH)",
            args.confset().display()
        );
        return ExitCode::from(2);
    }
    // The bases are made here once (and cached for the workers); a crashed case is made again
    // here to write its reproducer.
    let mut bases = Bases::load(&args.out);
    let started = Instant::now();
    let deadline = args
        .minutes
        .map(|m| started + Duration::from_secs_f64(m * 60.0));
    let limit = Duration::from_secs(args.case_seconds);
    let end = args.from + args.cases;
    let mut tally = Tally::default();
    let mut next = args.from;
    let mut in_flight: Option<u64> = None;
    let mut last_print = Instant::now();
    let mut case_start = Instant::now();
    let mut case_cpu = 0.0;
    let mut worker = start(args, next, end);
    while next < end {
        if deadline.is_some_and(|d| Instant::now() > d) {
            let _ = worker.child.kill();
            let _ = worker.child.wait();
            eprintln!("campaign: --minutes reached");
            break;
        }
        let charge = match worker.lines.recv_timeout(limit.min(Duration::from_secs(1))) {
            Ok(line) => {
                let mut w = line.split_whitespace();
                match (
                    w.next(),
                    w.next().and_then(|i| i.parse::<u64>().ok()),
                    w.next(),
                ) {
                    (Some("start"), Some(i), _) => {
                        in_flight = Some(i);
                        case_start = Instant::now();
                        case_cpu = cpu_seconds(worker.child.id());
                        progress(&mut last_print, &tally, next, started, args);
                        continue;
                    }
                    (Some("end"), Some(i), Some(class)) => {
                        let class = Class::from_name(class).unwrap_or(Class::BadMessage);
                        let ms = w.next().and_then(|t| t.parse().ok()).unwrap_or(0.0);
                        tally.add(cases::kind_of(&args.kinds, i), class, ms);
                        if class.is_failure() {
                            tally.failures.push(w.collect::<Vec<_>>().join(" "));
                        }
                        in_flight = None;
                        next = i + 1;
                        continue;
                    }
                    _ => continue,
                }
            }
            Err(RecvTimeoutError::Timeout) => match in_flight {
                // A hang is judged on the worker's own CPU time, not the clock: a loaded
                // machine (or `nice`) must not turn a slow case into a hang. The clock still
                // stops a case blocked without using CPU (or in a child process) at 6× the limit.
                Some(i)
                    if cpu_seconds(worker.child.id()) - case_cpu > limit.as_secs_f64()
                        || case_start.elapsed() > 6 * limit =>
                {
                    let _ = worker.child.kill();
                    let _ = worker.child.wait();
                    Some((
                        i,
                        Class::Hang,
                        format!(
                            "used over {} s of CPU (or 6× that on the clock)",
                            limit.as_secs()
                        ),
                    ))
                }
                _ => continue,
            },
            Err(RecvTimeoutError::Disconnected) => {
                let status = worker.child.wait().ok();
                match in_flight {
                    Some(i) => Some((i, Class::Abort, format!("the worker died: {status:?}"))),
                    // Finished its range (or died between cases).
                    None if next >= end => None,
                    None => {
                        eprintln!(
                            "campaign: the worker ended between cases ({status:?}); restarting"
                        );
                        worker = start(args, next, end);
                        continue;
                    }
                }
            }
        };
        let Some((i, class, detail)) = charge else {
            break;
        };
        let kind = cases::kind_of(&args.kinds, i).to_string();
        let case = cases::make(&mut bases, &kind, i);
        let line = write_repro(&args.out, &case, class, &detail);
        eprintln!("campaign: {line}");
        tally.add(&kind, class, limit.as_secs_f64() * 1e3);
        tally.failures.push(line);
        in_flight = None;
        next = i + 1;
        if next < end {
            worker = start(args, next, end);
        }
    }
    let secs = started.elapsed().as_secs_f64();
    let done = tally.cases();
    let table = tally.table(&args.kinds);
    let summary = format!(
        "Cases {} … {} of the campaign ({done} cases in {secs:.0} s, {:.0} cases/s; resume with --from {next}).\n\n{table}",
        args.from,
        next.saturating_sub(1),
        done as f64 / secs.max(1e-9),
    );
    println!("{summary}");
    for f in &tally.failures {
        println!("{f}");
    }
    let _ = std::fs::write(args.out.join("table.md"), &summary);
    if tally.failures.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

/// Every 30 s, the progress on stderr.
fn progress(last_print: &mut Instant, tally: &Tally, next: u64, started: Instant, args: &Args) {
    if last_print.elapsed() > Duration::from_secs(30) {
        *last_print = Instant::now();
        let done = tally.cases();
        eprintln!(
            "campaign: case {next} of {} … {}: {done} done, {:.0} cases/s, {} failures",
            args.from,
            args.from + args.cases,
            done as f64 / started.elapsed().as_secs_f64(),
            tally.failures.len()
        );
    }
}
