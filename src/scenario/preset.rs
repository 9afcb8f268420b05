//! A preset: a named scenario of the papers' examples, as the menu lists it.
//!
//! It lives in the scenario layer because every scenario file builds its own presets at its
//! bottom (`// Presets`) and returns them through `MethodScenario::presets`; the menu
//! ([`crate::presets`]) sits one layer up and only gathers them, so no arrow runs back up.

use super::Scenario;
use serde::Serialize;

/// Most characters of a preset's [`Preset::menu`] name (issue 28: the page's menu is cut past
/// about 300 CSS pixels, on a phone and in the desktop's controls column alike).
pub const MENU_CHARS: usize = 32;

/// A named scenario with a one-line description.
#[derive(Debug, Clone, Serialize)]
pub struct Preset {
    /// The id, in links and on the command line (`confset run --preset NAME`).
    pub name: String,
    /// What the preset is, for people: the paper's figure or section and what it shows (the
    /// CLI's list, the menu option's tooltip).
    pub label: String,
    /// The label short enough to show whole in the page's preset menu (at most
    /// [`MENU_CHARS`] characters: a phone's menu shows about 32): the same "source — what".
    pub menu: String,
    pub description: String,
    pub scenario: Scenario,
}
