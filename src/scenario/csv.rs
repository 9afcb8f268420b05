//! Measured data from CSV text: the one parser of the page (file upload, pasted text), the
//! command line (`confset run --data FILE.csv`) and the tests.
//!
//! One row per time step: the outputs y₁ … y_q, then optionally the inputs u₁ … u_r (q and r
//! come from the method's model: [`Scenario::data_shape`]).
//!
//! * **Header** (optional): a first line with no number in it (a first line with some numbers
//!   is data, and its bad cell an error). Its names decide
//!   which column is which, in any order: `y1`, `y_1`, `y₁`, `Y1`, `u2`, … (case-insensitive;
//!   a bare `y` or `u` when there is one output or one input). Every y₁ … y_q must be named,
//!   the inputs all or none; an unknown name is an error naming the column.
//! * **Without header**: q columns (no inputs) or q + r columns.
//! * **Delimiter**: tab, semicolon, comma or runs of spaces, the first of these (in that
//!   order) that splits the first line into more than one cell; a file of one column needs
//!   none. A decimal comma (`1,5`) is not read: write `1.5`.
//! * Blank lines and lines starting with `#` are skipped; Windows (CRLF) and old Mac (CR) line
//!   endings and a UTF-8 byte-order mark are accepted; a cell may be wrapped in double quotes.
//! * **Cells** are finite decimal numbers (`1`, `-2.5`, `1e-3`); `nan` and `inf` are refused
//!   (JSON has no such numbers, and the methods take finite data only).
//! * **Limits**, checked before any cell is read: [`MAX_CSV_BYTES`] of text and
//!   [`MAX_CSV_ROWS`] rows; each method's own step limits apply later, when it runs.
//!
//! Row numbers in errors are the file's line numbers (1-based, counting the header, blank and
//! comment lines), so an editor's "go to line" finds them. Every error names `data`,
//! `data.y` or `data.u`.

use super::{make_method, DataSpec, Scenario};
use crate::error::{Error, Result};

/// Most bytes of CSV text [`data_from_csv`] reads (20 MB).
pub const MAX_CSV_BYTES: usize = 20_000_000;
/// Most rows (time steps) [`data_from_csv`] reads; the methods take far fewer (the SCF at most
/// 100 000, the others at most a few thousand), and say so when they run.
pub const MAX_CSV_ROWS: usize = 200_000;

/// At most this many characters of a cell are echoed in an error.
const ECHO_CHARS: usize = 20;

/// The size limits of one parse (the public constants, smaller in the tests).
#[derive(Debug, Clone, Copy)]
struct Limits {
    bytes: usize,
    rows: usize,
}

/// Parse CSV text into `data` for a model with `outputs` = q outputs and `inputs` = r inputs
/// (see the module docs for the format). Errors name `data`, `data.y` or `data.u`.
pub fn data_from_csv(text: &str, outputs: usize, inputs: usize) -> Result<DataSpec> {
    parse(
        text,
        outputs,
        inputs,
        Limits {
            bytes: MAX_CSV_BYTES,
            rows: MAX_CSV_ROWS,
        },
    )
}

impl Scenario {
    /// The shape of this scenario's `data` as its method reads it: (q, r), the entries of each
    /// `data.y` row (outputs) and of each `data.u` row (inputs; 0 when the method takes none).
    /// Errors name the model field the shape cannot be read from (`model.H`, …).
    pub fn data_shape(&self) -> Result<(usize, usize)> {
        make_method(self.method).data_shape(self)
    }

    /// This scenario with `data` read from CSV text ([`data_from_csv`] with the shape of
    /// [`Scenario::data_shape`]) and no `simulate` block; nothing else changes.
    pub fn with_csv_data(&self, text: &str) -> Result<Scenario> {
        let (q, r) = self.data_shape()?;
        let data = data_from_csv(text, q, r)?;
        let mut s = self.clone();
        s.data = Some(data);
        s.simulate = None;
        Ok(s)
    }

