//! Reading a sweep file: its TOML form, and every check that can be made
//! before lanes are generated, each error naming the file, the line and
//! the key.

use std::collections::BTreeMap;
use std::path::Path;

use toml::Spanned;

use super::axes::parse_axes;
use super::file::{key_lines, At, ReportDef, SweepFile, TableDef};
use super::search::parse_search;
use super::study::parse_study;
use super::text::{suggest_in, toml_error};
use super::{Axis, AxisValues, Sweep};
use crate::error::{did_you_mean, Error, Result};
use crate::model::{FrictionTable, MAX_TABLES};
use crate::params::FrictionTables;
use crate::params::{Param, Spec, TableName};

impl Sweep {
    /// Reads and validates a sweep file.
    #[cfg(test)]
    pub(crate) fn from_file(path: &Path) -> Result<Sweep> {
        Sweep::parse(path, &super::text::read_text(path)?)
    }

    /// Parses sweep-file text; `path` names it in errors.
    pub fn parse(path: &Path, text: &str) -> Result<Sweep> {
        Sweep::parse_with_lanes(path, text, None)
    }

    /// Parses sweep-file text whose lanes come from elsewhere: `lanes`
    /// is the run's lane count (a lane table's rows) that `[trace]` lanes
    /// are checked against, instead of the sweep's own (one lane, its
    /// `[base]`). None: the sweep's own.
    pub(crate) fn parse_with_lanes(path: &Path, text: &str, lanes: Option<u64>) -> Result<Sweep> {
        let file: SweepFile = toml::from_str(text).map_err(|e| toml_error(path, text, &e))?;
        let at = At { path, text };
        let base = parse_base(&at, &file.base)?;
        let axes = parse_axes(&at, &file.grid)?;
        let tables = match &file.friction_table {
            Some(t) => parse_tables(&at, t)?,
            None => FrictionTables::default(),
        };
        check_table_names(&at, &file, &base, &axes, &tables)?;
        let study = parse_study(&at, &file, &base, &axes)?;
        let drives = match lanes {
            Some(n) => n,
            None => {
                let mut n = study.as_ref().map_or(1, |s| s.n);
                for a in &axes {
                    n = n.saturating_mul(a.len());
                }
                n
            }
        };
        // A lane table's rows are counted later (`Source::open`), and its
        // search's size checked then.
        let search = parse_search(
            &at,
            &file,
            &base,
            &axes,
            study.as_ref(),
            lanes.is_none().then_some(drives),
        )?;
        let mut sweep = Sweep {
            base,
            axes,
            study,
            tables,
            trace: None,
            report: Default::default(),
            search,
            key_lines: key_lines(text, &file),
        };
        let total = match lanes {
            Some(n) => n,
            None => sweep
                .lane_count_checked()
                .map_err(|m| Error::input(path, None, None, m))?,
        };
        if let Some(t) = &file.trace {
            let d = t.get_ref();
            sweep.trace = Some(
                super::TraceSpec::new(d.lanes.clone(), d.dt, total)
                    .map_err(|m| at.bad(t.span(), "trace", m))?,
            );
        }
        if let Some(r) = &file.report {
            sweep.report = parse_report(r.get_ref(), &sweep.axes)
                .map_err(|(key, m)| at.bad(r.span(), key, m))?;
            let sensitivity = sweep
                .study
                .as_ref()
                .is_some_and(|s| s.sensitivity.is_some());
            if sensitivity && sweep.report.require.is_some() {
                // A share's Wilson bound counts independent lanes; the
                // lanes of a row group share all inputs but one.
                return Err(at.bad(
                    r.span(),
                    "report.require",
                    "a requirement is answered on a [sampling] study, not on a [sensitivity] design (its lanes are not independent draws)".into(),
                ));
            }
        }
        Ok(sweep)
    }
}

