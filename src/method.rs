//! The methods of confset: one enum, parsed once from a scenario's `"method"`.
//!
//! Everything that lists methods dispatches on [`Method`] in one place: the scenario layer's
//! `scenario::make_method` (run, study, the method's own block), the plot layer's
//! `plot::make_figures` (useful panels, drawing), and through them the CLI and the bindings.
//! Adding a method is one arm here, one scenario file, one method file, one plot folder and
//! one page module.

use crate::error::{quoted, Error, Result};
use serde::{Deserialize, Serialize};
use std::fmt;

/// A state-estimation method. JSON: `"scf"`, `"kf"`, `"lscr"`, `"glls"`, `"uniform_lp"`, `"ubb"`,
/// `"conformal"`,
/// and `"compare"` (all of them on one record).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// State Conditional Filter regions beside the Kalman ones (Carè, Campi and Weyer).
    Scf,
    /// Kalman filter regions only (the same scenario, no SCF, no observability requirement).
    Kf,
    /// Leave-out Sign-dominant Correlation Regions (Weyer & Campi).
    Lscr,
    /// Generalized linear least squares on a moving horizon (Gubarev & Mishchenko).
    Glls,
    /// Linear models with uniform innovations, estimated by LP (Pavelková).
    UniformLp,
    /// Unknown-but-bounded noise, set-membership estimation (Tempo).
    Ubb,
    /// Split conformal state regions and adaptive conformal output intervals on the Kalman
    /// filter's scores (Vovk et al.; Gibbs & Candès): a promise on average over runs.
    Conformal,
    /// Every method above on one record, side by side (`scenario::compare`).
    Compare,
}

impl Method {
    /// Every method, in the order the page and the CLI list them.
    pub const ALL: [Method; 8] = [
        Method::Scf,
        Method::Kf,
        Method::Lscr,
        Method::Glls,
        Method::UniformLp,
        Method::Ubb,
        Method::Conformal,
        Method::Compare,
    ];

    /// The JSON name.
    pub fn name(self) -> &'static str {
        match self {
            Method::Scf => "scf",
            Method::Kf => "kf",
            Method::Lscr => "lscr",
            Method::Glls => "glls",
            Method::UniformLp => "uniform_lp",
            Method::Ubb => "ubb",
            Method::Conformal => "conformal",
            Method::Compare => "compare",
        }
    }

    /// The scenario block that holds this method's own options (SCF and KF share `"scf"`;
    /// their reports have no result block of that name, but the `steps`).
    pub fn block(self) -> Option<&'static str> {
        match self {
            Method::Scf | Method::Kf => Some("scf"),
            Method::Lscr => Some("lscr"),
            Method::Glls => Some("glls"),
            Method::UniformLp => Some("uniform"),
            Method::Ubb => Some("ubb"),
            Method::Conformal => Some("conformal"),
            Method::Compare => Some("compare"),
        }
    }

    /// The scenario block of the method's Monte Carlo study (`None`: the method has none):
    /// what `Scenario::study` runs, and what messages point to.
    pub fn study_block(self) -> Option<&'static str> {
        match self {
            Method::Scf | Method::Kf => Some("experiment"),
            Method::Lscr => Some("lscr.coverage"),
            Method::Glls => Some("glls.monte_carlo"),
            Method::UniformLp => None,
            Method::Ubb => Some("ubb.guarantee"),
            Method::Conformal => Some("conformal.study"),
            Method::Compare => Some("compare.study"),
        }
    }

    /// Parse a JSON name; the error lists the allowed ones.
    pub fn from_name(s: &str) -> Result<Method> {
        Method::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| {
                Error::field("method", format!("{} is unknown: {}", quoted(s), allowed()))
            })
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// "choose \"scf\", \"kf\", …".
pub(crate) fn allowed() -> String {
    let names: Vec<String> = Method::ALL.iter().map(|m| format!("\"{m}\"")).collect();
    format!("choose {}", names.join(", "))
}
