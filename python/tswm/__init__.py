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
import math
import numbers
import operator
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
Sweep = Union[str, bytes, "os.PathLike[str]", Dict[str, Any]]
#: A lane table: a path to a CSV lane table, or a table with parameter
#: columns (pandas or polars DataFrame or LazyFrame, a named pandas or
#: polars Series, pyarrow Table or RecordBatch, or any object with
#: ``__arrow_c_stream__``).
Lanes = Any
#: A run's output folder: a path as ``str``, ``bytes`` or ``os.PathLike``.
Folder = Union[str, bytes, "os.PathLike[str]"]


class Error(Exception):
    """A failure of the engine that is not bad input (a GPU that failed,
    a folder that cannot be written, ...)."""


class InputError(Error, ValueError):
    """Bad input: the message is the command line's one line, naming the
    file or argument, the line, row or lane, the parameter and what is
    allowed. Nothing was written."""


def _display(text: Union[str, bytes]) -> str:
    """`text` (a path or input) as a message shows it: a name the OS gave
    that is not UTF-8, or a lone surrogate, as U+FFFD (as Rust's
    `Path::display` shows it)."""
    if isinstance(text, bytes):
        return text.decode("utf-8", "replace")
    try:
        return os.fsencode(text).decode("utf-8", "replace")
    except UnicodeEncodeError:
        return re.sub("[\ud800-\udfff]", "\ufffd", text)


def _line(file: Union[str, bytes], at: Optional[str], param: Optional[str], msg: str) -> str:
    """The command line's one line of bad input in `file` (a file, or an
    argument's name), made as the engine makes it: control characters
    escaped (a path with a line break stays one line), a long parameter
    cut."""
    return _tswm.input_line(
        _display(file),
        None if at is None else _display(at),
        None if param is None else _display(param),
        _display(msg),
    )


def _input(file: Union[str, bytes], at: Optional[str], param: Optional[str], msg: str) -> "InputError":
    return InputError(_line(file, at, param, msg))


def _shown(text: Any, max: int = 40) -> str:
    """Input quoted in a message: one line, at most `max` characters."""
    return _tswm.shown(_display(str(text)), max)


def _raise(e: Exception, lines: Optional[List[str]] = None) -> "NoReturn":  # type: ignore[name-defined]
    """The package's exception for the engine's failure `e`; for a sweep
    given as a dict (`lines`: the key path of each line of its TOML), a
    line is named by its key path."""
    kind, message, file, at, param, msg = e.args
    if kind == "stopped":
        raise KeyboardInterrupt(message) from None
    if kind != "input":
        raise Error(message) from None
    by_key = lines is not None and at is not None and file == "sweep"
    if file is None or not by_key:
        raise InputError(message) from None

    # A line of the dict's TOML is named by its key path instead.
    def path(m: "re.Match[str]") -> str:
        n = int(m.group(1))
        return lines[n - 1] if 1 <= n <= len(lines) else m.group(0)

    at = re.sub(r"line (\d+)", path, at)
    raise InputError(_line(file, at, param, msg)) from None


def _path(value: Any, name: str, allowed: str) -> str:
    """A path argument (`str`, `bytes` or `os.PathLike`) as the engine takes
    it: a `str`, a name the OS gave that is not UTF-8 kept as `os.fsdecode`
    keeps it (so the engine gets its bytes again)."""
    try:
        p = os.fspath(value)
    except TypeError:
        raise TypeError(
            f"{name}: {type(value).__name__} is not a path; allowed: {allowed}"
        ) from None
    if isinstance(p, bytes):
        p = os.fsdecode(p)
    if p == "":
        raise _input(name, None, None, f"the path is empty; allowed: {allowed}")
    if "\0" in p:
        raise _input(name, None, None, f"`{_shown(p)}` holds a NUL character; allowed: {allowed}")
    try:
        os.fsencode(p)
    except UnicodeEncodeError as e:
        raise _input(
            name,
            None,
            None,
            f"`{_shown(p)}` holds a lone surrogate (U+{ord(p[e.start]):04X}), which no file name "
            f"holds; allowed: {allowed}",
        ) from None
    return p


