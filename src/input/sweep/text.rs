//! A sweep file's text and the TOML reader's errors, each made one line
//! that names the line and the key.

use std::path::Path;

use super::file::line_of;
use crate::error::{did_you_mean, Error, Result};

/// The TOML reader's error on one line; a duplicate key is named.
pub(super) fn toml_error(path: &Path, text: &str, e: &toml::de::Error) -> Error {
    let at = e.span().map(|s| line_of(text, s.start));
    let msg = e.message().trim().replace('\n', " ");
    if msg.starts_with("duplicate key") {
        let key = e
            .span()
            .and_then(|s| text.get(s))
            .map(|k| k.trim().trim_matches(['"', '\'']))
            .unwrap_or("");
        return Error::input(
            path,
            at,
            Some(key),
            "duplicate key; each key may appear once in its table",
        );
    }
    if let (Some(rest), Some(span)) = (msg.strip_prefix("invalid type: "), e.span()) {
        // A value of the wrong type: name its key, and say what it must be.
        let key = key_at(text, span.start);
        let (got, want) = rest.split_once(", expected ").unwrap_or((rest, ""));
        let want = match want {
            "i64" | "u64" | "usize" | "u32" => "a whole number",
            "f64" => "a number",
            "a string" => "a word in quotes",
            w => w,
        };
        return Error::input(path, at, key, format!("must be {want}, got {got}"));
    }
    if let Some(key) = msg
        .strip_prefix("missing field `")
        .and_then(|r| r.split_once('`'))
        .map(|(k, _)| k)
    {
        // A required key left out: name its table and what it takes.
        let table = e.span().and_then(|s| table_at(text, s.start));
        let at = table
            .as_ref()
            .map(|(line, _)| format!("line {line}"))
            .or(at);
        let table = table.map_or(String::new(), |(_, t)| t);
        return Error::input(path, at, Some(key), missing(&table, key));
    }
    Error::input(path, at, None, suggest_in(&msg))
}

/// What a required key of a table takes, for the line that says it is
/// missing.
fn missing(table: &str, key: &str) -> String {
    let what = match key {
        "seed" => {
            "a whole number from 0 to 9223372036854775807 (the same seed gives the same draws, \
             so a run can be repeated exactly)"
        }
        "n" if table.contains("sampling") || table.contains("sensitivity") => {
            "the number of sampled lanes (a whole number >= 1)"
        }
        "method" if table.contains("sampling") => "\"monte_carlo\" or \"latin_hypercube\"",
        "method" => "\"sobol\"",
        "param" => "the name of a parameter (see the guide's table of parameters)",
        "dist" => "\"uniform\", \"normal\" or \"triangular\"",
        _ => "see the guide for this table's keys",
    };
    if table.is_empty() {
        format!("is required and missing; allowed: {what}")
    } else {
        format!("is required in {table} and missing; allowed: {what}")
    }
}

/// The table header (`[sampling]`, `[[tolerance]]`) in force at byte
/// `pos` of `text`, with its line: the last header line at or before it.
fn table_at(text: &str, pos: usize) -> Option<(usize, String)> {
    let pos = pos.min(text.len());
    let end = text[pos..].find('\n').map_or(text.len(), |i| pos + i);
    text[..end]
        .lines()
        .enumerate()
        .filter(|(_, l)| l.trim_start().starts_with('['))
        .last()
        .map(|(i, l)| {
            let l = l.trim();
            let head = l.split('#').next().unwrap_or(l).trim();
            (i + 1, head.to_string())
        })
}

/// The key whose value starts at byte `pos` of `text` (`n` of `n = 2.5`),
/// if the line says `key = value` before it.
fn key_at(text: &str, pos: usize) -> Option<&str> {
    let pos = pos.min(text.len());
    let start = text[..pos].rfind('\n').map_or(0, |i| i + 1);
    let (key, _) = text[start..pos].split_once('=')?;
    let key = key.trim().trim_matches(['"', '\'']);
    (!key.is_empty()).then_some(key)
}

/// The TOML reader's "unknown field `x`, expected one of `a`, `b`" (or
/// "unknown variant"), with a "did you mean" for a near miss.
pub(super) fn suggest_in(msg: &str) -> String {
    for kind in ["unknown field `", "unknown variant `"] {
        let Some(rest) = msg.split(kind).nth(1) else {
            continue;
        };
        let Some((name, tail)) = rest.split_once('`') else {
            continue;
        };
        let candidates: Vec<&str> = tail.split('`').skip(1).step_by(2).collect();
        let hint = did_you_mean(name, candidates.iter().copied());
        if !hint.is_empty() {
            return msg.replacen(
                &format!("{kind}{name}`"),
                &format!("{kind}{name}`{hint}"),
                1,
            );
        }
    }
    msg.to_string()
}

/// A sweep file's text. A folder, an unreadable file or bytes that are
/// not UTF-8 (named by their line) are bad input.
pub(crate) fn read_text(path: &Path) -> Result<String> {
    if path.is_dir() {
        return Err(Error::input(
            path,
            None,
            None,
            "is a folder; allowed: a sweep file (TOML)",
        ));
    }
    let bytes = std::fs::read(path)
        .map_err(|e| Error::input(path, None, None, format!("cannot read the sweep file: {e}")))?;
    String::from_utf8(bytes).map_err(|e| {
        let ok = e.utf8_error().valid_up_to();
        let bytes = e.as_bytes();
        let line = bytes[..ok].iter().filter(|&&b| b == b'\n').count() + 1;
        Error::input(
            path,
            Some(format!("line {line}")),
            None,
            format!(
                "byte 0x{:02x} is not UTF-8 text; a sweep file is TOML, UTF-8 encoded",
                bytes[ok]
            ),
        )
    })
}