/// The friction tables: one unnamed `[friction_table]` (keys `vs`, `mu`),
/// or named ones, `[friction_table.NAME]` each, in name order.
fn parse_tables(at: &At, t: &Spanned<toml::Table>) -> Result<FrictionTables> {
    let bad = |key: &str, m: String| at.bad(t.span(), key, m);
    let table = |key: &str, v: &toml::Value| -> Result<FrictionTable> {
        let d: TableDef = v
            .clone()
            .try_into()
            .map_err(|e: toml::de::Error| bad(key, suggest_in(e.message().trim())))?;
        FrictionTable::new(&d.vs, &d.mu).map_err(|m| bad(key, m))
    };
    let mut out = FrictionTables::default();
    let body = t.get_ref();
    if body.contains_key("vs") || body.contains_key("mu") {
        out.tables
            .push(table("friction_table", &toml::Value::Table(body.clone()))?);
        out.names.push(TableName::UNNAMED);
        return Ok(out);
    }
    if body.is_empty() {
        return Err(bad(
            "friction_table",
            "is empty; give vs and mu, or named tables [friction_table.NAME] with vs and mu each"
                .into(),
        ));
    }
    if body.len() > MAX_TABLES {
        return Err(bad(
            "friction_table",
            format!(
                "has {} tables; at most {MAX_TABLES} in one sweep",
                body.len()
            ),
        ));
    }
    for (name, v) in body {
        let key = format!("friction_table.{name}");
        let name = TableName::new(name).map_err(|m| bad(&key, m))?;
        if !v.is_table() {
            return Err(bad(
                &key,
                "is not a table: give vs and mu under [friction_table], or name each table,                  [friction_table.NAME], with vs and mu"
                    .into(),
            ));
        }
        out.tables.push(table(&key, v)?);
        out.names.push(name);
    }
    Ok(out)
}

