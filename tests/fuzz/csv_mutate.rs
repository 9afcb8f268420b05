//! CSV data files and their mutations (cells at the extremes of f64 and past the JSON range,
//! words, ragged rows, headers that are wrong, delimiters mixed, BOM, CRLF, NUL and control
//! characters, too many rows), and garbage text for any input.

use crate::mutate::pick;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

/// Cells put in place of a number: what JSON `data.y` refuses or what f64 cannot hold, and
/// words.
const CELLS: [&str; 22] = [
    "1e308", "-1e308", "5e-324", "1e-101", "1e101", "1e999", "-1e999", "nan", "NaN", "inf", "-inf",
    "infinity", "", " ", "0x10", "1,5", "１", "1e", "--1", "+1", "0.5.5", "\"1\"",
];

/// A CSV file of `steps` rows of q outputs then r inputs (header now and then, a delimiter of
/// the accepted ones), mutated once or twice; and what was done.
pub fn mutated(q: usize, r: usize, steps: usize, rng: &mut ChaCha8Rng) -> (String, String) {
    let delimiter = pick(rng, &[",", ";", "\t", " "]).expect("delimiters");
    let mut rows: Vec<Vec<String>> = Vec::new();
    if rng.random::<bool>() {
        rows.push(
            (1..=q)
                .map(|i| format!("y{i}"))
                .chain((1..=r).map(|i| format!("u{i}")))
                .collect(),
        );
    }
    for _ in 0..steps.max(1) {
        rows.push(
            (0..q + r)
                .map(|_| format!("{}", rng.random_range(-3.0..3.0f64)))
                .collect(),
        );
    }
    let mut what = Vec::new();
    for _ in 0..[1, 1, 2][rng.random_range(0..3)] {
        what.push(mutate_rows(&mut rows, q + r, rng));
    }
    let mut text: String = rows
        .iter()
        .map(|row| row.join(delimiter))
        .collect::<Vec<_>>()
        .join("\n");
    match rng.random_range(0..12u32) {
        0 => {
            text = format!("\u{feff}{text}");
            what.push("with a BOM".into());
        }
        1 => {
            text = text.replace('\n', "\r\n");
            what.push("with CRLF".into());
        }
        2 => {
            text = format!("# a comment\n{text}\n# another\n");
            what.push("with comments".into());
        }
        _ => {}
    }
    (
        text,
        format!("{delimiter:?}-delimited, {}", what.join(", ")),
    )
}

/// One mutation of the rows; what it did.
fn mutate_rows(rows: &mut Vec<Vec<String>>, columns: usize, rng: &mut ChaCha8Rng) -> String {
    if rows.is_empty() {
        rows.push(vec!["0".into(); columns]);
    }
    let i = rng.random_range(0..rows.len());
    match rng.random_range(0..10u32) {
        0..=3 => {
            let j = rng.random_range(0..rows[i].len().max(1));
            let cell = pick(rng, &CELLS).expect("cells");
            if let Some(c) = rows[i].get_mut(j) {
                *c = cell.into();
            }
            format!("row {i} column {j} := {cell:?}")
        }
        4 => {
            rows[i].pop();
            format!("row {i} one cell short")
        }
        5 => {
            rows[i].push("0.5".into());
            format!("row {i} one cell long")
        }
        6 => {
            let c = pick(rng, &["\0", "\u{7}", "\u{1b}[31m", "\u{202e}", "<&>"]).expect("controls");
            rows[i].push(c.into());
            format!("row {i} with {c:?} appended")
        }
        7 => {
            // A header with a name unknown, repeated or of the wrong side.
            let h = pick(rng, &["y1", "u1", "y0", "y99", "x1", "Y₁", "y1 y1"]).expect("names");
            rows.insert(0, vec![h.to_string(); columns.max(1)]);
            format!("a header of {h:?} × {columns}")
        }
        8 => {
            let k = pick(rng, &[0usize, 1, 1000, 100_001]).expect("counts");
            let row = rows[i].clone();
            rows.truncate(k.min(rows.len()));
            while rows.len() < k {
                rows.push(row.clone());
            }
            format!("{k} rows")
        }
        _ => {
            let w = pick(rng, &[0usize, 1, 200]).expect("widths");
            rows[i] = vec!["1".into(); w];
            format!("row {i} of {w} cells")
        }
    }
}

/// Text that is not what it is read as: bytes at random, the base cut short or with a byte
/// flipped, deep nesting, numbers past f64, keys given twice, empty or blank text.
pub fn garbage(base: &str, rng: &mut ChaCha8Rng) -> (String, String) {
    match rng.random_range(0..9u32) {
        0 => {
            let n = rng.random_range(0..2000);
            let text = (0..n)
                .map(|_| char::from_u32(rng.random_range(0..0x3000)).unwrap_or('?'))
                .collect();
            (text, format!("{n} random characters"))
        }
        1 => {
            let mut cut = rng.random_range(0..=base.len());
            while !base.is_char_boundary(cut) {
                cut -= 1;
            }
            (
                base[..cut].to_string(),
                format!("the base cut at byte {cut}"),
            )
        }
        2 => {
            let mut bytes = base.as_bytes().to_vec();
            let i = rng.random_range(0..bytes.len().max(1));
            if let Some(b) = bytes.get_mut(i) {
                *b = b"{}[],:\"0e-.x\\"[rng.random_range(0..13)];
            }
            let text = String::from_utf8_lossy(&bytes).into_owned();
            (text, format!("the base with byte {i} replaced"))
        }
        3 => {
            let d = pick(rng, &[100usize, 129, 10_000, 1_000_000]).expect("depths");
            (
                format!("{}{}", "[".repeat(d), "]".repeat(d)),
                format!("{d} nested lists"),
            )
        }
        4 => {
            let n = pick(
                rng,
                &[
                    "1e999",
                    "-1e400",
                    "1e-400",
                    "123456789012345678901234567890",
                    "-0",
                    "NaN",
                ],
            )
            .expect("numbers");
            (
                format!("{{\"method\": \"scf\", \"alpha\": {n}}}"),
                format!("alpha {n}"),
            )
        }
        5 => {
            let text = base.replacen('{', "{\"method\": \"kf\", ", 1);
            (text, "the method key given twice".into())
        }
        6 => {
            let t = pick(
                rng,
                &[
                    "", " ", "\n", "null", "[]", "{}", "0", "\"scf\"", "\u{feff}",
                ],
            )
            .expect("texts");
            (t.to_string(), format!("the text {t:?}"))
        }
        7 => {
            let n = pick(rng, &[1000usize, 100_000, 3_000_000]).expect("lengths");
            let text = base.replacen(
                '{',
                &format!("{{\"title\": \"{}\", ", "ä\\u0000<".repeat(n / 8)),
                1,
            );
            (
                text,
                format!("a title of about {n} characters with NUL and <"),
            )
        }
        _ => (
            format!("{{\"a\":{}}}", "1,".repeat(10_000)),
            "a list of 10,000 commas".into(),
        ),
    }
}
