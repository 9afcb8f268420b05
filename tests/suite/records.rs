//! A researcher's record as a spreadsheet or a data frame writes it, read by the one CSV reader
//! (`scenario::csv`: the page's upload, `confset run --data`): every line after the header is
//! a row, so no row is ever dropped or shifted.
//!
//! * the Nile (tests/data/nile.csv, 100 annual flows 1871–1970) written as pandas and
//!   spreadsheets write it (an unnamed index column, `year,volume`, one column), with empty
//!   cells at rows 1, 50 and 100, a stretch of 20, and `NA`, `nan`, `#N/A` cells: exactly 100
//!   rows, the gaps (NaN) exactly there, every other value the file's, the times read;
//! * a `#` comment between rows is refused naming its line; a blank line in a one-column file
//!   is a gap row; blank lines at the end are not rows; a tab-separated all-empty row is kept;
//! * columns chosen by name (`data_from_csv_columns`, `--columns`) pick and order the columns;
//!   a gap in an input column, and a time that does not increase, are refused naming the row;
//! * a regression over many generated files: the rows kept are the lines counted by this
//!   test's own rule, the gaps where the generator put them;
//! * the gap reaches the methods' gate with the row and its time.

use confset::presets;
use confset::scenario::csv::{csv_columns, csv_time_column, read_csv};
use confset::scenario::{data_from_csv, data_from_csv_columns, DataSpec, RecordTime, Scenario};

const NILE: &str = include_str!("../data/nile.csv");
const NILE_GAPS: &str = include_str!("../data/nile-gaps.csv");

/// The Nile's (year, volume) pairs, read from tests/data/nile.csv by this test's own reading
/// (`#` lines and the header skipped, each line split at its comma), not the crate's reader.
fn nile() -> Vec<(i32, f64)> {
    NILE.lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| {
            let (year, volume) = l.split_once(',').expect("year,volume");
            (
                year.parse().expect("a year"),
                volume.parse().expect("a volume"),
            )
        })
        .collect()
}

fn years(from: i32, to: i32) -> Vec<RecordTime> {
    (from..=to).map(|y| RecordTime::Number(y.into())).collect()
}

fn read(text: &str, q: usize, r: usize) -> DataSpec {
    data_from_csv(text, q, r).unwrap_or_else(|e| panic!("{e}\n{}", head(text)))
}

/// The first lines of a text, for a failure message.
fn head(text: &str) -> String {
    text.lines().take(8).collect::<Vec<_>>().join("\n")
}

/// The rows (0-based) with a gap.
fn gap_rows(d: &DataSpec) -> Vec<usize> {
    (0..d.y.len())
        .filter(|&k| d.y[k].iter().any(|x| x.is_nan()))
        .collect()
}

/// The file's data rows by this test's own rule: the lines after the header line (the first
/// line that is neither blank nor a `#` comment) up to the last non-blank line.
fn data_lines(text: &str) -> usize {
    let lines: Vec<&str> = text.split('\n').map(|l| l.trim_end_matches('\r')).collect();
    let header = lines
        .iter()
        .position(|l| !l.trim().is_empty() && !l.starts_with('#'))
        .expect("a header");
    let last = lines
        .iter()
        .rposition(|l| !l.trim().is_empty())
        .expect("a line");
    last - header
}

