//! A preset: a named scenario of the papers' examples, as the menu lists it.
//!
//! It lives in the scenario layer because every scenario file builds its own presets at its
//! bottom (`// Presets`) and returns them through `MethodScenario::presets`; the menu
//! ([`crate::presets`]) sits one layer up and only gathers them, so no arrow runs back up.

use super::Scenario;
use serde::Serialize;

/// A named scenario with a one-line description.
#[derive(Debug, Clone, Serialize)]
pub struct Preset {
    /// The id, in links and on the command line (`confset run --preset NAME`).
    pub name: String,
    /// What the preset is, for people: the paper's figure or section and what it shows (the
    /// page's menu).
    pub label: String,
    pub description: String,
    pub scenario: Scenario,
}
