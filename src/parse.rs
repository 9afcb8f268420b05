//! JSON in, or an error in plain words that names the JSON path of the offending value.
//!
//! serde says what went wrong in Rust terms ("invalid type: string \"abc\", expected usize",
//! "expected struct GllsSpec", "data did not match any variant of untagged enum MatrixSpec")
//! and serde_json adds only a line and column. [`from_json`] parses with
//! serde_path_to_error, then words the failure for a JSON user: the field is the path of the
//! value at fault (`glls.monte_carlo.runs`, `model.F[0][1]`, `uniform.prior_overrides[0].lo`),
//! the message says what belongs there and what was found ("must be a whole number ≥ 0, found
//! the text \"abc\""), unknown keys and names list the accepted ones, and user strings are cut
//! ([`crate::error::quoted`]). No message names a Rust type.
//!
//! The text is read once, into a `serde_json::Value` (refusing a key given twice, which a
//! `Value` would silently keep one of), and the `T` is read from that value: the path then
//! reaches the value itself (read straight from text, an enum given a number is a JSON syntax
//! error, "expected value"), and the value at the path is at hand to describe what was found.
//! Reading every type from a `&Value` only also keeps one copy of serde's code per type in
//! the wasm module, not one per reader (text, value): about a third of the module is serde's.

use crate::error::{quoted, Error, Result};
use serde::de::{self, DeserializeOwned, Deserializer, MapAccess, SeqAccess, Visitor};
use serde::Deserialize;
use serde_json::Value;
use serde_path_to_error::Segment;

/// Parse `text` as a `T`; errors name the path below `root` (`""` for a scenario, `"view"`,
/// …). An error about the whole document names `root`, or `"scenario"` when `root` is empty.
pub fn from_json<T: DeserializeOwned>(text: &str, root: &str) -> Result<T> {
    from_value(&read_json(text, root)?, root)
}

/// The JSON document in `text` as a value; errors as [`from_json`]'s: a syntax error names
/// the path as far as the text got, a key given twice in one object names that key.
pub fn read_json(text: &str, root: &str) -> Result<Value> {
    let mut de = serde_json::Deserializer::from_str(text);
    match serde_path_to_error::deserialize::<_, KeysOnce>(&mut de) {
        Ok(KeysOnce(v)) => match de.end() {
            Ok(()) => Ok(v),
            Err(e) => Err(syntax_error(root, &[], &e)),
        },
        Err(e) => {
            let segments: Vec<Segment> = e.path().iter().cloned().collect();
            let e = e.into_inner();
            let message = strip_position(&e.to_string());
            match message.strip_prefix("duplicate field ") {
                // Only KeysOnce raises a data error; the rest is the text's syntax.
                Some(rest) if e.is_data() => Err(given_twice(root, &segments, &name_in(rest))),
                _ => Err(syntax_error(root, &segments, &e)),
            }
        }
    }
}

/// A `T` from a document [`read_json`] read; errors as [`from_json`]'s.
pub fn from_value<T: DeserializeOwned>(value: &Value, root: &str) -> Result<T> {
    serde_path_to_error::deserialize::<_, T>(value).map_err(|e| {
        let segments: Vec<Segment> = e.path().iter().cloned().collect();
        schema_error::<T>(root, value, &segments, &e.into_inner().to_string())
    })
}

/// Any JSON value, read from text like serde_json's `Value` except that a key given twice in
/// one object is an error, as it is for serde's derived structs.
struct KeysOnce(Value);

impl<'de> Deserialize<'de> for KeysOnce {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        d.deserialize_any(KeysOnceVisitor).map(KeysOnce)
    }
}

struct KeysOnceVisitor;

