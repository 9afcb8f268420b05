//! The paper examples as scenarios: data shipped once and used by the page, the CLI and the
//! tests (`confset presets`, `confset run --preset NAME`, the page's preset menu).
//!
//! Each method's presets live at the bottom of its scenario file (`src/scenario/<method>.rs`,
//! under `// Presets`), with their builders; this module only gathers them into the menu
//! ([`all`], driven by [`Method::ALL`]), looks them up by name ([`get`]) and re-exports the
//! builders under their old paths (`presets::scalar()`, `presets::ubb_preset(…)`, …) and the
//! [`Preset`] type, which lives in the scenario layer (`scenario::preset`) beside the builders.

use crate::error::{Error, Result};
use crate::method::Method;
use crate::scenario::{make_method, Scenario};

pub use crate::scenario::preset::Preset;

pub use crate::scenario::glls::{glls_preset, GllsKind};
pub use crate::scenario::lscr::{lscr_cascade, lscr_ma1, LscrTarget};
pub use crate::scenario::scf::{
    most_probable_collision_state, robot_f, robot_model, robots, scalar, NoiseReading, COLLISION_T,
    DELTA, D_MIN, KP, KU,
};
pub use crate::scenario::ubb::{ubb_preset, UbbKind};
pub use crate::scenario::uniform::{uniform_paper, uniform_paper_model};

/// Every preset, in menu order: method by method in [`Method::ALL`] order, each method's
/// presets in the order its scenario file lists them. Methods that share a scenario file
/// (`"kf"` runs SCF's) each take only the file's presets whose scenario runs that method, so
/// every preset is listed once, under its own method.
pub fn all() -> Vec<Preset> {
    Method::ALL
        .into_iter()
        .flat_map(|m| {
            make_method(m)
                .presets()
                .into_iter()
                .filter(move |p| p.scenario.method == m)
        })
        .collect()
}

/// Look a preset up by name.
pub fn get(name: &str) -> Result<Scenario> {
    all()
        .into_iter()
        .find(|p| p.name == name)
        .map(|p| p.scenario)
        .ok_or_else(|| {
            let names: Vec<String> = all().into_iter().map(|p| p.name).collect();
            Error::field(
                "preset",
                format!(
                    "{} is unknown; presets: {}",
                    crate::error::quoted(name),
                    names.join(", ")
                ),
            )
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn names_and_labels_are_unique_and_every_method_but_kf_has_a_preset() {
        let all = all();
        for (i, p) in all.iter().enumerate() {
            assert!(
                all[..i].iter().all(|q| q.name != p.name),
                "preset name {} is used twice",
                p.name
            );
            // The menu's label names the paper's figure or section and what it shows.
            assert!(
                p.label.contains(" — ") && all[..i].iter().all(|q| q.label != p.label),
                "preset {}: label {:?} is not a unique \"source — what\" label",
                p.name,
                p.label
            );
            // The page's menu shows the short name: it fits, says the same source, and is
            // unique (issue 28).
            let source = p.label.split(" — ").next().unwrap_or_default();
            let source_short = p.menu.split(" — ").next().unwrap_or_default();
            assert!(
                p.menu.contains(" — ")
                    && p.menu.chars().count() <= crate::scenario::preset::MENU_CHARS
                    && all[..i].iter().all(|q| q.menu != p.menu),
                "preset {}: menu name {:?} is not a unique \"source — what\" of at most {} characters",
                p.name,
                p.menu,
                crate::scenario::preset::MENU_CHARS
            );
            assert!(
                source_short.split_whitespace().next() == source.split_whitespace().next(),
                "preset {}: menu name {:?} names another source than {:?}",
                p.name,
                p.menu,
                p.label
            );
        }
        for m in Method::ALL {
            if m == Method::Kf {
                // "kf" is SCF without the SCF regions: it runs the SCF presets switched to it.
                continue;
            }
            assert!(
                all.iter().any(|p| p.scenario.method == m),
                "method \"{m}\" has no preset"
            );
        }
    }

    /// `all` filters each scenario file's presets by method: none may fall through the filter.
    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn every_preset_of_every_scenario_file_is_listed_once() {
        let all = all();
        for m in Method::ALL {
            for p in make_method(m).presets() {
                let listed = all.iter().filter(|q| q.name == p.name).count();
                assert_eq!(
                    listed, 1,
                    "preset {} of method \"{m}\"'s scenario file is listed {listed} times",
                    p.name
                );
            }
        }
    }
}