/// The Nile (published mean 919.35, Cobb 1978 / Durbin & Koopman's example) read whole: 100
/// rows, the years as the record's time, the volume column as y1 by the one-column rule.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn the_nile_file_reads_whole() {
    let want = nile();
    assert_eq!(want.len(), 100);
    assert_eq!((want[0], want[99]), ((1871, 1120.0), (1970, 740.0)));
    let mean = want.iter().map(|p| p.1).sum::<f64>() / 100.0;
    assert!((mean - 919.35).abs() < 1e-9, "mean {mean}");
    let d = read(NILE, 1, 0);
    assert_eq!(d.y, want.iter().map(|p| vec![p.1]).collect::<Vec<_>>());
    assert_eq!(d.t, years(1871, 1970));
    assert!(d.u.is_empty());
    // The gaps file: observations 21–40 and 61–80 blank, the rest the same.
    let g = read(NILE_GAPS, 1, 0);
    assert_eq!(g.y.len(), 100);
    assert_eq!(g.t, years(1871, 1970));
    let blank: Vec<usize> = (20..40).chain(60..80).collect();
    assert_eq!(gap_rows(&g), blank);
    for (k, row) in g.y.iter().enumerate() {
        if !blank.contains(&k) {
            assert_eq!(row, &vec![want[k].1], "row {}", k + 1);
        }
    }
}
in_browser!(the_nile_file_reads_whole);

/// How a variant writes one row k (0-based) of the Nile: its value, or a gap spelled so.
#[derive(Clone, Copy, PartialEq)]
enum Cell {
    Value,
    Empty,
    Na,
    Nan,
    ErrorCell,
}

/// The Nile as data frames and spreadsheets write it, with gaps at rows 1, 50 and 100, a
/// stretch of 20 (rows 61–80), `NA` at rows 10 and 30, `nan` at 31, `#N/A` at 90: every variant
/// has exactly 100 rows, the gaps exactly there, every other value the file's, the times read.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn the_nile_as_a_data_frame_writes_it() {
    let nile = nile();
    let cell_of = |k: usize| match k {
        0 | 49 | 99 | 60..=79 => Cell::Empty,
        9 | 29 => Cell::Na,
        30 => Cell::Nan,
        89 => Cell::ErrorCell,
        _ => Cell::Value,
    };
    let want_gaps: Vec<usize> = (0..100).filter(|&k| cell_of(k) != Cell::Value).collect();
    assert_eq!(want_gaps.len(), 3 + 20 + 2 + 1 + 1);
    let spell = |k: usize, float: bool| match cell_of(k) {
        Cell::Value if float => format!("{:.1}", nile[k].1),
        Cell::Value => format!("{}", nile[k].1),
        Cell::Empty => String::new(),
        Cell::Na => "NA".into(),
        Cell::Nan => "nan".into(),
        Cell::ErrorCell => "#N/A".into(),
    };
    // (name, text, the times it must read)
    let mut variants: Vec<(&str, String, Vec<RecordTime>)> = Vec::new();
    // pandas `df[['volume']].to_csv()`: an unnamed index column 0 … 99, floats.
    let mut text = String::from(",volume\n");
    for k in 0..100 {
        text += &format!("{k},{}\n", spell(k, true));
    }
    variants.push(("pandas index", text, years(0, 99)));
    // pandas `df.set_index('year').to_csv()`: the year as the index, written as floats.
    let mut text = String::from("year,volume\n");
    for (k, (year, _)) in nile.iter().enumerate() {
        text += &format!("{year}.0,{}\n", spell(k, true));
    }
    variants.push(("year index", text.clone(), years(1871, 1970)));
    // The same with Windows line ends and a byte-order mark (a spreadsheet's "CSV UTF-8").
    variants.push((
        "CRLF and BOM",
        format!("\u{feff}{}", text.replace('\n', "\r\n")),
        years(1871, 1970),
    ));
    // pandas `df.to_csv()` of a frame read back (`Unnamed: 0`), with a comment above.
    let mut text = String::from("# the Nile, re-saved\nUnnamed: 0;year;volume\n");
    for (k, (year, _)) in nile.iter().enumerate() {
        text += &format!("{k};{year};{}\n", spell(k, false));
    }
    variants.push(("re-saved, semicolons", text, years(1871, 1970)));
    // Tab-separated, the time column last.
    let mut text = String::from("volume\tYear\n");
    for (k, (year, _)) in nile.iter().enumerate() {
        text += &format!("{}\t{year}\n", spell(k, false));
    }
    variants.push(("tabs, time last", text, years(1871, 1970)));
    // One column (`df['volume'].to_csv(index=False)`): an empty cell is a blank line, but
    // the last row's must be NA (blank lines at the end are not rows).
    let mut text = String::from("volume\n");
    for k in 0..100 {
        let cell = spell(k, false);
        text += &if k == 99 && cell.is_empty() {
            "NA".to_string()
        } else {
            cell
        };
        text.push('\n');
    }
    variants.push(("one column", text, Vec::new()));
    for (name, text, times) in variants {
        assert_eq!(data_lines(&text), 100, "{name}: the test's own line count");
        let d = data_from_csv(&text, 1, 0).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(d.y.len(), 100, "{name}: rows");
        assert_eq!(gap_rows(&d), want_gaps, "{name}: gaps");
        for k in 0..100 {
            if cell_of(k) == Cell::Value {
                assert_eq!(d.y[k], vec![nile[k].1], "{name}: row {}", k + 1);
            }
        }
        assert_eq!(d.t, times, "{name}: times");
    }
}
in_browser!(the_nile_as_a_data_frame_writes_it);

