//! Measured data from CSV text: the one reader of the page (file upload, pasted text, its
//! column picker), the command line (`confset run --data FILE.csv [--columns NAME,…]`) and the
//! tests. It reads a record as a spreadsheet or a data frame writes it, and it **never drops
//! or shifts a row**: after the header, the k-th line of the file is the k-th row of the data,
//! whatever is in it.
//!
//! One row per time step: the outputs y₁ … y_q, then optionally the inputs u₁ … u_r (q and r
//! come from the method's model: [`Scenario::data_shape`]), and optionally the record's time.
//!
//! * **Header** (optional): a first line with no number or date in it that is not all gaps
//!   (a first line with some numbers is data, and its bad cell an error). Its names decide
//!   which column is which, in any order:
//!   - `y1`, `y_1`, `y₁`, `Y1`, `u2`, … (case-insensitive; a bare `y` or `u` when there is one
//!     output or one input): every y₁ … y_q must be named, the inputs all or none;
//!   - the **record's time**: the first column named `t`, `time`, `year`, `date` or `index`
//!     (case-insensitive), else an unnamed first column (a data frame's index: `""` or
//!     `Unnamed: 0`). Read into [`DataSpec::t`]: a number (a year, an index) or an ISO date
//!     (`1871`, `1959-03`, `1959-03-31`, `1959-03-31T00:00:00`), in every row, strictly
//!     increasing. An unnamed first column beside a named time column is not used;
//!   - with one output (q = 1), a header of one column besides the time (`year,volume`) is
//!     read as y₁ whatever its name;
//!   - any other name is an error that lists the header's columns. Then choose the columns by
//!     name ([`data_from_csv_columns`]; `--columns flow,rain` on the command line, the column
//!     picker on the page): the names given are y₁ … y_q, then optionally u₁ … u_r, in that
//!     order; the time is found among the other columns as above, and the rest are not used.
//! * **Without header**: q columns (no inputs) or q + r columns, in that order, and no time
//!   column (the reader never guesses one: name it in a header).
//! * **Delimiter**: tab, semicolon, comma or runs of spaces, the first of these (in that
//!   order) found in the first line (the header or the first row); a file of one column needs
//!   none. A decimal comma (`1,5`) is not read: write `1.5`.
//! * **Gaps**: in a y column, an empty cell, `NA`, `N/A`, `nan`, `null` (any case), `#N/A` and
//!   any spreadsheet error cell (`#VALUE!`, `#DIV/0!`, `#REF!`, `#NUM!`, `#NAME?`, `#NULL!`)
//!   is a missing measurement: NaN in [`DataSpec::y`], which each method takes or refuses
//!   ([`super::Gaps`]). An input or a time cannot be missing (an input is what was applied to
//!   the system, and a time places its row): such a cell is an error naming its row and column.
//! * **Rows**: after the header (without one: from the first row on) every line is a row, so
//!   no row is lost and none moves. A blank line is a row of gaps (in a one-column file, exactly
//!   an empty cell), as is a line of empty cells (`,,`, or tabs only in a tab-separated file);
//!   a row of gaps only is a row. Blank
//!   lines at the very end of the file are not rows (a note says so when there is more than the
//!   last line break), nor are blank lines before the header or first row, so a file without
//!   header cannot begin with an empty cell: write `NA` (or add a header).
//! * **Comments**: lines starting with `#`, only before the header or first row. After it a
//!   `#` line is a row (a one-column file's spreadsheet error cell, `#N/A`) or an error naming
//!   its line: skipping it would shift every row after it.
//! * Windows (CRLF) and old Mac (CR) line endings and a UTF-8 byte-order mark are accepted; a
//!   cell may be wrapped in double quotes (which do not protect a delimiter inside it).
//! * **Cells** are finite decimal numbers (`1`, `-2.5`, `1e-3`) in the scenario's number
//!   range; `inf` is refused (JSON has no such number, and the methods take finite data).
//! * **Limits**, checked before any cell is read: [`MAX_CSV_BYTES`] of text and
//!   [`MAX_CSV_ROWS`] rows (every line from the first row to the last non-blank one); each
//!   method's own step limits apply later, when it runs.
//!
//! Row numbers in errors are the file's line numbers (1-based, counting the header, blank and
//! comment lines), so an editor's "go to line" finds them. Every error names `data`, `data.y`,
//! `data.u`, `data.t`, or `columns` (a name given to choose a column). What the user should
//! know though nothing is wrong (columns not used, blank lines at the end) comes back as notes
//! ([`read_csv`]), which the command line prints.

use super::{iso_date_key, make_method, DataSpec, RecordTime, Scenario};
use crate::error::{Error, Result};

/// Most bytes of CSV text [`data_from_csv`] reads (20 MB).
pub const MAX_CSV_BYTES: usize = 20_000_000;
/// Most rows (time steps) [`data_from_csv`] reads; the methods take far fewer (the SCF at most
/// 100 000, the others at most a few thousand), and say so when they run.
pub const MAX_CSV_ROWS: usize = 200_000;

/// At most this many characters of a cell are echoed in an error.
const ECHO_CHARS: usize = 20;
/// At most this many of a header's names are listed in a message.
const LISTED_NAMES: usize = 12;
/// Most characters of a date in the time column (`1959-03-31T00:00:00.000+00:00` has 29).
const MAX_DATE_CHARS: usize = 40;

/// The size limits of one parse (the public constants, smaller in the tests).
#[derive(Debug, Clone, Copy)]
struct Limits {
    bytes: usize,
    rows: usize,
}

const LIMITS: Limits = Limits {
    bytes: MAX_CSV_BYTES,
    rows: MAX_CSV_ROWS,
};

/// A record read from CSV ([`read_csv`]): its data, and sentences the user should see though
/// nothing was wrong (the columns not used, a column read as y₁ by the one-column rule, blank
/// lines at the end or before the first row that are not rows).
#[derive(Debug, Clone, PartialEq)]
pub struct CsvRecord {
    pub data: DataSpec,
    pub notes: Vec<String>,
}

/// Parse CSV text into `data` for a model with `outputs` = q outputs and `inputs` = r inputs
/// (see the module docs for the format). Errors name `data`, `data.y`, `data.u` or `data.t`.
pub fn data_from_csv(text: &str, outputs: usize, inputs: usize) -> Result<DataSpec> {
    read_csv(text, outputs, inputs, &[]).map(|r| r.data)
}

/// [`data_from_csv`] with the columns chosen by the header's names: `columns` names the
/// header cells read as y₁ … y_q, then optionally u₁ … u_r, in that order (an exact name, or
/// one that matches a single column whatever its case). The record's time is found among the
/// other columns (module docs); the rest are not used. Empty `columns`: the header decides.
/// A name that is not the header's is a `columns` error listing the header's names.
pub fn data_from_csv_columns(
    text: &str,
    outputs: usize,
    inputs: usize,
    columns: &[String],
) -> Result<DataSpec> {
    read_csv(text, outputs, inputs, columns).map(|r| r.data)
}

