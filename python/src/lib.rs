//! `tswm._tswm`: the Rust side of Python's `tswm` package. Each function
//! takes plain values (paths, TOML text, an Arrow stream of lanes) that
//! the Python package has checked and normalised, runs the same library
//! code the command line runs, and returns Arrow tables (through the
//! Arrow C data interface: no copy of the columns) or plain values.
//!
//! Errors come back as `_tswm.Failure(kind, message, file, at, param,
//! msg)`: `kind` is "input" for bad input (the command line's exit code
//! 2; the message is its one line), "error" otherwise. The Python package
//! raises `tswm.InputError` or `tswm.Error` from it.

mod drive;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use arrow_array::RecordBatch;
use arrow_pyarrow::{PyArrowType, Table};
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use tswm::backend::{Choice, Precision};
use tswm::cli::{LanesArgs, Plan, RunFlags};
use tswm::columns::Kind;
use tswm::error::Error;
use tswm::input::frame::Frame;
use tswm::input::lanes::{Source, SweepIn, TableIn};
use tswm::output::table::Format;
use tswm::progress::Show;

create_exception!(
    _tswm,
    Failure,
    PyException,
    "A failure of the engine: (kind, message, file, at, param, msg)."
);

/// The engine's error as a [`Failure`]: kind, the one line, and for bad
/// input its parts.
fn failure(e: Error) -> PyErr {
    let line = tswm::error::one_line(&e.to_string());
    match e {
        Error::Input {
            file,
            at,
            param,
            msg,
        } => Failure::new_err(("input", line, file.display().to_string(), at, param, msg)),
        Error::Usage(m) => Failure::new_err((
            "input",
            line,
            None::<String>,
            None::<String>,
            None::<String>,
            m,
        )),
        Error::Stopped => Failure::new_err((
            "stopped",
            line.clone(),
            None::<String>,
            None::<String>,
            None::<String>,
            line,
        )),
        _ => Failure::new_err((
            "error",
            line.clone(),
            None::<String>,
            None::<String>,
            None::<String>,
            line,
        )),
    }
}

/// Where a call's lanes come from, as the Python package passes them.
struct Lanes {
    sweep_path: Option<PathBuf>,
    sweep_text: Option<(PathBuf, String)>,
    table_path: Option<PathBuf>,
    frame: Option<Arc<Frame>>,
    threads: Option<usize>,
    tol: Option<f64>,
    precision: Precision,
}

impl Lanes {
    /// The checked plan of these lanes (every lane read and checked),
    /// shown by `show`.
    fn plan(&self, show: &Show) -> tswm::error::Result<Plan> {
        let args = LanesArgs {
            sweep: None,
            lanes: None,
            threads: self.threads,
            tol: self.tol,
            precision: self.precision,
        };
        let (threads, settings) = args.settings()?;
        let sweep = match (&self.sweep_path, &self.sweep_text) {
            (Some(p), _) => Some(SweepIn::File(p)),
            (None, Some((name, text))) => Some(SweepIn::Text { name, text }),
            (None, None) => None,
        };
        let table = match (&self.table_path, &self.frame) {
            (Some(p), _) => Some(TableIn::File(p.clone())),
            (None, Some(f)) => Some(TableIn::Frame(f.clone())),
            (None, None) => None,
        };
        let source = Source::open_from(sweep, table, &|n, _| (0, n), show)?;
        Ok(Plan {
            source,
            threads,
            settings,
            precision: args.asked_precision(),
        })
    }
}

/// Where a call's lanes come from, as the package packs them once
/// (`_engine` in `tswm/__init__.py`): a sweep (a file, or TOML text named
/// by the third item) and a lane table (a file, or an Arrow table named by
/// the sixth).
#[derive(FromPyObject)]
struct LaneSource(
    Option<PathBuf>,
    Option<String>,
    String,
    Option<PathBuf>,
    Option<PyArrowType<Table>>,
    String,
);

impl LaneSource {
    /// The lanes, to run on `threads` threads at tolerance `tol`, the GPU
    /// in `precision` (its word).
    fn lanes(self, threads: Option<usize>, tol: Option<f64>, precision: &str) -> PyResult<Lanes> {
        let precision = match precision {
            "auto" => Precision::Auto,
            "f32" => Precision::F32,
            "f64" => Precision::F64,
            other => {
                return Err(failure(Error::Usage(format!(
                    "precision: `{}` is not a precision; allowed: auto, f32, f64",
                    tswm::error::shown(other, 40)
                ))))
            }
        };
        let LaneSource(sweep_path, sweep_text, sweep_name, lanes_path, lanes_table, lanes_name) =
            self;
        let frame = match lanes_table {
            Some(PyArrowType(t)) => {
                let (batches, schema) = t.into_inner();
                Some(Arc::new(
                    Frame::from_batches(Path::new(&lanes_name), &schema, &batches)
                        .map_err(failure)?,
                ))
            }
            None => None,
        };
        Ok(Lanes {
            sweep_path,
            sweep_text: sweep_text.map(|t| (PathBuf::from(sweep_name), t)),
            table_path: lanes_path,
            frame,
            threads,
            tol,
            precision,
        })
    }
}

