//! Statistics shared by every method: χ² quantiles for ellipsoidal regions (and back, an
//! ellipsoid's level: [`ellipsoid_level`]) and the exact binomial bands that every Monte Carlo
//! study (SCF, LSCR, GLLS, set-membership) compares its counts with. statrs does the work;
//! this module adds the round-trip checks and the one band definition, so that no method
//! carries its own.

use crate::error::{Error, Result};
use statrs::distribution::{Binomial, ChiSquared, Continuous, ContinuousCDF, DiscreteCDF};

/// The two-sided level of every band shown on the page and asserted in the tests.
pub const BAND_LEVEL: f64 = 0.999;

/// χ²(α, k): the quantile at probability α of the χ² law with k degrees of freedom, round-trip
/// checked (statrs 0.18 returned NaN in the lower tail: crate docs, toolchain facts), so no NaN ellipse escapes.
pub fn chi2_quantile(alpha: f64, k: usize) -> Result<f64> {
    // A report asks for the same (α, k) at every time step: remember the last answer.
    thread_local! {
        static LAST: std::cell::Cell<(f64, usize, f64)> = const { std::cell::Cell::new((f64::NAN, 0, 0.0)) };
    }
    let (a, kk, r) = LAST.with(|c| c.get());
    if a == alpha && kk == k {
        return Ok(r);
    }
    let r2 = chi2_quantile_uncached(alpha, k)?;
    LAST.with(|c| c.set((alpha, k, r2)));
    Ok(r2)
}

/// The level of an ellipsoid {(x − c)ᵀ Σ⁻¹ (x − c) ≤ r²} of N(c, Σ) in k dimensions: the
/// probability it holds, the χ² CDF with k degrees of freedom at r² (the inverse of
/// [`chi2_quantile`], which made r² from the level); `None` for k = 0 or an r² it cannot take.
pub fn ellipsoid_level(radius2: f64, k: usize) -> Option<f64> {
    let law = ChiSquared::new(k as f64).ok()?;
    let p = law.cdf(radius2);
    (radius2 >= 0.0 && p.is_finite()).then_some(p)
}

/// The levels a region is drawn at: from [`LEVEL_MIN`] to [`LEVEL_MAX`]. Below, the χ²
/// quantile is lost in the lower tail (statrs' inverse returns NaN or 0 there); above, 1 − α
/// has lost most of its digits to the rounding of α itself.
pub const LEVEL_MIN: f64 = 1e-6;
pub const LEVEL_MAX: f64 = 1.0 - 1e-9;
const LEVEL_WORDS: &str = "a level is a probability strictly between 0 and 1, accepted from 1e-6 to 1 − 1e-9 (0.999999999)";

/// A level α of a region (`alpha`, `lscr.level`, …) in the accepted range, or an error on
/// `field` saying the range.
pub fn check_level(field: &str, alpha: f64) -> Result<()> {
    if !(alpha > 0.0 && alpha < 1.0) {
        return Err(Error::field(
            field,
            format!(
                "must lie strictly between 0 and 1, found {} ({LEVEL_WORDS})",
                crate::error::shown(alpha)
            ),
        ));
    }
    if !(LEVEL_MIN..=LEVEL_MAX).contains(&alpha) {
        return Err(Error::field(
            field,
            format!(
                "= {} is outside the accepted range: {LEVEL_WORDS}, where its χ² quantile is resolved in double precision",
                crate::error::shown(alpha)
            ),
        ));
    }
    Ok(())
}

fn chi2_quantile_uncached(alpha: f64, k: usize) -> Result<f64> {
    check_level("alpha", alpha)?;
    if k == 0 {
        return Err(Error::field("alpha", "needs at least one dimension"));
    }
    let law = ChiSquared::new(k as f64).map_err(|e| Error::field("alpha", e.to_string()))?;
    let mut r2 = law.inverse_cdf(alpha);
    // statrs' inverse is only ~1e-10 relative (α = 0.95, k = 2: 5.9914645461 vs the exact
    // −2 ln 0.05 = 5.9914645471); two Newton steps on the CDF bring it to rounding level.
    for _ in 0..2 {
        let step = (law.cdf(r2) - alpha) / law.pdf(r2);
        let next = r2 - step;
        if next.is_finite()
            && next > 0.0
            && (law.cdf(next) - alpha).abs() <= (law.cdf(r2) - alpha).abs()
        {
            r2 = next;
        }
    }
    if !r2.is_finite() || (law.cdf(r2) - alpha).abs() > 1e-8 {
        return Err(Error::field(
            "alpha",
            format!(
                "has no χ² quantile (k = {k}) that double precision resolves at α = {}: {LEVEL_WORDS}",
                crate::error::shown(alpha)
            ),
        ));
    }
    Ok(r2)
}

/// Exact binomial central interval [lo, hi] holding a Binomial(runs, p) count with probability
/// ≥ 1 − 2·tail (tail = 0.0005 gives the 99.9 % band of [`BAND_LEVEL`]): lo is the largest
/// count with P(X < lo) ≤ tail, hi the smallest with P(X > hi) ≤ tail, from statrs' exact CDF
/// (no normal approximation, so it stays right for p near 0 or 1 and for few runs).
pub fn binomial_band(runs: usize, p: f64, tail: f64) -> (usize, usize) {
    match Binomial::new(p.clamp(0.0, 1.0), runs as u64) {
        Ok(b) => {
            let lo = b.inverse_cdf(tail) as usize;
            let hi = b.inverse_cdf(1.0 - tail) as usize;
            (lo.min(runs), hi.min(runs))
        }
        Err(_) => (0, runs),
    }
}

/// The [`BAND_LEVEL`] band of a Binomial(runs, p) count.
pub fn band(runs: usize, p: f64) -> (usize, usize) {
    binomial_band(runs, p, (1.0 - BAND_LEVEL) / 2.0)
}

/// The standard normal distribution function Φ(x).
pub fn normal_cdf(x: f64) -> f64 {
    0.5 * statrs::function::erf::erfc(-x / std::f64::consts::SQRT_2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ellipsoid_level_inverts_the_quantile() {
        for (alpha, k) in [(0.99, 2), (0.95, 2), (0.9, 3), (0.5, 1)] {
            let r2 = chi2_quantile(alpha, k).unwrap();
            let level = ellipsoid_level(r2, k).unwrap();
            assert!((level - alpha).abs() < 1e-12, "{alpha}, {k}: {level}");
        }
        // In the plane the CDF is 1 − e^{−r²/2}.
        let r2 = chi2_quantile(0.99, 2).unwrap();
        assert!((ellipsoid_level(r2, 2).unwrap() - (1.0 - (-0.5 * r2).exp())).abs() < 1e-14);
        assert_eq!(ellipsoid_level(1.0, 0), None);
        assert_eq!(ellipsoid_level(f64::NAN, 2), None);
    }
}
