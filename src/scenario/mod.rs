//! Scenario (input) and Report (output) JSON, and the dispatch from one to the other.
//!
//! A scenario names a `method`, a `model`, and either observed `data` or a `simulate` block
//! (seeded; optionally conditioned on a state x_c at time t_c, drawn backwards with the
//! backward representation). Everything numeric in a report is a JSON number; ellipsoids are
//! `{"center", "cov", "radius2"}` meaning (x − c)ᵀ cov⁻¹ (x − c) ≤ radius2.
//!
//! This module holds only what every method shares: the scenario and report types, JSON
//! parsing with field paths, the one observations step ([`Source`]: `data` or `simulate`, one
//! step-count check, one wording), the time [`Cursor`] (a report's per-step detail on demand),
//! the one dispatch from [`Method`] to its scenario file (`make_method`), the one check that a
//! scenario carries no other method's block (a loop over [`Method::block`] and
//! [`Method::study_block`]), and the reading of keys an older version wrote elsewhere
//! ([`Report::notices`] says so). Each method's block, validation, report and presets live in
//! its own file:
//! [`scf`], [`lscr`], [`glls`], [`uniform`], [`ubb`].

use crate::error::{Error, Result};
use crate::linalg;
use crate::method::Method;
use crate::model::{MatrixSpec, ModelSpec};
use crate::scf::{Asymptotic, ScfStep};
use crate::study::Study;
use nalgebra::DVector;
use serde::{Deserialize, Serialize};
use std::ops::RangeInclusive;

pub mod budget;
pub mod compare;
pub mod csv;
pub mod explain;
pub mod glls;
pub mod lscr;
pub mod preset;
/// The JSON reader with field paths, a layer below (studies read their parts with it too).
pub use crate::parse;
pub mod conformal;
pub mod scf;
pub mod ubb;
pub mod uniform;
pub use crate::scf::{CollisionSpec, CoverageCurve, CurveSpec, ExperimentSpec};
pub use budget::{Job, Work};
// `Gaps`, `TimeIndex`, `RecordTime`: defined below, beside `DataSpec`.
pub use compare::{CompareReport, CompareSpec};
pub use conformal::{ConformalReport, ConformalSpec};
pub use csv::{data_from_csv, data_from_csv_columns};
pub use explain::{StepExplanation, StepRow, StepValue};
pub use glls::{GllsReport, GllsSpec};
pub use lscr::{LscrReport, LscrSpec};
pub use preset::Preset;
pub use scf::ScfSpec;
pub use scf::{CollisionReport, ScfPrepared};
pub use ubb::{UbbReport, UbbSpec};
pub use uniform::{UniformReport, UniformSpec};

/// Observed data: a user's record.
///
/// A missing measurement (JSON `null`, a CSV cell that is empty, `NA` or `nan`) is a **gap**:
/// it is held as `f64::NAN` in [`DataSpec::y`] and written back as `null`. Nothing else can put
/// a NaN there (JSON has none, and the CSV reader refuses `inf`), so a NaN in `y` always means
/// "not measured". A gap keeps its row: a record of N rows is N steps in every report. Each
/// method says what it does with a gap ([`Gaps`]), and one check refuses a record with a gap
/// for a method that cannot take one, naming the row and its time, before any work.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DataSpec {
    /// y_1, y_2, …: one measurement vector per time step; `null` (NaN) entries are gaps.
    #[serde(with = "gap_rows")]
    pub y: Vec<Vec<f64>>,
    /// Measured inputs u_1, u_2, … (one vector is held constant).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub u: Vec<Vec<f64>>,
    /// The record's own time of each row (`data.t`: numbers such as years, or ISO dates such
    /// as `"1913"`, `"1959-03"`, `"1959-03-31"`), increasing; reports, tables and figures read
    /// it out beside the step index. Empty: steps 1, 2, … only.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub t: Vec<RecordTime>,
}

/// One row's time in a user's record (`data.t`): a number (a year, an index) or an ISO date.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum RecordTime {
    Number(f64),
    Date(String),
}

impl RecordTime {
    /// The time as shown: a whole number without decimals ("1913"), a date as written.
    pub fn label(&self) -> String {
        match self {
            RecordTime::Number(x) if x.fract() == 0.0 && x.abs() < 1e15 => format!("{}", *x as i64),
            RecordTime::Number(x) => format!("{x}"),
            RecordTime::Date(d) => d.clone(),
        }
    }
    /// A sortable key: the number, or the date's (year, month, day) as one number.
    fn key(&self) -> Option<f64> {
        match self {
            RecordTime::Number(x) => x.is_finite().then_some(*x),
            RecordTime::Date(d) => iso_date_key(d),
        }
    }
}

/// An ISO date `YYYY`, `YYYY-MM` or `YYYY-MM-DD` (a time after a `T` or space is allowed and
/// ordered by its text) as year·10⁴ + month·10² + day, or `None` when it is not one.
pub(crate) fn iso_date_key(d: &str) -> Option<f64> {
    let d = d.trim();
    let date = d.split(['T', ' ']).next()?;
    let parts: Vec<&str> = date.split('-').collect();
    if parts.is_empty() || parts.len() > 3 || parts[0].len() != 4 {
        return None;
    }
    let num = |p: &str, lo: u32, hi: u32| -> Option<u32> {
        (p.len() == 2 || p.len() == 4)
            .then(|| p.parse::<u32>().ok())
            .flatten()
            .filter(|v| (lo..=hi).contains(v))
    };
    let year = num(parts[0], 0, 9999)?;
    let month = parts.get(1).map_or(Some(0), |p| num(p, 1, 12))?;
    let day = parts.get(2).map_or(Some(0), |p| num(p, 1, 31))?;
    let time = d[date.len()..].trim_start_matches(['T', ' ']);
    let seconds = if time.is_empty() {
        0.0
    } else {
        let hms: Vec<f64> = time
            .trim_end_matches('Z')
            .split(':')
            .map(|x| x.parse::<f64>().ok())
            .collect::<Option<Vec<_>>>()?;
        hms.iter().fold(0.0, |acc, v| acc * 60.0 + v) / 86_400.0
    };
    Some(year as f64 * 1e4 + month as f64 * 1e2 + day as f64 + seconds)
}

/// `data.y` in JSON: rows of numbers where `null` is a gap (NaN inside).
mod gap_rows {
    use serde::{Deserialize, Deserializer, Serialize, Serializer};
    pub fn serialize<S: Serializer>(rows: &[Vec<f64>], s: S) -> Result<S::Ok, S::Error> {
        let v: Vec<Vec<Option<f64>>> = rows
            .iter()
            .map(|r| r.iter().map(|x| (!x.is_nan()).then_some(*x)).collect())
            .collect();
        v.serialize(s)
    }
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<Vec<f64>>, D::Error> {
        let v = Vec::<Vec<Option<f64>>>::deserialize(d)?;
        Ok(v.into_iter()
            .map(|r| r.into_iter().map(|x| x.unwrap_or(f64::NAN)).collect())
            .collect())
    }
}

/// What a method does with a gap in a user's record (a missing measurement, [`DataSpec`]):
/// a required item of every method's descriptor ([`MethodScenario::gaps`]), so a new method
/// decides, and one check ([`Scenario::source`]) refuses for it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Gaps {
    /// The method takes the gap by its own mathematics, said in these words (the report says
    /// them too): e.g. "the Kalman update is skipped: the set widens".
    Handled(&'static str),
    /// The method cannot take a gap, for this reason; a record with one is refused naming its
    /// row and time.
    Refused(&'static str),
}

/// How a method's CSV table and figures count time ([`MethodScenario::time_index`]), so the
/// record's own time ([`DataSpec::t`]) can be read out beside it in one place.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TimeIndex {
    /// The first column is t = 1, 2, …: row t of the record.
    OneBased,
    /// The first column is k = 0, 1, …: row k + 1 of the record (Tempo's y(0), y(1), …).
    ZeroBased,
    /// The table's rows are not times (GLLS's horizon s).
    NotTime,
}

/// A state x_c imposed at time t_c: the simulation draws the past backwards from it.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Condition {
    pub t: usize,
    pub x: Vec<f64>,
}

/// Seeded simulation.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SimulateSpec {
    pub steps: usize,
    #[serde(default)]
    pub seed: u64,
    /// Measured inputs u_1, u_2, … (one vector is held constant).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub u: Vec<Vec<f64>>,
    /// Fix x_c at t_c ("rare realization").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub condition: Option<Condition>,
    /// The true x(0) (method "ubb"; default: drawn in the box of x(0)).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x0: Option<Vec<f64>>,
    /// The noise the simulation draws, apart from the noise the filters assume (the model's
    /// V and W): methods "scf", "kf" and "lscr" only ([`TrueNoise`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub true_noise: Option<TrueNoise>,
}