    /// [`Scenario::with_csv_data`] from a file named `name`, titled after it ("measured data:
    /// real.csv"): the figures' title is the scenario's, and a preset's title claims the
    /// paper's figure ("… (LSCR paper, Fig. 1)"), which the user's data are not. The page's
    /// data box and `confset run --data` both go through it.
    pub fn with_csv_file(&self, text: &str, name: &str) -> Result<Scenario> {
        let mut s = self.with_csv_data(text)?;
        s.title = Some(crate::error::displayed(&format!("measured data: {name}")));
        Ok(s)
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Delimiter {
    Char(char),
    Whitespace,
}

impl Delimiter {
    /// The first of tab, semicolon, comma that splits `line` into more than one cell, else runs
    /// of white space (which also reads a single column).
    fn detect(line: &str) -> Delimiter {
        ['\t', ';', ',']
            .into_iter()
            .find(|&c| line.contains(c))
            .map_or(Delimiter::Whitespace, Delimiter::Char)
    }

    /// The cells of a line, trimmed and unquoted.
    fn cells(self, line: &str) -> Vec<&str> {
        match self {
            Delimiter::Char(c) => line.split(c).map(clean).collect(),
            Delimiter::Whitespace => line.split_whitespace().map(clean).collect(),
        }
    }
}

/// A cell without surrounding white space and one pair of double quotes.
fn clean(cell: &str) -> &str {
    let cell = cell.trim();
    cell.strip_prefix('"')
        .and_then(|c| c.strip_suffix('"'))
        .map_or(cell, str::trim)
}

/// The lines that hold data or a header, with their 1-based line numbers: not blank, not a
/// `#` comment. Lines end at LF (a CR before it is dropped) or, in a file without LF, at CR.
fn content_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    let sep = if text.contains('\n') { '\n' } else { '\r' };
    text.split(sep)
        .enumerate()
        .map(|(i, l)| (i + 1, l.strip_suffix('\r').unwrap_or(l)))
        .filter(|(_, l)| {
            let l = l.trim();
            !l.is_empty() && !l.starts_with('#')
        })
}

/// Which field a column fills: y_i or u_i (0-based).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Column {
    Y(usize),
    U(usize),
}

impl Column {
    fn name(self) -> String {
        match self {
            Column::Y(i) => format!("y{}", i + 1),
            Column::U(i) => format!("u{}", i + 1),
        }
    }
    fn field(self) -> &'static str {
        match self {
            Column::Y(_) => "data.y",
            Column::U(_) => "data.u",
        }
    }
}

/// `y1, y2, y3` (or `y1 … y9` for more than four), for messages.
fn names(prefix: char, k: usize) -> String {
    match k {
        0 => String::new(),
        1..=4 => (1..=k)
            .map(|i| format!("{prefix}{i}"))
            .collect::<Vec<_>>()
            .join(", "),
        _ => format!("{prefix}1 … {prefix}{k}"),
    }
}

/// "q = 2 outputs (y1, y2) and r = 1 input (u1)", for messages.
fn shape_words(q: usize, r: usize) -> String {
    let plural = |k: usize, one: &str, many: &str| if k == 1 { one } else { many }.to_string();
    let ys = format!(
        "q = {q} {} ({})",
        plural(q, "output", "outputs"),
        names('y', q)
    );
    if r == 0 {
        format!("{ys} and no inputs")
    } else {
        format!(
            "{ys} and r = {r} {} ({})",
            plural(r, "input", "inputs"),
            names('u', r)
        )
    }
}

/// A cell as echoed in a message: at most [`ECHO_CHARS`] characters (shorter than the
/// scenario's echo: it is read next to its line and column), in single quotes.
fn echo(cell: &str) -> String {
    format!("'{}'", crate::error::cut(cell, ECHO_CHARS))
}