def _utf8(text: str, name: str, lines: Optional[List[str]] = None) -> str:
    """TOML text `text`, checked to be text (a lone surrogate is not):
    the engine's line for a file that is not UTF-8 otherwise."""
    try:
        text.encode("utf-8")
    except UnicodeEncodeError as e:
        n = text.count("\n", 0, e.start) + 1
        c = ord(text[e.start])
        what = f"byte 0x{c - 0xDC00:02x}" if 0xDC80 <= c <= 0xDCFF else f"U+{c:04X} (a lone surrogate)"
        at = lines[n - 1] if lines is not None and 1 <= n <= len(lines) else f"line {n}"
        raise _input(name, at, None, f"{what} is not UTF-8 text; a sweep is TOML, UTF-8 encoded") from None
    return text


def _sweep_args(sweep: Optional[Sweep]) -> Tuple[Optional[str], Optional[str], Optional[List[str]]]:
    """(path, TOML text, key paths of its lines) of a sweep argument."""
    if sweep is None:
        return None, None, None
    if isinstance(sweep, dict):
        try:
            text, lines = dict_to_toml(sweep)
        except TypeError as e:
            raise InputError(_tswm.shown(_display(str(e)), 100_000)) from None
        return None, _utf8(text, "sweep", lines), lines
    if isinstance(sweep, (os.PathLike, bytes)):
        return _path(sweep, "sweep", "a sweep file's path, its TOML text or a dict"), None, None
    if isinstance(sweep, str):
        # TOML text has a line break, a key or a table; a path has none.
        if "\n" in sweep or "=" in sweep or sweep.lstrip().startswith("["):
            return None, _utf8(sweep, "sweep"), None
        return _path(sweep, "sweep", "a sweep file's path, its TOML text or a dict"), None, None
    raise TypeError(
        f"sweep: {type(sweep).__name__} is not a sweep; allowed: a path, TOML text or a dict"
    )


#: What a lane table may be, for the errors that say so.
_LANE_TABLES = (
    "a CSV path, a pandas or polars DataFrame (or LazyFrame), a pyarrow Table or RecordBatch, "
    "a named pandas or polars Series (one column), or an object with __arrow_c_stream__"
)

#: What a lane table's column may hold, for the errors that say so.
_CELLS = "numbers (any integer or float type) or words (the laws, a friction table's name)"


def _lanes_args(lanes: Optional[Lanes]) -> Tuple[Optional[str], Optional[pa.Table]]:
    """(path, table) of a lanes argument: a CSV file, or a table in memory
    as a pyarrow Table the engine reads (numbers int or float, words
    strings; missing values, None or NaN, "not set")."""
    if lanes is None:
        return None, None
    if isinstance(lanes, (str, bytes, os.PathLike)):
        return _path(lanes, "lanes", "a CSV lane table's path, or a table"), None
    return None, _normalised(_arrow_table(lanes))


def _arrow_table(lanes: Any) -> pa.Table:
    """A lane table in memory as a pyarrow Table (not yet normalised)."""
    top = type(lanes).__module__.split(".")[0]
    if top == "pandas":
        import pandas as pd

        if isinstance(lanes, pd.Series):
            lanes = _pandas_series(lanes)
        if isinstance(lanes, pd.DataFrame):
            return _from_pandas(lanes)
    elif top == "polars":
        import polars as pl

        if isinstance(lanes, pl.LazyFrame):
            lanes = lanes.collect()
        if isinstance(lanes, pl.Series):
            if not lanes.name:
                raise TypeError(
                    "lanes: a polars Series without a name is not a lane table (its name is its "
                    f"parameter's: pl.Series(\"f2\", [...])); allowed: {_LANE_TABLES}"
                )
            lanes = lanes.to_frame()
        if isinstance(lanes, pl.DataFrame):
            return lanes.to_arrow()
    elif top == "dask":
        raise TypeError(
            "lanes: a dask DataFrame is many lane tables: run tswm.run on each partition "
            f"(map_partitions, see docs/python.md); allowed: {_LANE_TABLES}"
        )
    elif isinstance(lanes, pa.Table):
        return lanes
    elif isinstance(lanes, pa.RecordBatch):
        return pa.Table.from_batches([lanes])
    elif hasattr(lanes, "__arrow_c_stream__") and not isinstance(lanes, pa.ChunkedArray):
        try:
            return pa.table(lanes)
        except (TypeError, ValueError, pa.ArrowException):
            pass
    raise TypeError(f"lanes: {type(lanes).__name__} is not a lane table; allowed: {_LANE_TABLES}")