/// `simulate.true_noise`: the simulated process noise has covariance `V`·V_t and the
/// simulated output noise `W`·W_t, while every filter still assumes the model's V_t and W_t
/// (SCF, KF, LSCR's BLUE and Kalman ellipses). Scales rather than matrices: a scale keeps the
/// noise's shape, which is what LSCR's guarantee needs (Theorem 3.2 holds for any σ_v², σ_w²
/// with the shape G Gᵀ known, Lemma 3.1), and a lecturer's question is "what if the noise is
/// 4 times larger than the filter thinks". Both default to 1 (the model's own noise).
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TrueNoise {
    /// Scale of the simulated process noise's covariance (V_t of the model times this).
    #[serde(rename = "V", default = "unit_scale")]
    pub v: f64,
    /// Scale of the simulated output noise's covariance (W_t of the model times this).
    #[serde(rename = "W", default = "unit_scale")]
    pub w: f64,
}

fn unit_scale() -> f64 {
    1.0
}

/// The range of each scale of `simulate.true_noise` (a factor of 10⁴ either way: ×10⁴ on a
/// variance is ×100 on the noise's standard deviation, far past what any lesson needs, and
/// keeps the simulated record within the precision check's reach).
pub const TRUE_NOISE_SCALES: RangeInclusive<f64> = 1e-4..=1e4;

/// A scenario: see the module docs and README.md for the fields.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// The method (parsed once; unknown names are refused with the list of methods).
    pub method: Method,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub title: Option<String>,
    pub model: ModelSpec,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub data: Option<DataSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub simulate: Option<SimulateSpec>,
    /// Probability level α of every region.
    #[serde(default = "default_alpha")]
    pub alpha: f64,
    /// SCF and KF options (methods "scf" and "kf"): see [`scf::ScfSpec`]. Older versions
    /// wrote them at the top level; [`Scenario::from_json`] still reads them there.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scf: Option<ScfSpec>,
    /// Time the figure shows (default: the last step).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<usize>,
    /// The two state components drawn in the state-plane figure (default `[0, 1]`, or `[0]` if n = 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plot: Option<Vec<usize>>,
    /// The SCF/KF conditional experiment (their Monte Carlo study, [`Method::study_block`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub experiment: Option<ExperimentSpec>,
    /// LSCR options (method "lscr"): see [`lscr::LscrSpec`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lscr: Option<LscrSpec>,
    /// GLLS options (method "glls"): see [`glls::GllsSpec`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub glls: Option<GllsSpec>,
    /// Uniform-innovation LP options (method "uniform_lp"): see [`uniform::UniformSpec`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uniform: Option<UniformSpec>,
    /// Set-membership options (method "ubb"): see [`ubb::UbbSpec`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ubb: Option<UbbSpec>,
    /// Conformal options (method "conformal"): see [`conformal::ConformalSpec`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub conformal: Option<ConformalSpec>,
    /// Compare options (method "compare"): see [`compare::CompareSpec`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compare: Option<CompareSpec>,
    /// Free text shown with the preset (where the numbers come from, which reading of the paper).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub notes: Option<String>,
    /// The keys this scenario's text held where an older version wrote them, read into their
    /// new place ([`Scenario::from_json`]): the report says so ([`Report::notices`]). Not
    /// written back: the scenario's JSON has the new shape.
    #[serde(skip)]
    pub moved: Vec<MovedKey>,
}

/// The smallest accepted value of the quantity a view animates by rerunning
/// ([`Scenario::first_accepted`]).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct FirstAccepted {
    /// The scenario field animated (`simulate.steps`, `glls.horizon`).
    pub field: String,
    /// Its smallest value the method accepts with the rest of the scenario unchanged.
    pub value: usize,
}

/// The smallest v in `lowest..=current` with `accepts(v)`, for a property that holds from some
/// value on: probing up from `lowest` by doubling gaps (the small values first: a method's
/// validation at t can cost O(t³)), then halving the last gap. `current` is asked only when
/// no smaller value is accepted, and its refusal is then the answer.
pub(crate) fn first_accepted_in(
    values: RangeInclusive<usize>,
    mut accepts: impl FnMut(usize) -> Result<()>,
) -> Result<usize> {
    let (lowest, current) = values.into_inner();
    // The largest value known to be refused (every value from `lowest` to it is, by the premise).
    let mut refused: Option<usize> = None;
    let (mut probe, mut gap) = (lowest, 1usize);
    let mut good = loop {
        if probe >= current {
            accepts(current)?;
            break current;
        }
        if accepts(probe).is_ok() {
            break probe;
        }
        refused = Some(probe);
        probe = probe.saturating_add(gap);
        gap = gap.saturating_mul(2);
    };
    while let Some(r) = refused {
        if good - r <= 1 {
            break;
        }
        let mid = r + (good - r) / 2;
        if accepts(mid).is_ok() {
            good = mid;
        } else {
            refused = Some(mid);
        }
    }
    Ok(good)
}

/// A key read from the place an older version of the scenario format wrote it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MovedKey {
    /// Where the text had it (`tau`).
    pub from: String,
    /// Where it belongs now (`scf.tau`).
    pub to: String,
}

fn default_alpha() -> f64 {
    0.95
}

/// The result of a scenario.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Report {
    pub method: Method,
    pub alpha: f64,
    pub n: usize,
    pub q: usize,
    /// Time shown by the figure.
    pub time: usize,
    pub plot: Vec<usize>,
    pub steps: Vec<ScfStep>,
    /// Measurements used; a gap of the record is `null` (NaN inside), read back as one.
    #[serde(with = "gap_rows")]
    pub y: Vec<Vec<f64>>,
    /// True states (simulation only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x_true: Option<Vec<Vec<f64>>>,
    /// Prior means m_t = E(x_t).
    pub prior_mean: Vec<Vec<f64>>,
    /// Steady-state quantities (stable, time-invariant, stationary prior).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub asymptotic: Option<Asymptotic>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub collision: Option<Vec<CollisionReport>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coverage_curve: Option<CoverageCurve>,
    /// The LSCR result (method "lscr"; `steps` is then empty).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lscr: Option<LscrReport>,
    /// The GLLS result (method "glls"; `steps` is then empty).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub glls: Option<GllsReport>,
    /// The uniform-innovation result (method "uniform_lp").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub uniform: Option<UniformReport>,
    /// The set-membership result (method "ubb").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ubb: Option<UbbReport>,
    /// The conformal result (method "conformal").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub conformal: Option<ConformalReport>,
    /// Every method's set on one record (method "compare").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compare: Option<CompareReport>,
    /// What the reader should know about the scenario itself, one sentence each: keys read
    /// from where an older version wrote them ([`Scenario::moved`]). The CLI prints them and
    /// the page shows them; absent when there is nothing to say.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub notices: Vec<String>,
    /// What the reader must know about the answer, one sentence each: an assumption of the
    /// method's promise that the scenario does not meet (GLLS's box under state noise, …), an
    /// estimate sitting on an artificial bound, the record's gaps and what the method did with
    /// them. The CLI prints them, the CSV table carries them as `#` lines above its header, and
    /// the page shows them beside the figures; absent when there is nothing to say.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// What the figures take from the scenario besides the numbers (title, axis names, …):
    /// made with the report, so the page and the CLI draw the same figure from it.
    #[serde(default)]
    pub figure: FigureContext,
}

/// The scenario's part of every figure of a report: built with the report
/// ([`FigureContext::of`]), so [`crate::plot::draw`] needs only the report and what the viewer
/// chooses ([`crate::plot::View`]: panel, time, zoom). Names and indices only; an empty field
/// is left out of the JSON.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FigureContext {
    /// The scenario's title (figures without one get a generic title naming the panel).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub title: Option<String>,
    /// Axis names of the state components, indexed by component (0-based), e.g.
    /// "position p_x of robot A \[m\]"; a missing or empty entry gets the panel's default
    /// ("state x₁").
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub names: Vec<String>,
    /// The state components measured directly, as pairs (component, measurement row): a row
    /// of a constant H equal to a unit vector, so the state plane can draw the measurements in
    /// state coordinates. Pairs rather than a `null` per unmeasured component, so that the
    /// report JSON holds no null.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub measured: Vec<[usize; 2]>,
    /// The scenario's collision check (the two bodies' components and d_min).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub collision: Option<CollisionSpec>,
    /// The record's own time of each row as shown ("1913", "1959-03-31"; `data.t`), row t − 1
    /// for step t: axes, cursors and tables read it out beside the step index. Empty for a
    /// simulation or a record without times.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub times: Vec<String>,
}

impl FigureContext {
    /// The record's time of step t (1-based) as shown, if the record has one.
    pub fn time_label(&self, t: usize) -> Option<&str> {
        t.checked_sub(1)
            .and_then(|i| self.times.get(i))
            .map(String::as_str)
    }

    /// The time of record row i (0-based) as shown, also past the record's end (a predicted
    /// state x_{t+1}, x_{t+τ}) when its times are evenly spaced whole numbers (years,
    /// quarters' indices): the last time plus the steps beyond it. `None` otherwise.
    pub fn row_time(&self, i: usize) -> Option<String> {
        if let Some(label) = self.times.get(i) {
            return Some(label.clone());
        }
        let numbers: Vec<i64> = self
            .times
            .iter()
            .map(|l| l.parse::<i64>().ok())
            .collect::<Option<_>>()?;
        let (&last, &before) = (numbers.last()?, numbers.get(numbers.len().checked_sub(2)?)?);
        let step = last - before;
        let even = numbers.windows(2).all(|w| w[1] - w[0] == step);
        let beyond = i64::try_from(i + 1 - numbers.len()).ok()?;
        (even && step > 0).then(|| (last + step * beyond).to_string())
    }
}