/// A header cell's column: `y1`, `Y_1`, `y₁`, `u2`, … (bare `y` / `u` when there is one).
fn column_name(cell: &str, q: usize, r: usize) -> Option<(char, usize)> {
    let lower = cell.to_lowercase();
    let mut chars = lower.chars();
    let kind = match chars.next()? {
        c @ ('y' | 'u') => c,
        _ => return None,
    };
    let rest = chars.as_str();
    if rest.is_empty() {
        let one = if kind == 'y' { q } else { r };
        return (one == 1).then_some((kind, 1));
    }
    let rest = rest.strip_prefix('_').unwrap_or(rest);
    if rest.is_empty() {
        return None;
    }
    let mut index: usize = 0;
    for c in rest.chars() {
        let digit = match c {
            '0'..='9' => c as usize - '0' as usize,
            '₀'..='₉' => c as usize - '₀' as usize,
            _ => return None,
        };
        index = index.checked_mul(10)?.checked_add(digit)?;
    }
    (index >= 1).then_some((kind, index))
}

/// The columns a header names, checked against the model's q and r.
fn header_columns(cells: &[&str], line: usize, q: usize, r: usize) -> Result<Vec<Column>> {
    let err = |m: String| Error::field("data", m);
    let mut columns = Vec::with_capacity(cells.len());
    for (k, cell) in cells.iter().enumerate() {
        let at = format!("header (row {line}), column {}", k + 1);
        let column = match column_name(cell, q, r) {
            None => {
                return Err(err(format!(
                    "{at}: {} is not a column name: the model has {}; name the columns {}{} (a first line that is not all numbers is read as a header)",
                    echo(cell),
                    shape_words(q, r),
                    names('y', q),
                    if r > 0 { format!(", then optionally {}", names('u', r)) } else { String::new() },
                )))
            }
            Some(('y', i)) if i <= q => Column::Y(i - 1),
            Some(('u', i)) if i <= r => Column::U(i - 1),
            Some((kind, i)) => {
                let (one, many, k) = if kind == 'y' {
                    ("output", "outputs", q)
                } else {
                    ("input", "inputs", r)
                };
                let has = if k == 0 {
                    format!("no {many}")
                } else {
                    format!("{} ({})", crate::error::counted(k, one, many), names(kind, k))
                };
                return Err(err(format!(
                    "{at}: {} names {kind}{i}, but the model has {has}",
                    echo(cell)
                )));
            }
        };
        if let Some(first) = columns.iter().position(|&c| c == column) {
            return Err(err(format!(
                "header (row {line}): columns {} and {} both name {}",
                first + 1,
                k + 1,
                column.name()
            )));
        }
        columns.push(column);
    }
    if let Some(i) = (0..q).find(|&i| !columns.contains(&Column::Y(i))) {
        return Err(err(format!(
            "header (row {line}) has no column y{}: the model has {}, and every output is needed",
            i + 1,
            shape_words(q, r)
        )));
    }
    let given = (0..r).filter(|&i| columns.contains(&Column::U(i))).count();
    if given > 0 && given < r {
        let missing = (0..r)
            .find(|&i| !columns.contains(&Column::U(i)))
            .unwrap_or(0);
        return Err(err(format!(
            "header (row {line}) has {given} of the r = {r_inputs} but no column u{}: give every input ({}) or none",
            missing + 1,
            names('u', r), r_inputs = crate::error::counted(r, "input", "inputs")
        )));
    }
    Ok(columns)
}

/// The columns of a file without header: y₁ … y_q, then u₁ … u_r when there are q + r.
fn positional_columns(count: usize, line: usize, q: usize, r: usize) -> Result<Vec<Column>> {
    let ys = (0..q).map(Column::Y);
    if count == q {
        return Ok(ys.collect());
    }
    if r > 0 && count == q + r {
        return Ok(ys.chain((0..r).map(Column::U)).collect());
    }
    let give = if r == 0 {
        format!(
            "give {q} {} ({})",
            if q == 1 { "column" } else { "columns" },
            names('y', q)
        )
    } else {
        format!(
            "give {q} {} ({}) or {} ({}, {})",
            if q == 1 { "column" } else { "columns" },
            names('y', q),
            q + r,
            names('y', q),
            names('u', r)
        )
    };
    Err(Error::field(
        "data",
        format!(
            "row {line} has {count} {}, but the model has {}: {give}, or name the columns in a header line",
            if count == 1 { "column" } else { "columns" },
            shape_words(q, r)
        ),
    ))
}

