//! The long fuzz campaign (issue 25): a million and more mutated cases against the library and
//! the `confset` binary, which cannot run in CI. The suite's fuzzer (`tests/suite/fuzz.rs`)
//! runs a sample of the same mutations on every `cargo test`; this runs them for hours.
//!
//! ```text
//! cargo build --profile bench --bin confset
//! cargo run --profile bench --example campaign -- --cases 1000000 --out target/campaign
//!     [--from N] [--minutes M] [--kinds lscr,csv,merge,…] [--replay FILE]
//! ```
//!
//! Case i is a pure function of i and the kinds selected (the kinds in turn, `cli` in one
//! round of four: `cases::kind_of`; its
//! mutation drawn from a seed of (kind, i)), so a run is resumable with `--from` and any case
//! is replayed from its reproducer. A supervisor (`supervisor.rs`) runs the cases in one
//! long-lived worker process (this binary with `--worker`, `worker.rs`: in-process calls as the
//! CLI makes them, a fraction through the real binary) under a memory cap, and restarts it
//! after a crash or a hang, recording the case that killed it. Every case is classified
//! (`tally.rs`): ok, refused (an error naming a field), panic, abort, hang, null (in a report,
//! a study's result or a merged result), non-finite (a CSV cell), bad message (no field, or a
//! word of Rust). The counts go to `<out>/table.md`, each failure to
//! `<out>/repro/<class>-<case>.json`.

#[cfg(not(target_arch = "wasm32"))]
#[path = "../suite/common/contract.rs"]
#[allow(dead_code)]
mod contract;
#[cfg(not(target_arch = "wasm32"))]
#[path = "../suite/common/mutate.rs"]
#[allow(dead_code)]
mod mutate;

#[cfg(not(target_arch = "wasm32"))]
mod cases;
#[cfg(not(target_arch = "wasm32"))]
mod csv_mutate;
#[cfg(not(target_arch = "wasm32"))]
mod supervisor;
#[cfg(not(target_arch = "wasm32"))]
mod tally;
#[cfg(not(target_arch = "wasm32"))]
mod worker;

#[cfg(not(target_arch = "wasm32"))]
use clap::Parser;
#[cfg(not(target_arch = "wasm32"))]
use std::path::PathBuf;

#[cfg(not(target_arch = "wasm32"))]
#[derive(Parser, Debug, Clone)]
#[command(about = "The long fuzz campaign of confset (issue 25)")]
pub struct Args {
    /// Cases to run, numbered from --from
    #[arg(long, default_value_t = 1_000_000)]
    cases: u64,
    /// The first case's number (resume a campaign cut short)
    #[arg(long, default_value_t = 0)]
    from: u64,
    /// Stop after this many minutes of wall time, printing how far the campaign got
    #[arg(long)]
    minutes: Option<f64>,
    /// The kinds of case, comma separated (default: all)
    #[arg(long, value_delimiter = ',', default_values_t = cases::kinds())]
    kinds: Vec<String>,
    /// Where the table, the reproducers and the cached light bases go
    #[arg(long, default_value = "target/campaign")]
    out: PathBuf,
    /// Run one reproducer in this process and print its class
    #[arg(long, value_name = "FILE")]
    replay: Option<PathBuf>,
    /// Seconds a case may take before it counts as a hang
    #[arg(long, default_value_t = 10)]
    case_seconds: u64,
    /// The worker's address-space cap in GB (RLIMIT_AS)
    #[arg(long, default_value_t = 4)]
    memory_gb: u64,
    /// The `confset` binary for the command-line cases (default: beside this example)
    #[arg(long)]
    confset: Option<PathBuf>,
    /// (internal) run as the worker of a supervisor
    #[arg(long, hide = true)]
    worker: bool,
}

#[cfg(not(target_arch = "wasm32"))]
impl Args {
    /// The `confset` binary: --confset, else the one cargo built beside this example
    /// (target/<profile>/confset, the example being in target/<profile>/examples/).
    fn confset(&self) -> PathBuf {
        self.confset.clone().unwrap_or_else(|| {
            let exe = std::env::current_exe().expect("the campaign's own path");
            let dir = exe
                .parent()
                .and_then(|d| d.parent())
                .expect("target/<profile>");
            dir.join("confset")
        })
    }
}

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    let args = Args::parse();
    for k in &args.kinds {
        if !cases::kinds().contains(k) {
            eprintln!(
                "--kinds: unknown kind {k:?} (kinds: {})",
                cases::kinds().join(", ")
            );
            return std::process::ExitCode::from(2);
        }
    }
    if let Some(file) = &args.replay {
        return worker::replay(&args, file);
    }
    if args.worker {
        return worker::main(&args);
    }
    supervisor::main(&args)
}

/// The wasm32 test build compiles every example; the campaign is native only.
#[cfg(target_arch = "wasm32")]
fn main() {}