impl FigureContext {
    /// The figure context of a scenario: its title and collision check, the directly measured
    /// components, and for a collision check the bodies' position axes ("position p_x of robot
    /// A \[m\]" when the title speaks of robots, else "position p_x of body A").
    pub fn of(s: &Scenario) -> FigureContext {
        let collision = s.scf.as_ref().and_then(|b| b.collision.as_ref());
        let names = match collision {
            Some(c) => {
                let robot = s
                    .title
                    .as_deref()
                    .is_some_and(|t| t.to_lowercase().contains("robot"));
                let (who, unit) = if robot {
                    ("robot", " [m]")
                } else {
                    ("body", "")
                };
                let n = c.a.iter().chain(&c.b).copied().max().map_or(0, |m| m + 1);
                // Empty entries: the panels' default names.
                let mut names = vec![String::new(); n];
                for (body, idx) in [("A", &c.a), ("B", &c.b)] {
                    for (k, &i) in idx.iter().enumerate() {
                        let axis = if k == 0 { "x" } else { "y" };
                        if let Some(slot) = names.get_mut(i) {
                            *slot = format!("position p_{axis} of {who} {body}{unit}");
                        }
                    }
                }
                names
            }
            None => Vec::new(),
        };
        // The one place user text enters a figure: cut and made XML-safe here, before any
        // layout (a 10⁶-character title took minutes to lay out in a PNG; a NUL in it made
        // the SVG ill-formed).
        FigureContext {
            title: s.title.as_deref().map(crate::error::displayed),
            names: names.iter().map(|n| crate::error::displayed(n)).collect(),
            measured: direct_measurements(&s.model),
            collision: collision.cloned(),
            times: s
                .data
                .as_ref()
                .filter(|d| d.t.len() == d.y.len())
                .map(|d| {
                    d.t.iter()
                        .map(|t| crate::error::displayed(&t.label()))
                        .collect()
                })
                .unwrap_or_default(),
        }
    }
}

/// The pairs (component, row) where a row of a constant H measures a state component directly.
fn direct_measurements(model: &ModelSpec) -> Vec<[usize; 2]> {
    let rows = match model.h.as_ref() {
        Some(MatrixSpec::Constant(rows)) => rows,
        Some(MatrixSpec::Sequence(seq)) if seq.iter().all(|m| Some(m) == seq.first()) => {
            match seq.first() {
                Some(first) => first,
                None => return Vec::new(),
            }
        }
        _ => return Vec::new(),
    };
    let n = rows.first().map_or(0, Vec::len);
    (0..n)
        .filter_map(|i| {
            rows.iter()
                .position(|r| {
                    r.len() == n
                        && r.iter()
                            .enumerate()
                            .all(|(j, &v)| if j == i { v == 1.0 } else { v == 0.0 })
                })
                .map(|row| [i, row])
        })
        .collect()
}

/// Largest value of any size or count field ([`COUNT_KEYS`]): steps, runs, horizons, windows,
/// strings, grid points, budgets, indices. Each method's own limits are tighter; this one
/// refuses the absurd (10⁹, 2⁶⁴ − 1) while parsing, before anything is allocated or looped.
pub const MAX_COUNT: u64 = 10_000_000;

/// The keys whose values are sizes, counts or indices (every integer field of the schema but
/// the seeds, which may be any 64-bit number).
pub const COUNT_KEYS: [&str; 22] = [
    "steps",
    "runs",
    "t",
    "time",
    "tau",
    "window",
    "horizon",
    "max_horizon",
    "points",
    "resolution",
    "budget",
    "m",
    "q",
    "p",
    "j",
    "index",
    "warning_t",
    "component",
    "components",
    "plane",
    "plot",
    "directions",
];

/// Fields named like a count that hold a real number: Tempo's process-noise bound `ubb.tau`
/// (`scf.tau` is SCF's prediction steps).
const REAL_VALUED_PATHS: [&str; 2] = ["ubb.tau", "ubb.sim_tau"];

/// The first leaf of a JSON value (depth first) that `hit` picks, with its path: `hit` sees
/// the leaf, the object key it stands under (for the entries of a list, the list's key),
/// whether it is an entry of a list, and its path. The one walker of the scenario and report
/// checks.
pub(crate) fn first_leaf<T>(
    v: &serde_json::Value,
    hit: &dyn Fn(&serde_json::Value, &str, bool, &str) -> Option<T>,
) -> Option<(String, T)> {
    fn walk<T>(
        v: &serde_json::Value,
        key: &str,
        in_list: bool,
        path: &str,
        hit: &dyn Fn(&serde_json::Value, &str, bool, &str) -> Option<T>,
    ) -> Option<(String, T)> {
        use serde_json::Value;
        match v {
            Value::Array(a) => a
                .iter()
                .enumerate()
                .find_map(|(i, x)| walk(x, key, true, &format!("{path}[{i}]"), hit)),
            Value::Object(o) => o.iter().find_map(|(k, x)| {
                let p = if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                };
                walk(x, k, false, &p, hit)
            }),
            leaf => hit(leaf, key, in_list, path).map(|t| (path.to_string(), t)),
        }
    }
    walk(v, "", false, "", hit)
}

/// The first size or count in `v` over [`MAX_COUNT`]: (path, value).
fn oversized_count(v: &serde_json::Value) -> Option<(String, f64)> {
    first_leaf(v, &|x, key, _, path| {
        x.as_f64().filter(|&f| {
            COUNT_KEYS.contains(&key) && !REAL_VALUED_PATHS.contains(&path) && f > MAX_COUNT as f64
        })
    })
}

/// Largest magnitude of any number in a scenario. Products of a few such numbers stay far from
/// f64's 1.8e308, so a model entry, a noise level or a bound cannot overflow a covariance,
/// a Gram matrix or an LP; [`MIN_MAGNITUDE`] likewise keeps reciprocals finite.
pub const MAX_MAGNITUDE: f64 = 1e100;
/// Smallest magnitude of a non-zero number in a scenario (subnormals such as 5e-324 and values
/// like 1e-300 would make reciprocals and condition numbers overflow).
pub const MIN_MAGNITUDE: f64 = 1e-100;

/// Most rows or columns of any model matrix (states, outputs, inputs, noise inputs): the
/// work budget of a report (≤ 2 s natively) at the methods' step limits. Each method may
/// hold its state dimension lower (its `steps` and messages say so).
pub const MAX_MODEL_DIM: usize = 100;

/// The first model matrix with more than [`MAX_MODEL_DIM`] rows or columns: (path, rows, cols).
fn oversized_model_matrix(v: &serde_json::Value) -> Option<(String, usize, usize)> {
    v.get("model")?.as_object()?.iter().find_map(|(k, m)| {
        let rows = m.as_array()?;
        let cols = rows
            .iter()
            .filter_map(|r| r.as_array().map(|r| r.len()))
            .max()
            .unwrap_or(0);
        (rows.len() > MAX_MODEL_DIM || cols > MAX_MODEL_DIM)
            .then(|| (format!("model.{k}"), rows.len(), cols))
    })
}

/// Most bytes of a scenario's JSON text: the largest preset is about 30 kB, and 20 MB holds
/// far more data than any method's step limit takes (`data.y` of 10,000 steps of 100 outputs
/// at 20 characters a number). Checked before the text is parsed; the command line reads at
/// most this many bytes of a file.
pub const MAX_SCENARIO_BYTES: usize = 20_000_000;

/// Most characters of any text field (`title`, `notes`, a name): a figure shows at most
/// [`crate::error::DISPLAY_CHARS`] of a text, and a longer one only costs memory and
/// copies (a 30 MB title made a compare report of 220 MB).
pub const MAX_TEXT_CHARS: usize = 10_000;

/// The lists whose length no other limit bounds, with their most entries: each entry is one
/// small piece of work and of report, so only their number is at stake (10⁶ probes took 3.4 s
/// and 1.09 GB; 10⁶ overrides 2.6 s and 1 GB).
pub const LIST_LIMITS: [(&str, usize); 2] =
    [("lscr.probes", 10_000), ("uniform.prior_overrides", 10_000)];

/// The first text over [`MAX_TEXT_CHARS`]: (path, characters).
fn overlong_text(v: &serde_json::Value) -> Option<(String, usize)> {
    first_leaf(v, &|x, _, _, _| {
        // Bytes bound characters from above: count only a text that may be too long.
        x.as_str()
            .filter(|t| t.len() > MAX_TEXT_CHARS)
            .map(|t| t.chars().count())
            .filter(|&c| c > MAX_TEXT_CHARS)
    })
}

/// The first list of [`LIST_LIMITS`] over its limit: (path, entries, limit).
fn overlong_list(v: &serde_json::Value) -> Option<(&'static str, usize, usize)> {
    LIST_LIMITS.iter().find_map(|&(path, limit)| {
        let pointer = format!("/{}", path.replace('.', "/"));
        let len = v.pointer(&pointer)?.as_array()?.len();
        (len > limit).then_some((path, len, limit))
    })
}