impl<'de> Visitor<'de> for KeysOnceVisitor {
    type Value = Value;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("any JSON value")
    }
    fn visit_bool<E>(self, b: bool) -> std::result::Result<Value, E> {
        Ok(Value::Bool(b))
    }
    fn visit_i64<E>(self, i: i64) -> std::result::Result<Value, E> {
        Ok(Value::from(i))
    }
    fn visit_u64<E>(self, u: u64) -> std::result::Result<Value, E> {
        Ok(Value::from(u))
    }
    fn visit_f64<E>(self, x: f64) -> std::result::Result<Value, E> {
        // JSON text has no NaN or infinity, so this is always a number.
        Ok(serde_json::Number::from_f64(x).map_or(Value::Null, Value::Number))
    }
    fn visit_str<E>(self, s: &str) -> std::result::Result<Value, E> {
        Ok(Value::String(s.to_string()))
    }
    fn visit_string<E>(self, s: String) -> std::result::Result<Value, E> {
        Ok(Value::String(s))
    }
    fn visit_unit<E>(self) -> std::result::Result<Value, E> {
        Ok(Value::Null)
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> std::result::Result<Value, A::Error> {
        let mut items = Vec::new();
        while let Some(KeysOnce(v)) = seq.next_element()? {
            items.push(v);
        }
        Ok(Value::Array(items))
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> std::result::Result<Value, A::Error> {
        let mut object = serde_json::Map::new();
        while let Some(key) = map.next_key::<String>()? {
            if object.contains_key(&key) {
                return Err(de::Error::custom(format_args!("duplicate field `{key}`")));
            }
            let KeysOnce(v) = map.next_value()?;
            object.insert(key, v);
        }
        Ok(Value::Object(object))
    }
}

/// The first name between backticks in serde's message (`` `F` `` in "duplicate field `F`").
fn name_in(rest: &str) -> String {
    rest.split_once('`')
        .map_or(rest, |(_, r)| r.split_once('`').map_or(r, |(n, _)| n))
        .to_string()
}

/// The key `key` of the object at `segments`, given twice.
fn given_twice(root: &str, segments: &[Segment], key: &str) -> Error {
    let mut at = segments.to_vec();
    at.push(Segment::Map {
        key: key.to_string(),
    });
    Error::field(field_of(root, &at), "is given twice")
}

/// serde_json's message without its " at line L column C".
fn strip_position(message: &str) -> String {
    match message.rsplit_once(" at line ") {
        Some((what, _)) => what.to_string(),
        None => message.to_string(),
    }
}

/// The field of a path below `root`: `glls.monte_carlo.runs`, `model.F[0][1]`.
fn field_of(root: &str, segments: &[Segment]) -> String {
    let mut field = root.to_string();
    for s in segments {
        match s {
            Segment::Seq { index } => field.push_str(&format!("[{index}]")),
            Segment::Map { key } | Segment::Enum { variant: key } => {
                if !field.is_empty() {
                    field.push('.');
                }
                field.push_str(&crate::error::cut(key, crate::error::ECHO_CHARS));
            }
            // serde_path_to_error could not name this step (past the end of the text).
            Segment::Unknown => break,
        }
    }
    if field.is_empty() {
        "scenario".to_string()
    } else {
        field
    }
}

/// The value at a path, if the path leads to one.
fn value_at<'v>(mut v: &'v Value, segments: &[Segment]) -> Option<&'v Value> {
    for s in segments {
        v = match s {
            Segment::Seq { index } => v.as_array()?.get(*index)?,
            Segment::Map { key } | Segment::Enum { variant: key } => v.as_object()?.get(key)?,
            Segment::Unknown => return None,
        };
    }
    Some(v)
}

/// The value at a path, for changing it.
fn value_at_mut<'v>(mut v: &'v mut Value, segments: &[Segment]) -> Option<&'v mut Value> {
    for s in segments {
        v = match s {
            Segment::Seq { index } => v.as_array_mut()?.get_mut(*index)?,
            Segment::Map { key } | Segment::Enum { variant: key } => {
                v.as_object_mut()?.get_mut(key)?
            }
            Segment::Unknown => return None,
        };
    }
    Some(v)
}

/// Text that is not JSON: the position is all there is besides the path.
fn syntax_error(root: &str, segments: &[Segment], e: &serde_json::Error) -> Error {
    let what = strip_position(&e.to_string());
    let what = match what.as_str() {
        "expected value" => {
            "a value is expected here (JSON has no NaN or Infinity: write a number)".to_string()
        }
        "trailing characters" => "more text follows the end of the JSON document".to_string(),
        "recursion limit exceeded" => "is nested more than 128 levels deep".to_string(),
        w if w.starts_with("EOF while parsing") => {
            "the text ends inside a value (a missing \"]\", \"}\" or closing quote?)".to_string()
        }
        w => w.replace('`', "\""),
    };
    Error::field(
        field_of(root, segments),
        format!(
            "is not valid JSON: {what} (line {}, column {})",
            e.line(),
            e.column()
        ),
    )
}

