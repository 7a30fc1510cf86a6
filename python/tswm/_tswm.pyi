"""Type stubs of tswm._tswm, the Rust extension under the tswm package.
Its functions take the arguments the package has normalised; call the
package's functions (tswm.run, ...) instead."""

from typing import Any, Callable, Dict, Optional

import pyarrow as pa

__version__: str

class Failure(Exception):
    """(kind, message, file, at, param, msg); kind: "input", "stopped" or "error"."""

Progress = Optional[Callable[[str, int, int], None]]

def run(
    sweep_path: Optional[str],
    sweep_text: Optional[str],
    sweep_name: str,
    lanes_path: Optional[str],
    lanes_table: Optional[pa.Table],
    lanes_name: str,
    backend_name: str,
    threads: Optional[int],
    tol: Optional[float],
    out: Optional[str],
    format: str,
    report: bool,
    progress: Progress,
) -> pa.Table: ...
def read(dir: str) -> pa.Table: ...
def report(dir: str) -> str: ...
def bench(
    sweep_path: Optional[str],
    sweep_text: Optional[str],
    sweep_name: str,
    lanes_path: Optional[str],
    lanes_table: Optional[pa.Table],
    lanes_name: str,
    backend_name: str,
    threads: Optional[int],
    tol: Optional[float],
    progress: Progress,
) -> Dict[str, Any]: ...
def check(
    sweep_path: Optional[str],
    sweep_text: Optional[str],
    sweep_name: str,
    lanes_path: Optional[str],
    lanes_table: Optional[pa.Table],
    lanes_name: str,
    threads: Optional[int],
    tol: Optional[float],
    progress: Progress,
) -> Dict[str, Any]: ...
def devices() -> Dict[str, Any]: ...