/// Why a number may not stand in a scenario or its data, in words (`None` when it may): the
/// one range of JSON numbers and CSV cells alike.
pub fn magnitude_problem(x: f64) -> Option<String> {
    (!x.is_finite() || x.abs() > MAX_MAGNITUDE || (x != 0.0 && x.abs() < MIN_MAGNITUDE)).then(|| {
        format!(
            "is {x:e}: every number in a scenario is 0 or between {MIN_MAGNITUDE:e} and {MAX_MAGNITUDE:e} in magnitude, so that products and reciprocals stay within double precision"
        )
    })
}

/// Sizes, lengths and magnitudes, checked on the JSON before it is read into a scenario: a
/// count of 10⁹, a list of 10⁶ probes, a text of 10⁶ characters or a number of 1e308 is
/// refused here, whatever field it is in.
fn check_sizes_and_magnitudes(v: &serde_json::Value) -> Result<()> {
    if let Some((field, chars)) = overlong_text(v) {
        return Err(Error::field(
            field,
            format!(
                "has {chars_characters}: a text field holds at most {MAX_TEXT_CHARS} (a figure shows the first {})",
                crate::error::DISPLAY_CHARS, chars_characters = crate::error::counted(chars, "character", "characters")
            ),
        ));
    }
    if let Some((field, len, limit)) = overlong_list(v) {
        return Err(Error::field(
            field,
            format!(
                "has {len_entries}: at most {limit} are taken",
                len_entries = crate::error::counted(len, "entry", "entries")
            ),
        ));
    }
    if let Some((field, rows, cols)) = oversized_model_matrix(v) {
        return Err(Error::field(
            field,
            format!(
                "is {rows} × {cols}: a model matrix has at most {MAX_MODEL_DIM} rows and columns (a report within about 2 s)"
            ),
        ));
    }
    if let Some((field, x)) = oversized_count(v) {
        return Err(Error::field(
            field,
            format!(
                "is {x:.3e}: no size, count or index may exceed {MAX_COUNT} (each method's own limit is lower; a seed may be any 64-bit number)"
            ),
        ));
    }
    if let Some((field, message)) =
        first_leaf(v, &|x, _, _, _| x.as_f64().and_then(magnitude_problem))
    {
        return Err(Error::field(field, message));
    }
    Ok(())
}

impl Scenario {
    /// A scenario of `method` on `model` with every option at its default and no block of any
    /// method: a builder then sets only its own method's block (`s.lscr = Some(…)`) and the
    /// shared fields it needs through the setters below.
    pub fn new(method: Method, model: ModelSpec) -> Scenario {
        Scenario {
            method,
            title: None,
            model,
            data: None,
            simulate: None,
            alpha: default_alpha(),
            scf: None,
            time: None,
            plot: None,
            experiment: None,
            lscr: None,
            glls: None,
            uniform: None,
            ubb: None,
            conformal: None,
            compare: None,
            notes: None,
            moved: Vec::new(),
        }
    }

    /// With a title (shown on every figure).
    pub fn with_title(mut self, title: impl Into<String>) -> Scenario {
        self.title = Some(title.into());
        self
    }

    /// With notes (where the numbers come from, which reading of the paper).
    pub fn with_notes(mut self, notes: impl Into<String>) -> Scenario {
        self.notes = Some(notes.into());
        self
    }

    /// With the probability level α of every region.
    pub fn with_alpha(mut self, alpha: f64) -> Scenario {
        self.alpha = alpha;
        self
    }

    /// With measured data (and no simulation).
    pub fn with_data(mut self, data: DataSpec) -> Scenario {
        self.data = Some(data);
        self.simulate = None;
        self
    }

    /// With a seeded simulation (and no data).
    pub fn with_simulate(mut self, simulate: SimulateSpec) -> Scenario {
        self.simulate = Some(simulate);
        self.data = None;
        self
    }

    /// With the time a figure shows.
    pub fn with_time(mut self, time: usize) -> Scenario {
        self.time = Some(time);
        self
    }

    /// With the two state components drawn in the plane.
    pub fn with_plot(mut self, plot: Vec<usize>) -> Scenario {
        self.plot = Some(plot);
        self
    }

    /// Parse JSON; an error names the JSON path of the offending value and says, in JSON
    /// words, what belongs there ([`parse`]).
    pub fn from_json(text: &str) -> Result<Self> {
        if text.len() > MAX_SCENARIO_BYTES {
            return Err(Error::field(
                "",
                format!(
                    "the scenario is {} bytes: a scenario file holds at most {MAX_SCENARIO_BYTES} bytes (20 MB)",
                    text.len()
                ),
            ));
        }
        let mut v = parse::read_json(text, "")?;
        // Sizes and magnitudes first: a count of 10⁹ or a number of 1e308 is refused before
        // any field is read, whatever field it is in (and named where the text has it).
        check_sizes_and_magnitudes(&v)?;
        // Keys where an older version wrote them go to their new place first; a parse error
        // about one names it where the text has it.
        let mut moved = Vec::new();
        if let Some(o) = v.as_object_mut() {
            for m in Method::ALL {
                moved.extend(make_method(m).read_moved_keys(o)?);
            }
        }
        let mut s: Scenario = parse::from_value(&v, "").map_err(|mut e| {
            if let Some(m) = moved.iter().find(|m| {
                e.field == m.to
                    || e.field.starts_with(&format!("{}.", m.to))
                    || e.field.starts_with(&format!("{}[", m.to))
            }) {
                e.field = format!("{}{}", m.from, &e.field[m.to.len()..]);
            }
            e
        })?;
        s.moved = moved;
        Ok(s)
    }

    /// What the report says about the scenario itself ([`Report::notices`]): each key read
    /// from where an older version wrote it.
    pub fn notices(&self) -> Vec<String> {
        self.moved
            .iter()
            .map(|m| {
                format!(
                    "{} is read as {}: the scenario has it where older versions wrote it (save the scenario again to write it in its new place)",
                    m.from, m.to
                )
            })
            .collect()
    }
}

impl DataSpec {
    /// The first gap: (row index, component), 0-based.
    pub fn first_gap(&self) -> Option<(usize, usize)> {
        self.gaps().next()
    }
    /// Every gap: (row index, component), 0-based, in order.
    pub fn gaps(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.y.iter().enumerate().flat_map(|(k, r)| {
            r.iter()
                .enumerate()
                .filter(|(_, x)| x.is_nan())
                .map(move |(j, _)| (k, j))
        })
    }
    /// The rows with at least one gap (0-based).
    pub fn gap_rows(&self) -> Vec<usize> {
        (0..self.y.len())
            .filter(|&k| self.y[k].iter().any(|x| x.is_nan()))
            .collect()
    }
    /// "row 21 (t = 21, time 1891)": a row (0-based index k) as a user finds it in the record.
    pub fn row_words(&self, k: usize) -> String {
        match self.t.get(k) {
            Some(time) => format!("row {} (t = {}, time {})", k + 1, k + 1, time.label()),
            None => format!("row {} (t = {})", k + 1, k + 1),
        }
    }
    /// The error of a gap at row k that a computation cannot take, with the reason.
    pub(crate) fn gap_error(&self, k: usize, why: &str) -> Error {
        let count = self.gap_rows().len();
        Error::field(
            format!("data.y[{k}]"),
            format!(
                "is missing at {} ({count} {} with a gap in all): {why}; fill the gap, cut the record before it, or use a method that takes gaps ({})",
                self.row_words(k),
                if count == 1 { "row" } else { "rows" },
                methods_taking_gaps()
            ),
        )
    }
    /// `data.t`: one time per row, each a finite number or an ISO date, strictly increasing.
    pub(crate) fn check_times(&self) -> Result<()> {
        if self.t.is_empty() {
            return Ok(());
        }
        if self.t.len() != self.y.len() {
            return Err(Error::field(
                "data.t",
                format!(
                    "has {} for {} of data.y: give one time per row, or none",
                    crate::error::counted(self.t.len(), "time", "times"),
                    crate::error::counted(self.y.len(), "row", "rows")
                ),
            ));
        }
        let mut last: Option<(f64, usize)> = None;
        for (k, time) in self.t.iter().enumerate() {
            let Some(key) = time.key() else {
                return Err(Error::field(
                    format!("data.t[{k}]"),
                    format!(
                        "is {}: a time is a number (a year, an index) or an ISO date (\"1913\", \"1959-03\", \"1959-03-31\")",
                        crate::error::quoted(&time.label())
                    ),
                ));
            };
            if let Some((prev, j)) = last {
                if key <= prev {
                    return Err(Error::field(
                        format!("data.t[{k}]"),
                        format!(
                            "is {}, not after row {}'s {}: the times of a record increase strictly (one row per time step)",
                            time.label(),
                            j + 1,
                            self.t[j].label()
                        ),
                    ));
                }
            }
            last = Some((key, k));
        }
        let kinds = self
            .t
            .iter()
            .filter(|t| matches!(t, RecordTime::Number(_)))
            .count();
        if kinds != 0 && kinds != self.t.len() {
            return Err(Error::field(
                "data.t",
                "mixes numbers and dates: give every time as a number or every time as a date",
            ));
        }
        Ok(())
    }
}