/// What a JSON value is, in words: `the text "abc"`, `the number 2.5`, `a list of 3 entries`.
fn describe(v: &Value) -> String {
    match v {
        Value::Null => "null".to_string(),
        Value::Bool(b) => format!("the value {b}"),
        Value::Number(n) => format!("the number {n}"),
        Value::String(s) => format!("the text {}", quoted(s)),
        Value::Array(a) if a.is_empty() => "an empty list".to_string(),
        Value::Array(a) if a.len() == 1 => "a list of 1 entry".to_string(),
        Value::Array(a) => format!("a list of {} entries", a.len()),
        Value::Object(_) => "an object".to_string(),
    }
}

/// serde's "unexpected" part ("string \"abc\"", "floating point `2.5`", "map"), for the rare
/// error whose value the path does not reach.
fn describe_unexpected(u: &str) -> String {
    let inner = |prefix: &str| {
        u.strip_prefix(prefix)
            .map(|rest| rest.trim_matches(|c| c == '`' || c == '"').to_string())
    };
    if let Some(s) = inner("string ") {
        format!("the text {}", quoted(&s))
    } else if let Some(n) = inner("integer ").or_else(|| inner("floating point ")) {
        format!("the number {n}")
    } else if let Some(b) = inner("boolean ") {
        format!("the value {b}")
    } else {
        match u {
            "map" => "an object".to_string(),
            "sequence" => "a list".to_string(),
            "null" | "unit value" => "null".to_string(),
            _ => "a value of another kind".to_string(),
        }
    }
}

/// serde's "expected" part in JSON words; `None` for an enum (its names come from a probe).
fn expected_words(e: &str) -> Option<String> {
    let e = e.trim();
    Some(match e {
        "usize" | "u8" | "u16" | "u32" | "u64" | "u128" => "a whole number ≥ 0".to_string(),
        "isize" | "i8" | "i16" | "i32" | "i64" | "i128" => "a whole number".to_string(),
        "f32" | "f64" => "a number".to_string(),
        "a string" | "string" => "text in double quotes".to_string(),
        "a boolean" | "bool" => "true or false".to_string(),
        "a character" | "char" => "a single character".to_string(),
        "a sequence" | "a tuple" => "a list".to_string(),
        "a map" | "map" => "an object".to_string(),
        "unit" => "null".to_string(),
        // An enum read from a value ("string or map"), or its name ("variant identifier").
        "string or map" | "variant identifier" => return None,
        _ if e.starts_with("enum ") => return None,
        _ if e.starts_with("struct ") => "an object".to_string(),
        _ if e.starts_with("tuple struct ") || e.starts_with("tuple of ") => "a list".to_string(),
        _ => match e.strip_prefix("an array of length ") {
            Some(n) => format!(
                "a list of {n} {}",
                if n == "1" { "entry" } else { "entries" }
            ),
            None => "a value of another kind".to_string(),
        },
    })
}

/// `"a", "b" or "c"` from serde's list (`` `a` ``, `` `a` or `b` ``, `` one of `a`, `b`, `c` ``):
/// the names are what stands between backticks.
fn names_of(list: &str) -> String {
    let names: Vec<String> = list
        .split('`')
        .skip(1)
        .step_by(2)
        .map(|n| format!("\"{n}\""))
        .collect();
    match names.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => String::new(),
    }
}

/// serde's own error for `replacement` put at `segments`, if it is about that same place: a
/// question to serde about what the place accepts (the names of an enum, the length of a
/// fixed list), whose answer its error for the user's value leaves out.
fn probe<T: DeserializeOwned>(
    value: &Value,
    segments: &[Segment],
    replacement: Value,
) -> Option<String> {
    let mut probe = value.clone();
    *value_at_mut(&mut probe, segments)? = replacement;
    let e = serde_path_to_error::deserialize::<_, T>(&probe).err()?;
    let at: Vec<Segment> = e.path().iter().cloned().collect();
    (field_of("", &at) == field_of("", segments)).then(|| e.into_inner().to_string())
}

