"""Plain text lists of simplices: one simplex per line, whitespace-separated integer vertex labels.

Blank lines and everything after ``#`` are ignored; lines may have different lengths (simplices
of mixed dimensions). Labels are non-negative integers; they need not be contiguous.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import InvalidSimplexError, MeshParseError
from dhlb.io._text import content_lines, no_gc, read_text, to_array
from dhlb.io.atomic import atomic_write

if TYPE_CHECKING:
    from collections.abc import Iterable, Sequence

    from numpy.typing import ArrayLike

    from dhlb.topology.complex import SimplicialComplex

__all__ = ["read_simplices", "parse_simplices_text", "write_simplices"]


@no_gc
def parse_simplices_text(text: str, source: str = "<string>") -> list[tuple[int, ...]]:
    r"""Parse the text of a simplex list (see :func:`read_simplices`); ``source`` names it in errors.

    Parameters
    ----------
    text : str
        One simplex per line as whitespace-separated non-negative integer vertex labels; ``#`` starts a comment.
    source : str, optional
        The name of the text (a file name) in the messages of errors.

    Returns
    -------
    list of tuple of int
        The simplices in text order, vertices as written.

    Raises
    ------
    MeshParseError
        No simplices, a token that is not an integer, a negative label, or a repeated vertex within a line;
        the message names ``source`` and the line.

    Examples
    --------
    >>> parse_simplices_text("# a triangle and a dangling edge\n0 1 2\n2 3  # edge\n")
    [(0, 1, 2), (2, 3)]
    >>> parse_simplices_text("0 1 2\n1 1 3\n", "cx.txt")
    Traceback (most recent call last):
    ...
    dhlb.errors.MeshParseError: cx.txt, line 2: simplex (1, 1, 3) repeats vertex 1; a k-simplex needs ...
    """
    by_len: dict[int, tuple[list, list, list]] = {}
    n = 0
    for line, toks in content_lines(text):
        rows, lines, order = by_len.setdefault(len(toks), ([], [], []))
        rows.append(toks)
        lines.append(line)
        order.append(n)
        n += 1
    if n == 0:
        raise MeshParseError("no simplices found (the file is empty or only has comments)", source)
    out: list = [None] * n
    for length, (rows, lines, order) in by_len.items():
        arr = to_array(rows, lines, np.int64, source, "vertex label")
        neg = np.flatnonzero((arr < 0).any(axis=1))
        if neg.size:
            i = int(neg[0])
            raise MeshParseError(f"vertex labels must be non-negative, found {arr[i].min()}", source, lines[i])
        srt = np.sort(arr, axis=1)
        rep = np.flatnonzero((srt[:, 1:] == srt[:, :-1]).any(axis=1)) if length > 1 else np.zeros(0, int)
        if rep.size:
            i = int(rep[0])
            dup = int(srt[i, 1:][srt[i, 1:] == srt[i, :-1]][0])
            raise MeshParseError(
                f"simplex {tuple(arr[i].tolist())} repeats vertex {dup}; a k-simplex needs k+1 distinct vertices",
                source,
                lines[i],
            )
        for pos, row in zip(order, arr.tolist()):
            out[pos] = tuple(row)
    return out


def read_simplices(path: str | os.PathLike[str]) -> list[tuple[int, ...]]:
    """Read a plain text list of simplices.

    Parameters
    ----------
    path : str or path-like
        One simplex per line as whitespace-separated non-negative integer vertex labels;
        ``#`` starts a comment; mixed dimensions are allowed.

    Returns
    -------
    list of tuple of int
        The simplices in file order, vertices as written.

    Raises
    ------
    MeshParseError
        Empty file, a token that is not an integer, a negative label, or a repeated vertex
        within a line; the message names the line.

    Examples
    --------
    >>> import os, tempfile
    >>> from dhlb.io import read_simplices, write_simplices
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = os.path.join(d, "x.txt")
    ...     write_simplices(p, [(0, 1, 2), (2, 3), (7,)])
    ...     read_simplices(p)
    [(0, 1, 2), (2, 3), (7,)]
    """
    path = os.fspath(path)
    return parse_simplices_text(read_text(path), path)


def write_simplices(
    path: str | os.PathLike[str], simplices: SimplicialComplex | Iterable[Sequence[int]] | ArrayLike
) -> None:
    """Write simplices (an iterable of vertex tuples, or an int array) one per line.

    Parameters
    ----------
    path : str or path-like
        The output file, written atomically (:func:`~dhlb.io.atomic_write`); its folder must exist.
    simplices : iterable of sequence of int, or (m, k+1) int array
        The simplices; each is written as its vertex labels in the given order.

    Raises
    ------
    InvalidSimplexError
        A simplex is empty or has a label that is not a non-negative integer (``bool`` included).
    OutputError
        The file cannot be written; nothing is left at ``path``.

    Examples
    --------
    >>> import os, tempfile, numpy as np
    >>> from dhlb.io import write_simplices
    >>> with tempfile.TemporaryDirectory() as d:
    ...     write_simplices(os.path.join(d, "x.txt"), np.array([[0, 1], [1, 2]]))
    ...     print(open(os.path.join(d, "x.txt")).read(), end="")
    0 1
    1 2
    """
    lines = []
    for i, s in enumerate(np.asarray(simplices).tolist() if isinstance(simplices, np.ndarray) else simplices):
        row = [s] if np.ndim(s) == 0 else list(s)
        if not row or any(isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 0 for v in row):
            raise InvalidSimplexError(f"simplex #{i} {s!r} must be a non-empty tuple of non-negative integers")
        lines.append(" ".join(str(int(v)) for v in row))
    with atomic_write(path, "w", encoding="ascii") as fh:
        fh.write("".join(line + "\n" for line in lines))