/// Every spreadsheet error cell is a gap in its row, alone in a one-column file or in a row.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn spreadsheet_error_cells_are_gaps() {
    let errors = [
        "#N/A", "#VALUE!", "#DIV/0!", "#REF!", "#NUM!", "#NAME?", "#NULL!",
    ];
    let mut one = String::from("flow\n");
    let mut two = String::from("y1,y2\n");
    for (k, e) in errors.iter().enumerate() {
        one += &format!("{k}\n{e}\n");
        two += &format!("{k},{e}\n{e},{k}\n");
    }
    let d = read(&one, 1, 0);
    assert_eq!(d.y.len(), 2 * errors.len());
    assert_eq!(
        gap_rows(&d),
        (0..errors.len()).map(|k| 2 * k + 1).collect::<Vec<_>>()
    );
    let d = read(&two, 2, 0);
    assert_eq!(d.y.len(), 2 * errors.len());
    for (k, row) in d.y.iter().enumerate() {
        let want = (k / 2) as f64;
        let (value, gap) = if k % 2 == 0 {
            (row[0], row[1])
        } else {
            (row[1], row[0])
        };
        assert_eq!(value, want, "row {}", k + 2);
        assert!(gap.is_nan(), "row {}", k + 2);
    }
}
in_browser!(spreadsheet_error_cells_are_gaps);

/// A `#` comment after the header is refused naming its line (skipping it would shift every
/// row after it); before the header it is a comment.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_comment_between_rows_is_refused_naming_its_line() {
    let lines: Vec<&str> = NILE.lines().collect();
    let header = lines
        .iter()
        .position(|l| l.starts_with("year"))
        .expect("header");
    for at in [header + 1, header + 50, lines.len()] {
        let mut l = lines.clone();
        l.insert(at, "# the gauge was moved here");
        let e = data_from_csv(&l.join("\n"), 1, 0).expect_err("a comment between rows");
        assert_eq!(e.field, "data");
        assert!(
            e.message.starts_with(&format!(
                "row {} is a comment ('# the gauge was move…'): comments are allowed only before the header",
                at + 1
            )),
            "{e}"
        );
    }
    // Above the header: a comment like the file's own.
    let mut l = lines.clone();
    l.insert(header, "# one more note");
    assert_eq!(read(&l.join("\n"), 1, 0).y.len(), 100);
}
in_browser!(a_comment_between_rows_is_refused_naming_its_line);

