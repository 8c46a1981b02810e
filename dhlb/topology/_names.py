"""Naming simplices in error messages, in the input vertex labels the user knows.

One home for what the topology, forms and bundles messages say about a simplex: its kind
(``"edge"``), its labels (``(7, 9)``), both (``"edge (7, 9)"``), and attaching the offending
simplex to a typed error.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, NoReturn

if TYPE_CHECKING:
    from dhlb.topology._protocol import ComplexLike

__all__ = ["kind_name", "simplex_labels", "simplex_name", "described_simplex", "raise_at"]

_KINDS = {0: "vertex", 1: "edge", 2: "triangle", 3: "tetrahedron"}


def kind_name(k: int) -> str:
    """``"vertex"``, ``"edge"``, ``"triangle"``, ``"tetrahedron"``, else ``"k-simplex"``.

    Examples
    --------
    >>> kind_name(2), kind_name(5)
    ('triangle', '5-simplex')
    """
    return _KINDS.get(k, f"{k}-simplex")


def simplex_labels(X: ComplexLike, k: int, row: int) -> tuple:
    """The k-simplex with row ``row`` as a tuple of input vertex labels.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> simplex_labels(SimplicialComplex([(3, 7, 9)]), 1, 2)
    (7, 9)
    """
    return tuple(int(v) for v in X.vertex_labels[X.simplices(k)[int(row)]])


def simplex_name(X: ComplexLike, k: int, row: int) -> str:
    """``"(a, b, ...)"`` in input vertex labels for the k-simplex with row ``row``.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> simplex_name(SimplicialComplex([(3, 7, 9)]), 1, 2)
    '(7, 9)'
    """
    return "(" + ", ".join(map(str, simplex_labels(X, k, row))) + ")"


def described_simplex(X: ComplexLike, k: int, row: int) -> str:
    """Kind and labels: ``"vertex 3"``, ``"edge (7, 9)"``, ``"triangle (3, 7, 9)"``.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(3, 7, 9)])
    >>> described_simplex(X, 0, 0), described_simplex(X, 1, 2)
    ('vertex 3', 'edge (7, 9)')
    """
    labels = simplex_labels(X, k, row)
    return f"vertex {labels[0]}" if k == 0 else f"{kind_name(k)} {labels}"


def raise_at(err: Exception, simplex: tuple, k: int) -> NoReturn:
    """Attach the offending simplex (input labels) and its dimension to a typed error and raise it."""
    err.simplex, err.k = simplex, k
    raise err
