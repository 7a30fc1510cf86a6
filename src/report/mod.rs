//! `report.html`: what a run answers, as one self-contained page built
//! from an output folder's files (`sweep.resolved.toml`, the results
//! table, `summary.csv`, `traces.csv`). Every file is read as a stream and
//! only bounded aggregates are kept (a few hundred cells a map, bins of a
//! histogram, a fixed number of time buckets a trace), so a run of any
//! size gets its report in bounded memory and in time linear in its rows.

mod aggregates;
mod answer;
pub mod axis;
mod bins;
mod cells;
pub mod charts;
mod extremes;
pub mod html;
mod line;
mod lines;
pub mod map_plots;
mod outcome;
mod pareto;
pub mod plots;
mod ranges;
mod require;
mod scan;
mod search;
mod sections;
mod sensitivity;
mod sheet;
mod stream;
mod summary_rows;
mod trace;
mod trace_rows;
mod words;

use std::path::Path;

use crate::error::{Error, Result};
use crate::input::sweep::Sweep;
use crate::output::names::{REPORT, RESOLVED, SENSITIVITY, SUMMARY, TRACES};
use crate::output::table::Format;
use crate::output::{AtomicFile, OutDir};
use html::Page;
use scan::Folder;
pub use stream::Scan;
use words::lanes_text;

/// Writes `DIR/report.html` from the run in the folder `dir` holds
/// (locked), committed beside its other files.
pub fn write(dir: &mut OutDir) -> Result<()> {
    write_with(dir, None)
}

/// Writes `DIR/report.html` as [`write()`] does, from the aggregates `scan`
/// gathered while the run's rows streamed past when given (the same page,
/// without reading the table back).
pub(crate) fn write_with(dir: &mut OutDir, scan: Option<Scan>) -> Result<()> {
    crate::output::atomic::pause_for_tests("before-report");
    let page = build_with(dir.path(), scan)?;
    let path = dir.join(REPORT);
    let mut f = AtomicFile::create(&path)?;
    std::io::Write::write_all(f.writer(), page.as_bytes()).map_err(|e| Error::io(&path, e))?;
    dir.commit_more(vec![f])
}

/// The report of the run in `dir`, as HTML.
pub fn build(dir: &Path) -> Result<String> {
    build_with(dir, None)
}

/// The aggregates of a run's report, gathered while its rows stream past,
/// for a run of `sweep` writing `format` and stating `stated` lanes; None
/// where the report needs the finished folder first (a study's
/// histograms).
pub(crate) fn scan_for(sweep: &Sweep, format: Format, stated: u64) -> Option<Scan> {
    Folder::streams(sweep)
        .then(|| Scan::new(Folder::start(format.file_name(), sweep), sweep, stated))
}

/// What ran and where: "tswm report: paper.toml, 2 lanes (folder out)",
/// from its `sweep.resolved.toml` (`text`), folder and lane count.
fn default_title(text: &str, dir: &Path, stated: u64) -> String {
    let source = crate::output::provenance::stated_source(text);
    let folder_name = dir
        .canonicalize()
        .unwrap_or(dir.to_path_buf())
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let lanes = lanes_text(stated);
    let lanes = lanes.trim_end_matches('.');
    if source.is_empty() {
        format!("tswm report: {lanes} (folder {folder_name})")
    } else {
        format!("tswm report: {source}, {lanes} (folder {folder_name})")
    }
}

/// The values of the paper's drive the run took because it left them
/// out, as its `sweep.resolved.toml` (`text`) states them: a warning.
fn paper_defaults(page: &mut Page, text: &str) {
    let paper = crate::output::provenance::stated_paper_defaults(text);
    if !paper.is_empty() {
        page.warning(&format!(
            "This run takes values of the paper's drive it was not given: {paper}. Set them \
             in [base] (or a lane table's columns) where the drive is another."
        ));
    }
}

/// The report of the run in `dir`, from `scan` when given.
fn build_with(dir: &Path, scan: Option<Scan>) -> Result<String> {
    let resolved_path = dir.join(RESOLVED);
    let text = std::fs::read_to_string(&resolved_path).map_err(|e| {
        Error::input(
            &resolved_path,
            None,
            None,
            format!(
                "cannot read it ({e}); allowed: a folder written by `tswm run` or `tswm merge`"
            ),
        )
    })?;
    let (sweep, stated) = crate::output::provenance::read_resolved(&resolved_path, &text)?;
    let folder = match scan {
        Some(s) => s.finish(dir, &dir.join(Format::of_folder(dir)?.file_name()))?,
        None => Folder::read(dir, &sweep, stated)?,
    };
    let spec = &sweep.report;
    let title = spec
        .title
        .clone()
        .unwrap_or_else(|| default_title(&text, dir, stated));
    let mut page = Page::new(&title);
    // Results first: what was found, what is not decided yet, the answer
    // to the requirement; what was run comes last.
    answer::findings(&mut page, &folder, &sweep);
    paper_defaults(&mut page, &text);
    answer::undecided(&mut page, &folder);
    if let Some(r) = folder.require.as_ref() {
        answer::requirement(&mut page, r);
    }
    if let Some(s) = &sweep.search {
        search::section(&mut page, dir, &sweep, s)?;
    }
    pareto::section(&mut page, dir, &sweep)?;
    if let Some(sheet) = &folder.sheet {
        sheet.section(&mut page);
    }

    sections::outcomes(&mut page, &folder);
    if folder.map.is_some() {
        sections::maps(&mut page, &folder);
    }
    if folder.line.is_some() {
        lines::lines(&mut page, &folder);
    }
    if let Some(sn) = sweep.study.as_ref().and_then(|s| s.sensitivity.as_ref()) {
        sensitivity::section(&mut page, dir, &sweep, sn)?;
    }
    if folder.study {
        sections::study(&mut page, &folder);
    }
    if !folder.traces.is_empty() {
        sections::traces(&mut page, &folder);
    }
    page.section("What was run");
    let header: Vec<&str> = text.lines().take_while(|l| l.starts_with('#')).collect();
    for l in &header {
        page.note(l.trim_start_matches('#').trim());
    }
    page.note(&format!("Folder: {}", dir.display()));
    page.heading(&format!("The resolved sweep ({RESOLVED})"));
    page.pre(&text);

    about(&mut page, &folder);
    Ok(page.finish(&title))
}

/// The last section: where the page comes from, and what its words mean.
fn about(page: &mut Page, folder: &Folder) {
    page.section("About this page");
    page.note(&format!(
        "Written by tswm from the files of its output folder: {} (one row per lane), {SUMMARY} \
         (statistics), {SENSITIVITY} (sensitivity indices, for a sensitivity design), {TRACES} \
         (traced lanes) and {RESOLVED}. Efficiencies are energy-averaged \
         over each lane's run: eta_direct = w2_out / w1_in (worm drives wheel), eta_inverse = \
         w1_out / w2_in (wheel drives worm); the _ss values are the running efficiencies at the \
         final sliding speed (a lane at rest at its end has no running point: this page leaves it \
         out of their ranges, maps and statistics), the _start values the starting (breakaway) \
         efficiencies with static friction; lock_margin_deg = atan(mu_s / cos alpha_n) - gamma > \
         0 means the drive holds its load at rest with the motor off; drive says what the motor \
         achieved (runs, overhauled, stalled, back_driven) in a lane whose motor runs to the end, hold what became of the load of a lane whose \
         motor is cut. Grey cells have no value (the lane did not finish, or the efficiency is \
         undefined).",
        folder.table
    ));
}
