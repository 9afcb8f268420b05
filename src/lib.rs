//! # confset — state estimation with guaranteed sets
//!
//! (crate map: filled in below)

pub mod error;
pub mod experiment;
pub mod kalman;
pub mod linalg;
pub mod model;
pub mod plot;
pub mod presets;
pub mod scenario;
pub mod scf;
pub mod sets;
#[cfg(target_arch = "wasm32")]
pub mod web;

pub use error::{Error, Result};