/// [`data_from_csv_columns`] with the notes of the read ([`CsvRecord`]).
pub fn read_csv(
    text: &str,
    outputs: usize,
    inputs: usize,
    columns: &[String],
) -> Result<CsvRecord> {
    parse(text, outputs, inputs, columns, LIMITS)
}

/// The header's names (cells trimmed and unquoted; an unnamed one is `""`), for choosing the
/// columns by name (the page's column picker); empty when the file has no header. Only the
/// lines up to the header are read.
pub fn csv_columns(text: &str) -> Result<Vec<String>> {
    let text = check_size(text, LIMITS.bytes)?;
    let Some((_, first)) = first_line(text) else {
        return Ok(Vec::new());
    };
    let cells = Delimiter::detect(first).cells(first);
    Ok(if is_header(&cells) {
        cells.into_iter().map(str::to_string).collect()
    } else {
        Vec::new()
    })
}

/// Which of a header's columns ([`csv_columns`]) is the record's time when no column is chosen
/// by name: the first named `t`, `time`, `year`, `date` or `index` (any case), else an unnamed
/// first column (a data frame's index). The page's picker leaves it out of its defaults.
pub fn csv_time_column<S: AsRef<str>>(names: &[S]) -> Option<usize> {
    time_column(names, |_| false)
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
        self.with_record(text, &[]).map(|(s, _)| s)
    }

    /// [`Scenario::with_csv_data`] from a file named `name`, titled after it ("measured data:
    /// real.csv"): the figures' title is the scenario's, and a preset's title claims the
    /// paper's figure ("… (LSCR paper, Fig. 1)"), which the user's data are not. The page's
    /// data box and `confset run --data` both go through it.
    pub fn with_csv_file(&self, text: &str, name: &str) -> Result<Scenario> {
        self.read_csv_file(text, name, &[]).map(|(s, _)| s)
    }

    /// [`Scenario::with_csv_file`] with the columns chosen by name
    /// ([`data_from_csv_columns`]; empty `columns`: the header decides).
    pub fn with_csv_file_columns(
        &self,
        text: &str,
        name: &str,
        columns: &[String],
    ) -> Result<Scenario> {
        self.read_csv_file(text, name, columns).map(|(s, _)| s)
    }

    /// [`Scenario::with_csv_file_columns`] with the notes of the read ([`CsvRecord`]), which
    /// `confset run --data` prints.
    pub fn read_csv_file(
        &self,
        text: &str,
        name: &str,
        columns: &[String],
    ) -> Result<(Scenario, Vec<String>)> {
        let (mut s, notes) = self.with_record(text, columns)?;
        s.title = Some(crate::error::displayed(&format!("measured data: {name}")));
        Ok((s, notes))
    }

    fn with_record(&self, text: &str, columns: &[String]) -> Result<(Scenario, Vec<String>)> {
        let (q, r) = self.data_shape()?;
        let record = read_csv(text, q, r, columns)?;
        let mut s = self.clone();
        s.data = Some(record.data);
        s.simulate = None;
        Ok((s, record.notes))
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

/// Every line with its 1-based number: lines end at LF (a CR before it is dropped) or, in a
/// file without LF, at CR. The text after the last line break is a line too (empty when the
/// file ends with one).
fn lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    let sep = if text.contains('\n') { '\n' } else { '\r' };
    text.split(sep)
        .enumerate()
        .map(|(i, l)| (i + 1, l.strip_suffix('\r').unwrap_or(l)))
}

fn is_blank(line: &str) -> bool {
    line.trim().is_empty()
}

/// A blank line among the rows: white space only, but a line of tabs in a tab-separated file
/// is a row of empty cells (a data frame's all-missing row), as `,,` is in a comma-separated one.
fn is_blank_row(line: &str, delimiter: Delimiter) -> bool {
    is_blank(line) && !(delimiter == Delimiter::Char('\t') && line.contains('\t'))
}

/// A `#` line that is not a spreadsheet error cell: the line's first cell (up to a tab,
/// semicolon, comma or space) is not `#N/A`, `#VALUE!`, … ([`is_error_cell`]).
fn is_comment(line: &str) -> bool {
    let line = line.trim_start();
    let first = line
        .split(|c: char| matches!(c, '\t' | ';' | ',') || c.is_whitespace())
        .next()
        .unwrap_or("");
    line.starts_with('#') && !is_error_cell(first)
}

/// The header or first row, with its line number: the first line neither blank nor a comment.
fn first_line(text: &str) -> Option<(usize, &str)> {
    lines(text).find(|(_, l)| !is_blank(l) && !is_comment(l))
}

/// A spreadsheet's error value: `#N/A` (any case) or `#` capitals, digits, `/` or `_` then `!`
/// or `?` (`#VALUE!`, `#DIV/0!`, `#REF!`, `#NUM!`, `#NAME?`, `#NULL!`, `#SPILL!`, …). A
/// spreadsheet writes one where a formula had no value: a missing measurement.
fn is_error_cell(cell: &str) -> bool {
    if cell.eq_ignore_ascii_case("#N/A") {
        return true;
    }
    let Some(body) = cell
        .strip_prefix('#')
        .and_then(|c| c.strip_suffix(['!', '?']))
    else {
        return false;
    };
    !body.is_empty()
        && body
            .chars()
            .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '/' || c == '_')
}

/// A missing value as spreadsheets and data frames write it: an empty cell, `NA`, `N/A`,
/// `nan`, `null` (any case), or a spreadsheet error cell ([`is_error_cell`]).
fn is_gap(cell: &str) -> bool {
    cell.is_empty()
        || ["na", "n/a", "nan", "null"]
            .iter()
            .any(|g| cell.eq_ignore_ascii_case(g))
        || is_error_cell(cell)
}

/// A first line is a header when no cell is a number (or a decimal-comma number, or an ISO
/// date) and some cell is not a gap: `NA` alone is a first row with a gap, `year,volume` and
/// pandas' `,volume` are headers.
fn is_header(cells: &[&str]) -> bool {
    let numeric = |c: &&str| {
        c.parse::<f64>().is_ok() || decimal_comma(c).is_some() || iso_date_key(c).is_some()
    };
    !cells.iter().any(numeric) && cells.iter().any(|c| !is_gap(c))
}

/// A header name of the record's time: `t`, `time`, `year`, `date`, `index` (any case).
fn is_time_name(name: &str) -> bool {
    ["t", "time", "year", "date", "index"]
        .iter()
        .any(|n| name.eq_ignore_ascii_case(n))
}

/// A data frame's unnamed index column, as the first header cell: `""` (pandas' `to_csv`) or
/// `Unnamed: 0` (a file pandas read and wrote again).
fn is_index_name(name: &str) -> bool {
    name.is_empty() || name.to_lowercase().starts_with("unnamed:")
}

/// The time column among the columns not `taken` (module docs).
fn time_column<S: AsRef<str>>(names: &[S], taken: impl Fn(usize) -> bool) -> Option<usize> {
    names
        .iter()
        .enumerate()
        .position(|(k, n)| !taken(k) && is_time_name(n.as_ref()))
        .or_else(|| (names.len() > 1 && !taken(0) && is_index_name(names[0].as_ref())).then_some(0))
}