def _pandas_series(s: Any) -> Any:
    """A pandas Series as a one-column DataFrame, where that is what it
    must be: named (by its parameter), its index not of names (a row of a
    DataFrame, `df.iloc[0]`, has its columns' names as its index)."""
    named = isinstance(s.name, str) and s.name != ""
    row_like = len(s.index) > 0 and all(isinstance(k, str) for k in s.index)
    if named and not row_like:
        return s.to_frame()
    why = (
        "its index holds names, as a row of a DataFrame does (for one lane, pass df.iloc[[i]] "
        "or series.to_frame().T)"
        if row_like
        else "it has no name (its name is its parameter's: pd.Series([...], name=\"f2\"))"
    )
    raise TypeError(f"lanes: a pandas Series is a lane table only as one column, and {why}; allowed: {_LANE_TABLES}")


def _from_pandas(df: Any) -> pa.Table:
    """A pandas DataFrame as a pyarrow Table, column by column: a column
    of numbers and words mixed (object dtype) becomes words, each number
    written as the text that reads back to it (the engine reads a number
    of a word column as a CSV lane table's cell)."""
    names = [str(c) for c in df.columns]
    seen = set()
    for n in names:
        if n in seen:
            raise _input("lanes", None, n, "column appears twice")
        seen.add(n)
    arrays = []
    for i, name in enumerate(names):
        col = df.iloc[:, i]
        arrays.append(_pandas_column(col, name))
    # A name that is not text (a lone surrogate) is no parameter's name:
    # shown as the engine shows it, it is refused as an unknown column.
    return pa.Table.from_arrays(arrays, names=[_display(n) for n in names])


def _pandas_column(col: Any, name: str) -> pa.Array:
    import numpy as np

    if col.dtype.kind == "f" and col.dtype.itemsize > 8:
        # long double: more than the engine's f64 holds; its nearest f64.
        col = col.astype("float64")
    try:
        return pa.array(col, from_pandas=True)
    except (pa.ArrowException, UnicodeEncodeError, TypeError, ValueError):
        pass
    if col.dtype == object or col.dtype.kind in "OSU" or str(col.dtype) in ("str", "string"):
        return _word_column(col.astype(object), name)
    raise _input("lanes", None, name, f"holds {col.dtype}; allowed: {_CELLS}")


def _word_column(col: Any, name: str) -> pa.Array:
    """An object column (numbers and words mixed, or words that are not
    text) as words: a number as the text that reads back to it, a missing
    value (None, NaN, pd.NA) as not set, a lone surrogate as U+FFFD (no
    law or table name holds one: the engine refuses the cell)."""
    out: List[Optional[str]] = []
    for lane, v in enumerate(col):
        if v is None or (isinstance(v, float) and math.isnan(v)) or _is_na(v):
            out.append(None)
        elif isinstance(v, str):
            out.append(_display(v))
        elif isinstance(v, bool) or type(v).__name__ == "bool_":
            raise _input("lanes", f"lane {lane}", name, f"`{v}` is a boolean; allowed: {_CELLS}")
        elif isinstance(v, numbers.Integral):
            out.append(str(int(v)))
        elif isinstance(v, numbers.Real):
            x = float(v)
            out.append(None if math.isnan(x) else repr(x))
        else:
            raise _input(
                "lanes", f"lane {lane}", name, f"holds a {type(v).__name__} (`{_shown(v)}`); allowed: {_CELLS}"
            )
    return pa.array(out, pa.string())


def _is_na(v: Any) -> bool:
    """pandas' missing value (pd.NA, pd.NaT) or numpy's NaN scalar."""
    if type(v).__name__ in ("NAType", "NaTType"):
        return True
    return isinstance(v, numbers.Real) and not isinstance(v, numbers.Integral) and math.isnan(float(v))


