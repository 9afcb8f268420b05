//! Where double precision stops resolving a method's sets, derived once for every method.
//!
//! Every set this crate computes is decided by quantities of the form ℓ = Σᵢ cᵢ yᵢ + (affine in
//! the state): a sign test of LSCR ((17): the sign of an affine function of x), an ellipsoid's
//! membership (SCF, Kalman, GLLS: a quadratic form of x − x̂ with x̂ = Σ Kᵢ yᵢ), a constraint of a
//! set-membership LP (ubb, uniform: |yᵢ − hᵢᵀx| ≤ εᵢ). The data enter as doubles, and a double of
//! magnitude Y is known only to its spacing δ(Y) (the gap to the next double: 2⁻⁵² Y up to a
//! factor 2). So, with N data in one such quantity:
//!
//! * its rounding is at most Σ |cᵢ| δ(Y) ≤ √N ‖c‖₂ δ(Y) (Cauchy–Schwarz);
//! * its noise spread is at least ‖c‖₂ σ, with σ the smallest noise standard deviation (the
//!   noise components are independent in the frame the method works in: LSCR's
//!   Karhunen–Loève frame, the whitened Kalman innovations);
//! * so rounding moves it by at most ρ = √N δ(Y) / σ of its own standard deviations, and a
//!   Gaussian quantity lands within ρ standard deviations of its threshold with probability at
//!   most 2ρ/√(2π) < 0.8 ρ.
//!
//! With T such tests deciding one verdict (LSCR: M·n sign tests; a membership: one), rounding
//! changes the verdict with probability at most 0.8 ρ T (a union bound). A coverage study counts
//! verdicts, and its exact binomial band at the presets' 2,000 runs is about ±1.3 % wide; a change
//! of [`MAX_FLIP`] = 10⁻⁴ is 100 times smaller than that, so below it the counts measure the
//! method and above it they may measure rounding. [`Resolution::check`] refuses above it,
//! before any heavy work, and says which magnitude would be resolved. For set-membership
//! (ubb, uniform) σ is the smallest noise bound: a bound below the data's spacing leaves a strip
//! that a double cannot even represent.
//!
//! Where the method is affine-equivariant and the magnitude is the user's own choice of origin,
//! the message says so: translating the problem (measuring from the prior mean or the first
//! measurement) recovers every digit.

use crate::{Error, Result};

/// The largest probability with which rounding may change one verdict (see the module docs).
pub const MAX_FLIP: f64 = 1e-4;

/// 2/√(2π), the most probability a unit Gaussian puts on an interval of width 2 per unit of
/// half-width, rounded up.
const GAUSS_DENSITY_BOUND: f64 = 0.8;

/// One method's precision question: data of magnitude `magnitude` against a noise scale `noise`.
#[derive(Debug, Clone)]
pub struct Resolution<'a> {
    /// The scenario field that sets the magnitude (`data.y`, `simulate.condition.x`, …).
    pub field: &'a str,
    /// What reaches that magnitude, in words ("the data y", "the state x(0)").
    pub what: &'a str,
    /// The largest magnitude Y the data or states reach.
    pub magnitude: f64,
    /// The smallest noise scale σ the sets resolve (a standard deviation or a bound).
    pub noise: f64,
    /// How the noise scale is named in the message ("σ, the smallest Karhunen–Loève noise
    /// standard deviation").
    pub noise_name: &'a str,
    /// N: how many data one tested quantity combines.
    pub combined: usize,
    /// T: how many tests decide one verdict.
    pub tests: usize,
    /// The method, for the message.
    pub method: &'a str,
}

/// The gap from a non-negative finite `y` to the next double: what a double of that magnitude
/// cannot tell apart.
pub fn spacing(y: f64) -> f64 {
    let y = y.abs();
    if !y.is_finite() {
        return f64::INFINITY;
    }
    f64::from_bits(y.to_bits() + 1) - y
}

/// The largest absolute entry of a list of vectors (0 for none): the magnitude Y of a record.
pub fn largest<'a, V>(vectors: impl IntoIterator<Item = &'a V>) -> f64
where
    V: AsRef<[f64]> + 'a + ?Sized,
{
    vectors
        .into_iter()
        .flat_map(|v| v.as_ref().iter())
        .fold(0.0_f64, |m, e| m.max(e.abs()))
}

impl Resolution<'_> {
    /// ρ T 0.8: the bound on the probability that rounding changes a verdict.
    pub fn flip_bound(&self) -> f64 {
        let rho = (self.combined.max(1) as f64).sqrt() * spacing(self.magnitude) / self.noise;
        GAUSS_DENSITY_BOUND * rho * self.tests.max(1) as f64
    }

    /// The largest magnitude whose spacing keeps [`Self::flip_bound`] under [`MAX_FLIP`]
    /// (spacing ≤ 2⁻⁵² Y, so this is a safe round figure).
    pub fn largest_resolved(&self) -> f64 {
        let ok_spacing = MAX_FLIP * self.noise
            / (GAUSS_DENSITY_BOUND
                * (self.combined.max(1) as f64).sqrt()
                * self.tests.max(1) as f64);
        ok_spacing / f64::EPSILON
    }

    /// Refuse when rounding could decide the verdicts (see the module docs), naming the field.
    pub fn check(&self) -> Result<()> {
        if !(self.noise > 0.0) || !self.noise.is_finite() {
            return Ok(()); // no noise scale: the method's own checks refuse or it is noise-free
        }
        let bound = self.flip_bound();
        if bound <= MAX_FLIP {
            return Ok(());
        }
        Err(Error::field(
            self.field,
            format!(
                "makes {} as large as {:.3e}: there the spacing of doubles is {:.3e}, against a noise scale of {:.3e} \
                 ({}), so rounding could change {}'s verdicts with probability up to {} (more than {:e}) and a study would \
                 count rounding, not the method. Magnitudes up to about {:.1e} are resolved at this noise level: \
                 measure from a nearer origin (e.g. the prior mean or the first measurement) or raise the noise",
                self.what,
                self.magnitude,
                spacing(self.magnitude),
                self.noise,
                self.noise_name,
                self.method,
                probability(bound),
                MAX_FLIP,
                self.largest_resolved(),
            ),
        ))
    }
}

fn probability(p: f64) -> String {
    if p >= 1.0 {
        "1 (certain)".into()
    } else {
        format!("{p:.1e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lscr_like(magnitude: f64) -> Resolution<'static> {
        Resolution {
            field: "simulate.condition.x",
            what: "the data y",
            magnitude,
            noise: 0.07,
            noise_name: "σ",
            combined: 20,
            tests: 40,
            method: "LSCR",
        }
    }

    #[test]
    fn spacing_is_the_gap_to_the_next_double() {
        assert_eq!(spacing(1.0), f64::EPSILON);
        assert_eq!(spacing(1e15), 0.125);
        assert_eq!(spacing(-1e15), 0.125);
        assert_eq!(spacing(0.0), 5e-324);
        assert_eq!(spacing(f64::NAN), f64::INFINITY);
    }

    #[test]
    fn the_issue_case_is_refused_and_a_moderate_one_resolved() {
        let e = lscr_like(1e15).check().unwrap_err();
        assert_eq!(e.field, "simulate.condition.x");
        assert!(e.message.contains("1.250e-1"), "{}", e.message);
        lscr_like(1e6).check().unwrap();
    }

    #[test]
    fn the_resolved_limit_is_where_the_check_turns() {
        let r = lscr_like(1.0);
        let limit = r.largest_resolved();
        lscr_like(limit / 2.0).check().unwrap();
        lscr_like(limit * 4.0).check().unwrap_err();
    }
}