/// The methods whose descriptor takes a gap ([`Gaps::Handled`]), for messages: "kf, scf, …".
fn methods_taking_gaps() -> String {
    let names: Vec<&str> = Method::ALL
        .into_iter()
        .filter(|&m| matches!(make_method(m).gaps(), Gaps::Handled(_)))
        .map(Method::name)
        .collect();
    if names.is_empty() {
        "none yet".into()
    } else {
        names.join(", ")
    }
}

/// Where a scenario's measurements come from: the user's `data` or a seeded `simulate` block.
/// Every method goes through `Scenario::source`, so the choice, the step-count limits and
/// their wording are the same for all five.
#[derive(Debug, Clone, Copy)]
pub enum Source<'a> {
    Data(&'a DataSpec),
    Simulate(&'a SimulateSpec),
}

impl<'a> Source<'a> {
    /// The number of time steps: data rows, or simulated steps.
    pub fn steps(&self) -> usize {
        match self {
            Source::Data(d) => d.y.len(),
            Source::Simulate(s) => s.steps,
        }
    }
    /// `"data"` or `"simulate"`: the block that errors about inputs name.
    pub fn prefix(&self) -> &'static str {
        match self {
            Source::Data(_) => "data",
            Source::Simulate(_) => "simulate",
        }
    }
    /// The field a step-count error names: `data.y` or `simulate.steps`.
    pub fn steps_field(&self) -> &'static str {
        match self {
            Source::Data(_) => "data.y",
            Source::Simulate(_) => "simulate.steps",
        }
    }
    /// Whether the measurements are the user's (then a report has no truth).
    pub fn is_data(&self) -> bool {
        matches!(self, Source::Data(_))
    }
    /// The simulation seed (0 for data).
    pub fn seed(&self) -> u64 {
        match self {
            Source::Data(_) => 0,
            Source::Simulate(s) => s.seed,
        }
    }
    /// The input rows with their field (`data.u` or `simulate.u`).
    pub fn input_rows(&self) -> (&'static str, &'a [Vec<f64>]) {
        match self {
            Source::Data(d) => ("data.u", &d.u),
            Source::Simulate(s) => ("simulate.u", &s.u),
        }
    }
    /// The input rows as vectors of length r (`None` when none are given), each field-named.
    pub fn inputs(&self, r: usize) -> Result<Option<Vec<DVector<f64>>>> {
        let (field, rows) = self.input_rows();
        if rows.is_empty() {
            return Ok(None);
        }
        if r == 0 {
            return Err(Error::field(
                field,
                "is given, but the model has no inputs (model.B)",
            ));
        }
        rows.iter()
            .enumerate()
            .map(|(k, row)| linalg::vector(&format!("{field}[{k}]"), row, r))
            .collect::<Result<Vec<_>>>()
            .map(Some)
    }
    /// The user's measurements y_1, y_2, … as vectors of length q (empty for a simulation),
    /// for a method that needs every one: a gap is refused naming its row and time (the
    /// generic gate, [`Scenario::source`], refuses first for a method whose [`Gaps`] says so).
    pub fn measurements(&self, q: usize) -> Result<Vec<DVector<f64>>> {
        let y = self.measurements_with_gaps(q)?;
        if let Source::Data(d) = self {
            if let Some((k, _)) = d.first_gap() {
                return Err(d.gap_error(k, "this computation needs every measurement"));
            }
        }
        Ok(y)
    }
    /// The user's measurements with their gaps: a NaN entry is a component not measured at
    /// that step ([`DataSpec`]). For the methods whose [`Gaps`] is `Handled`.
    pub fn measurements_with_gaps(&self, q: usize) -> Result<Vec<DVector<f64>>> {
        match self {
            Source::Data(d) => {
                d.y.iter()
                    .enumerate()
                    .map(|(k, r)| {
                        let field = format!("data.y[{k}]");
                        if r.len() != q {
                            return linalg::vector(&field, r, q);
                        }
                        if let Some(j) = r.iter().position(|x| x.is_infinite()) {
                            return Err(Error::field(
                                field,
                                format!("has a non-finite entry at position {j}"),
                            ));
                        }
                        Ok(DVector::from_column_slice(r))
                    })
                    .collect()
            }
            Source::Simulate(_) => Ok(Vec::new()),
        }
    }
    /// The record's own time of each step (empty for a simulation or a record without
    /// `data.t`).
    pub fn record_times(&self) -> &[RecordTime] {
        match self {
            Source::Data(d) => &d.t,
            Source::Simulate(_) => &[],
        }
    }
}

/// The time cursor of a prepared scenario: the costly part of a run (simulation, filters, the
/// on-line estimator, LP setup) done once, then the detail a report holds at its shown time
/// (its `at` block: the exact polygon, hull, face ranges … at t) computed for any step on
/// demand. `at(t)` is, bit for bit, the `at` of the report run with the method's time field
/// (`ubb.time`, `uniform.time`) set to t, so a page can move its cursor without a run
/// ([`Report::set_at`] puts the detail into a kept report). Only methods whose reports keep
/// one step's detail have one ([`Scenario::cursor`]).
pub trait Cursor {
    /// The steps with a detail of their own (a time the run would clamp, such as a step
    /// before the first bounded set, gives the detail of the step it is clamped to).
    fn steps(&self) -> RangeInclusive<usize>;
    /// The report's `at` block at time t, as JSON; a time the run refuses is the same error,
    /// naming the same field.
    fn at(&mut self, t: usize) -> Result<serde_json::Value>;
}

/// A method's cursor with the report's last defence: a non-finite number in a detail is an
/// error naming its report field, as [`Report::check_finite`] does for a whole report.
struct CheckedCursor {
    inner: Box<dyn Cursor>,
    block: &'static str,
}

impl Cursor for CheckedCursor {
    fn steps(&self) -> RangeInclusive<usize> {
        self.inner.steps()
    }
    fn at(&mut self, t: usize) -> Result<serde_json::Value> {
        let v = self.inner.at(t)?;
        check_finite(&v, &format!("report.{}.at", self.block), "")?;
        Ok(v)
    }
}

/// A method's study with the outputs' last defence ([`check_finite`] on every result, plain
/// or merged): a number that overflowed is an error naming its field (`study.mean_state_norm`),
/// never a `null` in the JSON. The result of no run (an empty shard's, before its first
/// step) is not checked: GLLS's spreads are `null` there until a run gives an error to
/// spread, and it holds no computed count.
struct CheckedStudy {
    inner: Box<dyn Study>,
    /// Whether the counts are a merge of parts (whose numbers the message then mentions).
    merged: bool,
}

impl Study for CheckedStudy {
    fn step(&mut self, runs: usize) -> Result<()> {
        self.inner.step(runs)
    }
    fn runs(&self) -> usize {
        self.inner.runs()
    }
    fn total(&self) -> usize {
        self.inner.total()
    }
    fn finished(&self) -> bool {
        self.inner.finished()
    }
    fn result(&self) -> Result<serde_json::Value> {
        let v = self.inner.result()?;
        if self.inner.runs() > 0 {
            let merged = if self.merged {
                "; after a merge, the parts' own numbers may be the cause (a part holding numbers near 1.8e308)"
            } else {
                ""
            };
            check_finite(&v, "study", merged)?;
        }
        Ok(v)
    }
    fn range(&self) -> std::ops::Range<usize> {
        self.inner.range()
    }
    fn restrict(&mut self, shard: usize, shards: usize) -> Result<()> {
        self.inner.restrict(shard, shards)
    }
    fn partial(&self) -> Result<serde_json::Value> {
        self.inner.partial()
    }
    fn merge_named(&mut self, parts: &[(&str, &serde_json::Value)]) -> Result<()> {
        self.inner.merge_named(parts)?;
        self.merged = true;
        Ok(())
    }
    fn complete(&self) -> Result<()> {
        self.inner.complete()
    }
    fn set_scenario_digest(&mut self, digest: &str) {
        self.inner.set_scenario_digest(digest)
    }
}

/// A detail ([`Cursor::at`]) as JSON.
pub(crate) fn detail_value<T: Serialize>(v: &T) -> Result<serde_json::Value> {
    serde_json::to_value(v)
        .map_err(|e| Error::field("at", format!("could not be written as JSON: {e}")))
}

/// A detail ([`Cursor::at`]) read back for [`Report::set_at`]; JSON of another shape is an
/// `at` error.
pub(crate) fn detail_of<T: serde::de::DeserializeOwned>(v: serde_json::Value) -> Result<T> {
    serde_json::from_value(v).map_err(|e| {
        Error::field(
            "at",
            format!("is not a detail of this report's method: {e}"),
        )
    })
}

