//! `confset` — the command line: scenario file in, report JSON or CSV, study results, SVG
//! figures and the papers' gallery out (`confset --help`; the README's "Command line").

// The wasm32 test build (`wasm-pack test`) compiles every binary of the package; the command
// line is native only (clap, indicatif and the file system), so there it is an empty program.
#[cfg(not(target_arch = "wasm32"))]
mod cli;

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    cli::main()
}

#[cfg(target_arch = "wasm32")]
fn main() {}
