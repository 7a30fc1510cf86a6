"""tswm: thousands to millions of worm-drive variants at once.

The engine of the ``tswm`` command line, in-process: :func:`run`
integrates a sweep's lanes (every variant of the drive) on all cores (or a
GPU) and returns the results table as a :class:`pyarrow.Table`, the same
columns, types and values as the ``lanes.parquet`` that ``tswm run
--format parquet`` writes. ``out=`` also writes the folder the command
writes. :func:`read`, :func:`summary` and :func:`sensitivity` read a run's
folder back; :func:`report` rebuilds its page; :func:`check`,
:func:`bench` and :func:`devices` are the commands of the same names.

Bad input raises :class:`InputError` (a :class:`ValueError`) whose message
is the command line's one line: the file (or argument), the line, row or
lane, the parameter and what is allowed. Nothing is written on bad input.
Other failures raise :class:`Error`; Ctrl-C stops a run within a second and
raises :class:`KeyboardInterrupt`, leaving no folder behind.
"""

from __future__ import annotations

import html as _html
import os
import re
import sys
import time
from typing import Any, Callable, Dict, List, Optional, Tuple, Union

import pyarrow as pa

# Mesa's Vulkan drivers print an error line while probing for a display
# that compute never needs, unless this is set (as the command line sets it).
if not os.environ.get("XDG_RUNTIME_DIR"):
    import tempfile as _tempfile

    os.environ["XDG_RUNTIME_DIR"] = _tempfile.gettempdir()

from . import _tswm
from ._toml import dict_to_toml

__all__ = [
    "Error",
    "InputError",
    "Report",
    "Check",
    "run",
    "read",
    "summary",
    "sensitivity",
    "report",
    "check",
    "bench",
    "devices",
]

__version__: str = _tswm.__version__

#: A sweep: a path to a sweep file (TOML), the TOML text itself, or a dict
#: with the sweep file's structure.
Sweep = Union[str, "os.PathLike[str]", Dict[str, Any]]
#: A lane table: a path to a CSV lane table, or a table with parameter
#: columns (pandas or polars DataFrame, pyarrow Table or RecordBatch, or
#: any object with ``__arrow_c_stream__``).
Lanes = Any
#: A run's output folder.
Folder = Union[str, "os.PathLike[str]"]


class Error(Exception):
    """A failure of the engine that is not bad input (a GPU that failed,
    a folder that cannot be written, ...)."""


class InputError(Error, ValueError):
    """Bad input: the message is the command line's one line, naming the
    file or argument, the line, row or lane, the parameter and what is
    allowed. Nothing was written."""


def _raise(e: Exception, lines: Optional[List[str]] = None) -> "NoReturn":  # type: ignore[name-defined]
    """The package's exception for the engine's failure `e`; for a sweep
    given as a dict (`lines`: the key path of each line of its TOML), a
    line is named by its key path."""
    kind, message, file, at, param, msg = e.args
    if kind == "stopped":
        raise KeyboardInterrupt(message) from None
    if kind != "input":
        raise Error(message) from None
    if lines is not None and at is not None and file == "sweep":
        # A line of the dict's TOML is named by its key path instead.
        def path(m: "re.Match[str]") -> str:
            n = int(m.group(1))
            return lines[n - 1] if 1 <= n <= len(lines) else m.group(0)

        at = re.sub(r"line (\d+)", path, at)
        message = ": ".join(x for x in (file, at, param, msg) if x)
    raise InputError(message) from None


def _sweep_args(sweep: Optional[Sweep]) -> Tuple[Optional[str], Optional[str], Optional[List[str]]]:
    """(path, TOML text, key paths of its lines) of a sweep argument."""
    if sweep is None:
        return None, None, None
    if isinstance(sweep, dict):
        try:
            text, lines = dict_to_toml(sweep)
        except TypeError as e:
            raise InputError(str(e)) from None
        return None, text, lines
    if isinstance(sweep, os.PathLike):
        return os.fspath(sweep), None, None
    if isinstance(sweep, str):
        # TOML text has a line break, a key or a table; a path has none.
        if "\n" in sweep or "=" in sweep or sweep.lstrip().startswith("["):
            return None, sweep, None
        return sweep, None, None
    raise TypeError(
        f"sweep: {type(sweep).__name__} is not a sweep; allowed: a path, TOML text or a dict"
    )


