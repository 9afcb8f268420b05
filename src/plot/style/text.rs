//! Text layer, above the palette: font sizes ([`Fonts`]), measured and wrapped text, the
//! title block, and the one helper that composes a figure's title with the scenario's.
//!
//! Sizes are in CSS pixels of the backend (the wasm bindings hand the figure a backend of the
//! canvas' CSS size and scale the context by devicePixelRatio).

use super::palette::{MUTED, TEXT};
use crate::error::Result;
use crate::plot::erase::de;
use crate::scenario::FigureContext;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Text sizes in CSS pixels, whatever the backend, and whether the figure is small.
///
/// plotters hands a font size to the SVG backend as `font-size: size / 1.24` but to the canvas
/// as `size` px; both measure text consistently with how they render it. To get the same
/// on-screen sizes from both, the nominal size is scaled by 1.24 for SVG.
#[derive(Debug, Clone, Copy)]
pub struct Fonts {
    scale: f64,
    /// Small figure (narrower than 640 or lower than 400 px): smaller text, fewer subtitle
    /// lines, legend over the chart.
    pub compact: bool,
}

impl Fonts {
    /// The fonts for backend type `DB` and a figure of `size` pixels.
    pub fn for_backend<DB: DrawingBackend>(size: (u32, u32)) -> Fonts {
        let svg = std::any::type_name::<DB>().contains("SVGBackend");
        Fonts {
            scale: if svg { 1.24 } else { 1.0 },
            compact: size.0 < 640 || size.1 < 400,
        }
    }
    fn pick(&self, normal: f64, small: f64) -> f64 {
        if self.compact {
            small
        } else {
            normal
        }
    }
    /// Regular text of `px` CSS pixels.
    pub fn px(&self, px: f64) -> TextStyle<'static> {
        ("sans-serif", px * self.scale).into_font().color(&TEXT)
    }
    pub fn bold(&self, px: f64) -> TextStyle<'static> {
        ("sans-serif", px * self.scale, FontStyle::Bold)
            .into_font()
            .color(&TEXT)
    }
    pub fn title(&self) -> TextStyle<'static> {
        self.bold(self.pick(17.0, 14.0))
    }
    pub fn subtitle(&self) -> TextStyle<'static> {
        self.px(self.pick(13.0, 11.5)).color(&MUTED)
    }
    pub fn axis(&self) -> TextStyle<'static> {
        self.px(self.pick(14.0, 12.0))
    }
    pub fn tick(&self) -> TextStyle<'static> {
        self.px(self.pick(12.0, 10.5)).color(&MUTED)
    }
    pub fn legend(&self) -> TextStyle<'static> {
        self.px(self.pick(13.0, 11.5))
    }
    pub fn note(&self) -> TextStyle<'static> {
        self.px(self.pick(12.0, 10.5)).color(&MUTED)
    }
    /// Labels on the chart ("A", "B").
    pub fn tag(&self) -> TextStyle<'static> {
        self.bold(self.pick(14.0, 12.0))
    }
}

/// The one title helper of the panels titled by what they show ("Singular values of Γₛ₊₁"):
/// "what — the scenario's title" when the scenario has a title, only `what` on a small figure
/// (where the scenario's title would crowd out what the panel shows), and `default` when the
/// scenario has none.
pub fn title(fig: &FigureContext, fonts: &Fonts, what: &str, default: &str) -> String {
    match &fig.title {
        Some(t) if !fonts.compact => format!("{what} — {t}"),
        Some(_) => what.to_string(),
        None => default.to_string(),
    }
}

/// Text width and height in pixels as the backend measures it.
pub fn text_size<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
    style: &TextStyle,
) -> Result<(u32, u32)> {
    if text.is_empty() {
        return Ok((0, 0));
    }
    area.estimate_text_size(text, style).map_err(de)
}

