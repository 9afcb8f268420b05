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

/// Draw the title (one line, shortened if needed) and the wrapped subtitle at the top of
/// `root`; returns the area below. Subtitle lines beyond the room of the figure are dropped
/// (put the important facts first).
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
    // Up to two lines of title before anything is cut: the page's 2 × 2 grids give a panel
    // about 480 px at 1366 px, narrower than most titles.
    let lines = wrap(root, title, &ts, max_w)?;
    for (i, line) in lines.iter().take(2).enumerate() {
        let line = if i == 1 && lines.len() > 2 {
            shorten(root, rest_after(title, &lines[..1]), &ts, max_w)?
        } else {
            line.clone()
        };
        text(root, &line, (x0 + pad, y), &ts, (HPos::Left, VPos::Top))?;
        y += text_size(root, &line, &ts)?.1 as i32 + 2;
    }
    y += 2;
    // A figure taller than wide (a phone's) has height to spare for the notes.
    let max_lines = if h < 300 {
        1
    } else if h > w {
        4
    } else if h < 450 || fonts.compact {
        2
    } else {
        4
    };
    let ss = fonts.subtitle();
    let lines = wrap(root, subtitle, &ss, max_w)?;
    for (i, line) in lines.iter().take(max_lines).enumerate() {
        // The last line that fits says, with "…", that the notes go on (in the report).
        let line = if i + 1 == max_lines && lines.len() > max_lines {
            shorten(root, rest_after(subtitle, &lines[..i]), &ss, max_w)?
        } else {
            line.clone()
        };
        text(root, &line, (x0 + pad, y), &ss, (HPos::Left, VPos::Top))?;
        y += text_size(root, &line, &ss)?.1 as i32 + 3;
    }
    let used = (y - y0 + 2).max(0);
    Ok(root.split_vertically(used).1)
}

/// What of `s` follows its first wrapped `lines` (as [`wrap`] made them), with its separators
/// (" · ", spaces) kept, so a shortened last line reads as the text does.
fn rest_after<'a>(s: &'a str, lines: &[String]) -> &'a str {
    let mut rest = s;
    for line in lines {
        rest = rest.trim_start_matches([' ', '·', '\n']);
        rest = rest.strip_prefix(line.as_str()).unwrap_or(rest);
    }
    rest.trim_start_matches([' ', '·', '\n'])
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

#[cfg(test)]
mod tests {
    use super::rest_after;

    #[test]
    fn the_rest_of_a_wrapped_text_keeps_its_separators() {
        let s = "in ball: yes, in box: yes · n = 3: projection on x₂, x₃ · more";
        // Broken at words inside the first piece, then at a " · ".
        let lines = ["in ball: yes,".to_string(), "in box: yes".to_string()];
        assert_eq!(
            rest_after(s, &lines[..1]),
            "in box: yes · n = 3: projection on x₂, x₃ · more"
        );
        assert_eq!(rest_after(s, &lines), "n = 3: projection on x₂, x₃ · more");
        assert_eq!(rest_after(s, &[]), s);
    }
}
