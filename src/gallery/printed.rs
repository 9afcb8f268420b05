//! The papers' printed numbers beside ours, and the verdict on each: the one catalogue of what
//! the gallery reproduces (`printed.json`: the paper's text for each number, where ours is in
//! the report or study JSON, and the erratum that explains a difference).
//!
//! The printed numbers are typed from the papers; every verdict is computed from the numbers
//! this build produces, when the gallery is built.

use crate::error::{Error, Result};
use serde::Deserialize;
use serde_json::Value;

/// The catalogue as written in `printed.json`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Catalogue {
    pub entries: Vec<Entry>,
    pub not_reproduced: Vec<NotReproduced>,
}

/// One figure or table of a paper.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Entry {
    /// The paper's numbering: "LSCR Fig. 1", "SCF Section II Monte Carlo", …
    pub id: String,
    /// scf, lscr, glls, tempo or pavelkova.
    pub paper: String,
    pub preset: String,
    /// The panels of the preset that show it (none: a table of numbers).
    pub panels: Vec<String>,
    pub caption: String,
    pub numbers: Vec<Printed>,
}

/// A figure or table no preset reproduces, and why.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NotReproduced {
    pub id: String,
    pub why: String,
}

/// How a printed number is compared.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// Deterministic: reproduced when ours, rounded to the printed decimals, is the printed text.
    Exact,
    /// A count out of the paper's runs, against ours out of our runs: the same probability
    /// within a 99.9 % band for the difference of two binomial proportions.
    MonteCarlo,
    /// Read off a figure: within an absolute tolerance.
    Read,
}

/// Where our number is: the scenario's report or its study's result.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Source {
    Report,
    Study,
}

/// One printed number.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Printed {
    pub what: String,
    /// Exactly as printed (its decimals are the precision of "reproduced").
    pub printed: String,
    pub kind: Kind,
    pub source: Source,
    /// Dot path into the report or study JSON (array indices as numbers).
    pub path: String,
    /// The study's run count, when the paper's differs from the preset's.
    #[serde(default)]
    pub runs: Option<usize>,
    #[serde(default)]
    pub paper_runs: Option<usize>,
    #[serde(default)]
    pub runs_path: Option<String>,
    #[serde(default)]
    pub tolerance: Option<f64>,
    #[serde(rename = "where")]
    pub place: String,
    /// The start of the erratum (in the crate docs' list) that explains a difference.
    #[serde(default)]
    pub erratum: Option<String>,
    /// The value when the catalogue was written (for its author; not used).
    #[serde(default)]
    pub ours_now: Option<f64>,
}

/// The catalogue compiled into the crate.
pub fn catalogue() -> Result<Catalogue> {
    let text = include_str!("printed.json");
    let mut de = serde_json::Deserializer::from_str(text);
    serde_path_to_error::deserialize(&mut de)
        .map_err(|e| Error::field("printed.json", format!("{}: {}", e.path(), e.inner())))
}

/// The errata list of the crate docs (`src/errata.md`), one bullet each, as written.
pub fn errata() -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for line in include_str!("../errata.md").lines() {
        if let Some(rest) = line.strip_prefix("* ") {
            out.push(rest.to_string());
        } else if let (Some(last), true) = (out.last_mut(), line.starts_with("  ")) {
            last.push(' ');
            last.push_str(line.trim());
        }
    }
    out
}

/// The erratum that starts with `prefix`.
pub fn erratum(prefix: &str) -> Option<String> {
    errata().into_iter().find(|e| e.starts_with(prefix.trim()))
}

/// The number at a dot path of a JSON value.
pub fn lookup<'a>(v: &'a Value, path: &str) -> Option<&'a Value> {
    path.split('.')
        .try_fold(v, |v, key| match key.parse::<usize>() {
            Ok(i) if v.is_array() => v.get(i),
            _ => v.get(key),
        })
}