/// Draw `text` with its `anchor` at absolute pixel `pos` of `area`'s backend.
pub fn text<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    s: &str,
    pos: (i32, i32),
    style: &TextStyle,
    anchor: (HPos, VPos),
) -> Result<()> {
    if s.is_empty() {
        return Ok(());
    }
    let (bx, by) = area.get_base_pixel();
    area.draw(&Text::new(
        s.to_string(),
        (pos.0 - bx, pos.1 - by),
        style.pos(Pos::new(anchor.0, anchor.1)),
    ))
    .map_err(de)
}

/// Greedy line breaking: first at " · " separators, then at spaces.
pub fn wrap<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    s: &str,
    style: &TextStyle,
    max_w: u32,
) -> Result<Vec<String>> {
    let mut lines = Vec::new();
    for para in s.split('\n') {
        let mut cur = String::new();
        for piece in para.split(" · ") {
            let cand = if cur.is_empty() {
                piece.to_string()
            } else {
                format!("{cur} · {piece}")
            };
            if text_size(area, &cand, style)?.0 <= max_w {
                cur = cand;
                continue;
            }
            if !cur.is_empty() {
                lines.push(std::mem::take(&mut cur));
            }
            // The piece alone: break at spaces if needed.
            for word in piece.split(' ') {
                let cand = if cur.is_empty() {
                    word.to_string()
                } else {
                    format!("{cur} {word}")
                };
                if cur.is_empty() || text_size(area, &cand, style)?.0 <= max_w {
                    cur = cand;
                } else {
                    lines.push(std::mem::replace(&mut cur, word.to_string()));
                }
            }
        }
        if !cur.is_empty() {
            lines.push(cur);
        }
    }
    Ok(lines)
}

/// Outer padding of a figure.
pub const PAD: i32 = 12;

/// Draw the title and the subtitle at the top of `root`, both wrapped and never cut; returns the
/// area below. The title is drawn in two lines at most ([`title_lines`]). The subtitle's notes (its " · "-separated facts, the
/// important ones first) are drawn whole in the lines the chart can spare (1 to 4 by the
/// figure's shape); the notes after the last that fits are left out whole (they are in the
/// report), so no line ends in "…" (issue 28: a cut line on a slide reads as a broken figure).
pub fn title_block<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    fonts: &Fonts,
    title: &str,
    subtitle: &str,
) -> Result<DrawingArea<DB, Shift>> {
    let (w, h) = root.dim_in_pixel();
    let (x0, y0) = root.get_base_pixel();
    let pad = if fonts.compact { PAD / 2 } else { PAD };
    let max_w = (w as i32 - 2 * pad).max(40) as u32;
    let mut y = y0 + pad;
    let ts = fonts.title();
    for line in title_lines(root, title, &ts, max_w)? {
        text(root, &line, (x0 + pad, y), &ts, (HPos::Left, VPos::Top))?;
        y += text_size(root, &line, &ts)?.1 as i32 + 2;
    }
    y += 2;
    let ss = fonts.subtitle();
    let line_h = text_size(root, "Ag", &ss)?.1 as i32 + 3;
    // Lines for the notes: what the chart can spare (a figure taller than wide, a phone's, has
    // height to spare; the stacked charts of a small one have none).
    let room = if h < 300 {
        1
    } else if h > w {
        4
    } else if h < 450 || fonts.compact {
        2
    } else {
        4
    };
    for line in notes_that_fit(root, subtitle, &ss, max_w, room)? {
        text(root, &line, (x0 + pad, y), &ss, (HPos::Left, VPos::Top))?;
        y += line_h;
    }
    let used = (y - y0 + 2).max(0);
    Ok(root.split_vertically(used).1)
}

