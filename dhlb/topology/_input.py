"""Validation of simplex input: from user iterables/arrays to clean integer rows."""

from __future__ import annotations

import numbers

import numpy as np

from dhlb.errors import EmptyComplexError, InvalidSimplexError, RaggedInputError


def _as_int_row(simplex, position: int) -> np.ndarray:
    try:
        row = np.asarray(simplex)
    except Exception as exc:  # pragma: no cover - numpy rarely fails here
        raise InvalidSimplexError(f"simplex #{position} {simplex!r} is not a sequence of vertex labels") from exc
    if row.ndim == 0:
        row = row.reshape(1)
    if row.ndim != 1:
        raise InvalidSimplexError(f"simplex #{position} {simplex!r} must be a flat sequence of vertex labels")
    return _check_labels(row, lambda: f"simplex #{position} {tuple(row.tolist()) if row.ndim else simplex!r}")


def _check_labels(values: np.ndarray, where) -> np.ndarray:
    """Return ``values`` as int64 after checking they are non-negative integers."""
    if values.size == 0:
        return values.astype(np.int64)
    if values.dtype == bool:
        raise InvalidSimplexError(f"{where()}: vertex labels must be integers, not booleans")
    if np.issubdtype(values.dtype, np.integer):
        if values.dtype == np.uint64 and np.any(values >= np.uint64(2**63)):
            raise InvalidSimplexError(f"{where()}: vertex label {int(values.max())} is too large (labels must be "
                                      "< 2**63); renumber the vertices")
        out = values.astype(np.int64)
    elif np.issubdtype(values.dtype, np.floating):
        if not np.all(np.isfinite(values)):
            raise InvalidSimplexError(f"{where()}: vertex labels must be finite integers (found NaN/inf)")
        if np.any(values != np.round(values)):
            first = values[values != np.round(values)][0]
            raise InvalidSimplexError(f"{where()}: vertex labels must be integers (found {first!r})")
        if np.any(np.abs(values) >= 2.0**63):
            raise InvalidSimplexError(f"{where()}: vertex label {np.abs(values).max():g} is too large (labels must "
                                      "be < 2**63); renumber the vertices")
        out = values.astype(np.int64)
    elif values.dtype == object and all(
        isinstance(v, numbers.Integral) and not isinstance(v, bool) for v in values.ravel()
    ):
        huge = [int(v) for v in values.ravel() if not -(2**63) <= int(v) < 2**63]
        if huge:
            raise InvalidSimplexError(f"{where()}: vertex label {huge[0]} is too large (labels must fit in 64 bits, "
                                      f"< 2**63); renumber the vertices")
        out = values.astype(np.int64)
    else:
        raise InvalidSimplexError(f"{where()}: vertex labels must be integers (got dtype {values.dtype})")
    if np.any(out < 0):
        raise InvalidSimplexError(f"{where()}: vertex labels must be non-negative (found {out[out < 0].ravel()[0]})")
    return out


def _check_repeats(rows: np.ndarray, offsets: np.ndarray | None, originals) -> None:
    """Raise on the first row with a repeated vertex (rows are sorted)."""
    if rows.shape[1] < 2:
        return
    bad = np.nonzero(np.any(rows[:, 1:] == rows[:, :-1], axis=1))[0]
    if bad.size:
        i = int(bad[0])
        pos = int(offsets[i]) if offsets is not None else i
        shown = tuple(int(v) for v in originals(pos))
        raise InvalidSimplexError(
            f"simplex #{pos} {shown} repeats a vertex; a k-simplex needs k+1 distinct vertices"
        )


def parse_simplices(simplices) -> dict[int, np.ndarray]:
    """Turn user input into ``{k: sorted int64 rows (m, k+1)}`` (duplicates allowed).

    Accepts a 2-d integer array (one simplex per row), a list of such arrays (blocks of possibly
    different widths; the fast way to pass several dimensions), or any iterable of vertex
    sequences of possibly different lengths.
    """
    if isinstance(simplices, np.ndarray):
        arr = simplices
        if arr.ndim == 1:
            arr = arr.reshape(-1, 1)
        if arr.ndim != 2:
            raise InvalidSimplexError(
                f"a simplex array must be 2-dimensional (one simplex per row), got shape {arr.shape}"
            )
        if arr.shape[0] == 0 or arr.shape[1] == 0:
            raise EmptyComplexError("no simplices given: pass at least one vertex tuple")
        rows = _check_labels(arr, lambda: "simplex array")
        if rows.shape[1] > 1 and np.any(rows < 0):  # pragma: no cover - checked above
            raise InvalidSimplexError("negative label")
        srt = np.sort(rows, axis=1)
        _check_repeats(srt, None, lambda i: arr[i])
        return {srt.shape[1] - 1: srt}

    if isinstance(simplices, (list, tuple)) and simplices and all(
        isinstance(b, np.ndarray) and b.ndim == 2 for b in simplices
    ):
        # fast path: one 2-d array (m, k+1) per block, e.g. one per dimension
        out: dict[int, list[np.ndarray]] = {}
        for b in simplices:
            if b.shape[0] == 0:
                continue
            if b.shape[1] == 0:
                raise InvalidSimplexError("a block of simplices has rows of length 0")
            block = parse_simplices(b)
            for k, rows in block.items():
                out.setdefault(k, []).append(rows)
        if not out:
            raise EmptyComplexError("no simplices given: pass at least one vertex tuple")
        return {k: np.concatenate(v) for k, v in out.items()}

    try:
        items = list(simplices)
    except TypeError as exc:
        raise InvalidSimplexError(
            f"simplices must be an iterable of vertex tuples or an int array, got {type(simplices).__name__}"
        ) from exc
    if not items:
        raise EmptyComplexError("no simplices given: pass at least one vertex tuple")
    by_len: dict[int, list[int]] = {}
    rows_list = []
    for pos, s in enumerate(items):
        row = _as_int_row(s, pos)
        if row.size == 0:
            raise InvalidSimplexError(f"simplex #{pos} is empty; every simplex needs at least one vertex")
        rows_list.append(row)
        by_len.setdefault(row.size, []).append(pos)
    out = {}
    for length, positions in by_len.items():
        pos_arr = np.asarray(positions)
        block = np.sort(np.stack([rows_list[p] for p in positions]), axis=1)
        _check_repeats(block, pos_arr, lambda p: items[p])
        out[length - 1] = block
    return out


def parse_rows(rows, k: int | None = None, what: str = "simplex") -> np.ndarray:
    """Validate a 2-d array of vertex rows used for look-ups (not sorted)."""
    try:
        arr = np.asarray(rows)
    except ValueError as exc:
        raise RaggedInputError(f"{what} rows have different lengths") from exc
    if arr.dtype == object:
        raise RaggedInputError(f"{what} rows have different lengths or are not integers")
    if arr.ndim == 1:
        arr = arr.reshape(1, -1) if k is None or arr.size == k + 1 else arr.reshape(-1, 1)
    if arr.ndim != 2:
        raise InvalidSimplexError(f"{what} rows must form a 2-d array, got shape {arr.shape}")
    if k is not None and arr.shape[1] != k + 1 and arr.shape[0] > 0:
        raise InvalidSimplexError(f"a {k}-simplex has {k + 1} vertices, got rows of length {arr.shape[1]}")
    return _check_labels(arr, lambda: f"{what} rows")
