//! Bottom layer of the figures' look: the colours (Okabe–Ito, colorblind-safe) and line
//! dashes every panel shares. It imports nothing of the plot layer.
//!
//! Conventions: KF is vermillion and dashed, SCF is blue and solid (with a light fill), the
//! truth is black, measurements are grey dots, the time cursor is a grey dotted line.

use plotters::style::RGBColor;

/// KF: vermillion (drawn dashed).
pub const KF: RGBColor = RGBColor(213, 94, 0);
/// SCF: blue (drawn solid, light fill).
pub const SCF: RGBColor = RGBColor(0, 114, 178);
/// True state and trajectory.
pub const TRUTH: RGBColor = RGBColor(0, 0, 0);
/// Measurements.
pub const MEASURE: RGBColor = RGBColor(125, 125, 125);
/// Reference lines (the level α): bluish green.
pub const REFERENCE: RGBColor = RGBColor(0, 158, 115);
/// Time cursor.
pub const CURSOR: RGBColor = RGBColor(120, 120, 120);
pub const TEXT: RGBColor = RGBColor(25, 25, 25);
pub const MUTED: RGBColor = RGBColor(85, 85, 85);
pub const GRID: RGBColor = RGBColor(222, 222, 222);
pub const GRID_LIGHT: RGBColor = RGBColor(240, 240, 240);
pub const FRAME: RGBColor = RGBColor(190, 190, 190);

/// LSCR region X̂ (outline) and its light tint.
pub const LSCR: RGBColor = RGBColor(20, 20, 20);
pub const LSCR_TINT: RGBColor = RGBColor(240, 228, 66);
/// BLUE estimate and ellipse (the SCF blue: both are "the estimator that knows the noise").
pub const BLUE_EST: RGBColor = SCF;
/// Hatch colours of the areas excluded by X̂_1, X̂_2, … (Okabe–Ito bluish green, reddish
/// purple, orange, sky blue; cycled with the directions of [`hatch_dir`]).
pub const HATCH: [RGBColor; 4] = [
    RGBColor(0, 150, 110),
    RGBColor(175, 60, 135),
    RGBColor(210, 140, 0),
    RGBColor(70, 160, 220),
];

/// Curves indexed by i (σ₁, σ₂, … of the GLLS figures): Okabe–Ito blue, vermillion, bluish
/// green, reddish purple, orange, sky blue, then black; cycled.
pub const SERIES: [RGBColor; 7] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
];

/// Colour of curve i (0-based).
pub fn series_color(i: usize) -> RGBColor {
    SERIES[i % SERIES.len()]
}

/// GLLS: the (G)LLS estimator (blue), the state-noise estimator (vermillion), the
/// regularized estimator and the projected truth (reddish purple), the guaranteed ball (blue,
/// light fill) and the interval box (bluish green).
pub const GLLS_EST: RGBColor = RGBColor(0, 114, 178);
pub const STATE_NOISE: RGBColor = RGBColor(213, 94, 0);
pub const REGULARIZED: RGBColor = RGBColor(204, 121, 167);
pub const BALL: RGBColor = RGBColor(0, 114, 178);
pub const INTERVAL_BOX: RGBColor = RGBColor(0, 158, 115);
/// Uniform-innovation panels (Pavelková): the LP (MAP) estimate blue like every estimator that
/// knows the noise's shape, the KF with variances r²/3 vermillion dashed, the ranges over the
/// LP's optimal face reddish purple, the consistent-state polygon bluish green, the sliding
/// window a grey band.
pub const UNIFORM_LP: RGBColor = RGBColor(0, 114, 178);
pub const FACE: RGBColor = RGBColor(204, 121, 167);
pub const POLYGON: RGBColor = RGBColor(0, 158, 115);
pub const WINDOW: RGBColor = RGBColor(160, 160, 160);
/// The floating-point floor (grey band).
pub const FLOOR: RGBColor = RGBColor(150, 150, 150);

/// Colour of the hatching of group l (0-based).
pub fn hatch_color(l: usize) -> RGBColor {
    HATCH[l % HATCH.len()]
}

/// Unit direction in screen pixels (y down) of the hatch lines of group l: "\\", "/", "—",
/// "|", then the same four again (drawn with a half-spacing offset so they interleave).
pub fn hatch_dir(l: usize) -> (f64, f64) {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    match l % 4 {
        0 => (h, h),
        1 => (h, -h),
        2 => (1.0, 0.0),
        _ => (0.0, 1.0),
    }
}

/// Dash and gap of KF lines, in pixels.
pub const DASH: (i32, i32) = (8, 5);
/// Dot and gap of the time cursor.
pub const DOT: (i32, i32) = (2, 4);

/// The compare panel's colours of the methods whose own panels use several (Okabe–Ito):
/// GLLS's ball reddish purple, Tempo's set bluish green, the uniform-LP set a sky blue.
pub const GLLS_BALL: RGBColor = RGBColor(204, 121, 167);
pub const TEMPO_SET: RGBColor = RGBColor(0, 158, 115);
pub const UNIFORM_SET: RGBColor = RGBColor(86, 150, 233);