/// The names an enum at `segments` accepts: for a name no enum has, serde's "unknown
/// variant" error lists the real ones.
fn accepted_names<T: DeserializeOwned>(value: &Value, segments: &[Segment]) -> Option<String> {
    let message = probe::<T>(value, segments, Value::String("\u{0}".to_string()))?;
    let names = names_of(message.strip_prefix("unknown variant `\u{0}`, expected ")?);
    (!names.is_empty()).then_some(names)
}

/// How many entries a fixed-length list at `segments` takes: for an empty list, serde's
/// "invalid length" error says.
fn accepted_length<T: DeserializeOwned>(value: &Value, segments: &[Segment]) -> Option<String> {
    let message = probe::<T>(value, segments, Value::Array(Vec::new()))?;
    let n = message.strip_prefix("invalid length 0, expected an array of length ")?;
    Some(format!(
        "a list of {n} {}",
        if n == "1" { "entry" } else { "entries" }
    ))
}

/// A hint for a value of the right meaning written the wrong way.
fn hint(expected: &str, found: Option<&Value>) -> &'static str {
    match found {
        Some(Value::Number(n)) if expected.starts_with("a whole number") && n.is_f64() => {
            " (write whole numbers without a decimal point)"
        }
        // Before the next arm: Rust reads "NaN" and "inf" as numbers, JSON does not.
        Some(Value::String(s))
            if expected.contains("number")
                && matches!(
                    s.trim()
                        .trim_start_matches(['+', '-'])
                        .to_lowercase()
                        .as_str(),
                    "nan" | "inf" | "infinity"
                ) =>
        {
            " (JSON has no NaN or Infinity)"
        }
        Some(Value::String(s))
            if expected.contains("number") && s.trim().parse::<f64>().is_ok() =>
        {
            " (write numbers without quotes)"
        }
        Some(Value::Null) if expected.contains("number") => " (JSON has no NaN or Infinity)",
        _ => "",
    }
}