/// One cell as a finite number, or an error naming its row and column.
fn number(cell: &str, line: usize, column: Column) -> Result<f64> {
    let at = format!("row {line}, column {}", column.name());
    let err = |m: String| Err(Error::field(column.field(), format!("{at}: {m}")));
    if cell.is_empty() {
        return err("the cell is empty".into());
    }
    match cell.parse::<f64>() {
        // The one range of scenario numbers (`magnitude_problem`): 1e308 or 5e-324 in a CSV
        // cell would break the same products and reciprocals as in `data.y`.
        Ok(v) if v.is_finite() => match super::magnitude_problem(v) {
            None => Ok(v),
            Some(why) => err(format!("{} {why}", echo(cell))),
        },
        Ok(v) if v.is_nan() || cell.to_lowercase().contains("inf") => err(format!(
            "{} is not a number (NaN and infinity are refused: JSON has neither, and the methods take finite data)",
            echo(cell)
        )),
        Ok(_) => err(format!(
            "{} is too large for double precision",
            echo(cell)
        )),
        Err(_) => {
            let hint = decimal_comma(cell).map_or(String::new(), |dot| {
                format!(" (a decimal comma is not supported: write {dot})")
            });
            err(format!("{} is not a number{hint}", echo(cell)))
        }
    }
}

/// A number written with a decimal comma (`1,5`), as it should be written (`1.5`).
fn decimal_comma(cell: &str) -> Option<String> {
    let dot = cell.replace(',', ".");
    (cell.matches(',').count() == 1 && dot.parse::<f64>().is_ok()).then_some(dot)
}

