"""The body of a PLY file: one element at a time, ASCII or binary (either byte order).

Private helpers of :mod:`dhlb.io.ply`, which parses the header into the ``_Element`` declarations
defined here (name, count, properties) and reads the body with :func:`ascii_element` or
:func:`binary_element`. Both return ``{property: values}`` per element, a list property as
``(flat values, list lengths, line numbers or None)``; both have a vectorized fast path for
elements whose lists all have the same length. Errors are :class:`~dhlb.errors.MeshParseError`
naming the line (ASCII) or the element instance (binary).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from dhlb.errors import MeshParseError
from dhlb.io._text import to_array, to_flat_int

__all__ = ["ascii_element", "binary_element"]


@dataclass
class _Prop:
    """A property of a PLY element: its name and numpy dtype (and the count dtype of a list property)."""

    name: str
    dtype: str
    count_dtype: str | None = None  # set for list properties


@dataclass
class _Element:
    """A PLY element declared in the header: name, instance count, header line and properties."""

    name: str
    count: int
    line: int
    props: list[_Prop] = field(default_factory=list)


# ---------------------------------------------------------------------------------- ASCII body
def ascii_element(lines, elem: _Element, path: str) -> dict:
    """Parse one element from an iterator of (line, tokens); return {prop: values or (flat, sizes, lines)}."""
    rows, numbers = [], []
    for i in range(elem.count):
        nxt = next(lines, None)
        if nxt is None:
            raise MeshParseError(f"the file ends after {i} of {elem.count} '{elem.name}' lines", path)
        numbers.append(nxt[0])
        rows.append(nxt[1])
    has_list = any(p.count_dtype for p in elem.props)
    if not rows:
        empty = (np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0, np.int64))
        out = {p.name: empty if p.count_dtype else np.zeros(0) for p in elem.props}
        out["__lines__"] = np.zeros(0, np.int64)
        return out
    if not has_list:
        bad = [i for i, r in enumerate(rows) if len(r) != len(elem.props)]
        if bad:
            raise MeshParseError(
                f"'{elem.name}' line has {len(rows[bad[0]])} values, the header declares {len(elem.props)}",
                path, numbers[bad[0]],
            )
        values = to_array(rows, numbers, np.float64, path, f"'{elem.name}' value")
        out = {p.name: values[:, j] for j, p in enumerate(elem.props)}
        out["__lines__"] = np.asarray(numbers)
        return out
    fast = _ascii_fixed_layout(rows, numbers, elem, path)
    if fast is not None:
        return fast
    out: dict = {p.name: ([], []) for p in elem.props}
    for toks, number in zip(rows, numbers):
        pos = 0
        to_array([toks], [number], np.float64, path, f"'{elem.name}' value")
        for p in elem.props:
            if pos >= len(toks):
                raise MeshParseError(f"'{elem.name}' line is too short for its declared properties", path, number)
            if p.count_dtype is None:
                out[p.name][0].append(toks[pos])
                pos += 1
                continue
            count = int(to_array([[toks[pos]]], [number], np.int64, path, "list length")[0, 0])
            if count < 0 or pos + 1 + count > len(toks):
                raise MeshParseError(
                    f"'{elem.name}' list '{p.name}' declares {count} entries but the line has fewer", path, number
                )
            out[p.name][0].append(toks[pos + 1 : pos + 1 + count])
            out[p.name][1].append(count)
            pos += 1 + count
        if pos != len(toks):
            raise MeshParseError(
                f"'{elem.name}' line has {len(toks) - pos} values more than its declared properties", path, number
            )
    result = {"__lines__": np.asarray(numbers)}
    for p in elem.props:
        vals, sizes = out[p.name]
        if p.count_dtype is None:
            result[p.name] = np.array(vals, dtype=np.float64)
        else:
            if p.dtype[0] == "f":
                flat = np.array([float(t) for row in vals for t in row], dtype=np.float64)  # validated above
            else:
                flat = to_flat_int(vals, numbers, path, f"'{p.name}' entry")
            result[p.name] = (flat, np.asarray(sizes, dtype=np.int64), np.asarray(numbers))
    return result


def _ascii_fixed_layout(rows, numbers, elem: _Element, path: str):
    """Fast path: every line has the same length and the same list lengths as the first one.

    Returns the parsed element, or None when the lines differ (the caller then walks them one by one).
    """
    if not rows or any(len(r) != len(rows[0]) for r in rows):
        return None
    table = to_array(rows, numbers, np.float64, path, f"'{elem.name}' value")
    layout, pos = [], 0
    for p in elem.props:
        if pos >= table.shape[1]:
            return None
        if p.count_dtype is None:
            layout.append((p, pos, None))
            pos += 1
            continue
        count = table[0, pos]
        if not np.isfinite(count) or count < 0 or count != int(count):
            return None
        layout.append((p, pos, int(count)))
        pos += 1 + int(count)
    if pos != table.shape[1] or any(c is not None and np.any(table[:, at] != c) for _, at, c in layout):
        return None
    out = {"__lines__": np.asarray(numbers)}
    for p, at, count in layout:
        if count is None:
            out[p.name] = table[:, at]
            continue
        vals = table[:, at + 1 : at + 1 + count]
        if p.dtype[0] != "f":
            frac = np.flatnonzero(np.any((vals != np.round(vals)) | ~np.isfinite(vals), axis=1))
            if frac.size:  # report the token as written
                i = int(frac[0])
                to_array([rows[i][at + 1 : at + 1 + count]], [numbers[i]], np.int64, path, f"'{p.name}' entry")
        out[p.name] = (vals.ravel(), np.full(len(rows), count, dtype=np.int64), np.asarray(numbers))
    return out


# --------------------------------------------------------------------------------- binary body
def binary_element(data: bytes, pos: int, elem: _Element, order: str, path: str):
    """Parse one binary element at byte ``pos``; return ({prop: values or (flat, sizes, None)}, new pos)."""
    n = elem.count
    if not any(p.count_dtype for p in elem.props):
        dt = np.dtype([(f"p{j}", order + p.dtype) for j, p in enumerate(elem.props)])
        _need(data, pos, n * dt.itemsize, elem, path)
        arr = np.frombuffer(data, dtype=dt, count=n, offset=pos)
        return {p.name: arr[f"p{j}"] for j, p in enumerate(elem.props)}, pos + n * dt.itemsize
    if n == 0:
        return {p.name: (np.zeros(0, np.int64), np.zeros(0, np.int64), None) if p.count_dtype else np.zeros(0)
                for p in elem.props}, pos
    # fast path: every instance has the same list lengths as the first one
    fields, cur = [], pos
    for j, p in enumerate(elem.props):
        if p.count_dtype is None:
            fields.append((f"p{j}", order + p.dtype))
            cur += np.dtype(p.dtype).itemsize
            continue
        _need(data, cur, np.dtype(p.count_dtype).itemsize, elem, path)
        c = int(np.frombuffer(data, order + p.count_dtype, 1, cur)[0])
        if c < 0:
            raise MeshParseError(f"'{elem.name}' 0 has a negative list length {c}", path)
        fields.append((f"n{j}", order + p.count_dtype))
        fields.append((f"p{j}", order + p.dtype, (c,)))
        cur += np.dtype(p.count_dtype).itemsize + c * np.dtype(p.dtype).itemsize
    dt = np.dtype(fields)
    if len(data) - pos >= n * dt.itemsize:
        arr = np.frombuffer(data, dtype=dt, count=n, offset=pos)
        counts = {j: arr[f"n{j}"] for j, p in enumerate(elem.props) if p.count_dtype}
        first = {j: dt[f"p{j}"].shape[0] for j in counts}
        if all(np.all(counts[j] == first[j]) for j in counts):
            out = {}
            for j, p in enumerate(elem.props):
                vals = arr[f"p{j}"]
                out[p.name] = vals if p.count_dtype is None else (
                    vals.reshape(-1), np.full(n, first[j], dtype=np.int64), None)
            return out, pos + n * dt.itemsize
    return _binary_element_slow(data, pos, elem, order, path)


def _binary_element_slow(data: bytes, pos: int, elem: _Element, order: str, path: str):
    """Instance-by-instance walk for lists of varying length (offsets only; values gathered at once)."""
    starts = {j: [] for j in range(len(elem.props))}
    counts = {j: [] for j in range(len(elem.props))}
    sizes = [np.dtype(p.dtype).itemsize for p in elem.props]
    csizes = [np.dtype(p.count_dtype).itemsize if p.count_dtype else 0 for p in elem.props]
    for i in range(elem.count):
        for j, p in enumerate(elem.props):
            if p.count_dtype is None:
                _need(data, pos, sizes[j], elem, path, i)
                starts[j].append(pos)
                pos += sizes[j]
                continue
            _need(data, pos, csizes[j], elem, path, i)
            c = int(np.frombuffer(data, order + p.count_dtype, 1, pos)[0])
            if c < 0:
                raise MeshParseError(f"'{elem.name}' {i} has a negative list length {c}", path)
            pos += csizes[j]
            _need(data, pos, c * sizes[j], elem, path, i)
            starts[j].append(pos)
            counts[j].append(c)
            pos += c * sizes[j]
    raw = np.frombuffer(data, dtype=np.uint8)
    out = {}
    for j, p in enumerate(elem.props):
        st = np.asarray(starts[j], dtype=np.int64)
        c = np.asarray(counts[j], dtype=np.int64) if p.count_dtype else np.ones(len(st), np.int64)
        item_start = np.repeat(st, c) + sizes[j] * (np.arange(c.sum()) - np.repeat(np.cumsum(c) - c, c))
        byte_idx = item_start[:, None] + np.arange(sizes[j])[None, :]
        vals = raw[byte_idx.ravel()].view(order + p.dtype) if byte_idx.size else np.zeros(0, p.dtype)
        out[p.name] = vals if p.count_dtype is None else (vals, c, None)
    return out, pos


def _need(data: bytes, pos: int, nbytes: int, elem: _Element, path: str, instance: int | None = None) -> None:
    if pos + nbytes > len(data):
        which = f" (at instance {instance} of {elem.count})" if instance is not None else ""
        raise MeshParseError(
            f"the file is truncated inside element '{elem.name}'{which}: {pos + nbytes - len(data)} bytes "
            f"missing at byte {len(data)} (the header declares {elem.count})",
            path,
        )