def _normalised(t: pa.Table) -> pa.Table:
    """A lane table as the engine reads it: dictionary (categorical) columns
    as their values, a column of no values (every cell None: not set) as
    words, float16 as f32, decimals as f64; other types as they are (the
    engine names a column of a type it does not take)."""
    fields, columns = [], []
    for f, col in zip(t.schema, t.columns):
        while pa.types.is_dictionary(col.type):
            col = pa.chunked_array([c.dictionary_decode() for c in col.chunks], type=col.type.value_type)
        if pa.types.is_null(col.type):
            col = col.cast(pa.string())
        elif pa.types.is_float16(col.type):
            col = col.cast(pa.float32())
        elif pa.types.is_decimal(col.type):
            col = col.cast(pa.float64())
        fields.append(pa.field(f.name, col.type))
        columns.append(col)
    return pa.Table.from_arrays(columns, schema=pa.schema(fields))


def _threads(threads: Any) -> Optional[int]:
    """The `threads` argument, checked: None or a whole number from 1 to
    the engine's most."""
    if threads is None:
        return None
    if isinstance(threads, bool) or type(threads).__name__ == "bool_":
        raise TypeError(f"threads: a bool is not a thread count; allowed: 1 to {_tswm.MAX_THREADS}, or None")
    try:
        n = operator.index(threads)
    except TypeError:
        raise TypeError(
            f"threads: {type(threads).__name__} is not a whole number; allowed: 1 to "
            f"{_tswm.MAX_THREADS}, or None (all cores)"
        ) from None
    if not 1 <= n <= _tswm.MAX_THREADS:
        cores = os.cpu_count() or 1
        raise _input(
            "threads",
            None,
            None,
            f"{_shown(n)} is not allowed; allowed: 1 to {_tswm.MAX_THREADS} (this machine runs "
            f"{cores} at once; None, the default, uses them all)",
        )
    return n


def _tol(tol: Any) -> Optional[float]:
    """The `tol` argument as a float (the engine checks its range)."""
    if tol is None:
        return None
    if isinstance(tol, bool) or not isinstance(tol, numbers.Real):
        raise TypeError(f"tol: {type(tol).__name__} is not a number; allowed: a float, or None")
    try:
        return float(tol)
    except OverflowError:
        # An integer past the floats: as far out of range as infinity.
        return math.inf if tol > 0 else -math.inf


def _word(value: Any, name: str, allowed: str) -> str:
    """A word argument (`backend`, `format`) as the engine takes it."""
    if not isinstance(value, str):
        raise TypeError(f"{name}: {type(value).__name__} is not a word; allowed: {allowed}")
    return _display(value)


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


#: The GPU's arithmetic, as `precision` names it.
_PRECISIONS = "auto, f32, f64"

#: What `out` may be, for the errors that say so.
_OUT = "a folder's path: a new or empty folder, or the folder of an earlier tswm run"


def run(
    sweep: Optional[Sweep] = None,
    *,
    lanes: Optional[Lanes] = None,
    backend: str = "auto",
    threads: Optional[int] = None,
    tol: Optional[float] = None,
    precision: str = "auto",
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
            columns: a CSV path, a pandas or polars DataFrame (or LazyFrame,
            or a named Series: one column) or a pyarrow Table; numbers of
            any integer or float type, words (categorical too); a missing
            value (None, NaN) means "not set".
        backend: ``"auto"``, ``"cpu"`` (the f64 path) or ``"gpu"``.
        threads: CPU threads (default: all cores).
        tol: the f64 path's per-step tolerance (1e-13 to 1e-4; 1e-8 by
            default).
        precision: the GPU's arithmetic: ``"auto"`` (f64 where the
            adapter has it and a trial finds it no slower, else f32),
            ``"f32"`` (rows within 5e-5, each checked, the untrusted ones
            recomputed in f64) or ``"f64"`` (the CPU path's bound, 1e-6;
            an adapter without 64-bit floats is refused).
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
        _word(backend, "backend", "auto, cpu, gpu"),
        _threads(threads),
        _tol(tol),
        _word(precision, "precision", _PRECISIONS),
        None if out is None else _path(out, "out", _OUT),
        _word(format, "format", "csv, parquet"),
        report,
    )