fn parse(text: &str, q: usize, r: usize, limits: Limits) -> Result<DataSpec> {
    if text.len() > limits.bytes {
        return Err(Error::field(
            "data",
            format!(
                "is {} bytes of text, at most {} ({} MB)",
                text.len(),
                limits.bytes,
                limits.bytes as f64 / 1e6
            ),
        ));
    }
    if q == 0 {
        return Err(Error::field(
            "data",
            "cannot be read from CSV: the model has no outputs (model.H is absent or has no rows), and a CSV row needs at least one",
        ));
    }
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let Some((first_line, first)) = content_lines(text).next() else {
        return Err(Error::field(
            "data",
            format!(
                "is empty: no rows of numbers (give one row per time step: {}{})",
                names('y', q),
                if r > 0 {
                    format!(", then optionally {}", names('u', r))
                } else {
                    String::new()
                }
            ),
        ));
    };
    let delimiter = Delimiter::detect(first);
    let first_cells = delimiter.cells(first);
    // A header has no number in it; a first line with some numbers is data (with a bad cell,
    // which the cell check names).
    let header = !first_cells
        .iter()
        .any(|c| c.parse::<f64>().is_ok() || decimal_comma(c).is_some());
    // The size check before any cell is read.
    let rows = content_lines(text).count() - usize::from(header);
    if rows > limits.rows {
        return Err(Error::field(
            "data",
            format!(
                "has {rows_rows}, at most {}",
                limits.rows,
                rows_rows = crate::error::counted(rows, "row", "rows")
            ),
        ));
    }
    if rows == 0 {
        return Err(Error::field(
            "data",
            format!("has a header (row {first_line}) but no rows of numbers"),
        ));
    }
    let columns = if header {
        header_columns(&first_cells, first_line, q, r)?
    } else {
        positional_columns(first_cells.len(), first_line, q, r).map_err(|e| {
            let count = first_cells.len();
            let halves = count == 2 * q || (r > 0 && count == 2 * (q + r));
            if delimiter == Delimiter::Char(',') && halves {
                Error::field(
                    e.field,
                    format!("{} (a comma separates columns: a decimal comma is not supported, write 1.5)", e.message),
                )
            } else {
                e
            }
        })?
    };
    let with_u = columns.iter().any(|c| matches!(c, Column::U(_)));
    let mut y = Vec::with_capacity(rows);
    let mut u = Vec::with_capacity(if with_u { rows } else { 0 });
    for (line, text) in content_lines(text).skip(usize::from(header)) {
        let cells = delimiter.cells(text);
        if cells.len() != columns.len() {
            let reference = if header {
                format!("the header (row {first_line})")
            } else {
                format!("row {first_line}")
            };
            return Err(Error::field(
                "data",
                format!(
                    "row {line} has {} {}, {reference} has {}",
                    cells.len(),
                    if cells.len() == 1 {
                        "column"
                    } else {
                        "columns"
                    },
                    columns.len()
                ),
            ));
        }
        let mut yr = vec![0.0; q];
        let mut ur = vec![0.0; if with_u { r } else { 0 }];
        for (cell, &column) in cells.iter().zip(&columns) {
            let v = number(cell, line, column)?;
            match column {
                Column::Y(i) => yr[i] = v,
                Column::U(i) => ur[i] = v,
            }
        }
        y.push(yr);
        if with_u {
            u.push(ur);
        }
    }
    Ok(DataSpec { y, u, t: Vec::new() })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ok(text: &str, q: usize, r: usize) -> DataSpec {
        data_from_csv(text, q, r).unwrap_or_else(|e| panic!("{text:?}: {e}"))
    }

    fn err(text: &str, q: usize, r: usize) -> Error {
        match data_from_csv(text, q, r) {
            Ok(d) => panic!("{text:?} was accepted: {d:?}"),
            Err(e) => e,
        }
    }

    fn data(y: &[&[f64]], u: &[&[f64]]) -> DataSpec {
        DataSpec {
            y: y.iter().map(|r| r.to_vec()).collect(),
            u: u.iter().map(|r| r.to_vec()).collect(),
            t: Vec::new(),
        }
    }

    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn every_delimiter_reads_the_same_rows() {
        let want = data(&[&[1.0, -2.5], &[3e-3, 4.0]], &[&[5.0], &[6.0]]);
        for text in [
            "1,-2.5,5\n3e-3,4,6\n",
            "1;-2.5;5\n3e-3;4;6",
            "1\t-2.5\t5\n3e-3\t4\t6\n",
            "1  -2.5   5\n  3e-3 4 6  \n",
            "1, -2.5, 5\r\n3e-3, 4, 6\r\n",
            "1,-2.5,5\r3e-3,4,6\r",
            "\u{feff}# a comment\n\n1,-2.5,5\n   \n# another\n3e-3,4,6\n",
            "\"1\",\"-2.5\",\"5\"\n\"3e-3\",\"4\",\"6\"\n",
        ] {
            assert_eq!(ok(text, 2, 1), want, "{text:?}");
        }
        // Without the inputs: y alone.
        assert_eq!(ok("1 2\n3 4", 2, 1), data(&[&[1.0, 2.0], &[3.0, 4.0]], &[]));
        // One column needs no delimiter.
        assert_eq!(
            ok("1\n2\n-3.5\n", 1, 0),
            data(&[&[1.0], &[2.0], &[-3.5]], &[])
        );
        // Numbers have the range of JSON's (`magnitude_problem`): 1e100 is read, 1e308 is not.
        assert_eq!(ok("1e100\n", 1, 0), data(&[&[1e100]], &[]));
        assert_eq!(err("1e308\n", 1, 0).field, "data.y");
    }

    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn a_header_orders_the_columns() {
        let want = data(&[&[1.0, 2.0], &[4.0, 5.0]], &[&[3.0], &[6.0]]);
        for text in [
            "y1,y2,u1\n1,2,3\n4,5,6\n",
            "u1;y2;y1\n3;2;1\n6;5;4\n",
            "Y_2\tU_1\tY_1\n2\t3\t1\n5\t6\t4\n",
            "y₁ y₂ u₁\n1 2 3\n4 5 6\n",
            "\"y1\",\"y2\",\"u1\"\r\n1,2,3\r\n4,5,6\r\n",
        ] {
            assert_eq!(ok(text, 2, 1), want, "{text:?}");
        }
        assert_eq!(
            ok("y2,y1\n2,1\n5,4\n", 2, 1),
            data(&[&[1.0, 2.0], &[4.0, 5.0]], &[])
        );
        // Bare names with one output and one input.
        assert_eq!(ok("u,y\n3,1\n", 1, 1), data(&[&[1.0]], &[&[3.0]]));
        // Twelve outputs, named from y12 down to y1.
        let row = |f: &dyn Fn(i32) -> String| (1..=12).rev().map(f).collect::<Vec<_>>().join(",");
        let wide = format!(
            "{}\n{}\n",
            row(&|i| format!("y{i}")),
            row(&|i| i.to_string())
        );
        assert_eq!(
            ok(&wide, 12, 0).y,
            vec![(1..=12).map(f64::from).collect::<Vec<_>>()]
        );
    }

    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn errors_name_the_row_and_the_column() {
        let text = "# measured\ny1,y2\n1,2\n3,4\n\n5,6\nabc,7\n8,abc\n";
        let e = err(text, 2, 0);
        assert_eq!(e.field, "data.y");
        assert_eq!(e.message, "row 7, column y1: 'abc' is not a number");
        let e = err("1;2;3\n4;5;x\n", 2, 1);
        assert_eq!(
            (e.field.as_str(), e.message.as_str()),
            ("data.u", "row 2, column u1: 'x' is not a number")
        );
        let e = err("1,5;2,5\n", 2, 0);
        assert_eq!(
            e.message,
            "row 1, column y1: '1,5' is not a number (a decimal comma is not supported: write 1.5)"
        );
        for cell in ["nan", "NaN", "inf", "-inf", "Infinity"] {
            let e = err(&format!("1\n{cell}\n"), 1, 0);
            assert!(
                e.message
                    .starts_with(&format!("row 2, column y1: '{cell}' is not a number")),
                "{e}"
            );
        }
        let e = err("1e999\n", 1, 0);
        assert_eq!(
            e.message,
            "row 1, column y1: '1e999' is too large for double precision"
        );
        let e = err("1,\n", 2, 0);
        assert_eq!(e.message, "row 1, column y2: the cell is empty");
        let e = err("1,abcdefghijklmnopqrstuvwxyz\n", 2, 0);
        assert_eq!(
            e.message,
            "row 1, column y2: 'abcdefghijklmnopqrst…' is not a number"
        );
    }

    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn shape_errors_say_what_the_model_takes() {
        let e = err("1,2,3\n", 2, 0);
        assert_eq!(e.field, "data");
        assert_eq!(
            e.message,
            "row 1 has 3 columns, but the model has q = 2 outputs (y1, y2) and no inputs: give 2 columns (y1, y2), or name the columns in a header line"
        );
        let e = err("1,5\n2,5\n", 1, 0);
        assert_eq!(
            e.message,
            "row 1 has 2 columns, but the model has q = 1 output (y1) and no inputs: give 1 column (y1), or name the columns in a header line (a comma separates columns: a decimal comma is not supported, write 1.5)"
        );
        let e = err("1\t2\t3\n", 1, 3);
        assert_eq!(
            e.message,
            "row 1 has 3 columns, but the model has q = 1 output (y1) and r = 3 inputs (u1, u2, u3): give 1 column (y1) or 4 (y1, u1, u2, u3), or name the columns in a header line"
        );
        let e = err("1,2\n3,4\n\n5\n", 2, 0);
        assert_eq!(e.message, "row 4 has 1 column, row 1 has 2");
        let e = err("y1,y2\n3,4\n5,6,7\n", 2, 0);
        assert_eq!(e.message, "row 3 has 3 columns, the header (row 1) has 2");
    }

    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn header_errors_name_the_column() {
        let e = err("y1,time,y2\n1,2,3\n", 2, 0);
        assert_eq!(e.field, "data");
        assert_eq!(
            e.message,
            "header (row 1), column 2: 'time' is not a column name: the model has q = 2 outputs (y1, y2) and no inputs; name the columns y1, y2 (a first line that is not all numbers is read as a header)"
        );
        let e = err("y1,y3\n1,2\n", 2, 0);
        assert_eq!(
            e.message,
            "header (row 1), column 2: 'y3' names y3, but the model has 2 outputs (y1, y2)"
        );
        let e = err("y1,u1\n1,2\n", 1, 0);
        assert_eq!(
            e.message,
            "header (row 1), column 2: 'u1' names u1, but the model has no inputs"
        );
        let e = err("y1,Y_1\n1,2\n", 1, 0);
        assert_eq!(e.message, "header (row 1): columns 1 and 2 both name y1");
        let e = err("# c\ny2\n1\n", 2, 0);
        assert!(
            e.message.starts_with("header (row 2) has no column y1"),
            "{e}"
        );
        let e = err("y1,u2\n1,2\n", 1, 2);
        assert_eq!(
            e.message,
            "header (row 1) has 1 of the r = 2 inputs but no column u1: give every input (u1, u2) or none"
        );
        let e = err("y,y0\n1,2\n", 2, 0);
        assert!(e.message.contains("'y' is not a column name"), "{e}");
    }

    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn empty_text_and_limits() {
        for text in ["", "\n\n", "# only a comment\n", "\u{feff}", "  \r\n"] {
            let e = err(text, 2, 1);
            assert_eq!(e.field, "data");
            assert_eq!(
                e.message,
                "is empty: no rows of numbers (give one row per time step: y1, y2, then optionally u1)"
            );
        }
        assert_eq!(
            err("y1\n", 1, 0).message,
            "has a header (row 1) but no rows of numbers"
        );
        let limits = Limits {
            bytes: 100,
            rows: 3,
        };
        assert_eq!(parse("1\n2\n3\n", 1, 0, limits).map(|d| d.y.len()), Ok(3));
        assert_eq!(
            parse("y1\n1\n2\n3\n", 1, 0, limits).map(|d| d.y.len()),
            Ok(3)
        );
        // Counted before any cell is read: the bad cell is never reached.
        let e = parse("1\n2\n3\nabc\n", 1, 0, limits).unwrap_err();
        assert_eq!(
            (e.field.as_str(), e.message.as_str()),
            ("data", "has 4 rows, at most 3")
        );
        let e = parse(&"1\n".repeat(51), 1, 0, limits).unwrap_err();
        assert_eq!(e.message, "is 102 bytes of text, at most 100 (0.0001 MB)");
        // A first line with numbers is data, even with a bad cell.
        assert_eq!(
            err("1,abc\n", 2, 0).message,
            "row 1, column y2: 'abc' is not a number"
        );
        assert_eq!(
            err("1\n", 0, 0).message,
            "cannot be read from CSV: the model has no outputs (model.H is absent or has no rows), and a CSV row needs at least one"
        );
    }
}

