//! The integration tests, as one test binary (one link instead of one per file; `wasm-pack
//! test` runs them all in one browser page). Each module is one former `tests/*.rs` file;
//! `common` holds the independent reference computations they share. `web` tests the wasm
//! bindings and exists only on wasm32; every other module runs natively (`cargo test`) and in
//! Chromium (`wasm-pack test`).

#[cfg(target_arch = "wasm32")]
wasm_bindgen_test::wasm_bindgen_test_configure!(run_in_browser);

mod common;

mod bad_input;
mod bench;
mod cli;
mod compare;
mod coverage;
mod csv;
mod determinism;
mod fuzz;
mod gallery;
mod glls;
mod lscr;
mod messages;
mod registry;
mod scf_paper;
mod sets;
mod shards;
mod ubb;
mod uniform;
#[cfg(target_arch = "wasm32")]
mod web;