/// What each method's scenario file provides; [`make_method`] is the one place that maps a
/// [`Method`] to it (the pattern of Clarabel.rs's `SupportedConeT` → `make_cone`).
pub(crate) trait MethodScenario: Sync {
    /// The time steps (data rows or simulated steps) the method accepts: checked by
    /// [`Scenario::source`] before any work.
    fn steps(&self) -> RangeInclusive<usize>;
    /// The shape of the method's `data`: (q, r), the entries of each `data.y` row (outputs)
    /// and of each `data.u` row (inputs, 0 when the method takes none), read from the model
    /// fields as the run reads them (so a CSV file can be split into columns before a run).
    fn data_shape(&self, s: &Scenario) -> Result<(usize, usize)>;
    /// The dominant costs of the report (or of a study's preparation and one run) from the
    /// scenario's sizes alone, before any validation or heavy work: [`Scenario::run`] and
    /// [`Scenario::study`] check it against the budget ([`budget`]). Sizes it cannot read count
    /// as small; the method's validation names those fields.
    fn work(&self, s: &Scenario, job: Job) -> Work;
    /// Validate and run: the report.
    fn run(&self, s: &Scenario) -> Result<Report>;
    /// The report as a table of its main estimates and set sizes, one row per time step
    /// (`confset run --format csv`).
    fn table(&self, report: &Report) -> csv::Table;
    /// The method's Monte Carlo study, not yet run (`runs` overrides the scenario's count).
    fn study(&self, s: &Scenario, runs: Option<usize>) -> Result<Box<dyn Study>>;
    /// The method's time cursor over the scenario, prepared once; `None` when its reports
    /// hold every step already (or have no time).
    fn cursor(&self, _s: &Scenario) -> Result<Option<Box<dyn Cursor>>> {
        Ok(None)
    }
    /// Put a detail of this method's [`Cursor::at`] into its report (the `at` block and the
    /// report's `time`).
    fn set_at(&self, report: &mut Report, _at: serde_json::Value) -> Result<()> {
        Err(Error::field(
            "at",
            format!(
                "cannot be set: the method \"{}\" has no time cursor (its reports hold every step)",
                report.method
            ),
        ))
    }
    /// The quantity a view animates by rerunning (LSCR's data length t, GLLS's horizon s) and
    /// the smallest value of it the method accepts with the rest of the scenario unchanged;
    /// `None` when the method animates nothing by rerunning (its time cursor only redraws).
    /// The search asks the method's own validation, so it cannot disagree with a run.
    fn first_accepted(&self, _s: &Scenario) -> Result<Option<FirstAccepted>> {
        Ok(None)
    }
    /// Why the method cannot draw its simulation from noise other than the noise it assumes
    /// (`simulate.true_noise`), or `None` when it honours it in its record, its conditioned
    /// draws and its study. Required, so a new method decides.
    fn true_noise(&self) -> Option<&'static str>;
    /// The most states n the method takes (its run refuses more, naming the model field).
    fn max_states(&self) -> usize;
    /// What the method does with a gap in a user's record ([`Gaps`]). Required, so a new
    /// method decides; [`Scenario::source`] refuses a gap for a method that cannot take one.
    fn gaps(&self) -> Gaps;
    /// How the method's CSV table counts time ([`TimeIndex`]), so [`Report::table`] adds the
    /// record's own time beside it. Required, so a new method decides.
    fn time_index(&self) -> TimeIndex;
    /// The keys of the method's report that hold or judge the true state, each with what it
    /// is: a report on `data` has none of them (beside the shared `x_true`, [`truth_keys`]).
    /// A key starting with '.' is a whole path in the report.
    fn truth_keys(&self) -> &'static [(&'static str, &'static str)];
    /// Move the keys of this method's block that an older version wrote elsewhere into the
    /// block, in `v` (the text of a scenario of *any* method, before it is read; the keys of
    /// another method's scenario that said something are refused, naming where the text has
    /// them): the keys moved. [`Scenario::from_json`] asks every method's file in turn.
    fn read_moved_keys(
        &self,
        _v: &mut serde_json::Map<String, serde_json::Value>,
    ) -> Result<Vec<MovedKey>> {
        Ok(Vec::new())
    }
    /// What a compare asks of this method ([`compare::CompareMember`]: its assumption, its
    /// scenario derived from the compare's record, its set read from its report), or `None`
    /// when the method does not join a compare. Required, so a new method decides.
    fn compare_member(&self) -> Option<&dyn compare::CompareMember>;
    /// The file's presets (the papers' examples), in menu order: built at the bottom of the
    /// scenario file, gathered by [`crate::presets::all`] under the method each one runs (a
    /// file shared by several methods, SCF's with KF, lists its presets once).
    fn presets(&self) -> Vec<Preset>;
    /// The steps a report's time cursor moves over (the same range as its [`Cursor::steps`],
    /// read from the report, so the page can place its slider without a cursor of its own);
    /// `None` for a method without a time cursor.
    fn cursor_steps(&self, _report: &Report) -> Option<RangeInclusive<usize>> {
        None
    }
    /// Put the result of the method's study (its [`Study`]'s JSON, as `confset experiment`
    /// prints it; `null` removes it) into the report, where the report of a scenario run with
    /// that study would hold it, so the figures draw it. A method whose report holds no study
    /// result refuses.
    /// One step of the report, step by step ([`Scenario::explain`]: the quantities of the
    /// update at `t` with the paper's equation numbers; `point` for a step that depends on a
    /// state). A method without a step-through refuses, naming the method.
    fn explain(
        &self,
        _s: &Scenario,
        report: &Report,
        _t: Option<usize>,
        _point: Option<&[f64]>,
    ) -> Result<explain::StepExplanation> {
        Err(Error::field(
            "explain",
            format!(
                "is not available: the method \"{}\" has no step-through card",
                report.method
            ),
        ))
    }
    fn set_study(&self, report: &mut Report, _result: serde_json::Value) -> Result<()> {
        Err(Error::field(
            "study",
            format!(
                "cannot be put into the report: a \"{}\" report holds no study result",
                report.method
            ),
        ))
    }
}

/// The one dispatch from a method to its scenario file.
pub(crate) fn make_method(m: Method) -> &'static dyn MethodScenario {
    match m {
        Method::Scf => &scf::Scf { kalman_only: false },
        Method::Kf => &scf::Scf { kalman_only: true },
        Method::Lscr => &lscr::Lscr,
        Method::Glls => &glls::Glls,
        Method::UniformLp => &uniform::Uniform,
        Method::Ubb => &ubb::Ubb,
        Method::Conformal => &conformal::Conformal,
        Method::Compare => &compare::Compare,
    }
}

/// The top-level keys of a scenario that belong to method `m`: its block and its study's.
fn method_blocks(m: Method) -> impl Iterator<Item = &'static str> {
    m.block()
        .into_iter()
        .chain(m.study_block().and_then(|b| b.split('.').next()))
}

/// What method `m` does with a gap in a user's record ([`MethodScenario::gaps`]).
pub fn gaps(m: Method) -> Gaps {
    make_method(m).gaps()
}

/// How method `m`'s CSV table counts time ([`MethodScenario::time_index`]).
pub fn time_index(m: Method) -> TimeIndex {
    make_method(m).time_index()
}

/// The most states n method `m` takes ([`MethodScenario::max_states`]).
pub fn max_states(m: Method) -> usize {
    make_method(m).max_states()
}

/// The keys of method `m`'s report that hold or judge the true state, each with what it is
/// (`x_true`, every method's, first; [`MethodScenario::truth_keys`]): what a report on `data`
/// leaves out.
pub fn truth_keys(m: Method) -> Vec<(&'static str, &'static str)> {
    std::iter::once(("x_true", "true states (every method)"))
        .chain(make_method(m).truth_keys().iter().copied())
        .collect()
}

/// Most runs any study may ask for.
pub const MAX_STUDY_RUNS: usize = 10_000_000;

/// The core's limits on the fields a page offers as sliders and number boxes, keyed by field
/// path, as `[min, max]` or, where the method decides, `{method: [min, max]}`: one source for
/// the controls' ranges and the messages (`"simulate.steps"`, `"runs"` for any study's run
/// count, `"uniform.window"`).
pub fn limits() -> serde_json::Value {
    let steps: serde_json::Map<String, serde_json::Value> = Method::ALL
        .iter()
        .map(|&m| {
            let r = make_method(m).steps();
            (
                m.name().to_string(),
                serde_json::json!([r.start(), r.end()]),
            )
        })
        .collect();
    serde_json::json!({
        "simulate.steps": steps,
        "simulate.true_noise": [TRUE_NOISE_SCALES.start(), TRUE_NOISE_SCALES.end()],
        "runs": [1, MAX_STUDY_RUNS],
        "uniform.window": [1, crate::uniform::MAX_WINDOW],
        // The noise bounds ubb assumes (ε > 0, τ ≥ 0) and the true noise it simulates (≥ 0):
        // finite numbers up to the scenario's largest magnitude.
        "ubb.eps": [0, MAX_MAGNITUDE],
        "ubb.tau": [0, MAX_MAGNITUDE],
        "ubb.sim_eps": [0, MAX_MAGNITUDE],
        "ubb.sim_tau": [0, MAX_MAGNITUDE],
        // Conformal's calibration runs (the least depends on the level and is named by the
        // refusal), ACI's step size γ ∈ (0, 1] and the Student-t's ν ∈ (2, 10⁶].
        "conformal.calibration": [1, conformal::MAX_CALIBRATION],
        "conformal.gamma": [0, 1],
        "conformal.nu": [conformal::NU_RANGE.start(), conformal::NU_RANGE.end()],
    })
}

