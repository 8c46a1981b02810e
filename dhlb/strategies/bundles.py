"""Hypothesis strategies for cochains, connections, hermitian line bundles, vector bundles, sections.

Every strategy takes the base complex as a :class:`~dhlb.SimplicialComplex`, a :class:`Known`
record, or a hypothesis strategy of either (drawn anew for every example); ``None`` means a
sensible default strategy.

Hermitian line bundles are drawn as ``(exp(iω), Ω = dω + 2πm)`` with real connection angles ω and
an integer 2-cocycle ``m``: every hermitian line bundle with curvature is of this form (take
``ω = angle(r)``; then ``m = (Ω − dω)/2π`` is an integer cocycle), and ``∫_C Ω = 2π ⟨m, C⟩ ∈ 2πZ``
for every integer 2-cycle ``C``, which is Weil's integrality. On a closed oriented surface the
degree is ``Σ_t o_t m_t`` because ``Σ_t o_t (dω)_t = ⟨ω, ∂ Σ_t o_t t⟩ = 0``
(derived in ``tests/test_strategies_proofs.py``).
"""

from __future__ import annotations

import numpy as np
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from dhlb._coerce import check_int
from dhlb.errors import InvalidParameterError
from dhlb.strategies.complexes import Known, closed_surfaces, simplicial_complexes
from dhlb.topology.complex import SimplicialComplex

__all__ = ["cochains", "connections", "hermitian_line_bundles", "vector_bundles", "sections"]

_ANGLES = st.floats(-np.pi, np.pi, allow_nan=False, allow_infinity=False, allow_subnormal=False)


# ---------------------------------------------------------------------------- helpers
def _unwrap(X):
    return X.complex if isinstance(X, Known) else X


def _complex_strategy(X, default, what: str = "X") -> st.SearchStrategy:
    """A strategy of SimplicialComplex from a complex, a Known record, a strategy of either, or None."""
    if X is None:
        return default
    if isinstance(X, (SimplicialComplex, Known)):
        return st.just(_unwrap(X))
    if isinstance(X, st.SearchStrategy):
        return X.map(_unwrap)
    raise InvalidParameterError(
        f"{what} must be a SimplicialComplex, a Known record, a hypothesis strategy of them, or None; "
        f"got {type(X).__name__}"
    )


def _float_array(n: int, elements=_ANGLES) -> st.SearchStrategy:
    return hnp.arrays(np.float64, (n,), elements=elements)


def _coboundary(X: SimplicialComplex, k: int, values: np.ndarray) -> np.ndarray:
    """``d_k`` applied to a real k-cochain (``d_k = ∂_{k+1}ᵀ``; empty above the dimension)."""
    if k + 1 > X.dim:
        return np.zeros(0)
    return np.asarray(X.boundary(k + 1).T @ values, dtype=np.float64)


def _closed_orientable_surface(X: SimplicialComplex) -> np.ndarray | None:
    """The orientation ``o`` of X if it is a closed orientable surface (every edge in two triangles), else None."""
    if X.dim != 2 or X.n_simplices(2) == 0:
        return None
    if np.any(np.bincount(X.faces(2).ravel(), minlength=X.n_simplices(1)) != 2):
        return None
    from dhlb.topology.orientation import is_orientable

    if not is_orientable(X):
        return None
    return np.asarray(X.orientation(), dtype=np.int64)


# ---------------------------------------------------------------------------- cochains and connections
_GROUPS = {"Z": "Z", "R": "R", "C": "C", "S1": "S1", "C*": "C*"}


@st.composite
def _cochain(draw, X: SimplicialComplex, k: int, group: str, exact: bool):
    from dhlb.forms import Cochain

    if exact:
        if k == 0:
            return Cochain.identity(X, 0, group)
        return draw(_cochain(X, k - 1, group, False)).d()
    n = X.n_simplices(k) if 0 <= k <= X.dim else 0
    if group == "Z":
        vals = hnp.arrays(np.int64, (n,), elements=st.integers(-3, 3))
    elif group == "R":
        vals = _float_array(n, st.floats(-10, 10, allow_subnormal=False))
    elif group == "S1":
        vals = _float_array(n)
    else:  # C and C*: modulus and angle
        if group == "C":
            mod = _float_array(n, st.floats(0, 4, allow_subnormal=False))
        else:
            mod = _float_array(n, st.floats(-2, 2, allow_subnormal=False)).map(np.exp2)
        vals = st.tuples(mod, _float_array(n)).map(lambda ra: ra[0] * np.exp(1j * ra[1]))
    return Cochain(X, k, draw(vals), group)


