//! The one error type of the crate.
//!
//! Every function that takes user input returns `Result<_, Error>`. An error names the offending
//! field with its path in the scenario JSON (`model.V`, `alpha`, `simulate.steps`, …) and says
//! why, so the CLI and the page can show it as is: "model.V must be symmetric positive
//! semidefinite (smallest eigenvalue −0.5)".

use std::fmt;

/// A rejected input or a computation that cannot go on, with the field it concerns.
#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    /// Path of the offending field in the scenario (`model.F`, `alpha`, …), or `""` when the
    /// error is not about one field.
    pub field: String,
    /// What is wrong, in words a user can act on.
    pub message: String,
}

impl Error {
    /// An error about `field`.
    pub fn field(field: impl Into<String>, message: impl Into<String>) -> Self {
        Error {
            field: field.into(),
            message: message.into(),
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.field.is_empty() {
            write!(f, "{}", self.message)
        } else {
            write!(f, "{} {}", self.field, self.message)
        }
    }
}

impl std::error::Error for Error {}

/// Most characters of a user's string that a message repeats: a pasted file in a name box
/// must not become a page-long message.
pub const ECHO_CHARS: usize = 40;

/// A user's string as a message repeats it: at most `max` characters, cut with "…". Every
/// message that echoes user text (names, enum values, CSV cells) goes through here, mostly by
/// [`quoted`].
pub fn cut(s: &str, max: usize) -> String {
    if s.chars().count() > max {
        let head: String = s.chars().take(max).collect();
        format!("{head}…")
    } else {
        s.to_string()
    }
}

/// Most characters of a user's text (a title, an axis name) that a figure shows: a title
/// is one line above the plot, and laying out a pasted file there took minutes (issue 25).
pub const DISPLAY_CHARS: usize = 200;

/// A user's text as a figure shows it: control characters dropped (tabs and line breaks
/// become spaces), since XML 1.0 forbids most of them and an SVG holding one is not
/// well-formed; the noncharacters U+FFFE and U+FFFF likewise; then cut at [`DISPLAY_CHARS`]
/// with "…". Every user text is made so before any layout ([`crate::scenario::FigureContext`]),
/// so the cost of a figure never grows with the text given.
pub fn displayed(s: &str) -> String {
    let mut out = String::new();
    let mut kept = 0;
    for c in s.chars() {
        let c = match c {
            '\t' | '\n' | '\r' => ' ',
            '\u{FFFE}' | '\u{FFFF}' => continue,
            c if c.is_control() => continue,
            c => c,
        };
        if kept == DISPLAY_CHARS {
            out.push('…');
            break;
        }
        out.push(c);
        kept += 1;
    }
    out
}

/// A user's string in double quotes, cut at [`ECHO_CHARS`]: `"gls"`, `"aaaaaaaa…"`.
pub fn quoted(s: &str) -> String {
    format!("\"{}\"", cut(s, ECHO_CHARS))
}

/// Result with the crate's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;

/// A count with its noun in the right number, for messages: `counted(1, "state", "states")`
/// is "1 state", `counted(3, …)` "3 states" (never "1 outputs").
pub fn counted(k: usize, one: &str, many: &str) -> String {
    format!("{k} {}", if k == 1 { one } else { many })
}

/// A number a user gave, as a message repeats it: as written when that is short (`0.95`,
/// `1200`), else in scientific notation with four digits (`1.000e-100`, not a hundred zeros).
pub fn shown(x: f64) -> String {
    let plain = format!("{x}");
    if plain.len() <= 12 {
        plain
    } else {
        format!("{x:.3e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn displayed_text_is_xml_safe_and_cut() {
        assert_eq!(
            displayed("a\u{0}b\u{7}c\td\ne\u{1b}[0m\u{FFFF}"),
            "abc d e[0m"
        );
        let long = "x".repeat(1_000_000);
        let d = displayed(&long);
        assert_eq!(d.chars().count(), DISPLAY_CHARS + 1);
        assert!(d.ends_with('…'));
        // Exactly the limit is kept whole.
        assert_eq!(
            displayed(&"y".repeat(DISPLAY_CHARS)),
            "y".repeat(DISPLAY_CHARS)
        );
    }
}