/// Every friction table a sweep names (in `[base]` or on a grid axis) is
/// one of its own; checked here so the error names its line.
fn check_table_names(
    at: &At,
    file: &SweepFile,
    base: &Spec,
    axes: &[Axis],
    tables: &FrictionTables,
) -> Result<()> {
    let known = |n: &str| tables.names.iter().any(|t| t.as_str() == n);
    let allowed = || {
        if tables.is_empty() || tables.unnamed() {
            "none: name the tables, [friction_table.NAME]".to_string()
        } else {
            tables
                .names
                .iter()
                .map(|t| t.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        }
    };
    if let Some(n) = base.friction_table.filter(|n| !known(n.as_str())) {
        let span = file.base.get("friction_table").map_or(0..0, |v| v.span());
        return Err(at.bad(
            span,
            "friction_table",
            format!(
                "`{n}` is not a friction table of the sweep; allowed: {}",
                allowed()
            ),
        ));
    }
    for (a, def) in axes.iter().zip(&file.grid) {
        if let (Param::FrictionTable, AxisValues::Words(w)) = (a.param, &a.values) {
            if let Some(n) = w.iter().find(|n| !known(n)) {
                // The line of the word itself, inside the `values` list.
                let list = def
                    .get_ref()
                    .values
                    .as_ref()
                    .map_or(def.span(), |v| v.span());
                let word = at
                    .text
                    .get(list.clone())
                    .and_then(|t| t.find(&format!("\"{n}\"")).or(t.find(&format!("'{n}'"))))
                    .map_or(list.start, |i| list.start + i);
                return Err(at.bad(
                    word..word,
                    "friction_table",
                    format!(
                        "`{n}` is not a friction table of the sweep; allowed: {}",
                        allowed()
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// The `[report]` table, checked against the grid; an error names its key.
fn parse_report(
    d: &ReportDef,
    axes: &[Axis],
) -> std::result::Result<super::ReportSpec, (&'static str, String)> {
    let chosen = report_axes(d, axes)?;
    let allowed: Vec<&str> = crate::columns::number_columns().map(|c| c.name).collect();
    for r in &d.results {
        if !allowed.contains(&r.as_str()) {
            return Err((
                "report.results",
                format!(
                    "`{r}` is not a result number column; allowed: {}",
                    allowed.join(", ")
                ),
            ));
        }
    }
    let max = super::ReportSpec::MAX_PANELS;
    let panels = match d.panels {
        None => 0,
        Some(n) if n >= 1 && n as usize <= max => n as usize,
        Some(n) => {
            return Err((
                "report.panels",
                format!("{n} is out of range; allowed: 1 to {max}"),
            ))
        }
    };
    let require =
        match (&d.require, d.at_least) {
            (None, None) => None,
            (Some(r), Some(a)) => {
                Some(super::require::Requirement::parse(r, a).map_err(|m| ("report.require", m))?)
            }
            (Some(_), None) => {
                return Err((
                    "report.at_least",
                    "require needs at_least, the least share of lanes that must meet it, in (0, 1]"
                        .into(),
                ))
            }
            (None, Some(_)) => return Err((
                "report.require",
                "at_least needs require, the test it applies to (e.g. require = \"hold = held\")"
                    .into(),
            )),
        };
    let pareto = match &d.pareto {
        None => Vec::new(),
        Some(items) => super::pareto::parse(items).map_err(|m| ("report.pareto", m))?,
    };
    Ok(super::ReportSpec {
        title: d.title.clone(),
        axes: chosen,
        results: d.results.clone(),
        panels,
        require,
        pareto,
    })
}

fn parse_base(at: &At, keys: &BTreeMap<String, Spanned<toml::Value>>) -> Result<Spec> {
    let mut base = Spec::default();
    for (key, val) in keys {
        let span = val.span();
        let p = Param::from_name(key).ok_or_else(|| {
            at.bad(
                span.clone(),
                key,
                format!(
                    "unknown parameter{}; allowed: {}",
                    did_you_mean(key, Param::COLUMNS.map(|p| p.name())),
                    Param::all_names()
                ),
            )
        })?;
        let text_form = match (p, val.get_ref()) {
            (Param::Num(_), toml::Value::Float(f)) => format!("{f:?}"),
            (Param::Num(_), toml::Value::Integer(i)) => i.to_string(),
            (Param::Num(_), v) => {
                return Err(at.bad(
                    span,
                    key,
                    format!("expected a number, found {}", v.type_str()),
                ))
            }
            (_, toml::Value::String(s)) => s.clone(),
            (_, v) => {
                return Err(at.bad(
                    span,
                    key,
                    format!("expected a string, found {}", v.type_str()),
                ))
            }
        };
        base.set_text(p, &text_form)
            .map_err(|m| at.bad(span, key, m))?;
    }
    Ok(base)
}

/// `[report] axes`: at most two numeric grid axes, each once.
fn report_axes(
    d: &ReportDef,
    axes: &[Axis],
) -> std::result::Result<Vec<crate::params::Param>, (&'static str, String)> {
    // Only numeric axes can be a map's x or y; an axis of words (laws,
    // tables) gets panels of its own.
    let grid: Vec<&str> = axes
        .iter()
        .filter(|a| !a.is_words())
        .map(|a| a.param.name())
        .collect();
    let mut chosen = Vec::new();
    for name in &d.axes {
        match axes.iter().find(|a| a.param.name() == name) {
            Some(a) if a.is_words() => {
                return Err((
                    "report.axes",
                    format!(
                        "`{name}` runs over words; it gets a panel for each of its values, not a \
                         map axis; allowed: {}",
                        if grid.is_empty() {
                            "none".into()
                        } else {
                            grid.join(", ")
                        }
                    ),
                ))
            }
            Some(a) if !chosen.contains(&a.param) => chosen.push(a.param),
            Some(_) => return Err(("report.axes", format!("`{name}` is given twice"))),
            None => {
                return Err((
                    "report.axes",
                    format!(
                        "`{name}` is not a grid parameter of this sweep; allowed: {}",
                        if grid.is_empty() {
                            "none (the sweep has no grid)".into()
                        } else {
                            grid.join(", ")
                        }
                    ),
                ))
            }
        }
    }
    if chosen.len() > 2 {
        return Err(("report.axes", "at most 2 axes (x, then y)".into()));
    }
    Ok(chosen)
}