def _lanes_args(lanes: Optional[Lanes]) -> Tuple[Optional[str], Optional[pa.Table]]:
    """(path, table) of a lanes argument: a CSV file, or a table in memory
    (pandas and polars DataFrames become pyarrow Tables; missing values,
    None or NaN, mean "not set")."""
    if lanes is None:
        return None, None
    if isinstance(lanes, (str, os.PathLike)):
        return os.fspath(lanes), None
    module = type(lanes).__module__
    if module.startswith("pandas"):
        return None, pa.Table.from_pandas(lanes, preserve_index=False)
    if module.startswith("polars"):
        return None, lanes.to_arrow()
    if isinstance(lanes, pa.Table):
        return None, lanes
    if isinstance(lanes, pa.RecordBatch):
        return None, pa.Table.from_batches([lanes])
    if hasattr(lanes, "__arrow_c_stream__"):
        return None, pa.table(lanes)
    raise TypeError(
        f"lanes: {type(lanes).__name__} is not a lane table; allowed: a CSV path, a pandas "
        "or polars DataFrame, a pyarrow Table"
    )


def _interactive() -> bool:
    """Whether a person is likely watching: a terminal, or a notebook."""
    if "ipykernel" in sys.modules:
        return True
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False


class _Bar:
    """The progress bar of a call, shown once it has run a second
    (`tqdm`: a text bar in a terminal, a widget in Jupyter)."""

    def __init__(self, show: Optional[bool]):
        self.show = _interactive() if show is None else bool(show)
        self.start = time.monotonic()
        self.bar: Any = None
        self.phase = ""

    def __call__(self, phase: str, done: int, total: int) -> None:
        if not self.show or time.monotonic() - self.start < 1.0:
            return
        if phase != self.phase:
            self.close()
            self.phase = phase
            if phase:
                from tqdm.auto import tqdm

                desc = "checking lanes" if phase == "checking" else "tswm"
                self.bar = tqdm(total=total, desc=desc, unit=" lanes", unit_scale=True, leave=False)
        if self.bar is not None:
            self.bar.update(done - self.bar.n)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
            self.bar = None


def _engine(
    call: Callable[..., Any],
    sweep: Optional[Sweep],
    lanes: Optional[Lanes],
    progress: Optional[bool],
    *args: Any,
) -> Any:
    """`call(source, *args, progress)` with the package's errors and
    progress bar; `source` is where the lanes come from, packed once."""
    sweep_path, sweep_text, lines = _sweep_args(sweep)
    lanes_path, lanes_table = _lanes_args(lanes)
    bar = _Bar(progress)
    try:
        source = (sweep_path, sweep_text, "sweep", lanes_path, lanes_table, "lanes")
        return call(source, *args, bar)
    except _tswm.Failure as e:
        _raise(e, lines)
    finally:
        bar.close()


def run(
    sweep: Optional[Sweep] = None,
    *,
    lanes: Optional[Lanes] = None,
    backend: str = "auto",
    threads: Optional[int] = None,
    tol: Optional[float] = None,
    out: Optional[Folder] = None,
    format: str = "csv",
    report: bool = True,
    progress: Optional[bool] = None,
) -> pa.Table:
    """Runs a sweep's lanes and returns the results table.

    Args:
        sweep: a path to a sweep file, its TOML text, or a dict with the
            sweep file's structure (``{"base": {...}, "grid": [{...}]}``).
            With ``lanes``, it may give only ``[base]``, friction tables,
            ``[trace]`` and ``[report]``.
        lanes: a lane table, one lane a row, the parameters' names as
            columns: a CSV path, a pandas or polars DataFrame or a pyarrow
            Table; a missing value (None, NaN) means "not set".
        backend: ``"auto"``, ``"cpu"`` (the f64 path) or ``"gpu"``.
        threads: CPU threads (default: all cores).
        tol: the f64 path's per-step tolerance (1e-13 to 1e-4; 1e-8 by
            default).
        out: also write the folder ``tswm run --out OUT`` writes
            (``lanes.csv`` or ``lanes.parquet``, ``summary.csv``,
            ``sweep.resolved.toml``, ``report.html``, ...).
        format: the table's format in ``out``: ``"csv"`` or ``"parquet"``.
        report: write ``report.html`` in ``out``.
        progress: show a progress bar once the run has taken a second
            (None: when a terminal or a notebook shows it; False: never).

    Returns:
        The results table: the same columns (parameters, then results),
        types and values as ``lanes.parquet``, one row a lane in lane order.

    Raises:
        InputError: bad input (nothing was written).
        Error: any other failure.
        KeyboardInterrupt: Ctrl-C; the run stopped, nothing was written.
    """
    return _engine(
        _tswm.run,
        sweep,
        lanes,
        progress,
        backend,
        threads,
        tol,
        None if out is None else os.fspath(out),
        format,
        report,
    )


def read(dir: Folder) -> pa.Table:
    """The results table of a run's folder (``lanes.csv`` or
    ``lanes.parquet``), as :func:`run` returns it."""
    try:
        return _tswm.read(os.fspath(dir))
    except _tswm.Failure as e:
        _raise(e)


#: The text columns of summary.csv and sensitivity.csv (the others are
#: numbers, or the grid's parameters).
_TEXT_COLUMNS = {"kind", "name", "input", "quantiles", "output"}