/// A blank line in a one-column file is a row with a gap, and the rows after it stay in
/// place (the bug: 100 rows read as 99, every later row one step early).
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_blank_line_in_a_one_column_file_is_a_gap_row() {
    let nile = nile();
    for with_header in [true, false] {
        let mut text = if with_header {
            "volume\n".to_string()
        } else {
            String::new()
        };
        for (k, (_, v)) in nile.iter().enumerate() {
            text += &if k == 49 {
                "   ".to_string()
            } else {
                v.to_string()
            };
            text.push('\n');
        }
        let d = read(&text, 1, 0);
        assert_eq!(d.y.len(), 100, "header {with_header}");
        assert_eq!(gap_rows(&d), vec![49]);
        for k in 50..100 {
            assert_eq!(d.y[k], vec![nile[k].1], "row {} stays in place", k + 1);
        }
    }
}
in_browser!(a_blank_line_in_a_one_column_file_is_a_gap_row);

/// Blank lines at the very end are not rows (a note says so beyond the last line break).
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn trailing_blank_lines_are_not_rows() {
    for (end, notes) in [("", 0), ("\n", 1), ("\n\n\n", 1), ("\r\n \r\n\t", 1)] {
        let text = format!("{NILE}{end}");
        let r = read_csv(&text, 1, 0, &[]).unwrap_or_else(|e| panic!("{end:?}: {e}"));
        assert_eq!(r.data.y.len(), 100, "{end:?}");
        // The one-column rule's note, and the trailing lines' when there are some.
        assert_eq!(r.notes.len(), 1 + notes, "{end:?}: {:?}", r.notes);
        if notes > 0 {
            assert!(
                r.notes[1].contains("at the end of the file (row")
                    && r.notes[1].contains("not read as rows"),
                "{:?}",
                r.notes
            );
        }
    }
}
in_browser!(trailing_blank_lines_are_not_rows);

/// A tab-separated file keeps an all-empty row (tabs only) and a blank line as rows of gaps.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_tab_separated_all_empty_row_is_kept() {
    let text = "y1\ty2\n1\t2\n\t\n3\t4\n\n5\t6\n";
    let d = read(text, 2, 0);
    assert_eq!(d.y.len(), 5);
    assert_eq!(gap_rows(&d), vec![1, 3]);
    assert!(d.y[1].iter().chain(&d.y[3]).all(|x| x.is_nan()));
    assert_eq!(
        (d.y[2].clone(), d.y[4].clone()),
        (vec![3.0, 4.0], vec![5.0, 6.0])
    );
    // Last, too: tabs only are cells, not a blank line at the end.
    let d = read("y1\ty2\ty3\n1\t2\t3\n\t\t\n", 3, 0);
    assert_eq!(d.y.len(), 2);
    assert!(d.y[1].iter().all(|x| x.is_nan()));
}
in_browser!(a_tab_separated_all_empty_row_is_kept);

/// A record with a time column and three value columns: y and u chosen by name, in the order
/// given; the other column not used (a note names it); the names offered to the page.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn columns_chosen_by_name_pick_and_order() {
    let text = "date,rain,flow,level\n1959-01,1,10,100\n1959-02,2,,200\n1959-03,3,30,300\n";
    let names = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<String>>();
    let d = data_from_csv_columns(text, 2, 0, &names(&["level", "flow"])).expect("two outputs");
    assert_eq!(d.y[0], vec![100.0, 10.0]);
    assert!(d.y[1][1].is_nan() && d.y[1][0] == 200.0);
    assert_eq!(
        d.t,
        ["1959-01", "1959-02", "1959-03"]
            .map(|s| RecordTime::Date(s.into()))
            .to_vec()
    );
    let r = read_csv(text, 1, 1, &names(&["level", "rain"])).expect("output and input");
    assert_eq!(r.data.y, vec![vec![100.0], vec![200.0], vec![300.0]]);
    assert_eq!(r.data.u, vec![vec![1.0], vec![2.0], vec![3.0]]);
    assert_eq!(
        r.notes,
        vec!["column 'flow' is not used (the columns chosen: y1 = 'level', u1 = 'rain', time = 'date')".to_string()]
    );
    // Without a choice the header's names are not the model's: refused, listing them.
    let e = data_from_csv(text, 1, 0).expect_err("three candidate columns");
    assert!(
        e.message
            .contains("the header's columns are 'date', 'rain', 'flow', 'level'")
            && e.message.ends_with(
                "or choose the columns with --columns NAME,… (CLI) or the column picker (page)"
            ),
        "{e}"
    );
    // What the page's picker offers, and the time column it leaves out.
    let columns = csv_columns(text).expect("header");
    assert_eq!(columns, names(&["date", "rain", "flow", "level"]));
    assert_eq!(csv_time_column(&columns), Some(0));
    // Through a preset's scenario, titled after the file.
    let (name, s) = preset_of_shape(|q, _| q == 1);
    let chosen = s
        .with_csv_file_columns(text, "river.csv", &names(&["level"]))
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    let data = chosen.data.as_ref().expect("data");
    assert_eq!(data.y, vec![vec![100.0], vec![200.0], vec![300.0]]);
    assert_eq!(chosen.title.as_deref(), Some("measured data: river.csv"));
    assert!(chosen.simulate.is_none());
}
in_browser!(columns_chosen_by_name_pick_and_order);