/// Valid JSON that does not fit `T`: serde's message at `segments` in JSON words.
fn schema_error<T: DeserializeOwned>(
    root: &str,
    value: &Value,
    segments: &[Segment],
    message: &str,
) -> Error {
    let here = value_at(value, segments);
    let field = field_of(root, segments);
    let below = |key: &str| {
        let mut s = segments.to_vec();
        s.push(Segment::Map {
            key: key.to_string(),
        });
        field_of(root, &s)
    };
    if let Some(rest) = message.strip_prefix("missing field ") {
        return Error::field(below(&name_in(rest)), "is missing");
    }
    // Two names of one field (a serde alias) in one object.
    if let Some(rest) = message.strip_prefix("duplicate field ") {
        return given_twice(root, segments, &name_in(rest));
    }
    if let Some(rest) = message.strip_prefix("unknown field ") {
        // The path ends at the unknown key itself (as the text names it); the object is its
        // parent.
        let key = name_in(rest);
        let parent = match segments.split_last() {
            Some((Segment::Map { key: last }, parent)) if *last == key => parent,
            _ => segments,
        };
        let object = if parent.is_empty() && root.is_empty() {
            "a scenario".to_string()
        } else {
            field_of(root, parent)
        };
        let mut at = parent.to_vec();
        at.push(Segment::Map { key });
        // The user's key is the first name between backticks; the accepted ones follow.
        let keys = match rest.rsplit_once(", expected ") {
            Some((_, list)) => format!(": the keys are {}", names_of(list)),
            None => ": it takes no keys".to_string(),
        };
        return Error::field(
            field_of(root, &at),
            format!("is not a key of {object}{keys}"),
        );
    }
    if let Some(rest) = message.strip_prefix("unknown variant ") {
        let found = match here {
            Some(Value::String(s)) => quoted(s),
            _ => quoted(&name_in(rest)),
        };
        let names = rest
            .rsplit_once(", expected ")
            .map_or(String::new(), |(_, l)| names_of(l));
        return Error::field(
            field,
            if names.is_empty() {
                format!("cannot be {found}: no names are accepted here")
            } else {
                format!("must be one of {names}, found {found}")
            },
        );
    }
    if message.contains("did not match any variant of untagged enum MatrixSpec") {
        return match here {
            Some(v) => matrix_problem(root, segments, v),
            None => Error::field(field, format!("must be {MATRIX}")),
        };
    }
    // A name that takes no options written as an object (`{"bounded": 3}`): the path ends at
    // the variant.
    if let (Some((Segment::Enum { variant }, parent)), true) = (
        segments.split_last(),
        message.ends_with(", expected unit") || message.ends_with(", expected unit variant"),
    ) {
        return Error::field(
            field_of(root, parent),
            format!(
                "must be the name {} alone, in double quotes (it takes no options)",
                quoted(variant)
            ),
        );
    }
    let typed = message
        .strip_prefix("invalid type: ")
        .or_else(|| message.strip_prefix("invalid value: "));
    if let Some((unexpected, expected)) = typed.and_then(|t| t.rsplit_once(", expected ")) {
        let found = here.map_or_else(|| describe_unexpected(unexpected), describe);
        let want = match expected_words(expected) {
            Some(w) => w,
            None => match accepted_names::<T>(value, segments) {
                Some(names) => format!("one of {names}"),
                None => "a name in double quotes".to_string(),
            },
        };
        let hint = hint(&want, here);
        return Error::field(field, format!("must be {want}, found {found}{hint}"));
    }
    if let Some(rest) = message.strip_prefix("invalid length ") {
        let found = here.map_or_else(|| format!("{} entries", name_in(rest)), describe);
        // Too many entries for a fixed list read from a value: serde says only "fewer
        // elements in array".
        let want = match rest.split_once(", expected ").map(|(_, e)| e) {
            Some(e) if e.starts_with("an array of length ") => expected_words(e),
            _ => accepted_length::<T>(value, segments),
        };
        return Error::field(
            field,
            match want {
                Some(w) => format!("must be {w}, found {found}"),
                None => format!("has the wrong number of entries: found {found}"),
            },
        );
    }
    // A message of our own or of a library: only the Rust spellings go.
    Error::field(
        field,
        format!("is not valid: {}", message.replace('`', "\"")),
    )
}

/// What a matrix field holds, in words.
const MATRIX: &str =
    "a matrix: a list of rows of numbers, or a list of such matrices (one per time step)";

/// The first entry of a matrix field that is not what a matrix holds: serde's untagged enum
/// says only that neither reading fits. The first entry decides the reading (a constant
/// matrix: rows of numbers; a sequence: matrices of rows); the first entry that breaks it is
/// named with its indices.
fn matrix_problem(root: &str, segments: &[Segment], v: &Value) -> Error {
    let field = field_of(root, segments);
    let Value::Array(items) = v else {
        return Error::field(field, format!("must be {MATRIX}, found {}", describe(v)));
    };
    let is_list = |v: Option<&Value>| v.is_some_and(Value::is_array);
    let first = items.first();
    let depth = if is_list(first) && is_list(first.and_then(|r| r.get(0))) {
        3
    } else {
        2
    };
    // The first value at `path` that is not a list (levels above `depth`) or not a number.
    fn walk(v: &Value, levels: usize, path: &mut Vec<Segment>) -> Option<&'static str> {
        if levels == 0 {
            return (!v.is_number()).then_some("a number");
        }
        let Value::Array(a) = v else {
            return Some(if levels == 1 {
                "a row: a list of numbers"
            } else {
                "a matrix: a list of rows"
            });
        };
        for (i, x) in a.iter().enumerate() {
            path.push(Segment::Seq { index: i });
            if let Some(want) = walk(x, levels - 1, path) {
                return Some(want);
            }
            path.pop();
        }
        None
    }
    let mut path = segments.to_vec();
    match walk(v, depth, &mut path) {
        Some(want) => {
            let here = value_at(v, &path[segments.len()..]);
            let found = here.map_or_else(|| "something else".to_string(), describe);
            let hint = hint(want, here);
            Error::field(
                field_of(root, &path),
                format!("must be {want}, found {found}{hint}"),
            )
        }
        None => Error::field(field, format!("must be {MATRIX}")),
    }
}