impl Scenario {
    /// Validate and run: the report of this scenario.
    pub fn run(&self) -> Result<Report> {
        self.check_method_blocks()?;
        self.work(Job::Report).check(Job::Report)?;
        let mut report = make_method(self.method).run(self)?;
        report.check_finite()?;
        report.notices = self.notices();
        Ok(report)
    }

    /// The time cursor of this scenario ([`Cursor`]): the run prepared once, the detail of
    /// any step on demand. `None` for a method whose reports hold every step (SCF, KF) or
    /// have no time (LSCR, GLLS). The scenario's own time field is not used.
    pub fn cursor(&self) -> Result<Option<Box<dyn Cursor>>> {
        self.check_method_blocks()?;
        let block = self.method.block().unwrap_or("");
        Ok(make_method(self.method)
            .cursor(self)?
            .map(|inner| Box::new(CheckedCursor { inner, block }) as Box<dyn Cursor>))
    }

    /// The quantity the method's view animates by rerunning and the smallest value of it the
    /// method accepts, the rest of this scenario unchanged ([`FirstAccepted`]): LSCR's data
    /// length (`simulate.steps`: t ≥ n, M ≤ 2^t, t above the smoothed index), GLLS's horizon
    /// (`glls.horizon`: the first s at which x(k − s) is observable). Values from it up to this
    /// scenario's are accepted. An error when the method animates nothing by rerunning, or
    /// when this scenario itself is refused (its own message). Checked against the work budget
    /// first: every value searched is at most this scenario's.
    pub fn first_accepted(&self) -> Result<FirstAccepted> {
        self.check_method_blocks()?;
        self.work(Job::Report).check(Job::Report)?;
        make_method(self.method).first_accepted(self)?.ok_or_else(|| {
            Error::field(
                "method",
                format!(
                    "\"{}\" has no quantity its view animates by rerunning (its time cursor only redraws)",
                    self.method
                ),
            )
        })
    }

    /// The Monte Carlo study of this scenario's method, not yet run: the SCF conditional
    /// experiment (`experiment`), the LSCR coverage experiment (`lscr.coverage`), the GLLS
    /// study (`glls.monte_carlo`) or the set-membership guarantee (`ubb.guarantee`). `runs`
    /// overrides the scenario's run count (the CLI's `--runs`, the page's field). Its results,
    /// plain or merged, pass [`check_finite`] (`study.<field>`).
    pub fn study(&self, runs: Option<usize>) -> Result<Box<dyn Study>> {
        self.check_method_blocks()?;
        if let Some(r) = runs {
            if !(1..=MAX_STUDY_RUNS).contains(&r) {
                return Err(Error::field(
                    "runs",
                    format!("must be a whole number from 1 to {MAX_STUDY_RUNS}, found {r}"),
                ));
            }
        }
        let job = Job::Study { runs };
        self.work(job).check(job)?;
        let mut study = make_method(self.method).study(self, runs)?;
        study.set_scenario_digest(&self.digest()?);
        Ok(Box::new(CheckedStudy {
            inner: study,
            merged: false,
        }))
    }

    /// A stable digest of the scenario: FNV-1a (64 bits, 16 hex digits) of its canonical JSON
    /// (keys sorted, numbers as serde_json writes them). A study's partial counts carry it, so
    /// a merge refuses the parts of another scenario.
    pub fn digest(&self) -> Result<String> {
        let v = serde_json::to_value(self)
            .map_err(|e| Error::field("", format!("the scenario could not be written: {e}")))?;
        let text = v.to_string();
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for b in text.bytes() {
            h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
        Ok(format!("{h:016x}"))
    }

    /// The estimated work of this scenario's report or study ([`budget`]), without running it.
    pub fn work(&self, job: Job) -> Work {
        let method = make_method(self.method);
        // Steps past the method's range are the step check's to refuse ([`Scenario::source`]).
        if !method.steps().contains(&self.written_steps()) {
            return Work::default();
        }
        method.work(self, job)
    }

    /// The one observations step: `data` or `simulate` (exactly one), with the number of
    /// steps checked against what the method accepts, and `simulate.true_noise` against what
    /// the method can honour ([`MethodScenario::true_noise`]).
    pub(crate) fn source(&self, method: &dyn MethodScenario) -> Result<Source<'_>> {
        if let Some(sim) = &self.simulate {
            if let Some(noise) = &sim.true_noise {
                if self.data.is_some() {
                    return Err(Error::field(
                        "simulate.true_noise",
                        "needs a simulated record: the scenario has data (measured data carry their own noise)",
                    ));
                }
                if let Some(why) = method.true_noise() {
                    return Err(Error::field(
                        "simulate.true_noise",
                        format!(
                            "is not used by method \"{}\": {why}; remove it",
                            self.method
                        ),
                    ));
                }
                for (field, x) in [
                    ("simulate.true_noise.V", noise.v),
                    ("simulate.true_noise.W", noise.w),
                ] {
                    if !TRUE_NOISE_SCALES.contains(&x) {
                        return Err(Error::field(
                            field,
                            format!(
                                "is {x}: a scale of the true noise's covariance is a positive number from {:e} to {:e}",
                                TRUE_NOISE_SCALES.start(),
                                TRUE_NOISE_SCALES.end()
                            ),
                        ));
                    }
                }
            }
        }
        let source = match (&self.data, &self.simulate) {
            (Some(_), Some(_)) => {
                return Err(Error::field(
                    "data",
                    "and simulate are both given: choose one",
                ))
            }
            (None, None) => {
                return Err(Error::field(
                    "data",
                    "is missing (give data.y or a simulate block)",
                ))
            }
            (Some(d), None) => Source::Data(d),
            (None, Some(s)) => Source::Simulate(s),
        };
        if let Source::Data(d) = &source {
            d.check_times()?;
            // The one gate of gaps (a missing measurement): a method that cannot take one is
            // refused here, naming the row and its time, before any work.
            if let (Some((k, _)), Gaps::Refused(why)) = (d.first_gap(), method.gaps()) {
                return Err(d.gap_error(
                    k,
                    &format!("method \"{}\" cannot take a gap: {why}", self.method),
                ));
            }
        }
        let range = method.steps();
        let steps = source.steps();
        if !range.contains(&steps) {
            let what = if source.is_data() {
                "measurements"
            } else {
                "steps"
            };
            let found = if steps == 0 && source.is_data() {
                "is empty".to_string()
            } else {
                format!(
                    "gives {}",
                    crate::error::counted(steps, what.trim_end_matches('s'), what)
                )
            };
            return Err(Error::field(
                source.steps_field(),
                format!(
                    "{found}: method \"{}\" takes {} to {} {what}",
                    self.method,
                    range.start(),
                    range.end()
                ),
            ));
        }
        // Inputs past the last time a run uses would be read, kept and silently ignored (10⁶
        // rows of `simulate.u` cost a second and a gigabyte for nothing): one row per step,
        // up to the simulated or measured end (or the conditioning time, if later) and τ
        // predicted steps beyond it; fewer rows hold the last one.
        let (u_field, u_rows) = source.input_rows();
        let end = match source {
            Source::Simulate(sim) => steps.max(sim.condition.as_ref().map_or(0, |c| c.t)),
            Source::Data(_) => steps,
        };
        let tau = self.scf.as_ref().map_or(0, |b| b.tau);
        let used = end.saturating_add(tau);
        if u_rows.len() > used {
            return Err(Error::field(
                u_field,
                format!(
                    "has {} rows, but the run uses u_1 … u_{used} (one row per step{}; fewer rows hold the last one): give at most {used_rows}",
                    u_rows.len(),
                    if tau > 0 { ", and one per predicted step of scf.tau" } else { "" }, used_rows = crate::error::counted(used, "row", "rows")
                ),
            ));
        }
        Ok(source)
    }

    /// A method's blocks belong to it only: its options ([`Method::block`]) and its study
    /// ([`Method::study_block`]'s top-level key), which another method would ignore without a
    /// word. The top-level keys of the scenario's JSON that are some method's block are
    /// checked against the scenario's own method, so a new method's block is checked as soon
    /// as [`Method`] names it.
    fn check_method_blocks(&self) -> Result<()> {
        // The scenario without its data and model, whose size is not at stake here.
        let shell = Scenario {
            data: None,
            simulate: None,
            model: ModelSpec::default(),
            ..self.clone()
        };
        let v = serde_json::to_value(&shell)
            .map_err(|e| Error::field("", format!("the scenario could not be written: {e}")))?;
        let Some(keys) = v.as_object() else {
            return Ok(());
        };
        let own: Vec<&str> = method_blocks(self.method).collect();
        for key in keys.keys().filter(|k| !own.contains(&k.as_str())) {
            let owners: Vec<Method> = Method::ALL
                .into_iter()
                .filter(|&m| method_blocks(m).any(|b| b == key))
                .collect();
            let Some(&first) = owners.first() else {
                continue;
            };
            let names: Vec<String> = owners.iter().map(|m| format!("\"{m}\"")).collect();
            let names = names.join(" or ");
            let message = if first.study_block() == Some(key.as_str()) {
                let theirs = match self.method.study_block() {
                    Some(b) => format!("whose Monte Carlo study is {b}"),
                    None => "which has no Monte Carlo study".to_string(),
                };
                format!(
                    "is a Monte Carlo study, used only with \"method\": {names} (found \"{}\", {theirs})",
                    self.method
                )
            } else {
                format!(
                    "is only used with \"method\": {names} (found \"{}\")",
                    self.method
                )
            };
            return Err(Error::field(key.as_str(), message));
        }
        Ok(())
    }