/// A preset whose data shape (q, r) passes `fits`, found in the registry.
fn preset_of_shape(fits: impl Fn(usize, usize) -> bool) -> (String, Scenario) {
    presets::all()
        .into_iter()
        .find(|p| p.scenario.data_shape().is_ok_and(|(q, r)| fits(q, r)))
        .map(|p| (p.name, p.scenario))
        .expect("a preset of that shape")
}

/// A gap in an input column is refused, naming the row and the column and saying why.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn an_input_gap_is_refused_naming_row_and_column() {
    let (name, s) = preset_of_shape(|q, r| q >= 1 && r >= 1);
    let (q, r) = s.data_shape().expect("shape");
    let header: Vec<String> = (1..=q)
        .map(|i| format!("y{i}"))
        .chain((1..=r).map(|i| format!("u{i}")))
        .collect();
    let row = vec!["1"; q + r].join(",");
    let mut bad = vec!["1"; q + r];
    bad[q + r - 1] = "NA";
    // Line 1 header, 2–4 rows, line 5 the gap in u_r.
    let text = format!(
        "{}\n{row}\n{row}\n{row}\n{}\n{row}\n",
        header.join(","),
        bad.join(",")
    );
    let e = s.with_csv_data(&text).expect_err("an input gap");
    assert_eq!(e.field, "data.u", "{name}: {e}");
    assert!(
        e.message.starts_with(&format!(
            "row 5, column u{r}: 'NA' is a gap: an input has no gaps (it is what was applied to the system"
        )),
        "{name}: {e}"
    );
}
in_browser!(an_input_gap_is_refused_naming_row_and_column);

/// A time that does not increase is refused naming its row and the row before.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_non_increasing_time_is_refused_naming_the_row() {
    let lines: Vec<&str> = NILE.lines().collect();
    let header = lines
        .iter()
        .position(|l| l.starts_with("year"))
        .expect("header");
    // Row 31 of the record (1901) written with the year before it.
    let mut l: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
    let at = header + 31;
    l[at] = l[at].replacen("1901", "1900", 1);
    let e = data_from_csv(&l.join("\n"), 1, 0).expect_err("a repeated year");
    assert_eq!(e.field, "data.t");
    assert_eq!(
        e.message,
        format!(
            "row {}, column 'year' (the record's time): '1900' is not after 1900 (row {}): the times of a record increase strictly (one row per time step)",
            at + 1,
            at
        )
    );
}
in_browser!(a_non_increasing_time_is_refused_naming_the_row);

