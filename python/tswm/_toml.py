"""A sweep given as a dict, written as the TOML of a sweep file, with the
key path of each line: the engine's errors name a line of the file, and
for a dict the key path names it instead (``sweep["grid"][0]["n"]``)."""

from __future__ import annotations

import math
from typing import Any, Dict, List, Tuple

__all__ = ["dict_to_toml"]

#: Tables and lists nested deeper than this are no sweep's (a sweep file
#: nests two tables, `[friction_table.NAME]`, and lists of numbers in them).
MAX_DEPTH = 16


def _too_deep(path: str) -> TypeError:
    shown = path if len(path) <= 80 else path[:80] + "..."
    return TypeError(
        f"{shown}: nested more than {MAX_DEPTH} deep; allowed: a sweep file's tables and lists "
        "(docs/guide.md)"
    )


def _key(k: str) -> str:
    """A TOML key: bare where TOML allows it, else quoted."""
    if k and all(c.isalnum() or c in "-_" for c in k):
        return k
    return _string(k)


def _string(s: str) -> str:
    out = ['"']
    for c in s:
        if c == '"':
            out.append('\\"')
        elif c == "\\":
            out.append("\\\\")
        elif c == "\n":
            out.append("\\n")
        elif c == "\t":
            out.append("\\t")
        elif ord(c) < 0x20 or ord(c) == 0x7F:
            out.append("\\u%04X" % ord(c))
        else:
            out.append(c)
    out.append('"')
    return "".join(out)


def _value(v: Any, path: str, depth: int = 0) -> str:
    """A TOML value (no tables: those are written as sections)."""
    if depth > MAX_DEPTH:
        raise _too_deep(path)
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return _string(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x, f"{path}[{i}]", depth + 1) for i, x in enumerate(v)) + "]"
    if hasattr(v, "item") and callable(v.item):
        # A numpy scalar.
        return _value(v.item(), path)
    raise TypeError(f"{path}: {type(v).__name__} is not a TOML value; allowed: numbers, strings, booleans, lists")


def _is_table_list(v: Any) -> bool:
    return isinstance(v, (list, tuple)) and len(v) > 0 and all(isinstance(x, dict) for x in v)


def dict_to_toml(sweep: Dict[str, Any], name: str = "sweep") -> Tuple[str, List[str]]:
    """The TOML text of `sweep` and, for each line (from line 1), the key
    path it holds (`name["base"]["f2"]`), or its section's path."""
    lines: List[str] = []
    paths: List[str] = []

    def emit(text: str, path: str) -> None:
        lines.append(text)
        paths.append(path)

    def table(d: Dict[str, Any], dotted: str, array: bool, path: str, depth: int) -> None:
        """Table `d` named `dotted` ("" for the top), an element of an
        array of tables when `array`, its values' key paths under `path`,
        `depth` tables and lists deep."""
        if depth > MAX_DEPTH:
            raise _too_deep(path)
        if dotted:
            emit(f"[[{dotted}]]" if array else f"[{dotted}]", path)
        plain = [(k, v) for k, v in d.items() if not isinstance(v, dict) and not _is_table_list(v)]
        nested = [(k, v) for k, v in d.items() if isinstance(v, dict) or _is_table_list(v)]
        for k, v in plain + nested:
            if not isinstance(k, str):
                raise TypeError(f"{path}: key {k!r} is not a string")
        for k, v in plain:
            p = f"{path}[{k!r}]"
            emit(f"{_key(k)} = {_value(v, p, depth + 1)}", p)
        for k, v in nested:
            full = f"{dotted}.{_key(k)}" if dotted else _key(k)
            p = f"{path}[{k!r}]"
            if isinstance(v, dict):
                table(v, full, False, p, depth + 1)
            else:
                for i, item in enumerate(v):
                    table(item, full, True, f"{p}[{i}]", depth + 2)

    if not isinstance(sweep, dict):
        raise TypeError(f"{name}: a dict with the sweep file's structure is required")
    table(sweep, "", False, name, 0)
    return "\n".join(lines) + "\n", paths
