//! `sweep.resolved.toml`: the header lines that say where a run's lanes
//! came from and how they ran, above the sweep with every lane's source
//! spelled out.

use std::path::Path;

use crate::error::{Error, Result};
use crate::input::lanes::Source;
use crate::input::sweep::{Sweep, TraceSpec};

/// A string as a one-line TOML basic string (quoted, every control
/// character, quote and backslash escaped; the serializer would choose a
/// multi-line string for text with a line break), so no file name or
/// device name can break a line of `sweep.resolved.toml`.
pub(crate) fn toml_string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if c.is_control() => out.push_str(&format!("\\u{:04X}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// The text of `sweep.resolved.toml`: header lines naming the tool, the
/// lanes' source, backend, tolerance, lane count, run time
/// (`seconds`) and, for a shard, its lanes; then the sweep with every
/// lane's source spelled out and the traces the run writes (`trace`).
/// Every string in the header is a TOML string (escaped); the body is
/// written by the TOML serializer.
pub fn provenance(
    source: &Source,
    trace: Option<&TraceSpec>,
    backend: &str,
    tol: f64,
    seconds: f64,
    shard: Option<((u64, u64), (u64, u64))>,
) -> String {
    let from = match source {
        Source::Sweep { file, .. } => format!(
            "# every lane follows from this file\n{SWEEP_LINE}{}\n",
            toml_string(&file.display().to_string())
        ),
        Source::Table { table, .. } => format!(
            "{TABLE_LINE}{} ({} rows) over the [base] and [friction_table] below\n",
            toml_string(&table.name().display().to_string()),
            source.lane_count()
        ),
    };
    let resolved = source.resolved_text(trace);
    let defaults = crate::params::paper::paper_defaults(&source.given());
    let paper = if defaults.is_empty() {
        String::new()
    } else {
        format!("# {}\n", crate::params::paper::note(&defaults))
    };
    let (shard_line, run) = match shard {
        Some(((k, n), (a, b))) => (
            format!(
                "{SHARD_LINE}{k}/{n} (lanes {a} to {}, {} lanes)\n",
                b.max(1) - 1,
                b - a
            ),
            b - a,
        ),
        None => (String::new(), source.lane_count()),
    };
    format!(
        "# tswm {} resolved sweep\n{from}{paper}\
         # backend: {}, tol: {tol:e}\n\
         {LANES_LINE}{}\n\
         {shard_line}{}{resolved}",
        env!("CARGO_PKG_VERSION"),
        toml_string(backend),
        source.lane_count(),
        time_line(seconds, run),
    )
}

/// How the header of a lane table's `sweep.resolved.toml` names the table.
pub(crate) const TABLE_LINE: &str = "# every lane follows from the lane table ";

/// Whether a `sweep.resolved.toml` is a lane table's: its body is the
/// `[base]` the table's rows run over, not the run's lanes.
pub(crate) fn from_lane_table(text: &str) -> bool {
    text.lines()
        .take_while(|l| l.starts_with('#'))
        .any(|l| l.starts_with(TABLE_LINE))
}

/// Reads a run's `sweep.resolved.toml` (text `text`, at `path`): its
/// sweep and the lane count its header states. A lane table's sweep is
/// read as what it is, the base of the header's lanes, so its `[trace]`
/// lanes are checked against the run's lanes.
pub(crate) fn read_resolved(path: &Path, text: &str) -> Result<(Sweep, u64)> {
    let stated = stated_lanes(text).ok_or_else(|| {
        Error::input(
            path,
            None,
            None,
            "its header states no lane count (`# lanes: N`); not written by this tswm version",
        )
    })?;
    let lanes = from_lane_table(text).then_some(stated);
    Ok((Sweep::parse_with_lanes(path, text, lanes)?, stated))
}

/// How `sweep.resolved.toml` names the sweep file it was resolved from.
pub(crate) const SWEEP_LINE: &str = "# sweep: ";

/// What a run's lanes came from, as its `sweep.resolved.toml` names it:
/// the sweep file's or the lane table's name (without its folders), or
/// "" where the header names neither.
pub(crate) fn stated_source(text: &str) -> String {
    let name = text
        .lines()
        .take_while(|l| l.starts_with('#'))
        .find_map(|l| {
            l.strip_prefix(SWEEP_LINE)
                .or_else(|| l.strip_prefix(TABLE_LINE))
                .and_then(|r| toml::from_str::<toml::Value>(&format!("x = {}", quoted(r))).ok())
                .and_then(|v| v.get("x").and_then(|x| x.as_str().map(str::to_string)))
        })
        .unwrap_or_default();
    Path::new(&name)
        .file_name()
        .map_or(String::new(), |n| n.to_string_lossy().into_owned())
}

/// The quoted string at the start of `r` (a header line's rest).
fn quoted(r: &str) -> &str {
    let mut escaped = false;
    for (i, c) in r.char_indices().skip(1) {
        match c {
            '\\' if !escaped => escaped = true,
            '"' if !escaped => return &r[..=i],
            _ => escaped = false,
        }
    }
    r
}

/// The paper's drive's values a run took by default, as its
/// `sweep.resolved.toml` states them (empty when none).
pub(crate) fn stated_paper_defaults(text: &str) -> String {
    text.lines()
        .take_while(|l| l.starts_with('#'))
        .find_map(|l| {
            l.strip_prefix("# ")
                .and_then(|r| r.strip_prefix(crate::params::paper::PHRASE))
        })
        .unwrap_or("")
        .to_string()
}

/// How `sweep.resolved.toml` begins its line of the run's lane count.
pub(crate) const LANES_LINE: &str = "# lanes: ";

/// The lane count the header of a `sweep.resolved.toml` states.
pub(crate) fn stated_lanes(text: &str) -> Option<u64> {
    text.lines()
        .take_while(|l| l.starts_with('#'))
        .find_map(|l| l.strip_prefix(LANES_LINE))
        .and_then(|n| n.trim().parse().ok())
}

/// How a shard's `sweep.resolved.toml` names the shard (a merge drops
/// the line).
pub(crate) const SHARD_LINE: &str = "# shard: ";
/// How `sweep.resolved.toml` begins its line of the run time.
pub(crate) const TIME_LINE: &str = "# time: ";

/// The line of the run time of `lanes` lanes in `seconds`.
pub(crate) fn time_line(seconds: f64, lanes: u64) -> String {
    format!(
        "{TIME_LINE}{seconds:.3} s ({:.0} lanes/s)\n",
        lanes as f64 / seconds.max(1e-9)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lane_tables_resolved_sweep_reads_its_traces_against_its_rows() {
        let text = format!(
            "# tswm 0.1.0 resolved sweep\n{TABLE_LINE}\"t.csv\" (5 rows) over the [base] and \
             [friction_table] below\n{LANES_LINE}5\n[base]\nf2 = 1.0\n\n[trace]\ndt = 0.1\nlanes = [4]\n"
        );
        let (s, n) = read_resolved(Path::new("r.toml"), &text).unwrap();
        assert_eq!((s.trace.unwrap().lanes, n), (vec![4], 5));
        let over = text.replace("lanes = [4]", "lanes = [5]");
        assert!(read_resolved(Path::new("r.toml"), &over).is_err());
    }

    #[test]
    fn toml_strings_stay_on_one_line_and_read_back() {
        for s in ["a\nb.csv", "q\"uo\\te", "tab\tand\u{1}", "plain"] {
            let t = toml_string(s);
            assert_eq!(t.lines().count(), 1, "{t}");
            let v: toml::Table = toml::from_str(&format!("x = {t}")).unwrap();
            assert_eq!(v["x"].as_str(), Some(s));
        }
    }
}