/// The gap reaches the methods' one gate with its row and time: LSCR cannot take one.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn a_gap_reaches_the_methods_gate_with_its_time() {
    let s = presets::get("lscr-predict").expect("preset");
    let s = s.with_csv_file(NILE_GAPS, "nile-gaps.csv").expect("read");
    let e = s.run().expect_err("LSCR refuses a gap");
    assert_eq!(e.field, "data.y[20]");
    assert!(
        e.message
            .starts_with("is missing at row 21 (t = 21, time 1891) (40 rows with a gap in all)"),
        "{e}"
    );
}
in_browser!(a_gap_reaches_the_methods_gate_with_its_time);

/// A small deterministic generator (xorshift64*), so every run checks the same files.
struct Rng(u64);

impl Rng {
    fn below(&mut self, n: u64) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 33) % n
    }
}

/// Many generated files (one or two columns, with or without header, three delimiters, LF or
/// CRLF, comments and blank lines above, blank lines, `NA`, `nan`, `#N/A` and empty cells in
/// random rows, blank lines at the end, sometimes a comment between rows): the rows kept are
/// the lines this test counts by its own rule, the gaps exactly where it put them, the values
/// the ones it wrote; a comment between rows is refused naming its line.
#[cfg_attr(not(target_arch = "wasm32"), test)]
fn generated_files_keep_every_row() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let files = if cfg!(target_arch = "wasm32") {
        200
    } else {
        1000
    };
    let (mut refused, mut with_trailing) = (0, 0);
    for file in 0..files {
        let q = 1 + rng.below(2) as usize;
        let header = rng.below(2) == 0;
        let delimiter = [",", ";", "\t"][rng.below(3) as usize];
        let eol = if rng.below(4) == 0 { "\r\n" } else { "\n" };
        let mut lines: Vec<String> = Vec::new();
        for _ in 0..rng.below(4) {
            lines.push(if rng.below(2) == 0 {
                "# a note".into()
            } else {
                String::new()
            });
        }
        if header {
            lines.push(
                (1..=q)
                    .map(|i| format!("y{i}"))
                    .collect::<Vec<_>>()
                    .join(delimiter),
            );
        }
        // The rows as meant: per row, each y cell's value or None (a gap).
        let rows = 1 + rng.below(60) as usize;
        let mut meant: Vec<Vec<Option<f64>>> = Vec::new();
        // Which rows were written as blank lines (those at the end are not rows).
        let mut blank_lines: Vec<bool> = Vec::new();
        for k in 0..rows {
            // A file without header begins at its first non-blank line: its first row is not
            // blank, nor all empty cells (tabs only would be blank there); and some row is not
            // blank (else the blank lines are all at the end: no rows).
            let first_row = !header && k == 0;
            let only_blanks = k + 1 == rows && blank_lines.iter().all(|b| *b);
            let blank_line = rng.below(8) == 0 && !first_row && !only_blanks;
            blank_lines.push(blank_line);
            if blank_line {
                lines.push(if rng.below(2) == 0 {
                    String::new()
                } else {
                    "  ".into()
                });
                meant.push(vec![None; q]);
                continue;
            }
            let mut cells = Vec::new();
            let mut row = Vec::new();
            for j in 0..q {
                let value = k as f64 + 0.25 * j as f64;
                let spelling = match rng.below(10) {
                    0 if q > 1 && !first_row => Some(""),
                    1 => Some("NA"),
                    2 => Some("nan"),
                    3 => Some("#N/A"),
                    _ => None,
                };
                match spelling {
                    Some(s) => {
                        cells.push(s.to_string());
                        row.push(None);
                    }
                    None => {
                        cells.push(value.to_string());
                        row.push(Some(value));
                    }
                }
            }
            lines.push(cells.join(delimiter));
            meant.push(row);
        }
        // Sometimes a comment between rows: refused, naming its (1-based) line.
        let comment_at = (rng.below(8) == 0).then(|| {
            let first_row = lines.len() - rows;
            first_row + 1 + rng.below(rows as u64) as usize
        });
        if let Some(at) = comment_at {
            lines.insert(at.min(lines.len()), "# moved the gauge".into());
        }
        let trailing = rng.below(3) as usize;
        with_trailing += usize::from(trailing > 0);
        let mut text = lines.join(eol);
        text += eol;
        for _ in 0..trailing {
            text += eol;
        }
        let label = format!("file {file} (q = {q}, header {header}, {delimiter:?}):\n{text}");
        let got = data_from_csv(&text, q, 0);
        if let Some(at) = comment_at {
            let line = at + 1;
            let e = got.expect_err(&label);
            assert!(
                e.message.starts_with(&format!("row {line} is a comment")),
                "{label}\n{e}"
            );
            refused += 1;
            continue;
        }
        let d = got.unwrap_or_else(|e| panic!("{label}\n{e}"));
        // The test's own count: lines after the header (or from the first row) up to the
        // last non-blank line (tabs only are a row of empty cells in a tab-separated file).
        let text_lines: Vec<&str> = text.split('\n').map(|l| l.trim_end_matches('\r')).collect();
        let blank = |l: &str| l.trim().is_empty() && !(delimiter == "\t" && l.contains('\t'));
        let first = text_lines
            .iter()
            .position(|l| !l.trim().is_empty() && !l.starts_with("# "))
            .expect("a first line");
        let last = text_lines
            .iter()
            .rposition(|l| !blank(l))
            .expect("a last line");
        let counted = last + 1 - first - usize::from(header);
        assert_eq!(d.y.len(), counted, "{label}");
        // The generator's own view: the rows meant, but blank lines at the end.
        let at_end = blank_lines.iter().rev().take_while(|b| **b).count();
        assert_eq!(counted, meant.len() - at_end, "{label}");
        for (k, row) in d.y.iter().enumerate() {
            let got: Vec<Option<f64>> = row.iter().map(|x| (!x.is_nan()).then_some(*x)).collect();
            assert_eq!(got, meant[k], "{label}\nrow {}", k + 1);
        }
    }
    assert!(
        refused > 0 && with_trailing > 0,
        "the generator covers both: {refused}, {with_trailing}"
    );
}
in_browser!(generated_files_keep_every_row);