/// A report as a table: one row per time step (or horizon) of the method's main estimates and
/// set sizes, what `confset run --format csv` writes. Each method's scenario file says which
/// columns ([`super::Report::table`]); a yes/no column holds 1 or 0, and a column the report cannot
/// fill at a row (no SCF region before t = n, no truth on measured data) is left empty.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    pub columns: Vec<String>,
    pub rows: Vec<Vec<Option<f64>>>,
    /// The record's own time of each row (`data.t` as shown), written as the second column
    /// `record_time` when the record has times ([`super::Report::table`] fills it).
    pub record_time: Vec<String>,
    /// The report's warnings, written as `# warning: …` lines above the header.
    pub warnings: Vec<String>,
}

impl Table {
    /// A table with these columns and no rows.
    pub fn new(columns: Vec<String>) -> Table {
        Table {
            columns,
            rows: Vec::new(),
            record_time: Vec::new(),
            warnings: Vec::new(),
        }
    }

    /// `prefix_1 … prefix_n`: the columns of a vector.
    pub fn numbered(prefix: &str, n: usize) -> Vec<String> {
        (1..=n).map(|i| format!("{prefix}_{i}")).collect()
    }

    /// Append a row; a row of another length than the header is a bug of the method's table.
    pub(crate) fn push(&mut self, row: Vec<Option<f64>>) {
        debug_assert_eq!(row.len(), self.columns.len(), "{:?}", self.columns);
        self.rows.push(row);
    }

