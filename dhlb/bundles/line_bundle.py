"""Line bundles: connection forms and the class in Hom(ker ∂₁, F*) (seed part 3, §5–§6).

For a rank-1 bundle the transports are scalars ``η_ij ∈ F*``; in the given frames they *are*
a connection form (Definition 6, base connection = the product connection).  Connection forms
are defined modulo exact forms ``(dg)_ij = g_j / g_i`` (gauge), and by Theorems 3–6

    iso classes of line bundles  ≅  Ω¹(X, F*) / dΩ⁰(X, F*)  ≅  Hom(ker ∂₁, F*),

the last map being restriction of a form to the closed 1-chains.  :class:`LineBundleClass`
stores an element of Hom(ker ∂₁, F*) by its values on the Z-basis of ker ∂₁ formed by the
fundamental cycles of the (deterministic) BFS spanning forest; the group law is the tensor
product.

Examples
--------
>>> from dhlb import SimplicialComplex
>>> from dhlb.bundles import VectorBundle
>>> X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])
>>> L = VectorBundle(X, [2, 1, 1], field=("GF", 5))
>>> c = line_bundle_class(L)
>>> c.values.tolist(), (c * c).values.tolist(), (c * c.inverse()).is_trivial()
([2], [4], True)
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from dhlb.bundles.fields import field_ops
from dhlb.bundles.vector_bundle import VectorBundle
from dhlb.errors import InvalidConnectionError, NotClosedError, NotExactError
from dhlb.topology import graph

if TYPE_CHECKING:
    from typing import Any

    import scipy.sparse as sp
    from numpy.typing import ArrayLike

    from dhlb.topology.complex import SimplicialComplex

__all__ = [
    "LineBundleClass",
    "line_bundle_class",
    "connection_form",
    "form_class",
    "integrate_exact_form",
]


class LineBundleClass:
    """An element of Hom(ker ∂₁, F*): values on the fundamental cycles of the BFS forest.

    Parameters
    ----------
    X : SimplicialComplex
        The complex.
    values : (m,) array_like
        One nonzero F value per non-tree edge of ``spanning_forest(X)`` (``m = forest.nontree.size``).
    field : ``"R"``, ``"C"`` or ``("GF", p)``, default "C"
        The field F.
    atol : float, default 1e-9
        Tolerance of the floating-point comparisons.

    Raises
    ------
    InvalidConnectionError
        ``values`` does not have one entry per fundamental cycle, has a zero, or is not numeric
        (over GF(p): not integer); ``field`` is unknown.
    NonFiniteError
        ``values`` contains NaN or infinity (R, C).

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])
    >>> c = LineBundleClass(X, [-1.0], "R")                         # the Möbius band
    >>> c.bundle().is_trivial(), (c * c).is_trivial(), float(c.evaluate([1, -1, 1]))
    (False, True, -1.0)
    """

    def __init__(self, X: SimplicialComplex, values: ArrayLike, field: str | tuple[str, int] = "C", atol: float = 1e-9):
        self.X = X
        self.ops = field_ops(field, atol)
        self.forest = graph.spanning_forest(X)
        v = self.ops.asarray(np.asarray(values).reshape(-1), "class values")
        if v.size != self.forest.nontree.size:
            raise InvalidConnectionError(
                f"need one value per fundamental cycle ({self.forest.nontree.size}), got {v.size}"
            )
        if np.any(v == 0):
            raise InvalidConnectionError("values of a class in Hom(ker ∂₁, F*) must be nonzero")
        self.values = v

    def _new(self, values) -> LineBundleClass:
        return LineBundleClass(self.X, values, self.ops.spec, self.ops.atol)

    @property
    def cycles(self) -> sp.csr_matrix:
        """The Z-basis of ker ∂₁ the values refer to (sparse rows, see :func:`graph.fundamental_cycles`)."""
        return graph.fundamental_cycles(self.X, self.forest)

    def __mul__(self, other: LineBundleClass) -> LineBundleClass:
        """The class of the tensor product."""
        if self.ops.exact:
            return self._new(self.values * other.values % self.ops.p)
        return self._new(self.values * other.values)

    def inverse(self) -> LineBundleClass:
        """The class of the dual bundle."""
        if self.ops.exact:
            from dhlb.bundles.finite_field import pow_mod

            return self._new(pow_mod(self.values, self.ops.p - 2, self.ops.p))
        return self._new(1.0 / self.values)

    def __eq__(self, other) -> bool:
        if not isinstance(other, LineBundleClass):
            return NotImplemented
        if self.values.shape != other.values.shape or self.ops.name != other.ops.name:
            return False
        return bool(np.all(self.ops.close(self.values[None, :], other.values[None, :])))

    __hash__ = None

    def is_trivial(self) -> bool:
        """True if the class is trivial (value 1 on every fundamental cycle)."""
        return bool(np.all(self.ops.close(self.values[None, :], np.ones((1, self.values.size)))))

    def evaluate(self, cycle: ArrayLike) -> Any:
        """The value ``Π ω_e^{c_e}`` on an integer 1-cycle ``c`` (length n_1).

        A complex number over C, a float over R, an int in ``1 .. p-1`` over GF(p).

        Raises
        ------
        NotClosedError
            if ``c`` is not a cycle.
        """
        c = np.asarray(cycle, dtype=np.int64).reshape(-1)
        if c.size != self.X.n_simplices(1):
            raise NotClosedError(f"a 1-chain has n_1 = {self.X.n_simplices(1)} entries, got {c.size}")
        b = self.X.boundary(1) @ c
        if np.any(b != 0):
            v = int(np.nonzero(b)[0][0])
            raise NotClosedError(
                f"the 1-chain is not a cycle: its boundary is {int(b[v])} at vertex {int(self.X.vertex_labels[v])}"
            )
        w = self.connection_form()
        if self.ops.exact:
            from dhlb.bundles.finite_field import pow_mod

            out = 1
            for e in np.nonzero(c)[0]:
                out = out * int(pow_mod(w[e], int(c[e]) % (self.ops.p - 1), self.ops.p)) % self.ops.p
            return out
        return np.prod(w.astype(np.complex128 if self.ops.name == "C" else np.float64) ** c)

    def connection_form(self) -> np.ndarray:
        """The normalized representative: 1 on tree edges, the class value on each non-tree edge."""
        w = np.ones(self.X.n_simplices(1), self.ops.dtype)
        w[self.forest.nontree] = self.values
        return w

    def bundle(self) -> VectorBundle:
        """A line bundle in this class (Theorem 3 surjectivity)."""
        return VectorBundle(self.X, self.connection_form(), self.ops.spec, atol=self.ops.atol)

    def __repr__(self) -> str:
        return f"LineBundleClass(field={self.ops.spec!r}, values={self.values!r})"


def line_bundle_class(L: VectorBundle) -> LineBundleClass:
    """The class of a rank-1 bundle in Hom(ker ∂₁, F*) (Theorem 6: abelianized monodromy).

    Parameters
    ----------
    L : VectorBundle
        A line bundle (rank 1).

    Returns
    -------
    LineBundleClass
        Its monodromy around the fundamental cycles of ``spanning_forest(L.X)``, in the field of ``L``.

    Raises
    ------
    InvalidConnectionError
        ``L`` does not have rank 1.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])
    >>> line_bundle_class(VectorBundle(X, [2.0, 1.0, 1.0])).values.tolist()
    [2.0]
    """
    if L.rank != 1:
        raise InvalidConnectionError(f"line_bundle_class needs a line bundle (rank 1), got rank {L.rank}")
    return LineBundleClass(L.X, L.monodromy_representation()[:, 0, 0], L.field, L.atol)


def connection_form(L: VectorBundle) -> np.ndarray:
    """A connection form of a line bundle (Definition 6): ``ω_ij = η_ij`` in the given frames.

    Parameters
    ----------
    L : VectorBundle
        A line bundle (rank 1).

    Returns
    -------
    (n_1,) array
        ``ω[e] = η_ij`` for the canonical edge ``e = (i < j)``, in the field's dtype (a copy).

    Raises
    ------
    InvalidConnectionError
        ``L`` does not have rank 1.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])
    >>> connection_form(VectorBundle(X, [2.0, 1.0, 1.0])).tolist()
    [2.0, 1.0, 1.0]
    """
    if L.rank != 1:
        raise InvalidConnectionError(f"connection forms are for line bundles (rank 1), got rank {L.rank}")
    return L.transports[:, 0, 0].copy()


def form_class(
    X: SimplicialComplex, omega: ArrayLike, field: str | tuple[str, int] = "C", atol: float = 1e-9
) -> LineBundleClass:
    """The class of an F*-valued 1-form ``ω`` (per canonical edge) in Hom(ker ∂₁, F*).

    Parameters
    ----------
    X : SimplicialComplex
        The complex.
    omega : (n_1,) array_like
        One nonzero value per edge of ``X.simplices(1)``.
    field : ``"R"``, ``"C"`` or ``("GF", p)``, default "C"
        The field F.
    atol : float, default 1e-9
        Tolerance of the floating-point checks.

    Returns
    -------
    LineBundleClass
        The products of ``ω`` around the fundamental cycles.

    Raises
    ------
    InvalidConnectionError
        ``omega`` has the wrong length, a zero (a singular transport) or non-numeric entries;
        ``field`` is unknown.
    NonFiniteError
        ``omega`` contains NaN or infinity.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])           # cycle = (0,1) + (1,2) − (0,2)
    >>> form_class(X, [2.0, 4.0, 1.0], "R").values.tolist()
    [0.5]
    """
    return line_bundle_class(VectorBundle(X, np.asarray(omega).reshape(-1), field, atol=atol))


def integrate_exact_form(
    X: SimplicialComplex, omega: ArrayLike, field: str | tuple[str, int] = "C", atol: float = 1e-9
) -> np.ndarray:
    """``g`` with ``ω_ij = g_j / g_i`` (``g = 1`` at the roots) for an exact F*-valued 1-form.

    Parameters
    ----------
    X : SimplicialComplex
        The complex.
    omega : (n_1,) array_like
        One nonzero value per edge of ``X.simplices(1)``.
    field : ``"R"``, ``"C"`` or ``("GF", p)``, default "C"
        The field F.
    atol : float, default 1e-9
        Tolerance of the test that every cycle product is 1.

    Returns
    -------
    (n_0,) array
        ``g`` per vertex, 1 at the root of each component, in the field's dtype.

    Raises
    ------
    NotExactError
        naming a fundamental cycle (by its non-tree edge) on which ``ω`` is not 1.
    InvalidConnectionError
        ``omega`` has the wrong length, a zero or non-numeric entries; ``field`` is unknown.
    NonFiniteError
        ``omega`` contains NaN or infinity.

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1), (1, 2), (0, 2)])           # edges (0,1), (0,2), (1,2)
    >>> integrate_exact_form(X, [2.0, 6.0, 3.0], "R").tolist()
    [1.0, 2.0, 6.0]
    """
    L = VectorBundle(X, np.asarray(omega).reshape(-1), field, atol=atol)
    c = line_bundle_class(L)
    ok = L.ops.close(c.values[:, None, None], np.ones((c.values.size, 1, 1)))
    if not np.all(ok):
        from dhlb.topology._names import simplex_name

        e = int(L.forest.nontree[int(np.argmin(ok))])
        raise NotExactError(
            f"the 1-form is not exact: its product around the fundamental cycle of edge "
            f"{simplex_name(X, 1, e)} is {c.values[int(np.argmin(ok))]!r}, not 1"
        )
    return L.tree_transports[:, 0, 0].copy()