/// The wrapped lines of the longest run of `notes`' first facts (split at " · " and at line
/// breaks) that wraps into at most `room` lines; a first fact that alone needs more is wrapped
/// and its lines beyond `room` are left out whole.
fn notes_that_fit<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    notes: &str,
    style: &TextStyle,
    max_w: u32,
    room: usize,
) -> Result<Vec<String>> {
    let all = wrap(area, notes, style, max_w)?;
    if all.len() <= room {
        return Ok(all);
    }
    // Facts with the separator that follows each (" · " or a line break), in order.
    let mut facts: Vec<(&str, &str)> = Vec::new();
    for (p, para) in notes.split('\n').enumerate() {
        if p > 0 {
            if let Some(last) = facts.last_mut() {
                last.1 = "\n";
            }
        }
        for piece in para.split(" · ").filter(|f| !f.trim().is_empty()) {
            facts.push((piece, " · "));
        }
    }
    let mut best: Vec<String> = Vec::new();
    let mut prefix = String::new();
    for (fact, sep) in &facts {
        prefix.push_str(fact);
        let lines = wrap(area, &prefix, style, max_w)?;
        if lines.len() > room {
            break;
        }
        best = lines;
        prefix.push_str(sep);
    }
    if best.is_empty() {
        best = all.into_iter().take(room).collect();
    }
    Ok(best)
}

/// Separators before a title's or label's trailing qualifiers, the last of which goes first
/// when it does not fit.
const QUALIFIERS: [&str; 6] = [" — ", " (", ", ", " · ", ": ", " at "];

/// `s` without its last trailing qualifier (None when it has none).
fn drop_qualifier(s: &str) -> Option<&str> {
    QUALIFIERS
        .iter()
        .filter_map(|sep| s.rfind(sep))
        .max()
        .filter(|&at| at > 0)
        .map(|at| s[..at].trim_end())
}

/// A title in at most two wrapped lines (a grid cell has room for no more): whole, else without
/// its trailing qualifiers ("…, Fig. 3", " (n = 4)") until it fits, else cut as a last resort.
fn title_lines<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    style: &TextStyle,
    max_w: u32,
) -> Result<Vec<String>> {
    let mut t = title.trim();
    loop {
        let lines = wrap(area, t, style, max_w)?;
        if lines.len() <= 2 {
            return Ok(lines);
        }
        match drop_qualifier(t) {
            Some(shorter) => t = shorter,
            None => {
                let first = lines[0].clone();
                let rest = t[t.find(first.as_str()).map_or(0, |i| i + first.len())..].trim_start();
                return Ok(vec![first, shorten(area, rest, style, max_w)?]);
            }
        }
    }
}

/// An axis label that fits `max_w`: `s` itself, else `s` without its trailing qualifiers (the
/// part from its last " — ", " (", ", ", " · ", ": " or " at " on, again while it is too long: "horizon s
/// (estimates from y(k−s) … y(k))" becomes "horizon s"), else [`shorten`]'s cut.
pub fn fit_label<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    s: &str,
    style: &TextStyle,
    max_w: u32,
) -> Result<String> {
    match without_qualifiers(area, s, style, max_w)? {
        Some(label) => Ok(label),
        None => shorten(area, s, style, max_w),
    }
}

/// `s`, or `s` without as few trailing qualifiers as make it fit `max_w`; None when even its
/// head does not fit.
pub fn without_qualifiers<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    s: &str,
    style: &TextStyle,
    max_w: u32,
) -> Result<Option<String>> {
    let mut label = s.trim();
    while text_size(area, label, style)?.0 > max_w {
        match drop_qualifier(label) {
            Some(shorter) => label = shorter,
            None => return Ok(None),
        }
    }
    Ok(Some(label.to_string()))
}

/// `s`, cut with "…" to fit `max_w`.
pub fn shorten<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    s: &str,
    style: &TextStyle,
    max_w: u32,
) -> Result<String> {
    if text_size(area, s, style)?.0 <= max_w {
        return Ok(s.to_string());
    }
    let chars: Vec<char> = s.chars().collect();
    let (mut lo, mut hi) = (0, chars.len());
    while lo < hi {
        let mid = (lo + hi).div_ceil(2);
        let cand: String = chars[..mid].iter().collect::<String>() + "…";
        if text_size(area, &cand, style)?.0 <= max_w {
            lo = mid;
        } else {
            hi = mid - 1;
        }
    }
    Ok(chars[..lo]
        .iter()
        .collect::<String>()
        .trim_end()
        .to_string()
        + "…")
}