/// `confset run --data FILE --columns NAME` prints the core's report for the columns chosen,
/// says on standard error which column is not used, and refuses a name not in the header,
/// naming `--columns` and the file.
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn cli_columns_choose_by_name() {
    let nile = nile();
    let mut text = String::from("year,rain,flow\n");
    for (k, (year, v)) in nile.iter().enumerate() {
        text += &format!("{year},{},{v}\n", k % 7);
    }
    let dir = std::env::temp_dir().join(format!("confset-records-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("river.csv");
    std::fs::write(&path, &text).expect("write");
    let p = path.to_string_lossy().to_string();
    let out = crate::cli::confset(
        &[
            "run",
            "--preset",
            "scf-scalar",
            "--data",
            &p,
            "--columns",
            "flow",
        ],
        None,
    );
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains(&format!(
            "note: {p}: column 'rain' is not used (the columns chosen: y1 = 'flow', time = 'year')"
        )),
        "{stderr}"
    );
    let got: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let s = presets::get("scf-scalar").expect("preset");
    let want = s
        .with_csv_file_columns(&text, "river.csv", &["flow".to_string()])
        .and_then(|s| s.run())
        .expect("core");
    assert_eq!(got, serde_json::to_value(&want).expect("JSON"));
    assert_eq!(got["y"][0], serde_json::json!([1120.0]));
    let out = crate::cli::confset(
        &[
            "run",
            "--preset",
            "scf-scalar",
            "--data",
            &p,
            "--columns",
            "flux",
        ],
        None,
    );
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert_eq!(
        stderr.trim(),
        format!("error: --columns 'flux' (for y1) is not a column of the header (row 1): its columns are 'year', 'rain', 'flow' (in {p})")
    );
    let _ = std::fs::remove_dir_all(&dir);
}