    /// Every cell is a finite number or empty: else an error naming the first other cell,
    /// `csv.<column> at <first column>=<its value>` (`csv.volume_kf at t=3`), with the reason
    /// every output's finiteness check gives ([`super::check_finite`]).
    pub fn check_finite(&self) -> crate::error::Result<()> {
        for row in &self.rows {
            let Some(col) = row.iter().position(|v| v.is_some_and(|x| !x.is_finite())) else {
                continue;
            };
            let at = match (self.columns.first(), row.first().copied().flatten()) {
                (Some(name), Some(v)) if col > 0 => format!(" at {name}={}", csv_number(v)),
                _ => String::new(),
            };
            let name = self.columns.get(col).map_or("", String::as_str);
            return Err(super::not_finite(
                &format!("csv.{name}{at}"),
                " (the JSON report holds no such column: it may still be written)",
            ));
        }
        Ok(())
    }

    /// Comma-separated text with a header line; whole numbers as integers, others in Rust's
    /// shortest round-trip form (a value read back is the value written; exponent notation
    /// for very small and large ones), empty cells where a row has no value.
    pub fn to_csv(&self) -> String {
        let mut out = String::new();
        for w in &self.warnings {
            out.push_str("# warning: ");
            out.push_str(&w.replace(['\n', '\r'], " "));
            out.push('\n');
        }
        let with_time = !self.record_time.is_empty();
        let mut header = self.columns.clone();
        if with_time {
            header.insert(header.len().min(1), "record_time".into());
        }
        out.push_str(&header.join(","));
        out.push('\n');
        for (i, row) in self.rows.iter().enumerate() {
            let mut cells: Vec<String> = row
                .iter()
                .map(|v| v.map(csv_number).unwrap_or_default())
                .collect();
            if with_time {
                let label = self.record_time.get(i).cloned().unwrap_or_default();
                let label = if label.contains([',', '"']) {
                    format!("\"{}\"", label.replace('"', "\"\""))
                } else {
                    label
                };
                cells.insert(cells.len().min(1), label);
            }
            out.push_str(&cells.join(","));
            out.push('\n');
        }
        out
    }
}

/// One CSV number: `3`, `-0.25`, `3.396582675734097e-10`.
fn csv_number(x: f64) -> String {
    if x == x.trunc() && x.abs() < 1e15 {
        format!("{}", x as i64)
    } else {
        format!("{x:?}")
    }
}

/// The cells of a vector that may be missing (`n` empty cells then).
pub(crate) fn cells(v: Option<&[f64]>, n: usize) -> impl Iterator<Item = Option<f64>> + '_ {
    (0..n).map(move |i| v.and_then(|v| v.get(i).copied()))
}

/// A yes/no cell: 1 or 0.
pub(crate) fn flag(b: Option<bool>) -> Option<f64> {
    b.map(|b| if b { 1.0 } else { 0.0 })
}