def read(dir: Folder) -> pa.Table:
    """The results table of a run's folder (``lanes.csv`` or
    ``lanes.parquet``), as :func:`run` returns it."""
    d = _path(dir, "dir", "a folder written by `tswm run` or `tswm merge`")
    try:
        return _tswm.read(d)
    except _tswm.Failure as e:
        _raise(e)


#: The Arrow type of each kind of cell.
_KIND_TYPES = {"float": pa.float64(), "int": pa.int64(), "text": pa.string()}


def _folder(dir: Folder) -> str:
    """A run's folder argument, checked to be a folder."""
    d = _path(dir, "dir", "a folder written by `tswm run` or `tswm merge`")
    if not os.path.isdir(d):
        raise _input(d, None, None, "is not a folder; allowed: a folder written by `tswm run` or `tswm merge`")
    return d


def _stats_table(dir: Folder, name: str, what: str) -> pa.Table:
    """`name` (summary.csv or sensitivity.csv) of a run's folder, read with
    its declared columns: numbers float64 or int64, words strings (`NA`,
    `null` or `true` are words, never a null or a bool), an empty cell a
    null; anything else is bad input naming the file, line and column."""
    import pyarrow.csv as pcsv

    d = _folder(dir)
    path = os.path.join(d, name)
    if not os.path.isfile(path):
        raise _input(d, None, None, f"holds no {name}; {what}")
    header, kinds = _stats_header(path, name)
    try:
        # A file object: pyarrow takes no path that is not UTF-8.
        with open(path, "rb") as f:
            return pcsv.read_csv(
                f,
                read_options=pcsv.ReadOptions(use_threads=True),
                parse_options=pcsv.ParseOptions(newlines_in_values=True),
                convert_options=pcsv.ConvertOptions(
                    column_types={n: _KIND_TYPES[k] for n, k in zip(header, kinds)},
                    null_values=[""],
                    strings_can_be_null=True,
                    quoted_strings_can_be_null=True,
                ),
            )
    except (pa.ArrowException, UnicodeError) as e:
        raise _stats_bad_cell(path, header, kinds, e) from None


def _stats_header(path: str, name: str) -> Tuple[List[str], List[str]]:
    """The header of `path` (a `name` of a run's folder), checked against
    the columns the engine writes; the columns and their kinds."""
    import csv

    before, after = _tswm.stats_columns(name)
    params = dict(_tswm.param_columns())
    allowed = ",".join(n for n, _ in before)
    if name == "summary.csv":
        allowed += ", the grid's parameters, then " + ",".join(n for n, _ in after)
    with open(path, encoding="utf-8", errors="replace", newline="") as f:
        header = next(csv.reader(f), None)
    if header is None:
        raise _input(path, None, None, f"is empty; allowed: the {name} tswm writes (a header line: {allowed})")
    wrong = _input(path, "line 1", "header", f"allowed: {allowed}")
    head, tail = header[: len(before)], header[len(header) - len(after) :] if after else []
    axes = header[len(before) : len(header) - len(after)]
    if len(header) < len(before) + len(after) or head != [n for n, _ in before] or tail != [n for n, _ in after]:
        raise wrong
    if name != "summary.csv" and axes:
        raise wrong
    for i, a in enumerate(axes):
        if a not in params or a in axes[:i]:
            raise _input(
                path,
                "line 1",
                a,
                "is not a parameter of the grid (or is named twice); allowed: "
                + allowed,
            )
    kinds = [k for _, k in before] + [params[a] for a in axes] + [k for _, k in after]
    return header, kinds


