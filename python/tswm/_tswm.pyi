"""Type stubs of tswm._tswm, the Rust extension under the tswm package.
Its functions take the arguments the package has normalised; call the
package's functions (tswm.run, ...) instead."""

import os
from typing import Any, Callable, Dict, List, Optional, Tuple

import pyarrow as pa

__version__: str
#: The most CPU threads a run takes.
MAX_THREADS: int

class Failure(Exception):
    """(kind, message, file, at, param, msg); kind: "input", "stopped" or "error"."""

Progress = Optional[Callable[[str, int, int], None]]

# Where a call's lanes come from: (sweep path, sweep TOML text, the name
# the text is called in errors, lane-table path, lane table, its name).
LaneSource = Tuple[Optional[str], Optional[str], str, Optional[str], Optional[pa.Table], str]

def run(
    source: LaneSource,
    backend_name: str,
    threads: Optional[int],
    tol: Optional[float],
    precision: str,
    out: Optional[str],
    format: str,
    report: bool,
    progress: Progress,
) -> pa.Table: ...
def read(dir: str) -> pa.Table: ...
def report(dir: str) -> "os.PathLike[str]": ...  # a pathlib.Path, as the OS names the file
def input_line(file: str, at: Optional[str], param: Optional[str], msg: str) -> str: ...
def shown(text: str, max: int) -> str: ...
# (name, kind): kind "float", "int" or "text".
def param_columns() -> List[Tuple[str, str]]: ...
def stats_columns(file: str) -> Tuple[List[Tuple[str, str]], List[Tuple[str, str]]]: ...
def bench(
    source: LaneSource,
    backend_name: str,
    threads: Optional[int],
    tol: Optional[float],
    precision: str,
    progress: Progress,
) -> Dict[str, Any]: ...
def check(
    source: LaneSource,
    threads: Optional[int],
    tol: Optional[float],
    precision: str,
    progress: Progress,
) -> Dict[str, Any]: ...
def devices() -> Dict[str, Any]: ...