def cochains(X=None, k: int = 1, coefficients: str = "R", *, exact: bool = False) -> st.SearchStrategy:
    """Random discrete k-forms (:class:`dhlb.forms.Cochain`).

    Parameters
    ----------
    X : SimplicialComplex, Known, strategy of them, or None
        The base complex (default: :func:`~dhlb.strategies.simplicial_complexes`).
    k : int
        The degree (a form of degree above ``X.dim`` has no values).
    coefficients : {"Z", "R", "C", "S1", "C*"}
        Z: integers in [−3, 3]; R: reals in [−10, 10]; C: modulus in [0, 4] times a phase;
        S1: angles in [−π, π] (stored wrapped to (−π, π]); C*: modulus in [1/4, 4] times a phase.
    exact : bool
        Draw ``d`` of a random (k−1)-form instead (in the group law; ``k = 0``: the identity).

    Returns
    -------
    SearchStrategy of Cochain
        Shrinks towards the zero (identity) form.

    Raises
    ------
    InvalidParameterError
        unknown coefficients, negative ``k``, or a bad ``X``.

    Examples
    --------
    >>> from hypothesis import given, settings
    >>> @settings(max_examples=25)
    ... @given(cochains(k=1, coefficients="Z", exact=True))
    ... def dd_is_zero(w):
    ...     assert not w.d().values.any()
    >>> dd_is_zero()
    """
    if coefficients not in _GROUPS:
        raise InvalidParameterError(f"coefficients must be one of {sorted(_GROUPS)}, got {coefficients!r}")
    k = check_int(k, "k", 0)
    Xs = _complex_strategy(X, simplicial_complexes(max_dim=3))
    return Xs.flatmap(lambda Y: _cochain(Y, k, coefficients, exact))


def connections(X=None) -> st.SearchStrategy:
    """Random connection angles: S¹-valued 1-cochains ``ω`` (``r_ij = exp(iω_ij)``).

    Parameters
    ----------
    X : SimplicialComplex, Known, strategy of them, or None
        Default: :func:`~dhlb.strategies.simplicial_complexes`.

    Returns
    -------
    SearchStrategy of Cochain
        S¹-valued 1-forms; shrinks towards the trivial connection ``ω = 0``. Use
        ``np.exp(1j * w.values)`` for the unit complex transports.

    Examples
    --------
    >>> import numpy as np
    >>> from hypothesis import given, settings
    >>> from dhlb.examples import torus
    >>> @settings(max_examples=25)
    ... @given(connections(torus()))
    ... def unit_transports(w):
    ...     assert np.allclose(np.abs(np.exp(1j * w.values)), 1) and w.group == "S1"
    >>> unit_transports()
    """
    return cochains(X, 1, "S1")


# ---------------------------------------------------------------------------- hermitian line bundles
def _integer_2_cocycles(X: SimplicialComplex) -> np.ndarray | None:
    """Integer 2-cocycle representatives of H²(X; Z) (None for a complex without tetrahedra)."""
    if X.dim < 3 or X.n_simplices(3) == 0:
        return None
    from dhlb.topology.homology import cohomology

    return np.asarray(cohomology(X, "Z")[2].cocycles, dtype=np.int64)


@st.composite
def _line_bundle(draw, X: SimplicialComplex, curvature: str, degree):
    from dhlb.bundles.hermitian import HermitianLineBundle

    n1, n2 = X.n_simplices(1), X.n_simplices(2)
    o = _closed_orientable_surface(X)
    if degree is not None and o is None:
        raise InvalidParameterError(
            f"degree={degree!r} needs closed orientable surfaces, but a drawn complex is not one ({X!r}); "
            "pass X=closed_surfaces(orientable=True) or degree=None"
        )
    if curvature == "flat":
        return _flat_bundle(draw, X)
    omega = draw(_float_array(n1))
    m = np.zeros(n2, np.int64)
    if n2:
        gens = _integer_2_cocycles(X)
        if gens is None:  # no tetrahedra: every integer 2-cochain is a cocycle
            for t, c in draw(st.lists(st.tuples(st.integers(0, n2 - 1), st.integers(-2, 2)), max_size=4)):
                m[t] += c
        else:  # d of an integer 1-cochain plus a combination of H² generators
            for e, c in draw(st.lists(st.tuples(st.integers(0, n1 - 1), st.integers(-2, 2)), max_size=3)):
                m += c * np.asarray(X.boundary(2)[[e], :].toarray()).ravel().astype(np.int64)
            if gens.shape[1]:
                coef = draw(st.lists(st.integers(-2, 2), min_size=gens.shape[1], max_size=gens.shape[1]))
                m += gens @ np.asarray(coef, dtype=np.int64)
        if o is not None:  # fix the degree Σ o_t m_t on a closed oriented surface
            want = draw(st.integers(-3, 3)) if degree is None else int(degree)
            t0 = draw(st.integers(0, n2 - 1))
            m[t0] += o[t0] * (want - int(o @ m))
    Om = _coboundary(X, 1, omega) + 2 * np.pi * m
    return HermitianLineBundle(X, np.exp(1j * omega), Om)


