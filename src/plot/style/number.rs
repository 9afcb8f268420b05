//! Bottom layer: numbers and indices as figure text (fixed decimals with a typographic minus,
//! significant digits, 10ᵏ, subscripts, percentages). Pure string work: it imports nothing of
//! the plot layer.

/// Decimals that make ticks over `span` distinct (about 8 ticks).
pub fn decimals(span: f64) -> usize {
    if !(span.is_finite() && span > 0.0) {
        return 2;
    }
    let step = span / 8.0;
    (-(step.log10().floor())).clamp(0.0, 8.0) as usize
}

/// A number for a label: fixed decimals, typographic minus, no "−0".
pub fn num(v: f64, decimals: usize) -> String {
    let s = format!("{v:.decimals$}");
    let neg_zero = s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.');
    if neg_zero {
        s[1..].to_string()
    } else if let Some(rest) = s.strip_prefix('-') {
        format!("−{rest}")
    } else {
        s
    }
}

/// A number with about 3 significant digits.
pub fn sig(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return num(v, 0);
    }
    let d = (2.0 - v.abs().log10().floor()).clamp(0.0, 8.0) as usize;
    let s = num(v, d);
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// A number for prose: 3 significant digits, or "2.17 × 10⁻⁵" for tiny and huge magnitudes.
pub fn sci(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 || !v.is_finite() || (1e-3..1e5).contains(&a) {
        return sig(v);
    }
    let e = a.log10().floor() as i32;
    let m = v / 10f64.powi(e);
    format!("{} × 10{}", num(m, 2), sup(e))
}

/// Unicode superscript of an integer (−5 → "⁻⁵").
pub fn sup(e: i32) -> String {
    e.to_string()
        .chars()
        .map(|c| match c {
            '-' => '⁻',
            '1' => '¹',
            '2' => '²',
            '3' => '³',
            d => char::from_u32(0x2070 + d.to_digit(10).unwrap_or(0)).unwrap_or(d),
        })
        .collect()
}

/// A power of ten for a log axis: "10⁻³".
pub fn pow10(e: i32) -> String {
    format!("10{}", sup(e))
}

/// Unicode subscript of a number (t = 40 → "₄₀").
pub fn sub(n: usize) -> String {
    n.to_string()
        .chars()
        .map(|c| char::from_u32(0x2080 + c.to_digit(10).unwrap_or(0)).unwrap_or(c))
        .collect()
}

/// α as a percentage ("95 %").
pub fn pct(alpha: f64) -> String {
    let p = alpha * 100.0;
    if (p - p.round()).abs() < 1e-9 {
        format!("{} %", p.round())
    } else {
        format!("{} %", sig(p))
    }
}

/// A probability as a percentage for a figure: whole when within 0.05 of one ("90 %"), else
/// one decimal ("99.1 %").
pub fn percent(p: f64) -> String {
    let v = 100.0 * p;
    if (v - v.round()).abs() < 0.05 {
        format!("{:.0} %", v)
    } else {
        format!("{:.1} %", v)
    }
}