/// A backend by its name on the command line.
fn backend(name: &str) -> PyResult<Choice> {
    match name {
        "auto" => Ok(Choice::Auto),
        "cpu" => Ok(Choice::Cpu),
        "gpu" => Ok(Choice::Gpu),
        other => Err(failure(Error::Usage(format!(
            "backend: `{}` is not a backend; allowed: auto, cpu, gpu",
            tswm::error::shown(other, 40)
        )))),
    }
}

/// The results table's batches as a `pyarrow.Table` (no copy).
fn table(batches: Vec<RecordBatch>) -> PyResult<PyArrowType<Table>> {
    // A search run's batches have its columns too.
    let schema = batches
        .first()
        .map_or_else(tswm::output::batch::schema, |b| b.schema());
    let t = Table::try_new(batches, schema).map_err(|e| failure(Error::Internal(e.to_string())))?;
    Ok(PyArrowType(t))
}

/// Runs a sweep's lanes; the results table. With `out`, writes the
/// folder `tswm run` writes too. `progress(phase, done, total)` is
/// called from time to time.
#[pyfunction]
#[pyo3(signature = (source, backend_name, threads, tol, precision, out, format, report, progress))]
#[allow(clippy::too_many_arguments)]
fn run(
    py: Python<'_>,
    source: LaneSource,
    backend_name: &str,
    threads: Option<usize>,
    tol: Option<f64>,
    precision: &str,
    out: Option<PathBuf>,
    format: &str,
    report: bool,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<PyArrowType<Table>> {
    let lanes = source.lanes(threads, tol, precision)?;
    let choice = backend(backend_name)?;
    let format = match format {
        "csv" => Format::Csv,
        "parquet" => Format::Parquet,
        other => {
            return Err(failure(Error::Usage(format!(
                "format: `{}` is not a format; allowed: csv, parquet",
                tswm::error::shown(other, 40)
            ))))
        }
    };
    let batches = drive::drive(py, progress, move |show| {
        let plan = lanes.plan(&show)?;
        match out {
            Some(out) => {
                let flags = RunFlags {
                    out,
                    backend: choice,
                    trace: Vec::new(),
                    trace_dt: None,
                    no_report: !report,
                    shard: None,
                    format,
                    dry_run: false,
                };
                Ok(tswm::commands::run::execute(plan, None, &flags, &show, true)?.batches)
            }
            None => tswm::commands::run::collect(&plan, choice, &show),
        }
    })?;
    table(batches)
}

/// The results table of a run's folder (`lanes.csv` or `lanes.parquet`).
#[pyfunction]
fn read(py: Python<'_>, dir: PathBuf) -> PyResult<PyArrowType<Table>> {
    let batches = py
        .detach(move || {
            let names = tswm::output::table::folder_columns(&dir)?;
            let mut batches = Vec::new();
            tswm::output::table::read_batches(&dir, &names, |b| {
                batches.push(b.clone());
                Ok(())
            })?;
            Ok(batches)
        })
        .map_err(failure)?;
    table(batches)
}

/// Writes the folder's `report.html` again; its path, as the OS names it
/// (a name that is not UTF-8 comes back as `os.fsdecode` gives it, so
/// `os.fsencode` gives its bytes again).
#[pyfunction]
fn report(py: Python<'_>, dir: PathBuf) -> PyResult<PathBuf> {
    py.detach(move || tswm::commands::report::rebuild(&dir))
        .map_err(failure)
}

/// The one line of bad input in `file` (at `at`, of `param`): the
/// command line's, made one line as it makes it.
#[pyfunction]
#[pyo3(signature = (file, at, param, msg))]
fn input_line(file: PathBuf, at: Option<String>, param: Option<String>, msg: String) -> String {
    tswm::error::one_line(&Error::input(&file, at, param.as_deref(), msg).to_string())
}

/// Input quoted in a message: one line, at most `max` characters.
#[pyfunction]
fn shown(text: &str, max: usize) -> String {
    tswm::error::shown(text, max)
}

/// A column kind's name in Python: "float", "int" or "text".
fn kind_name(k: Kind) -> &'static str {
    match k {
        Kind::Float => "float",
        Kind::Int => "int",
        Kind::Text => "text",
    }
}

/// The parameters' columns (as a lane table, the results table or a
/// grid axis of `summary.csv` holds them), with their kinds.
#[pyfunction]
fn param_columns() -> Vec<(&'static str, &'static str)> {
    tswm::output::batch::columns()
        .into_iter()
        .take(tswm::params::Param::COLUMNS.len())
        .map(|(n, k)| (n, kind_name(k)))
        .collect()
}