def _flat_bundle(draw, X: SimplicialComplex):
    """ω = dφ + Σ θ_i ε_i + Σ k_j τ_j over the S¹-cocycles of H¹(X; S¹); Ω = 0."""
    from dhlb.bundles.hermitian import HermitianLineBundle
    from dhlb.topology.homology import cohomology

    n1, n2 = X.n_simplices(1), X.n_simplices(2)
    phi = draw(_float_array(X.n_vertices))
    omega = _coboundary(X, 0, phi)
    if X.dim >= 1 and n1:
        H = cohomology(X, "S1")[1]
        C = np.asarray(H.cocycles, dtype=np.float64)
        b = H.rank
        if b:
            omega = omega + C[:, :b] @ draw(_float_array(b))
        if C.shape[1] > b:
            ks = [draw(st.integers(0, int(d) - 1)) for d in H.torsion]
            omega = omega + C[:, b:] @ np.asarray(ks, dtype=np.float64)
    return HermitianLineBundle(X, np.exp(1j * omega), np.zeros(n2))


def hermitian_line_bundles(X=None, curvature: str = "any", degree: int | None = None) -> st.SearchStrategy:
    """Random hermitian line bundles with curvature (:class:`~dhlb.bundles.HermitianLineBundle`).

    The degree is drawn first (on closed oriented surfaces), then an integral curvature with
    that total, then a connection: ``r = exp(iω)`` with random angles ω and
    ``Ω = dω + 2πm`` for a sparse integer 2-cocycle ``m`` with ``Σ_t o_t m_t = degree``. So the
    curvature satisfies Weil's integrality ``∫_C Ω ∈ 2πZ`` by construction; on complexes with
    tetrahedra ``m`` is ``d`` of an integer 1-cochain plus integer multiples of the H²
    generators.

    Parameters
    ----------
    X : SimplicialComplex, Known, strategy of them, or None
        Default: closed orientable surfaces when ``degree`` is given, otherwise closed
        surfaces or random complexes of dimension ≤ 3.
    curvature : {"any", "flat"}
        ``"flat"``: Ω = 0, the connection is a gauge transformation of a random point of
        ``H¹(X; S¹)`` (free angles and torsion residues).
    degree : int, optional
        The degree ``(1/2π) Σ_t o_t Ω_t`` for the orientation ``X.orientation()`` (X must be a
        closed orientable surface); default: drawn from −3 … 3 on closed orientable surfaces.

    Returns
    -------
    SearchStrategy of HermitianLineBundle
        Shrinks towards ``ω = 0`` and the curvature concentrated on one triangle.

    Raises
    ------
    InvalidParameterError
        unknown ``curvature``, ``curvature="flat"`` with a nonzero degree, or ``degree`` given
        and a complex (given or drawn) that is not a closed orientable surface.

    Examples
    --------
    >>> from hypothesis import given, settings
    >>> from dhlb.examples import torus
    >>> @settings(max_examples=25)
    ... @given(hermitian_line_bundles(torus(), degree=2))
    ... def weil(L):
    ...     assert L.degree() == 2 and L.check_integrality().tolist() == [2]
    >>> weil()
    """
    if curvature not in ("any", "flat"):
        raise InvalidParameterError(f"curvature must be 'any' or 'flat', got {curvature!r}")
    if degree is not None:
        degree = check_int(degree, "degree")
        if curvature == "flat" and degree != 0:
            raise InvalidParameterError(f"a flat bundle has degree 0, but degree={degree} was asked for")
    if degree is not None:
        default = closed_surfaces(orientable=True, max_moves=3)
    else:
        default = st.one_of(closed_surfaces(max_moves=3), simplicial_complexes(max_dim=3))
    if isinstance(X, SimplicialComplex) and degree is not None and _closed_orientable_surface(X) is None:
        raise InvalidParameterError(f"degree={degree!r} needs a closed orientable surface; {X!r} is not one")
    Xs = _complex_strategy(X, default.map(_unwrap))
    return Xs.flatmap(lambda Y: _line_bundle(Y, curvature, degree))


