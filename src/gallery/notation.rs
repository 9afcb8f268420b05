//! The papers' plain-text notation as HTML scripts: the catalogue and the presets write
//! `X_40^SCF`, `U_tA_t`, `v^b_t`, `x_{t+1}`, `σ_v²`; the gallery shows X<sub>40</sub><sup>SCF</sup>.
//!
//! A symbol is one letter (with an optional combining mark: `X̂_l`) at the start of a word, or
//! right after another symbol's script (`U_tA_t`), followed by scripts: `_` then `{…}` or one to
//! three lower-case letters or digits, `^` then `{…}` or one to three letters. A script must end
//! the word or be followed by another symbol, a capital or a non-letter, so identifiers stay as
//! they are (`runs_path`, `q_prime`, `a_singular` keep their underscores).

/// Most letters of an unbraced script: longer runs are words (`a_singular`), not scripts.
const MAX_SCRIPT: usize = 3;

/// `text`, HTML-escaped, with its scripts as `<sub>`/`<sup>`.
pub fn notation(text: &str) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::new();
    let mut i = 0;
    // Whether the character before `i` lets a symbol start: a word's start, or a script's end.
    let mut may_start = true;
    while i < chars.len() {
        let c = chars[i];
        if may_start && c.is_alphabetic() {
            let mut j = i + 1;
            if j < chars.len() && ('\u{300}'..='\u{36f}').contains(&chars[j]) {
                j += 1;
            }
            let mut scripts = String::new();
            let mut k = j;
            while let Some((tag, body, next)) = script(&chars, k) {
                scripts.push_str(&format!("<{tag}>{}</{tag}>", escape(&body)));
                k = next;
            }
            let ends_word = chars
                .get(k)
                .is_none_or(|n| !(n.is_lowercase() || n.is_ascii_digit() || *n == '_'));
            if !scripts.is_empty() && ends_word {
                out.push_str(&escape(&chars[i..j].iter().collect::<String>()));
                out.push_str(&scripts);
                i = k;
                may_start = true;
                continue;
            }
        }
        out.push_str(&escape(&c.to_string()));
        may_start = !(c.is_alphanumeric() || c == '_' || ('\u{300}'..='\u{36f}').contains(&c));
        i += 1;
    }
    out
}

/// The script at `k` (`_x`, `_{…}`, `^b`, `^{…}`): its tag, its text and where it ends.
fn script(chars: &[char], k: usize) -> Option<(&'static str, String, usize)> {
    let tag = match chars.get(k)? {
        '_' => "sub",
        '^' => "sup",
        _ => return None,
    };
    if chars.get(k + 1) == Some(&'{') {
        let close = (k + 2..chars.len()).find(|&m| chars[m] == '}')?;
        if chars[k + 2..close].contains(&'{') {
            return None;
        }
        return Some((tag, chars[k + 2..close].iter().collect(), close + 1));
    }
    let fits = |c: char| {
        if tag == "sub" {
            c.is_lowercase() || c.is_ascii_digit()
        } else {
            c.is_alphabetic()
        }
    };
    let end = (k + 1..chars.len())
        .find(|&m| !fits(chars[m]))
        .unwrap_or(chars.len());
    let len = end - (k + 1);
    (1..=MAX_SCRIPT)
        .contains(&len)
        .then(|| (tag, chars[k + 1..end].iter().collect(), end))
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::notation;

    #[test]
    fn the_papers_notation_becomes_scripts_and_identifiers_stay() {
        for (text, html) in [
            (
                "inside X_40^SCF (count)",
                "inside X<sub>40</sub><sup>SCF</sup> (count)",
            ),
            (
                "ratio U_tA_t → 0.9",
                "ratio U<sub>t</sub>A<sub>t</sub> → 0.9",
            ),
            (
                "x_t = F^b x_{t+1} + v^b_t",
                "x<sub>t</sub> = F<sup>b</sup> x<sub>t+1</sub> + v<sup>b</sup><sub>t</sub>",
            ),
            (
                "every X̂_l, y_t and p_x",
                "every X̂<sub>l</sub>, y<sub>t</sub> and p<sub>x</sub>",
            ),
            ("σ_v² = 0.005", "σ<sub>v</sub>² = 0.005"),
            (
                "runs_path, q_prime, a_singular, theta_true",
                "runs_path, q_prime, a_singular, theta_true",
            ),
            ("a <b> & \"c\"", "a &lt;b&gt; &amp; &quot;c&quot;"),
            (
                "file compare-uniform_lp-t30.json",
                "file compare-uniform_lp-t30.json",
            ),
        ] {
            assert_eq!(notation(text), html, "{text}");
        }
    }
}