def _stats_bad_cell(path: str, header: List[str], kinds: List[str], e: Exception) -> "InputError":
    """The first bad line of `path` (pyarrow, which refused it as `e`,
    names no line): its cell that is not of its column's kind, or its
    count of cells."""
    import csv

    with open(path, encoding="utf-8", newline="") as f:
        rd = csv.reader(f)
        try:
            next(rd)
            for row in rd:
                at = f"line {rd.line_num}"
                if len(row) != len(header):
                    return _input(path, at, None, f"holds {len(row)} cells; allowed: {len(header)}, one a column")
                for cell, col, kind in zip(row, header, kinds):
                    if kind == "text" or cell == "":
                        continue
                    try:
                        pa.array([cell], pa.string()).cast(_KIND_TYPES[kind])
                    except pa.ArrowException:
                        what = "a number" if kind == "float" else "a whole number"
                        return _input(path, at, col, f"`{_shown(cell)}` is not {what}; allowed: {what}, or empty")
        except UnicodeDecodeError:
            return _input(path, f"line {rd.line_num + 1}", None, "is not UTF-8 text; a tswm CSV file is")
    return _input(path, None, None, f"is not a CSV file tswm wrote ({_shown(str(e), 120)})")


def summary(dir: Folder) -> pa.Table:
    """``summary.csv`` of a run's folder: statistics per group (a grid
    point of a sampled sweep, or the whole run), as a pyarrow Table."""
    return _stats_table(dir, "summary.csv", "every tswm run writes one (a shard does not)")


def sensitivity(dir: Folder) -> pa.Table:
    """``sensitivity.csv`` of a run's folder: Sobol' indices per grid
    point, result and input (a ``[sensitivity]`` design), as a pyarrow
    Table."""
    return _stats_table(
        dir, "sensitivity.csv", "a run of a sweep with a [sensitivity] design writes one"
    )


class Report:
    """A run's ``report.html``: ``path``, the page's text (``html()``),
    shown inline in Jupyter. ``path`` is the file as the OS names it: a
    ``str`` (a folder name that is not UTF-8 as :func:`os.fsdecode` gives
    it, so :func:`os.fsencode` gives its bytes), or ``bytes`` where the
    folder was given as bytes."""

    def __init__(self, path: Union[str, bytes]):
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
    d = _path(dir, "dir", "a folder written by `tswm run` or `tswm merge`")
    try:
        path = _tswm.report(d)
    except _tswm.Failure as e:
        _raise(e)
    # As the caller named the folder: bytes for bytes, else a str.
    return Report(os.fsencode(path) if isinstance(os.fspath(dir), bytes) else os.fspath(path))


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
    precision: str = "auto",
    progress: Optional[bool] = None,
) -> Check:
    """Runs the lanes on the GPU and on the f64 CPU path and compares
    every row against the bounds of ``tswm check``: the f32 path's, or with
    ``precision="f64"`` the f64 path's (1e-6, every lane; the CPU at the
    same tolerances); a missed bound is ``passed = False``, not an error.
    Raises :class:`Error` when there is no GPU, and :class:`InputError`
    for ``"f64"`` on an adapter without 64-bit floats."""
    return Check(
        _engine(
            _tswm.check,
            sweep,
            lanes,
            progress,
            _threads(threads),
            _tol(tol),
            _word(precision, "precision", _PRECISIONS),
        )
    )


def bench(
    sweep: Optional[Sweep] = None,
    *,
    lanes: Optional[Lanes] = None,
    backend: str = "auto",
    threads: Optional[int] = None,
    tol: Optional[float] = None,
    precision: str = "auto",
    progress: Optional[bool] = None,
) -> Dict[str, Any]:
    """Integrates the lanes, writing nothing: ``{"lanes", "seconds",
    "lanes_per_second", "backend"}`` (the lanes' check before is not
    timed)."""
    return _engine(
        _tswm.bench,
        sweep,
        lanes,
        progress,
        _word(backend, "backend", "auto, cpu, gpu"),
        _threads(threads),
        _tol(tol),
        _word(precision, "precision", _PRECISIONS),
    )


def devices() -> Dict[str, Any]:
    """The CPU path (``{"threads", "lanes", "width"}``) and the GPU
    adapters (name, type, API, driver, whether hardware, the limits a
    run's work is sized by, and the work a run gets), as ``tswm
    devices`` lists them."""
    try:
        return _tswm.devices()
    except _tswm.Failure as e:
        _raise(e)