# ---------------------------------------------------------------------------- vector bundles
def _parse_field(field):
    if field in ("R", "C"):
        return field
    if isinstance(field, str) and field.upper().startswith("Z/"):
        try:
            p = int(field[2:])
        except ValueError:
            p = 0
    elif isinstance(field, (tuple, list)) and len(field) == 2 and str(field[0]).upper() == "GF":
        p = field[1]
    else:
        raise InvalidParameterError(f"field must be 'R', 'C', 'Z/p' or ('GF', p), got {field!r}")
    if isinstance(p, bool) or not isinstance(p, (int, np.integer)) or p < 2 or any(p % q == 0 for q in range(2, p)):
        raise InvalidParameterError(f"Z/p needs a prime p, got {field!r}")
    return ("GF", int(p))


def _real_matrix(K: int, metric: bool) -> st.SearchStrategy:
    """K×K real matrices Q·U: Q orthogonal (from the QR factorization of I + A), U upper triangular.

    U has diagonal entries in [1/2, 2] and off-diagonal entries in [−1, 1], so the matrices are
    invertible with bounded condition number; ``A = 0, U = I`` gives the identity.
    """
    entries = st.floats(-1, 1, allow_subnormal=False)

    def build(args):
        A, U = args
        Q, R = np.linalg.qr(np.eye(K) + A)
        Q = Q * np.where(np.diag(R) < 0, -1.0, 1.0)
        if metric:
            return Q
        return Q @ (np.triu(U, 1) + np.diag(np.exp2(np.diag(U))))

    return st.tuples(hnp.arrays(np.float64, (K, K), elements=entries),
                     hnp.arrays(np.float64, (K, K), elements=entries)).map(build)


def _complex_matrix(K: int, metric: bool) -> st.SearchStrategy:
    """K×K complex matrices Q·U as in :func:`_real_matrix`, Q unitary times random phases."""
    def build(args):
        Ar, Ai = args
        return Ar + 1j * Ai

    def combine(args):
        A, U, phases = args
        Q, R = np.linalg.qr(np.eye(K) + A)
        r = np.diag(R)
        Q = Q @ np.diag(np.exp(1j * phases) * np.where(r == 0, 1.0, np.conj(r) / np.maximum(np.abs(r), 1e-300)))
        if metric:
            return Q
        return Q @ (np.triu(U, 1) + np.diag(np.exp2(np.diag(U).real)))

    entries = st.floats(-1, 1, allow_subnormal=False)
    mat = st.tuples(hnp.arrays(np.float64, (K, K), elements=entries),
                    hnp.arrays(np.float64, (K, K), elements=entries)).map(build)
    return st.tuples(mat, mat, _float_array(K)).map(combine)


def _gf_matrix(K: int, p: int) -> st.SearchStrategy:
    """Invertible K×K matrices over GF(p): P·L·U with unit lower L and U with nonzero diagonal."""
    def build(args):
        perm, L, U, d = args
        Lm = np.tril(L, -1) + np.eye(K, dtype=np.int64)
        Um = np.triu(U, 1) + np.diag(d)
        return (np.eye(K, dtype=np.int64)[list(perm)] @ Lm @ Um) % p

    ints = hnp.arrays(np.int64, (K, K), elements=st.integers(0, p - 1))
    return st.tuples(st.permutations(range(K)), ints, ints,
                     hnp.arrays(np.int64, (K,), elements=st.integers(1, p - 1))).map(build)


@st.composite
def _vector_bundle(draw, X: SimplicialComplex, rank, field, metric: bool):
    from dhlb.bundles.vector_bundle import VectorBundle

    K = draw(st.integers(1, 3)) if rank is None else rank
    n1 = X.n_simplices(1)
    if field == "R":
        mat = _real_matrix(K, metric)
    elif field == "C":
        mat = _complex_matrix(K, metric)
    else:
        mat = _gf_matrix(K, field[1])
    if n1:
        # a few distinct transports, the other edges carry a common one (sparse, shrinks to few distinct)
        common = draw(mat)
        eta = np.broadcast_to(common, (n1, K, K)).copy()
        for e, M in draw(st.lists(st.tuples(st.integers(0, n1 - 1), mat), max_size=min(n1, 8))):
            eta[e] = M
    else:
        dtype = np.int64 if isinstance(field, tuple) else (np.complex128 if field == "C" else np.float64)
        eta = np.zeros((0, K, K), dtype=dtype)
    return VectorBundle(X, eta, field, metric=metric)