def _csv_table(dir: Folder, name: str, what: str) -> pa.Table:
    import pyarrow.csv as pcsv

    path = os.path.join(os.fspath(dir), name)
    if not os.path.isdir(os.fspath(dir)):
        raise InputError(
            f"{os.fspath(dir)}: is not a folder; allowed: a folder written by `tswm run` or "
            "`tswm merge`"
        )
    if not os.path.isfile(path):
        raise InputError(f"{os.fspath(dir)}: holds no {name}; {what}")
    t = pcsv.read_csv(
        path, convert_options=pcsv.ConvertOptions(strings_can_be_null=True)
    )
    # A column with no cell given reads as nulls of no type: give it its own.
    fields = []
    for f in t.schema:
        if pa.types.is_null(f.type):
            f = f.with_type(pa.string() if f.name in _TEXT_COLUMNS else pa.float64())
        fields.append(f)
    return t.cast(pa.schema(fields))


def summary(dir: Folder) -> pa.Table:
    """``summary.csv`` of a run's folder: statistics per group (a grid
    point of a sampled sweep, or the whole run), as a pyarrow Table."""
    return _csv_table(dir, "summary.csv", "every tswm run writes one (a shard does not)")


def sensitivity(dir: Folder) -> pa.Table:
    """``sensitivity.csv`` of a run's folder: Sobol' indices per grid
    point, result and input (a ``[sensitivity]`` design), as a pyarrow
    Table."""
    return _csv_table(
        dir, "sensitivity.csv", "a run of a sweep with a [sensitivity] design writes one"
    )


class Report:
    """A run's ``report.html``: ``path``, the page's text (``html()``),
    shown inline in Jupyter."""

    def __init__(self, path: str):
        self.path = path

    def html(self) -> str:
        """The page, one self-contained HTML document."""
        with open(self.path, encoding="utf-8") as f:
            return f.read()

    def _repr_html_(self) -> str:
        # In a frame of its own, so that its styles stay its own.
        return (
            '<iframe style="width: 100%; height: 900px; border: 1px solid #ccc" '
            f'srcdoc="{_html.escape(self.html(), quote=True)}"></iframe>'
        )

    def __repr__(self) -> str:
        return f"Report({self.path!r})"


def report(dir: Folder) -> Report:
    """Writes ``report.html`` of a run's folder again from its files (as
    ``tswm report DIR``) and returns it."""
    try:
        return Report(_tswm.report(os.fspath(dir)))
    except _tswm.Failure as e:
        _raise(e)


class Check:
    """What :func:`check` found: ``lanes`` compared, the ``gpu`` and ``cpu``
    backends, ``passed`` (every bound held), ``disagreeing`` lanes,
    ``recomputed`` GPU rows, and the ``table`` ``tswm check`` prints."""

    def __init__(self, d: Dict[str, Any]):
        self.lanes: int = d["lanes"]
        self.gpu: str = d["gpu"]
        self.cpu: str = d["cpu"]
        self.passed: bool = d["passed"]
        self.disagreeing: int = d["disagreeing"]
        self.recomputed: int = d["recomputed"]
        self.table: str = d["table"]

    def __repr__(self) -> str:
        verdict = "passed" if self.passed else "failed"
        return f"Check({self.lanes} lanes, {self.gpu} against {self.cpu}: {verdict})"

    def __str__(self) -> str:
        return f"{self.lanes} lanes, {self.gpu} against {self.cpu}\n{self.table}"


def check(
    sweep: Optional[Sweep] = None,
    *,
    lanes: Optional[Lanes] = None,
    threads: Optional[int] = None,
    tol: Optional[float] = None,
    progress: Optional[bool] = None,
) -> Check:
    """Runs the lanes on the GPU (f32) and on the f64 CPU path and compares
    every row against the bounds of ``tswm check``; a missed bound is
    ``passed = False``, not an error. Raises :class:`Error` when there is
    no GPU."""
    return Check(_engine(_tswm.check, sweep, lanes, progress, threads, tol))


def bench(
    sweep: Optional[Sweep] = None,
    *,
    lanes: Optional[Lanes] = None,
    backend: str = "auto",
    threads: Optional[int] = None,
    tol: Optional[float] = None,
    progress: Optional[bool] = None,
) -> Dict[str, Any]:
    """Integrates the lanes, writing nothing: ``{"lanes", "seconds",
    "lanes_per_second", "backend"}`` (the lanes' check before is not
    timed)."""
    return _engine(_tswm.bench, sweep, lanes, progress, backend, threads, tol)


def devices() -> Dict[str, Any]:
    """The CPU path (``{"threads", "lanes", "width"}``) and the GPU
    adapters (name, type, API, driver, whether hardware, the limits a
    run's work is sized by, and the work a run gets), as ``tswm
    devices`` lists them."""
    try:
        return _tswm.devices()
    except _tswm.Failure as e:
        _raise(e)