/// The columns of a run folder's `summary.csv` or `sensitivity.csv`
/// (`file`) with their kinds, as the crate declares them: those before
/// the grid's axes (a summary's axes are parameters, [`param_columns`])
/// and those after them.
#[pyfunction]
#[allow(clippy::type_complexity)]
fn stats_columns(
    file: &str,
) -> PyResult<(Vec<(String, &'static str)>, Vec<(String, &'static str)>)> {
    use tswm::stats::{sensitivity, summary};
    let named = |f: &mut dyn Iterator<Item = (&'static str, Kind)>| -> Vec<(String, &'static str)> {
        f.map(|(n, k)| (n.to_string(), kind_name(k))).collect()
    };
    match file {
        "summary.csv" => Ok((
            vec![("group".to_string(), kind_name(summary::GROUP_KIND))],
            named(&mut summary::summary_fields()),
        )),
        "sensitivity.csv" => Ok((named(&mut sensitivity::sensitivity_fields()), Vec::new())),
        other => Err(failure(Error::Internal(format!(
            "{other}: not a statistics file"
        )))),
    }
}

/// Integrates the lanes on a backend, writing nothing: lanes, seconds,
/// lanes/s and the backend's name.
#[pyfunction]
#[pyo3(signature = (source, backend_name, threads, tol, precision, progress))]
#[pyo3(name = "bench")]
fn bench_lanes<'py>(
    py: Python<'py>,
    source: LaneSource,
    backend_name: &str,
    threads: Option<usize>,
    tol: Option<f64>,
    precision: &str,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let lanes = source.lanes(threads, tol, precision)?;
    let choice = backend(backend_name)?;
    let b = drive::drive(py, progress, move |show| {
        tswm::commands::bench::measure(&lanes.plan(&show)?, choice, &show)
    })?;
    let d = PyDict::new(py);
    d.set_item("lanes", b.lanes)?;
    d.set_item("seconds", b.seconds)?;
    d.set_item("lanes_per_second", b.rate())?;
    d.set_item("backend", b.backend)?;
    Ok(d)
}

/// Runs the lanes on the GPU and on the f64 CPU path and compares them:
/// lanes, the two backends, whether every bound held, and the table of
/// deviations `tswm check` prints.
#[pyfunction]
#[pyo3(signature = (source, threads, tol, precision, progress))]
fn check<'py>(
    py: Python<'py>,
    source: LaneSource,
    threads: Option<usize>,
    tol: Option<f64>,
    precision: &str,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let lanes = source.lanes(threads, tol, precision)?;
    let c = drive::drive(py, progress, move |show| {
        let plan = tswm::commands::check::checked_plan(lanes.plan(&show)?, lanes.precision);
        let checked = tswm::commands::check::compare(&plan, None, &show)?;
        Ok((
            checked.report.lanes,
            checked.report.disagree,
            checked.report.recomputed,
            checked.report.passes(),
            checked.report.text(),
            checked.gpu,
            checked.cpu,
        ))
    })?;
    let d = PyDict::new(py);
    d.set_item("lanes", c.0)?;
    d.set_item("disagreeing", c.1)?;
    d.set_item("recomputed", c.2)?;
    d.set_item("passed", c.3)?;
    d.set_item("table", c.4)?;
    d.set_item("gpu", c.5)?;
    d.set_item("cpu", c.6)?;
    Ok(d)
}

/// The CPU path's width and the GPU adapters.
#[pyfunction]
fn devices(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let d = py.detach(tswm::commands::devices::list).map_err(failure)?;
    let out = PyDict::new(py);
    let cpu = PyDict::new(py);
    cpu.set_item("threads", d.threads)?;
    cpu.set_item("lanes", d.lanes)?;
    cpu.set_item("width", d.width)?;
    out.set_item("cpu", cpu)?;
    let adapters = pyo3::types::PyList::empty(py);
    for a in d.adapters {
        let x = PyDict::new(py);
        x.set_item("name", a.name)?;
        x.set_item("device_type", a.device_type)?;
        x.set_item("api", a.api)?;
        x.set_item("driver", a.driver)?;
        x.set_item("hardware", a.hardware)?;
        x.set_item("shader_f64", a.shader_f64)?;
        let [binding, buffer, groups, invocations] = a.limits;
        x.set_item("max_storage_buffer_binding_size", binding)?;
        x.set_item("max_buffer_size", buffer)?;
        x.set_item("max_compute_workgroups_per_dimension", groups)?;
        x.set_item("max_compute_invocations_per_workgroup", invocations)?;
        let [chunk, part, in_flight, slots] = a.work;
        x.set_item("chunk_lanes", chunk)?;
        x.set_item("part_lanes", part)?;
        x.set_item("parts_in_flight", in_flight)?;
        x.set_item("slots", slots)?;
        adapters.append(x)?;
    }
    out.set_item("adapters", adapters)?;
    Ok(out)
}

/// The Python extension module.
#[pymodule]
fn _tswm(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("Failure", m.py().get_type::<Failure>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("MAX_THREADS", tswm::cli::MAX_THREADS)?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(read, m)?)?;
    m.add_function(wrap_pyfunction!(report, m)?)?;
    m.add_function(wrap_pyfunction!(bench_lanes, m)?)?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(devices, m)?)?;
    m.add_function(wrap_pyfunction!(input_line, m)?)?;
    m.add_function(wrap_pyfunction!(shown, m)?)?;
    m.add_function(wrap_pyfunction!(param_columns, m)?)?;
    m.add_function(wrap_pyfunction!(stats_columns, m)?)?;
    Ok(())
}