/// What a column holds.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Slot {
    /// y_i (0-based)
    Y(usize),
    /// u_i (0-based)
    U(usize),
    /// The record's time.
    Time,
    /// Not read (a column not chosen).
    Unused,
}

impl Slot {
    /// `y1`, `u2`: the name the reader gives it.
    fn name(self) -> String {
        match self {
            Slot::Y(i) => format!("y{}", i + 1),
            Slot::U(i) => format!("u{}", i + 1),
            Slot::Time => "the record's time".into(),
            Slot::Unused => "not used".into(),
        }
    }
}

/// How the columns are read, and what the user should know about it.
struct Plan<'a> {
    slots: Vec<Slot>,
    /// The header's names (empty without header), for [`Plan::label`].
    header: Vec<&'a str>,
    q: usize,
    r: usize,
    notes: Vec<String>,
}

impl<'a> Plan<'a> {
    fn positional(slots: Vec<Slot>, q: usize, r: usize) -> Plan<'a> {
        Plan {
            slots,
            header: Vec::new(),
            q,
            r,
            notes: Vec::new(),
        }
    }

    /// How a message names column k: `y1`, `y1 ('flow')`, `'year' (the record's time)`. Made
    /// for the one message that needs it (a header may have millions of columns).
    fn label(&self, k: usize) -> String {
        let slot = self.slots[k];
        let Some(&cell) = self.header.get(k) else {
            return slot.name();
        };
        match slot {
            Slot::Y(_) | Slot::U(_) => {
                let own = column_name(cell, self.q, self.r)
                    .is_some_and(|(kind, i)| slot.name() == format!("{kind}{i}"));
                if own {
                    slot.name()
                } else {
                    format!("{} ({})", slot.name(), column_words(&self.header, k))
                }
            }
            Slot::Time => format!("{} (the record's time)", column_words(&self.header, k)),
            Slot::Unused => column_words(&self.header, k),
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

/// A header column as a message names it: `'flow'`, or `column 1 (unnamed)`.
fn column_words(cells: &[&str], k: usize) -> String {
    if cells[k].is_empty() {
        format!("column {} (unnamed)", k + 1)
    } else {
        echo(cells[k])
    }
}

/// The header's names for a message: `'year', 'flow', 'rain'` (the first [`LISTED_NAMES`]).
fn header_list(cells: &[&str]) -> String {
    let mut parts: Vec<String> = cells
        .iter()
        .take(LISTED_NAMES)
        .map(|c| {
            if c.is_empty() {
                "(unnamed)".into()
            } else {
                echo(c)
            }
        })
        .collect();
    if cells.len() > LISTED_NAMES {
        parts.push(format!("… ({} in all)", cells.len()));
    }
    parts.join(", ")
}

/// How to choose columns by name, the end of every header error about names.
const CHOOSE: &str =
    "or choose the columns with --columns NAME,… (CLI) or the column picker (page)";

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

/// How the columns of a header are read (module docs): by the names in `chosen` when given,
/// else by the header's own names.
fn header_plan<'a>(
    cells: &[&'a str],
    line: usize,
    q: usize,
    r: usize,
    chosen: &[String],
) -> Result<Plan<'a>> {
    let n = cells.len();
    let mut slots = vec![Slot::Unused; n];
    let mut notes = Vec::new();
    if chosen.is_empty() {
        named_columns(cells, line, q, r, &mut slots, &mut notes)?;
    } else {
        chosen_columns(cells, line, q, r, chosen, &mut slots)?;
        if let Some(k) = time_column(cells, |k| slots[k] != Slot::Unused) {
            slots[k] = Slot::Time;
        }
        let count = slots.iter().filter(|&&s| s == Slot::Unused).count();
        let mut unused: Vec<String> = (0..n)
            .filter(|&k| slots[k] == Slot::Unused)
            .take(LISTED_NAMES)
            .map(|k| column_words(cells, k))
            .collect();
        if count > LISTED_NAMES {
            unused.push(format!("… ({count} in all)"));
        }
        if count > 0 {
            notes.push(format!(
                "{} not used (the columns chosen: {})",
                if count == 1 {
                    format!("column {} is", unused[0])
                } else {
                    format!("columns {} are", unused.join(", "))
                },
                chosen_words(cells, &slots)
            ));
        }
    }
    Ok(Plan {
        slots,
        header: cells.to_vec(),
        q,
        r,
        notes,
    })
}

/// `y1 = 'flow', u1 = 'rain', time = 'year'`: what the chosen columns are read as.
fn chosen_words(cells: &[&str], slots: &[Slot]) -> String {
    let mut read: Vec<(Slot, usize)> = slots
        .iter()
        .enumerate()
        .filter(|(_, s)| **s != Slot::Unused)
        .map(|(k, s)| (*s, k))
        .collect();
    let order = |s: Slot| match s {
        Slot::Y(i) => (0, i),
        Slot::U(i) => (1, i),
        _ => (2, 0),
    };
    read.sort_by_key(|&(s, _)| order(s));
    read.iter()
        .map(|&(s, k)| {
            let name = if s == Slot::Time {
                "time".to_string()
            } else {
                s.name()
            };
            format!("{name} = {}", column_words(cells, k))
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The columns by the header's own names: the time column, then `y1`, `u1`, … names, or the
/// one-column rule for q = 1.
fn named_columns(
    cells: &[&str],
    line: usize,
    q: usize,
    r: usize,
    slots: &mut [Slot],
    notes: &mut Vec<String>,
) -> Result<()> {
    let err = |m: String| Error::field("data", m);
    let n = cells.len();
    let time = time_column(cells, |_| false);
    if let Some(k) = time {
        slots[k] = Slot::Time;
    }
    // An unnamed first column beside a named time column: a data frame's row numbers.
    let index = time != Some(0) && n > 1 && is_index_name(cells[0]);
    if let (true, Some(k)) = (index, time) {
        notes.push(format!(
            "column 1 (unnamed: a data frame's row index) is not used: the record's time is column {} {}",
            k + 1,
            echo(cells[k])
        ));
    }
    let value: Vec<usize> = (0..n)
        .filter(|&k| slots[k] == Slot::Unused && !(index && k == 0))
        .collect();
    let named: Vec<Option<(char, usize)>> =
        value.iter().map(|&k| column_name(cells[k], q, r)).collect();
    let list = || {
        format!(
            "the header's columns are {}: name the outputs {}{} (a column named t, time, year, date or index is the record's time), {CHOOSE}",
            header_list(cells),
            names('y', q),
            if r > 0 {
                format!(", then optionally the inputs {}", names('u', r))
            } else {
                String::new()
            }
        )
    };
    if let Some(j) = named.iter().position(Option::is_none) {
        // The one-column rule: with one output, the one column besides the time is y1.
        if q == 1 && value.len() == 1 {
            slots[value[0]] = Slot::Y(0);
            notes.push(format!(
                "column {} is read as y1 (the one column{})",
                echo(cells[value[0]]),
                time.map_or(String::new(), |k| format!(
                    " besides the time, {}",
                    column_words(cells, k)
                ))
            ));
            return Ok(());
        }
        let k = value[j];
        return Err(err(format!(
            "header (row {line}), column {}: {} is not a column name: the model has {}; {}",
            k + 1,
            if cells[k].is_empty() {
                "an unnamed column".to_string()
            } else {
                echo(cells[k])
            },
            shape_words(q, r),
            list()
        )));
    }
    for (&k, name) in value.iter().zip(&named) {
        let at = format!("header (row {line}), column {}", k + 1);
        // Every name was read above (a column without one returned).
        let Some((kind, i)) = *name else { continue };
        let slot = match (kind, i) {
            ('y', i) if i <= q => Slot::Y(i - 1),
            ('u', i) if i <= r => Slot::U(i - 1),
            (kind, i) => {
                let (what, count) = if kind == 'y' {
                    ("outputs", q)
                } else {
                    ("inputs", r)
                };
                let has = if count == 0 {
                    format!("no {what}")
                } else {
                    format!("{count} {what} ({})", names(kind, count))
                };
                return Err(err(format!(
                    "{at}: {} names {kind}{i}, but the model has {has}",
                    echo(cells[k])
                )));
            }
        };
        if let Some(first) = slots.iter().position(|&s| s == slot) {
            return Err(err(format!(
                "header (row {line}): columns {} and {} both name {}",
                first + 1,
                k + 1,
                slot.name()
            )));
        }
        slots[k] = slot;
    }
    if let Some(i) = (0..q).find(|&i| !slots.contains(&Slot::Y(i))) {
        return Err(err(format!(
            "header (row {line}) has no column y{}: the model has {}, and every output is needed; {}",
            i + 1,
            shape_words(q, r),
            list()
        )));
    }
    let given = (0..r).filter(|&i| slots.contains(&Slot::U(i))).count();
    if given > 0 && given < r {
        let missing = (0..r).find(|&i| !slots.contains(&Slot::U(i))).unwrap_or(0);
        return Err(err(format!(
            "header (row {line}) has {given} of the r = {r_inputs} but no column u{}: give every input ({}) or none",
            missing + 1,
            names('u', r), r_inputs = crate::error::counted(r, "input", "inputs")
        )));
    }
    Ok(())
}

/// The columns chosen by name: `chosen[i]` is y_{i+1} for i < q, then u_{i-q+1}.
fn chosen_columns(
    cells: &[&str],
    line: usize,
    q: usize,
    r: usize,
    chosen: &[String],
    slots: &mut [Slot],
) -> Result<()> {
    let err = |m: String| Error::field("columns", m);
    let given = chosen
        .iter()
        .take(LISTED_NAMES)
        .map(|c| echo(c))
        .collect::<Vec<_>>()
        .join(", ");
    if chosen.len() != q && !(r > 0 && chosen.len() == q + r) {
        return Err(err(format!(
            "{} {} given ({given}), but the model has {}: name {q} {} for {}{}, in that order; the header's columns are {}",
            chosen.len(),
            if chosen.len() == 1 { "name is" } else { "names are" },
            shape_words(q, r),
            if q == 1 { "column" } else { "columns" },
            names('y', q),
            if r > 0 {
                format!(", then optionally {r} for {}", names('u', r))
            } else {
                String::new()
            },
            header_list(cells)
        )));
    }
    for (i, want) in chosen.iter().enumerate() {
        let want = clean(want);
        let k = cells.iter().position(|c| *c == want).or_else(|| {
            let lower = want.to_lowercase();
            let same: Vec<usize> = (0..cells.len())
                .filter(|&k| cells[k].to_lowercase() == lower)
                .collect();
            (same.len() == 1).then(|| same[0])
        });
        let slot = if i < q { Slot::Y(i) } else { Slot::U(i - q) };
        let Some(k) = k else {
            return Err(err(format!(
                "{} (for {}) is not a column of the header (row {line}): its columns are {}",
                echo(want),
                slot.name(),
                header_list(cells)
            )));
        };
        if slots[k] != Slot::Unused {
            return Err(err(format!(
                "{} is chosen for both {} and {}: choose each column once",
                echo(want),
                slots[k].name(),
                slot.name()
            )));
        }
        slots[k] = slot;
    }
    Ok(())
}

/// The columns of a file without header: y₁ … y_q, then u₁ … u_r when there are q + r.
fn positional_columns(count: usize, line: usize, q: usize, r: usize) -> Result<Vec<Slot>> {
    let ys = (0..q).map(Slot::Y);
    if count == q {
        return Ok(ys.collect());
    }
    if r > 0 && count == q + r {
        return Ok(ys.chain((0..r).map(Slot::U)).collect());
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
    // One column too many may be the record's time: it is read only when a header names it.
    let time = if count == q + 1 || (r > 0 && count == q + r + 1) {
        format!(
            " (a first column of times is read only under a header that names it: year,{})",
            names('y', q).replace(' ', "")
        )
    } else {
        String::new()
    };
    Err(Error::field(
        "data",
        format!(
            "row {line} has {count} {}, but the model has {}: {give}, or name the columns in a header line{time}",
            if count == 1 { "column" } else { "columns" },
            shape_words(q, r)
        ),
    ))
}

/// One measured cell as a finite number, or an error naming its row and column (`at`).
fn number(cell: &str, at: &str, field: &str) -> Result<f64> {
    let err = |m: String| Err(Error::field(field, format!("{at}: {m}")));
    match cell.parse::<f64>() {
        // The one range of scenario numbers (`magnitude_problem`): 1e308 or 5e-324 in a CSV
        // cell would break the same products and reciprocals as in `data.y`.
        Ok(v) if v.is_finite() => match super::magnitude_problem(v) {
            None => Ok(v),
            Some(why) => err(format!("{} {why}", echo(cell))),
        },
        Ok(v) if v.is_nan() || cell.to_lowercase().contains("inf") => err(format!(
            "{} is not a number (infinity and a signed NaN are refused: JSON has neither, and the methods take finite data; a missing measurement is an empty cell or NA)",
            echo(cell)
        )),
        Ok(_) => err(format!("{} is too large for double precision", echo(cell))),
        Err(_) => {
            let hint = decimal_comma(cell).map_or(String::new(), |dot| {
                format!(" (a decimal comma is not supported: write {dot})")
            });
            err(format!("{} is not a number{hint}", echo(cell)))
        }
    }
}

/// A gap where none can be: "the line is blank", "the cell is empty", "'NA' is a gap".
fn gap_words(cell: &str, blank: bool) -> String {
    if blank {
        "the line is blank, a gap".into()
    } else if cell.is_empty() {
        "the cell is empty, a gap".into()
    } else {
        format!("{} is a gap", echo(cell))
    }
}

/// One cell of the time column: a number or an ISO date (module docs).
fn record_time(cell: &str, at: &str, blank: bool) -> Result<RecordTime> {
    let err = |m: String| Err(Error::field("data.t", format!("{at}: {m}")));
    if is_gap(cell) {
        return err(format!(
            "{}: every row needs its time (it places the row in the record, measured or not); fill it in, or remove the time column",
            gap_words(cell, blank)
        ));
    }
    let what = "a time is a number (a year, an index) or an ISO date (1871, 1959-03, 1959-03-31, 1959-03-31T00:00:00)";
    match cell.parse::<f64>() {
        Ok(v) if v.is_finite() => match super::magnitude_problem(v) {
            None => Ok(RecordTime::Number(v)),
            Some(why) => err(format!("{} {why}", echo(cell))),
        },
        Ok(_) => err(format!("{} is not a time: {what}", echo(cell))),
        Err(_) if cell.chars().count() <= MAX_DATE_CHARS && iso_date_key(cell).is_some() => {
            Ok(RecordTime::Date(cell.to_string()))
        }
        Err(_) => err(format!("{} is not a time: {what}", echo(cell))),
    }
}

/// A number written with a decimal comma (`1,5`), as it should be written (`1.5`).
fn decimal_comma(cell: &str) -> Option<String> {
    let dot = cell.replace(',', ".");
    (cell.matches(',').count() == 1 && dot.parse::<f64>().is_ok()).then_some(dot)
}

/// The text without a byte-order mark, once its size is checked.
fn check_size(text: &str, bytes: usize) -> Result<&str> {
    if text.len() > bytes {
        return Err(Error::field(
            "data",
            format!(
                "is {} bytes of text, at most {} ({} MB)",
                text.len(),
                bytes,
                bytes as f64 / 1e6
            ),
        ));
    }
    Ok(text.strip_prefix('\u{feff}').unwrap_or(text))
}

/// "row 7" or "rows 7–9".
fn row_range(first: usize, last: usize) -> String {
    if first == last {
        format!("row {first}")
    } else {
        format!("rows {first}–{last}")
    }
}

fn parse(text: &str, q: usize, r: usize, chosen: &[String], limits: Limits) -> Result<CsvRecord> {
    let text = check_size(text, limits.bytes)?;
    if q == 0 {
        return Err(Error::field(
            "data",
            "cannot be read from CSV: the model has no outputs (model.H is absent or has no rows), and a CSV row needs at least one",
        ));
    }
    let Some((first_line, first)) = first_line(text) else {
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
    let header = is_header(&first_cells);
    // The first row's line; from it on every line is a row, up to the last non-blank line.
    // Counted before any cell is read (the size check), without holding the lines.
    let start = first_line + usize::from(header);
    let (mut last, mut total) = (start - 1, start - 1);
    for (n, l) in lines(text).skip(start - 1) {
        if !is_blank_row(l, delimiter) {
            last = n;
        }
        total = n;
    }
    let rows = last + 1 - start;
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
    let mut plan = if header {
        header_plan(&first_cells, first_line, q, r, chosen)?
    } else if !chosen.is_empty() {
        return Err(Error::field(
            "columns",
            format!(
                "columns are chosen by the names of a header line, and this file has none (row {first_line} is data): add a header line naming the columns"
            ),
        ));
    } else {
        positional_columns(first_cells.len(), first_line, q, r)
            .map(|slots| Plan::positional(slots, q, r))
            .map_err(|e| {
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
    // Blank lines at the end are not rows; more than the file's last line break is said.
    let line_break_at_end = usize::from(text.ends_with(['\n', '\r']));
    let trailing = (total - last).saturating_sub(line_break_at_end);
    if trailing > 0 {
        plan.notes.push(format!(
            "{} at the end of the file ({}) {} not read as rows of the record: a missing last measurement is written NA",
            if trailing == 1 { "a blank line".to_string() } else { format!("{trailing} blank lines") },
            row_range(last + 1, last + trailing),
            if trailing == 1 { "is" } else { "are" },
        ));
    }
    // Without header, blank lines before the first row are not rows either: said when there is
    // one right before it (a data frame writes a missing first value of one column so).
    if !header
        && first_line > 1
        && lines(text)
            .nth(first_line - 2)
            .is_some_and(|(_, l)| is_blank(l))
    {
        plan.notes.push(format!(
            "the blank line before the first row (row {}) is not read as a row of the record (a file without header starts at its first line of data): a missing first measurement is written NA",
            first_line - 1
        ));
    }
    let n = plan.slots.len();
    let with_u = plan.slots.iter().any(|s| matches!(s, Slot::U(_)));
    let with_t = plan.slots.contains(&Slot::Time);
    let mut y = Vec::with_capacity(rows);
    let mut u = Vec::with_capacity(if with_u { rows } else { 0 });
    let mut t = Vec::with_capacity(if with_t { rows } else { 0 });
    // The previous row's time: (its sort key, its line).
    let mut previous: Option<(f64, usize)> = None;
    let blank_row = vec![""; n];
    for (line, row_text) in lines(text).skip(start - 1).take(rows) {
        let blank = is_blank_row(row_text, delimiter);
        let split;
        let cells: &[&str] = if blank {
            &blank_row
        } else if is_comment(row_text) {
            return Err(Error::field(
                "data",
                format!(
                    "row {line} is a comment ({}): comments are allowed only before the {}, since after it every line is a row of the record, and skipping one would shift every row after it; move it to the top of the file or delete it",
                    echo(row_text.trim()),
                    if header { "header" } else { "first row" }
                ),
            ));
        } else {
            split = delimiter.cells(row_text);
            &split
        };
        if cells.len() != n {
            let reference = if header {
                format!("the header (row {first_line})")
            } else {
                format!("row {first_line}")
            };
            return Err(Error::field(
                "data",
                format!(
                    "row {line} has {} {}, {reference} has {n}",
                    cells.len(),
                    if cells.len() == 1 {
                        "column"
                    } else {
                        "columns"
                    },
                ),
            ));
        }
        let mut yr = vec![f64::NAN; q];
        let mut ur = vec![0.0; if with_u { r } else { 0 }];
        for (k, (&cell, &slot)) in cells.iter().zip(&plan.slots).enumerate() {
            let at = || format!("row {line}, column {}", plan.label(k));
            match slot {
                Slot::Y(i) if is_gap(cell) => yr[i] = f64::NAN,
                Slot::Y(i) => yr[i] = number(cell, &at(), "data.y")?,
                Slot::U(_) if is_gap(cell) => {
                    return Err(Error::field(
                        "data.u",
                        format!(
                            "{}: {}: an input has no gaps (it is what was applied to the system, known by definition, and the model uses it at every step); fill it in",
                            at(),
                            gap_words(cell, blank)
                        ),
                    ))
                }
                Slot::U(i) => ur[i] = number(cell, &at(), "data.u")?,
                Slot::Time => {
                    let time = record_time(cell, &at(), blank)?;
                    let key = match &time {
                        RecordTime::Number(x) => *x,
                        RecordTime::Date(d) => iso_date_key(d).unwrap_or(f64::NAN),
                    };
                    if let (Some((before, j)), Some(prev)) = (previous, t.last()) {
                        let prev: &RecordTime = prev;
                        if std::mem::discriminant(prev) != std::mem::discriminant(&time) {
                            return Err(Error::field(
                                "data.t",
                                format!(
                                    "{}: {} is {}, the time of row {j} ({}) {}: give every time as a number or every time as a date",
                                    at(),
                                    echo(cell),
                                    if matches!(time, RecordTime::Date(_)) { "a date" } else { "a number" },
                                    prev.label(),
                                    if matches!(prev, RecordTime::Date(_)) { "a date" } else { "a number" },
                                ),
                            ));
                        }
                        if key.partial_cmp(&before) != Some(std::cmp::Ordering::Greater) {
                            return Err(Error::field(
                                "data.t",
                                format!(
                                    "{}: {} is not after {} (row {j}): the times of a record increase strictly (one row per time step)",
                                    at(),
                                    echo(cell),
                                    prev.label()
                                ),
                            ));
                        }
                    }
                    previous = Some((key, line));
                    t.push(time);
                }
                Slot::Unused => {}
            }
        }
        y.push(yr);
        if with_u {
            u.push(ur);
        }
    }
    let data = DataSpec { y, u, t };
    // The record's own check (`data.t` in JSON): the reader's checks above named the rows.
    data.check_times()?;
    Ok(CsvRecord {
        data,
        notes: plan.notes,
    })
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

    fn chosen(text: &str, q: usize, r: usize, columns: &[&str]) -> Result<CsvRecord> {
        let columns: Vec<String> = columns.iter().map(|c| c.to_string()).collect();
        read_csv(text, q, r, &columns)
    }

    fn data(y: &[&[f64]], u: &[&[f64]]) -> DataSpec {
        DataSpec {
            y: y.iter().map(|r| r.to_vec()).collect(),
            u: u.iter().map(|r| r.to_vec()).collect(),
            t: Vec::new(),
        }
    }

    /// The y entries with NaN written as `None`, so gaps compare equal.
    fn cells(d: &DataSpec) -> Vec<Vec<Option<f64>>> {
        d.y.iter()
            .map(|r| r.iter().map(|x| (!x.is_nan()).then_some(*x)).collect())
            .collect()
    }

    fn years(from: i32, to: i32) -> Vec<RecordTime> {
        (from..=to).map(|y| RecordTime::Number(y.into())).collect()
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
            "\u{feff}# a comment\n\n# another\n1,-2.5,5\n3e-3,4,6\n\n\n",
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
        for cell in ["inf", "-inf", "Infinity", "-nan"] {
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
        let e = err("1,abcdefghijklmnopqrstuvwxyz\n", 2, 0);
        assert_eq!(
            e.message,
            "row 1, column y2: 'abcdefghijklmnopqrst…' is not a number"
        );
        // A column chosen by another name is named both ways.
        let e = chosen("year,flow\n1871,1\n1872,x\n", 1, 0, &["flow"]).unwrap_err();
        assert_eq!(e.message, "row 3, column y1 ('flow'): 'x' is not a number");
    }

    /// Every spelling of a missing value in a y column is a gap (NaN) in its own row; in an
    /// input column it is refused, naming the row and the column and saying why.
    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn missing_values_are_gaps_in_their_rows() {
        let spellings = [
            "", "NA", "na", "N/A", "n/a", "nan", "NaN", "NAN", "null", "NULL", "#N/A", "#n/a",
            "#VALUE!", "#DIV/0!", "#REF!", "#NUM!", "#NAME?", "#NULL!", "\"\"", "\"NA\"",
        ];
        for gap in spellings {
            // Two outputs: the gap in y2 of row 2 (line 3), y1 kept.
            let d = ok(&format!("y1,y2\n1,2\n3,{gap}\n5,6\n"), 2, 0);
            assert_eq!(
                cells(&d),
                vec![
                    vec![Some(1.0), Some(2.0)],
                    vec![Some(3.0), None],
                    vec![Some(5.0), Some(6.0)]
                ],
                "{gap:?}"
            );
            // One column without header: the gap keeps its row (the first row too, unless it
            // is blank: a file without header begins at its first non-blank line).
            if !gap.is_empty() {
                let d = ok(&format!("{gap}\n1\n{gap}\n2\n"), 1, 0);
                assert_eq!(
                    cells(&d),
                    vec![None, Some(1.0), None, Some(2.0)]
                        .into_iter()
                        .map(|c| vec![c])
                        .collect::<Vec<_>>(),
                    "{gap:?}"
                );
            }
            // In an input column: refused.
            let e = err(&format!("y1,u1\n1,2\n3,{gap}\n"), 1, 1);
            assert_eq!(e.field, "data.u", "{gap:?}");
            assert!(
                e.message.starts_with("row 3, column u1: ")
                    && e.message
                        .contains("an input has no gaps (it is what was applied to the system"),
                "{gap:?}: {e}"
            );
        }
        // A row of gaps only is a row.
        let d = ok("y1;y2\n1;2\n;\nNA;#N/A\n3;4\n", 2, 0);
        assert_eq!(d.y.len(), 4);
        assert_eq!(d.gap_rows(), vec![1, 2]);
        // A first line of gaps only is a row, not a header.
        assert_eq!(cells(&ok("NA,NA\n1,2\n", 2, 0))[0], vec![None, None]);
        assert_eq!(
            err("1,\n", 1, 1).message,
            "row 1, column u1: the cell is empty, a gap: an input has no gaps (it is what was applied to the system, known by definition, and the model uses it at every step); fill it in"
        );
    }

    /// After the header every line is a row: a blank line is a row of gaps (a one-column
    /// file's empty cell), blank lines at the very end are not rows, and a comment between rows
    /// is refused, naming its line.
    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn every_line_after_the_header_is_a_row() {
        // The bug this reader fixes: 100 rows, one blank, read as 99 and shifted.
        let mut text = String::from("volume\n");
        for k in 0..100 {
            if k == 40 {
                text.push('\n');
            } else {
                text += &format!("{k}\n");
            }
        }
        let d = ok(&text, 1, 0);
        assert_eq!(d.y.len(), 100);
        assert_eq!(d.gap_rows(), vec![40]);
        assert_eq!(
            d.y[41],
            vec![41.0],
            "the row after the gap stays in its place"
        );
        // A blank first row under a header is a row too; whitespace is blank.
        let d = ok("y\n\n1\n   \n2\n", 1, 0);
        assert_eq!(
            cells(&d),
            vec![vec![None], vec![Some(1.0)], vec![None], vec![Some(2.0)]]
        );
        // In a file of several columns a blank line is a row of empty cells.
        assert_eq!(ok("y1,y2\n1,2\n\n3,4\n", 2, 0).gap_rows(), vec![1]);
        assert_eq!(ok("1 2\n\n3 4\n", 2, 0).gap_rows(), vec![1]);
        // Trailing blank lines are not rows; more than the last line break is noted.
        for (text, notes) in [
            ("1\n2", 0),
            ("1\n2\n", 0),
            ("1\n2\r\n", 0),
            ("1\n2\n\n", 1),
            ("1\r2\r\r\r", 1),
            ("1\n2\n \n\t\n", 1),
        ] {
            let read = read_csv(text, 1, 0, &[]).unwrap_or_else(|e| panic!("{text:?}: {e}"));
            assert_eq!(read.data.y, vec![vec![1.0], vec![2.0]], "{text:?}");
            assert_eq!(read.notes.len(), notes, "{text:?}: {:?}", read.notes);
        }
        assert_eq!(
            read_csv("1\n2\n\n\n", 1, 0, &[]).map(|r| r.notes),
            Ok(vec!["2 blank lines at the end of the file (rows 3–4) are not read as rows of the record: a missing last measurement is written NA".to_string()])
        );
        // A comment after the data has started is refused, naming its line.
        let e = err("# fine here\ny1\n1\n# not here\n2\n", 1, 0);
        assert_eq!(e.field, "data");
        assert!(
            e.message.starts_with(
                "row 4 is a comment ('# not here'): comments are allowed only before the header"
            ),
            "{e}"
        );
        assert!(err("1\n2\n#comment\n", 1, 0)
            .message
            .starts_with("row 3 is a comment"));
        assert!(err("1,2\n# a, b\n", 2, 0)
            .message
            .starts_with("row 2 is a comment"));
        // ... unless it is a spreadsheet error cell: a gap.
        assert_eq!(
            cells(&ok("1\n#N/A\n#DIV/0!\n2\n", 1, 0)),
            vec![vec![Some(1.0)], vec![None], vec![None], vec![Some(2.0)]]
        );
        assert_eq!(
            cells(&ok("#VALUE!,1\n2,3\n", 2, 0))[0],
            vec![None, Some(1.0)]
        );
        // A blank line under inputs or times is refused (they cannot be missing).
        let e = err("y1,u1\n1,2\n\n3,4\n", 1, 1);
        assert!(
            e.message
                .starts_with("row 3, column u1: the line is blank, a gap"),
            "{e}"
        );
        let e = err("year,volume\n1871,2\n\n1873,4\n", 1, 0);
        assert_eq!(e.field, "data.t");
        assert!(e.message.starts_with("row 3, column 'year' (the record's time): the line is blank, a gap: every row needs its time"), "{e}");
    }

    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn a_time_column_is_the_records_time() {
        let want = |t: Vec<RecordTime>| DataSpec {
            y: vec![vec![1120.0], vec![f64::NAN], vec![963.0]],
            u: Vec::new(),
            t,
        };
        for (text, t) in [
            (
                "year,volume\n1871,1120\n1872,\n1873,963\n",
                years(1871, 1873),
            ),
            (",volume\n0,1120\n1,NA\n2,963\n", years(0, 2)),
            ("Unnamed: 0,volume\n0,1120\n1,NA\n2,963\n", years(0, 2)),
            (
                "Date;y\n1959-03;1120\n1959-04;nan\n1959-05;963\n",
                ["1959-03", "1959-04", "1959-05"]
                    .map(|d| RecordTime::Date(d.into()))
                    .to_vec(),
            ),
            (
                "volume,TIME\n1120,0.5\n#N/A,1\n963,1.5\n",
                [0.5, 1.0, 1.5].map(RecordTime::Number).to_vec(),
            ),
            ("index\ty1\n1\t1120\n2\t\n3\t963\n", years(1, 3)),
            (
                "t y\n1959-03-31T00:00:00 1120\n1959-06-30T00:00:00 NA\n1959-09-30T00:00:00 963\n",
                [
                    "1959-03-31T00:00:00",
                    "1959-06-30T00:00:00",
                    "1959-09-30T00:00:00",
                ]
                .map(|d| RecordTime::Date(d.into()))
                .to_vec(),
            ),
        ] {
            let d = ok(text, 1, 0);
            assert_eq!(format!("{d:?}"), format!("{:?}", want(t)), "{text:?}");
        }
        // A named time column beside a data frame's unnamed index: the index is not used.
        let read = read_csv(",year,volume\n0,1871,1\n1,1872,2\n", 1, 0, &[]).expect("read");
        assert_eq!(read.data.t, years(1871, 1872));
        assert!(
            read.notes[0].starts_with("column 1 (unnamed: a data frame's row index) is not used"),
            "{:?}",
            read.notes
        );
        // The time with named outputs and inputs, in any order.
        let d = ok("u1,year,y2,y1\n5,2001,2,1\n6,2002,4,3\n", 2, 1);
        assert_eq!(d.t, years(2001, 2002));
        assert_eq!(
            (d.y, d.u),
            (
                vec![vec![1.0, 2.0], vec![3.0, 4.0]],
                vec![vec![5.0], vec![6.0]]
            )
        );
        // Strictly increasing, checked with the rows named.
        let e = err("year,volume\n1871,1\n1872,2\n1872,3\n", 1, 0);
        assert_eq!(
            (e.field.as_str(), e.message.as_str()),
            ("data.t", "row 4, column 'year' (the record's time): '1872' is not after 1872 (row 3): the times of a record increase strictly (one row per time step)")
        );
        let e = err("date,volume\n1959-03,1\n1959-02,2\n", 1, 0);
        assert!(
            e.message.starts_with(
                "row 3, column 'date' (the record's time): '1959-02' is not after 1959-03 (row 2)"
            ),
            "{e}"
        );
        let e = err("year,volume\n1871,1\n1872-03,2\n", 1, 0);
        assert!(
            e.message
                .contains("is a date, the time of row 2 (1871) a number"),
            "{e}"
        );
        for bad in ["x", "inf", "1959-13", "1e308"] {
            let e = err(&format!("year,volume\n1871,1\n{bad},2\n"), 1, 0);
            assert_eq!(e.field, "data.t", "{bad}");
            assert!(
                e.message.starts_with(&format!(
                    "row 3, column 'year' (the record's time): '{bad}' "
                )),
                "{e}"
            );
        }
        let e = err("year,volume\nNA,1\n", 1, 0);
        assert!(
            e.message
                .starts_with("row 2, column 'year' (the record's time): 'NA' is a gap"),
            "{e}"
        );
        // Without a header there is no time column, even if the first column increases.
        let e = err("1871,1\n1872,2\n", 1, 0);
        assert_eq!(
            e.message,
            "row 1 has 2 columns, but the model has q = 1 output (y1) and no inputs: give 1 column (y1), or name the columns in a header line (a first column of times is read only under a header that names it: year,y1) (a comma separates columns: a decimal comma is not supported, write 1.5)"
        );
    }

    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn columns_are_chosen_by_name() {
        let text = "year,flow,rain,level\n2001,1,2,3\n2002,4,,6\n";
        let read = chosen(text, 1, 1, &["level", "flow"]).expect("read");
        assert_eq!(
            (&read.data.y, &read.data.u, &read.data.t),
            (
                &vec![vec![3.0], vec![6.0]],
                &vec![vec![1.0], vec![4.0]],
                &years(2001, 2002)
            )
        );
        // An input chosen by name cannot have a gap either.
        let e = chosen(text, 2, 1, &["level", "flow", "rain"]).unwrap_err();
        assert!(
            e.message
                .starts_with("row 3, column u1 ('rain'): the cell is empty, a gap"),
            "{e}"
        );
        let read = chosen(text, 2, 0, &["level", "Rain"]).expect("read");
        assert_eq!(
            cells(&read.data),
            vec![vec![Some(3.0), Some(2.0)], vec![Some(6.0), None]]
        );
        assert_eq!(read.notes, vec!["column 'flow' is not used (the columns chosen: y1 = 'level', y2 = 'rain', time = 'year')".to_string()]);
        // Without a choice, the header's names are not the model's: the error lists them.
        let e = err(text, 1, 0);
        assert_eq!(e.field, "data");
        assert_eq!(
            e.message,
            "header (row 1), column 2: 'flow' is not a column name: the model has q = 1 output (y1) and no inputs; the header's columns are 'year', 'flow', 'rain', 'level': name the outputs y1 (a column named t, time, year, date or index is the record's time), or choose the columns with --columns NAME,… (CLI) or the column picker (page)"
        );
        // One value column besides the time, q = 1: read whatever its name.
        let read = read_csv("year,flow\n2001,1\n", 1, 0, &[]).expect("read");
        assert_eq!(read.data.y, vec![vec![1.0]]);
        assert_eq!(
            read.notes,
            vec![
                "column 'flow' is read as y1 (the one column besides the time, 'year')".to_string()
            ]
        );
        assert_eq!(ok("volume\n1\n2\n", 1, 0).y, vec![vec![1.0], vec![2.0]]);
        // Chosen names: unknown, too few, twice, no header.
        let e = chosen(text, 1, 0, &["flux"]).unwrap_err();
        assert_eq!(
            (e.field.as_str(), e.message.as_str()),
            ("columns", "'flux' (for y1) is not a column of the header (row 1): its columns are 'year', 'flow', 'rain', 'level'")
        );
        let e = chosen(text, 2, 0, &["flow"]).unwrap_err();
        assert_eq!(e.message, "1 name is given ('flow'), but the model has q = 2 outputs (y1, y2) and no inputs: name 2 columns for y1, y2, in that order; the header's columns are 'year', 'flow', 'rain', 'level'");
        let e = chosen(text, 2, 0, &["flow", "FLOW"]).unwrap_err();
        assert_eq!(
            e.message,
            "'FLOW' is chosen for both y1 and y2: choose each column once"
        );
        let e = chosen("1,2\n", 1, 0, &["flow"]).unwrap_err();
        assert_eq!(e.field, "columns");
        // The time column chosen as an output: the time is looked for among the others.
        let d = chosen("year,t,v\n1,10,5\n2,20,6\n", 1, 0, &["year"])
            .expect("read")
            .data;
        assert_eq!(
            (d.y, d.t),
            (
                vec![vec![1.0], vec![2.0]],
                years(10, 20).into_iter().step_by(10).collect()
            )
        );
        // Many columns not used: the note lists a few.
        let wide: Vec<String> = (0..1000).map(|k| format!("c{k}")).collect();
        let text = format!("{}\n{}\n", wide.join(","), vec!["1"; 1000].join(","));
        let read = chosen(&text, 1, 0, &["c500"]).expect("read");
        assert_eq!(read.notes.len(), 1);
        assert!(
            read.notes[0].starts_with("columns 'c0', 'c1',")
                && read.notes[0].contains(
                    "'c11', … (999 in all) are not used (the columns chosen: y1 = 'c500')"
                ),
            "{:?}",
            read.notes
        );
        // The header's names for the page's picker, and its time column.
        assert_eq!(
            csv_columns("\u{feff}# c\n,\"volume\"\n1,2\n"),
            Ok(vec![String::new(), "volume".into()])
        );
        assert_eq!(csv_columns("1,2\n"), Ok(Vec::new()));
        assert_eq!(csv_columns(""), Ok(Vec::new()));
        assert_eq!(csv_time_column(&["flow", "Year", "rain"]), Some(1));
        assert_eq!(csv_time_column(&["", "volume"]), Some(0));
        assert_eq!(csv_time_column(&["flow", "rain"]), None);
    }

    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn shape_errors_say_what_the_model_takes() {
        let e = err("1,2,3,4,5\n", 2, 0);
        assert_eq!(e.field, "data");
        assert_eq!(
            e.message,
            "row 1 has 5 columns, but the model has q = 2 outputs (y1, y2) and no inputs: give 2 columns (y1, y2), or name the columns in a header line"
        );
        let e = err("1,5,3,5\n2,5,1,1\n", 2, 0);
        assert_eq!(
            e.message,
            "row 1 has 4 columns, but the model has q = 2 outputs (y1, y2) and no inputs: give 2 columns (y1, y2), or name the columns in a header line (a comma separates columns: a decimal comma is not supported, write 1.5)"
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
        let e = err("y1,flow,y2\n1,2,3\n", 2, 0);
        assert_eq!(e.field, "data");
        assert!(
            e.message.starts_with("header (row 1), column 2: 'flow' is not a column name: the model has q = 2 outputs (y1, y2) and no inputs; the header's columns are 'y1', 'flow', 'y2': name the outputs y1, y2"),
            "{e}"
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
        // A long header is listed in part.
        let wide: Vec<String> = (0..30).map(|k| format!("c{k}")).collect();
        let e = err(
            &format!("{}\n{}\n", wide.join(","), vec!["1"; 30].join(",")),
            2,
            0,
        );
        assert!(
            e.message.contains("'c11', … (30 in all): name the outputs"),
            "{e}"
        );
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
        for text in ["y1\n", "y1\n\n\n"] {
            assert_eq!(
                err(text, 1, 0).message,
                "has a header (row 1) but no rows of numbers"
            );
        }
        let limits = Limits {
            bytes: 100,
            rows: 3,
        };
        let rows = |text: &str| parse(text, 1, 0, &[], limits).map(|d| d.data.y.len());
        assert_eq!(rows("1\n2\n3\n"), Ok(3));
        assert_eq!(rows("y1\n1\n2\n3\n"), Ok(3));
        assert_eq!(rows("y1\n1\n\n3\n\n\n\n"), Ok(3));
        // Counted before any cell is read: the bad cell is never reached; blank lines between
        // rows count, as they are rows.
        for text in ["1\n2\n3\nabc\n", "1\n\n\n2\n", "y1\n\n\n\nx\n"] {
            let e = parse(text, 1, 0, &[], limits).unwrap_err();
            assert_eq!(
                (e.field.as_str(), e.message.as_str()),
                ("data", "has 4 rows, at most 3"),
                "{text:?}"
            );
        }
        let e = parse(&"1\n".repeat(51), 1, 0, &[], limits).unwrap_err();
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