    /// The scales of the simulated noise (`simulate.true_noise`: (V ×, W ×); (1, 1) when
    /// absent). Checked by [`Scenario::source`].
    pub fn true_noise_scales(&self) -> (f64, f64) {
        self.simulate
            .as_ref()
            .and_then(|s| s.true_noise)
            .map_or((1.0, 1.0), |t| (t.v, t.w))
    }

    /// The model the simulation draws from: `model` with its noise scaled by
    /// `simulate.true_noise` ([`crate::model::LinearModel::with_noise_scaled`]), `model` itself
    /// when the scales are 1.
    pub(crate) fn true_model(
        &self,
        model: &crate::model::LinearModel,
    ) -> Result<crate::model::LinearModel> {
        let (v, w) = self.true_noise_scales();
        model.with_noise_scaled(v, w).map_err(|e| {
            Error::field(
                "simulate.true_noise.V",
                format!("gives a process with no stationary law ({})", e.message),
            )
        })
    }

    /// `simulate.condition` (the fixed state of a study), or a field error saying `why`.
    pub(crate) fn condition(&self, why: &str) -> Result<&Condition> {
        self.simulate
            .as_ref()
            .and_then(|s| s.condition.as_ref())
            .ok_or_else(|| Error::field("simulate.condition", format!("is needed: {why}")))
    }

    /// The method's own block, or a field error saying what it needs.
    pub(crate) fn block<'a, T>(&self, block: &'a Option<T>, needs: &str) -> Result<&'a T> {
        block.as_ref().ok_or_else(|| {
            let name = self.method.block().unwrap_or("");
            Error::field(
                name,
                format!(
                    "is missing: the method \"{}\" needs a {name} block ({needs})",
                    self.method
                ),
            )
        })
    }
}

/// The path of the first null in a report's JSON that stands for a non-finite number (a null
/// under a nullable key is an absent region; an entry of a list never is one).
fn first_null(v: &serde_json::Value) -> Option<String> {
    first_leaf(v, &|x, key, in_list, path| {
        // A `null` in the report's measurements `y` (and its `ubb.y`) is a gap of the
        // user's record ([`DataSpec`]): no number stands there.
        // A compare's members keep their own scenario on the record, gaps included
        // (`compare.at.sets[i].scenario.data.y`; in a cursor's detail `sets[i].scenario…`).
        let gap = in_list
            && key == "y"
            && (path.starts_with("y[")
                || path.starts_with("ubb.y[")
                || path.contains("].scenario.data.y["));
        (x.is_null() && !gap && (in_list || !NULLABLE_REPORT_KEYS.iter().any(|(k, _)| *k == key)))
            .then_some(())
    })
    .map(|(path, ())| path)
}

/// The one finiteness check of every output: a report ([`Report::check_finite`]), a
/// cursor's detail, a study's result, plain or merged (`root` `"study"`). serde_json writes a
/// NaN or ±∞ as `null`, so a `null` where a number belongs (anywhere but under a
/// [`NULLABLE_REPORT_KEYS`] key; never in a list) is an error naming its field under `root`
/// (`study.mean_state_norm`). `also` is added to the reason (what else may cause it). The CSV
/// table has its own cells and the same message ([`csv::Table::check_finite`]).
pub fn check_finite(v: &serde_json::Value, root: &str, also: &str) -> Result<()> {
    match first_null(v) {
        None => Ok(()),
        Some(path) if path.is_empty() => Err(not_finite(root, also)),
        Some(path) => Err(not_finite(&format!("{root}.{path}"), also)),
    }
}

/// The error of an output field that is not a finite number: why it happens and what to lower.
pub(crate) fn not_finite(field: &str, also: &str) -> Error {
    Error::field(
        field,
        format!(
            "is not a finite number: the computation overflowed (past 1.8e308) or divided by zero. \
             An input is too large, too small or too ill-conditioned for double precision, or an \
             unstable model ran over so many steps that its states overflowed: lower the steps or \
             horizons, the noise, bounds or data, or use a better-conditioned model{also}"
        ),
    )
}

/// Keys whose value may be JSON null in a report: `Option` fields serialized without
/// `skip_serializing_if` (the reason after each). Everywhere else a null would be a non-finite
/// f64, which serde_json writes as null: [`Report::check_finite`] refuses those.
pub const NULLABLE_REPORT_KEYS: [(&str, &str); 5] = [
    (
        "scf",
        "ScfStep, RegionPair: no SCF region while the ratio matrix is singular (t < n)",
    ),
    (
        "ratio",
        "RegionPair: no closed-form R = I − PΓ⁻¹ while the prior Γ_t is singular",
    ),
    (
        "scf_distance",
        "CollisionReport: no SCF region yet at that time (t < n)",
    ),
    ("scf_warning", "CollisionReport: no SCF region yet"),
    (
        "true_distance",
        "CollisionReport: t + τ lies past the simulation, or the data have no truth",
    ),
];

impl Report {
    /// Every number of the report is finite (the JSON contract: a number, never a null where
    /// a number belongs). The last defence behind the input checks: a value that overflowed or
    /// divided by zero in the computation becomes an error naming the report field, not a null.
    pub fn check_finite(&self) -> Result<()> {
        let v = serde_json::to_value(self)
            .map_err(|e| Error::field("report", format!("could not be written as JSON: {e}")))?;
        check_finite(&v, "report", "")
    }

    /// The report's main estimates and set sizes, one row per time step (horizon for GLLS,
    /// the one target time for LSCR): what `confset run --format csv` writes. A cell that is
    /// not a finite number (a set's volume that overflowed, which the JSON report does not
    /// hold) is an error naming `csv.<column> at <first column>=<row>`
    /// ([`csv::Table::check_finite`]), never an `inf` in the file.
    pub fn table(&self) -> Result<csv::Table> {
        let method = make_method(self.method);
        let mut table = method.table(self);
        // The record's own time beside the method's time column ([`TimeIndex`]).
        let row_of = |x: f64| match method.time_index() {
            TimeIndex::OneBased => (x >= 1.0).then(|| x as usize - 1),
            TimeIndex::ZeroBased => (x >= 0.0).then_some(x as usize),
            TimeIndex::NotTime => None,
        };
        if !self.figure.times.is_empty() && method.time_index() != TimeIndex::NotTime {
            table.record_time = table
                .rows
                .iter()
                .map(|r| {
                    r.first()
                        .copied()
                        .flatten()
                        .and_then(row_of)
                        .and_then(|i| self.figure.row_time(i))
                        .unwrap_or_default()
                })
                .collect();
        }
        // The report's warnings first, then the table's own (a compare's methods without a set).
        table.warnings.splice(0..0, self.warnings.iter().cloned());
        table.check_finite()?;
        Ok(table)
    }

    /// Put a detail of the method's [`Cursor`] (its `at(t)`) into this report: its `at` block
    /// and `time` become those of the report run at t, so the figures draw step t. A detail of
    /// another method's shape is an `at` error, and the report stays as it was.
    pub fn set_at(&mut self, at: serde_json::Value) -> Result<()> {
        make_method(self.method).set_at(self, at)
    }

    /// The steps the method's time cursor moves over for this report (a time outside them
    /// shows the nearest of them), or `None` when the method has no time cursor.
    pub fn cursor_steps(&self) -> Option<RangeInclusive<usize>> {
        make_method(self.method).cursor_steps(self)
    }

    /// Put a result of the method's study into this report (`null` removes it), so the
    /// figures draw it; a method whose report holds none refuses, and the report stays.
    pub fn set_study(&mut self, result: serde_json::Value) -> Result<()> {
        make_method(self.method).set_study(self, result)
    }

    /// The report with the scenario's method and figure context and every method's result
    /// empty: the caller sets its own (its block, or SCF's `steps` and their companions), so
    /// no scenario file names another method's result.
    pub(crate) fn of(
        s: &Scenario,
        alpha: f64,
        (n, q): (usize, usize),
        time: usize,
        plot: Vec<usize>,
        y: Vec<Vec<f64>>,
    ) -> Report {
        Report {
            method: s.method,
            alpha,
            n,
            q,
            time,
            plot,
            steps: Vec::new(),
            y,
            x_true: None,
            prior_mean: Vec::new(),
            asymptotic: None,
            collision: None,
            coverage_curve: None,
            lscr: None,
            glls: None,
            uniform: None,
            ubb: None,
            conformal: None,
            compare: None,
            notices: Vec::new(),
            warnings: Vec::new(),
            figure: FigureContext::of(s),
        }
    }
}

/// A whole number in Unicode subscript digits ("x" + subscript(12) = "x₁₂"): the names shown to
/// users carry no raw `_` notation.
pub(crate) fn subscript(n: usize) -> String {
    n.to_string()
        .chars()
        .map(|c| char::from_u32(0x2080 + c.to_digit(10).unwrap_or(0)).unwrap_or(c))
        .collect()
}