def vector_bundles(X=None, rank: int | None = None, field="C", *, metric: bool = False) -> st.SearchStrategy:
    """Random discrete vector bundles with connection (:class:`~dhlb.bundles.VectorBundle`).

    Parameters
    ----------
    X : SimplicialComplex, Known, strategy of them, or None
        Default: closed surfaces or random complexes of dimension ≤ 3.
    rank : int, optional
        The fibre dimension K (default: drawn from 1 … 3).
    field : {"C", "R", "Z/p"} or ("GF", p)
        The coefficient field; ``"Z/5"`` means GF(5).
    metric : bool
        Orthogonal / unitary transports (R or C only).

    Returns
    -------
    SearchStrategy of VectorBundle
        Transports are random well-conditioned invertible matrices: a
        common one on most edges and independent ones on up to 8 edges. Shrinks towards the
        trivial bundle.

    Raises
    ------
    InvalidParameterError
        unknown field, non-prime p, ``rank < 1``, or ``metric`` over GF(p).

    Examples
    --------
    >>> from hypothesis import given, settings
    >>> @settings(max_examples=10)
    ... @given(vector_bundles(rank=2, field="Z/3"))
    ... def dual_of_dual(E):
    ...     assert E.rank == 2 and E.field == ("GF", 3)
    ...     assert (E.dual().dual().transports == E.transports).all()
    >>> dual_of_dual()
    """
    f = _parse_field(field)
    if rank is not None:
        rank = check_int(rank, "rank", 1)
    if metric and isinstance(f, tuple):
        raise InvalidParameterError("metric=True needs field 'R' or 'C' (no inner products over GF(p))")
    default = st.one_of(closed_surfaces(max_moves=2), simplicial_complexes(max_dim=3)).map(_unwrap)
    Xs = _complex_strategy(X, default)
    return Xs.flatmap(lambda Y: _vector_bundle(Y, None if rank is None else int(rank), f, bool(metric)))


# ---------------------------------------------------------------------------- sections
def _has_tie(L, z: np.ndarray, tol: float = 1e-6) -> bool:
    E = L.X.simplices(1)
    if not len(E):
        return False
    xi = np.angle(z[E[:, 1]] * np.conj(L.connection * z[E[:, 0]]))
    return bool(np.any(np.pi - np.abs(xi) < tol))


def sections(L, kind: str = "nowhere_vanishing") -> st.SearchStrategy:
    """Random sections ``ψ_i = z_i X_i`` of a hermitian line bundle: one complex ``z_i`` per vertex.

    Parameters
    ----------
    L : HermitianLineBundle or SimplicialComplex
        The bundle (or just its base: then ``kind="generic"`` is relative to the trivial
        connection).
    kind : {"nowhere_vanishing", "generic"}
        ``"nowhere_vanishing"``: modulus in [1/4, 4], any phase (ties ``η_ij ψ_i = −ψ_j`` are
        possible; the tie rule of Remark 8 decides them). ``"generic"``: in addition no edge is
        within 1e-6 of a tie, so the zeros of the section lie inside triangles.

    Returns
    -------
    SearchStrategy of ndarray
        ``(n_vertices,)`` complex128, never zero; shrinks towards the constant section 1.
        To draw a bundle and a section together, use
        ``hermitian_line_bundles().flatmap(lambda L: st.tuples(st.just(L), sections(L)))``.

    Raises
    ------
    InvalidParameterError
        unknown ``kind`` or an ``L`` that is neither a bundle nor a complex.

    Examples
    --------
    >>> from hypothesis import given, settings
    >>> from dhlb.examples import torus
    >>> from dhlb.bundles import HermitianLineBundle, index_sum
    >>> L = HermitianLineBundle.trivial(torus())
    >>> @settings(max_examples=25)
    ... @given(sections(L, kind="generic"))
    ... def poincare_hopf(z):
    ...     assert index_sum(L, z) == L.degree() == 0
    >>> poincare_hopf()
    """
    from dhlb.bundles.hermitian import HermitianLineBundle

    if kind not in ("nowhere_vanishing", "generic"):
        raise InvalidParameterError(f"kind must be 'nowhere_vanishing' or 'generic', got {kind!r}")
    if isinstance(L, (SimplicialComplex, Known)):
        L = HermitianLineBundle.trivial(_unwrap(L))
    if not isinstance(L, HermitianLineBundle):
        raise InvalidParameterError(f"L must be a HermitianLineBundle or a SimplicialComplex, got {type(L).__name__}")
    n = L.X.n_vertices
    mod = _float_array(n, st.floats(-2, 2, allow_subnormal=False))
    z = st.tuples(mod, _float_array(n)).map(lambda ma: np.exp2(ma[0]) * np.exp(1j * ma[1]))
    if kind == "generic":
        z = z.filter(lambda v: not _has_tie(L, v))
    return z
