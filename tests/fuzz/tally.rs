//! The classes of outcome, the counts table (kind × class) and the reproducer files.

use crate::cases::Case;
use serde_json::json;
use std::collections::BTreeMap;
use std::path::Path;

/// What a case gave. Every class but `Ok` and `Refused` is a failure with a reproducer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Class {
    Ok,
    /// A clean error naming a field (or a usage error of the binary).
    Refused,
    Panic,
    /// The process died of a signal (an allocation past the memory cap aborts).
    Abort,
    /// Still running after the per-case limit.
    Hang,
    /// A JSON null where a number belongs (report, study result, merged result).
    Null,
    /// inf or NaN in a CSV table.
    NonFinite,
    /// An error with no field path, no words, or words of Rust.
    BadMessage,
}

pub const CLASSES: [Class; 8] = [
    Class::Ok,
    Class::Refused,
    Class::Panic,
    Class::Abort,
    Class::Hang,
    Class::Null,
    Class::NonFinite,
    Class::BadMessage,
];

impl Class {
    pub fn name(self) -> &'static str {
        match self {
            Class::Ok => "ok",
            Class::Refused => "refused",
            Class::Panic => "panic",
            Class::Abort => "abort",
            Class::Hang => "hang",
            Class::Null => "null",
            Class::NonFinite => "non-finite",
            Class::BadMessage => "bad-message",
        }
    }

    pub fn from_name(name: &str) -> Option<Class> {
        CLASSES.into_iter().find(|c| c.name() == name)
    }

    pub fn is_failure(self) -> bool {
        !matches!(self, Class::Ok | Class::Refused)
    }
}

/// Counts per kind and class, and the failures' one-line descriptions.
#[derive(Default)]
pub struct Tally {
    counts: BTreeMap<String, [u64; CLASSES.len()]>,
    /// Wall milliseconds per kind (the worker's clock; a hang or crash counts the limit).
    millis: BTreeMap<String, f64>,
    pub failures: Vec<String>,
}

impl Tally {
    pub fn add(&mut self, kind: &str, class: Class, ms: f64) {
        *self.millis.entry(kind.to_string()).or_default() += ms;
        let row = self.counts.entry(kind.to_string()).or_default();
        row[CLASSES.iter().position(|&c| c == class).unwrap_or(0)] += 1;
    }

    pub fn cases(&self) -> u64 {
        self.counts.values().flatten().sum()
    }

    /// The table as Markdown: one row per kind, then the total.
    pub fn table(&self, kinds: &[String]) -> String {
        let mut out = String::from("| kind | cases |");
        for c in CLASSES {
            out.push_str(&format!(" {} |", c.name()));
        }
        out.push_str(" ms/case |\n|---|---:|");
        out.push_str(&"---:|".repeat(CLASSES.len() + 1));
        let mut total = [0u64; CLASSES.len()];
        let row = |name: &str, r: &[u64; CLASSES.len()], ms: f64| {
            let cases = r.iter().sum::<u64>();
            let mut line = format!("\n| {name} | {cases} |");
            for n in r {
                line.push_str(&format!(" {n} |"));
            }
            line.push_str(&format!(" {:.1} |", ms / cases.max(1) as f64));
            line
        };
        for k in kinds {
            let r = self.counts.get(k).copied().unwrap_or_default();
            for (t, n) in total.iter_mut().zip(r) {
                *t += n;
            }
            out.push_str(&row(k, &r, self.millis.get(k).copied().unwrap_or(0.0)));
        }
        out.push_str(&row("**all**", &total, self.millis.values().sum()));
        out.push('\n');
        out
    }
}

/// Write the reproducer of a failing case: `<out>/repro/<class>-<kind>-<index>.json` (the case
/// and what it gave), and a command-line case's input files beside it in a directory of the
/// same name. Returns the one-line description.
pub fn write_repro(out: &Path, case: &Case, class: Class, detail: &str) -> String {
    let dir = out.join("repro");
    let stem = format!("{}-{}", class.name(), case.id.replace(':', "-"));
    let _ = std::fs::create_dir_all(&dir);
    let v = json!({"class": class.name(), "detail": detail, "case": case});
    let _ = std::fs::write(dir.join(format!("{stem}.json")), v.to_string());
    if let crate::cases::Job::Cli { files, .. } = &case.job {
        let fdir = dir.join(&stem);
        let _ = std::fs::create_dir_all(&fdir);
        for f in files {
            let _ = std::fs::write(fdir.join(&f.name), crate::worker::file_bytes(f));
        }
    }
    let short: String = detail.chars().take(300).collect();
    format!("{} {}: {} — {short}", class.name(), case.id, case.what)
}