/// The verdict on one number.
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    /// Ours, at the printed decimals, is the printed text.
    Reproduced,
    /// A Monte Carlo count whose proportion is the paper's within the 99.9 % band; the band is
    /// the range of our counts that would be.
    WithinBand { lo: f64, hi: f64 },
    /// Within the tolerance of a number read off a figure.
    WithinTolerance(f64),
    /// Not the paper's (the erratum says why, when one does).
    Differs { band: Option<(f64, f64)> },
    /// Our number could not be found or computed.
    Missing(String),
}

impl Verdict {
    /// One word for the summary: reproduced, band, differs, missing.
    pub fn word(&self) -> &'static str {
        match self {
            Verdict::Reproduced | Verdict::WithinTolerance(_) => "reproduced",
            Verdict::WithinBand { .. } => "within the Monte Carlo band",
            Verdict::Differs { .. } => "differs",
            Verdict::Missing(_) => "not computed",
        }
    }
}

/// Decimals of a printed number: "0.60" → 2, "9498" → 0, "1.2e-3" → 1 (of the mantissa).
fn decimals(printed: &str) -> usize {
    let mantissa = printed.split(['e', 'E']).next().unwrap_or(printed);
    mantissa.split_once('.').map_or(0, |(_, d)| d.len())
}

/// `x` as printed with `printed`'s decimals (and exponent, if it has one).
pub fn at_printed_digits(x: f64, printed: &str) -> String {
    let d = decimals(printed);
    let s = if printed.contains(['e', 'E']) {
        format!("{x:.d$e}")
    } else {
        format!("{x:.d$}")
    };
    // "-0.00" is printed "0.00".
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_string()
    } else {
        s
    }
}

/// z of a two-sided 99.9 % normal band.
const Z_999: f64 = 3.290_526_731_491_926;

/// The verdict on `p` given our number `ours` and, for a Monte Carlo count, our run count.
pub fn verdict(p: &Printed, ours: Option<f64>, our_runs: Option<f64>) -> Verdict {
    let Some(x) = ours else {
        return Verdict::Missing(format!("no number at {}", p.path));
    };
    let printed: Option<f64> = p.printed.replace(['−', '\u{2212}'], "-").parse().ok();
    match p.kind {
        Kind::Exact => {
            let mine = at_printed_digits(x, &p.printed);
            let theirs = p.printed.replace('−', "-");
            let same =
                mine == theirs || printed.is_some_and(|v| at_printed_digits(v, &p.printed) == mine);
            if same {
                Verdict::Reproduced
            } else {
                Verdict::Differs { band: None }
            }
        }
        Kind::Read => match (printed, p.tolerance) {
            (Some(v), Some(tol)) if (x - v).abs() <= tol => Verdict::WithinTolerance(tol),
            (Some(_), Some(_)) => Verdict::Differs { band: None },
            _ => Verdict::Missing(
                "a read number needs a numeric printed value and a tolerance".into(),
            ),
        },
        Kind::MonteCarlo => {
            let (Some(kp), Some(np), Some(n)) = (printed, p.paper_runs, our_runs) else {
                return Verdict::Missing("a Monte Carlo count needs both run counts".into());
            };
            let np = np as f64;
            // The difference of two independent binomial proportions, pooled: the paper's
            // proportion kp/np and ours x/n estimate the same probability when they differ by
            // at most z·√(p(1−p)(1/n + 1/np)).
            let pooled = (x + kp) / (n + np);
            let se = (pooled * (1.0 - pooled) * (1.0 / n + 1.0 / np)).sqrt();
            let centre = kp / np;
            let (lo, hi) = (
                ((centre - Z_999 * se) * n).max(0.0),
                ((centre + Z_999 * se) * n).min(n),
            );
            if (x / n - centre).abs() <= Z_999 * se {
                Verdict::WithinBand { lo, hi }
            } else {
                Verdict::Differs {
                    band: Some((lo, hi)),
                }
            }
        }
    }
}
