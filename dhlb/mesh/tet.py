"""Tetrahedral meshes of solids: validation, orientation, and deterministic structured generators.

A :class:`TetMesh` is a tetrahedral mesh of a region of R³ whose tetrahedra all have positive
signed volume ``det(p_1 − p_0, p_2 − p_0, p_3 − p_0) / 6 > 0`` in the stored vertex order,
which is a combinatorial 3-manifold (possibly with boundary) and whose neighbouring tetrahedra
lie on opposite sides of their common triangle (no folds).  :func:`check_tet_mesh` builds one
from arrays ``(V, T)`` or says precisely what is wrong; :func:`box_tet_mesh` and
:func:`ball_tet_mesh` generate them deterministically.

Examples
--------
>>> from dhlb.mesh import box_tet_mesh, check_tet_mesh
>>> mesh = box_tet_mesh(2, upper=(2.0, 1.0, 1.0))
>>> mesh.complex.counts, round(float(mesh.volumes.sum()), 12)
((27, 98, 120, 48), 2.0)
>>> T = mesh.tets[:, [1, 0, 2, 3]]                 # every tetrahedron inverted
>>> fixed = check_tet_mesh(mesh.points, T)
>>> bool(fixed.flipped.all()), bool((fixed.volumes > 0).all())
(True, True)
"""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from dhlb._coerce import as_points, as_vec3, check_int
from dhlb._memory_errors import check_memory, largest_fitting
from dhlb.errors import (
    DegenerateSimplexError,
    InconsistentOrientationError,
    InvalidParameterError,
    NonManifoldError,
    ResourceLimitError,
)
from dhlb.examples import cube_nd
from dhlb.mesh.arrays import check_row_lengths, mesh_complex
from dhlb.topology.complex import SimplicialComplex
from dhlb.topology.manifold import manifold_report

if TYPE_CHECKING:
    from collections.abc import Sequence

    from numpy.typing import ArrayLike

__all__ = ["TetMesh", "signed_volumes", "tet_signs", "check_tet_complex", "check_tet_mesh", "box_corners",
           "box_tet_mesh", "ball_tet_mesh", "box_memory_estimate", "check_box_memory"]

DEFAULT_RTOL = 1e-10
"""A tetrahedron with ``|vol| <= rtol · L³`` (``L`` its longest edge) counts as degenerate."""


class TetMesh(NamedTuple):
    """A validated, positively oriented tetrahedral mesh.

    Made by :func:`check_tet_mesh` (the constructor checks nothing); every parameter is kept as the
    attribute of the same name.

    Parameters
    ----------
    points : (N, 3) float array
        Coordinates of the compact vertices ``0 .. N-1`` of :attr:`complex` (the input row of
        vertex ``v`` is ``complex.vertex_labels[v]``).
    tets : (m, 4) int array
        The input tetrahedra in compact vertex indices and input row order, each with positive
        signed volume (inverted input rows have their last two vertices swapped).
    complex : SimplicialComplex
        The 3-complex of the mesh.
    index : (m,) int array
        Row of each tetrahedron in ``complex.simplices(3)``.
    flipped : (m,) bool array
        Which input tetrahedra were negatively oriented.

    Examples
    --------
    >>> from dhlb.mesh import box_tet_mesh
    >>> mesh = box_tet_mesh(2)                            # the unit cube, 2 × 2 × 2 cells
    >>> mesh.tets.shape, mesh.complex.counts, round(float(mesh.volumes.sum()), 6), mesh.boundary_faces.shape
    ((48, 4), (27, 98, 120, 48), 1.0, (48, 3))
    """

    points: np.ndarray
    tets: np.ndarray
    complex: SimplicialComplex
    index: np.ndarray
    flipped: np.ndarray

    @classmethod
    def from_validated(cls, points: ArrayLike, tets: ArrayLike) -> TetMesh:
        """The mesh of tetrahedra that :func:`check_tet_mesh` already validated, built without checks.

        For a patch of a validated mesh (e.g. the local mesh of a rank, :func:`dhlb.mesh.partition.tet_part`):
        its tetrahedra are positively oriented and non-degenerate, but at the edge of the patch a
        vertex or an edge may have a disconnected star, which :func:`check_tet_mesh` (rightly)
        refuses as a 3-manifold. Nothing is checked or reoriented here; give only cells that passed
        :func:`check_tet_mesh` (its ``tets``, or a subset of them, renumbered).

        Parameters
        ----------
        points : (N, 3) float array
            Vertex coordinates; every row is used by some tetrahedron.
        tets : (m, 4) int array
            Positively oriented tetrahedra as rows of ``points`` (0 .. N-1, all used).

        Returns
        -------
        TetMesh
            ``tets`` as given, ``flipped`` all False, ``complex.vertex_labels == arange(N)``.

        Examples
        --------
        >>> import numpy as np
        >>> mesh = box_tet_mesh(2)
        >>> T = mesh.tets[np.any((mesh.tets == 0) | (mesh.tets == 2), axis=1)]   # the tets at two corners
        >>> used = np.unique(T)
        >>> V, T = mesh.points[used], np.searchsorted(used, T)                    # pinched at vertex 1
        >>> try:
        ...     check_tet_mesh(V, T)
        ... except NonManifoldError as err:
        ...     print(str(err)[:67])
        not a tetrahedral 3-manifold mesh: the vertex (1,) (input labels) h
        >>> patch = TetMesh.from_validated(V, T)
        >>> patch.tets.shape, bool((patch.volumes > 0).all()), patch.complex.n_vertices == used.size
        ((8, 4), True, True)
        """
        P = np.asarray(points, dtype=np.float64)
        T = np.asarray(tets, dtype=np.int64)
        X = SimplicialComplex(T)
        flipped = np.zeros(T.shape[0], bool)
        for a in (T, flipped):
            a.setflags(write=False)
        return cls(P, T, X, X.index(3, T), flipped)

    @property
    def volumes(self) -> np.ndarray:
        """Volume of each tetrahedron (positive), in the row order of :attr:`tets`."""
        return signed_volumes(self.points, self.tets)

    @property
    def boundary_faces(self) -> np.ndarray:
        """``(b, 3)`` boundary triangles, oriented so that their normals point out of the solid."""
        return _boundary_faces(self.tets)


def signed_volumes(points: ArrayLike, tets: ArrayLike) -> np.ndarray:
    """``det(p_1 − p_0, p_2 − p_0, p_3 − p_0) / 6`` for every row ``(p_0, p_1, p_2, p_3)`` of ``tets``.

    Parameters
    ----------
    points : (n, 3) float array
        Vertex positions.
    tets : (m, 4) int array
        Tetrahedra as rows of ``points`` (not checked: an index out of range raises numpy's ``IndexError``).

    Returns
    -------
    (m,) float array
        The signed volume of each tetrahedron, positive when ``p_1 − p_0, p_2 − p_0, p_3 − p_0`` is a
        right-handed basis.

    Examples
    --------
    >>> signed_volumes([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], [[0, 1, 2, 3], [1, 0, 2, 3]]).tolist()
    [0.16666666666666666, -0.16666666666666666]
    """
    P = np.asarray(points, dtype=np.float64)
    T = np.asarray(tets, dtype=np.int64)
    e = P[T[:, 1:]] - P[T[:, :1]]
    return np.einsum("ij,ij->i", e[:, 0], np.cross(e[:, 1], e[:, 2])) / 6.0


def _boundary_faces(tets: np.ndarray) -> np.ndarray:
    # faces of a positively oriented tet (p0, p1, p2, p3) with outward normals (right-hand rule)
    local = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]])
    F = tets[:, local].reshape(-1, 3)
    key = np.sort(F, axis=1)
    _, inv, cnt = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    return F[cnt[inv.ravel()] == 1]


def _edge_lengths_max(P: np.ndarray, T: np.ndarray) -> np.ndarray:
    a, b = np.triu_indices(4, 1)
    return np.linalg.norm(P[T[:, a]] - P[T[:, b]], axis=2).max(axis=1)


def _name_tet(r: int, T_input: np.ndarray) -> str:
    return f"tetrahedron #{r} (vertices {tuple(int(v) for v in T_input[r])})"


def check_tet_mesh(V: ArrayLike, T: ArrayLike, *, orientation: str = "fix", rtol: float = DEFAULT_RTOL) -> TetMesh:
    """Validate a tetrahedral mesh and orient every tetrahedron positively.

    Parameters
    ----------
    V : (n, 3) float array
        Vertex coordinates.
    T : (m, 4) int array
        Tetrahedra as rows of vertex indices into ``V`` (0-based).
    orientation : {"fix", "require"}
        ``"fix"`` (default) swaps the last two vertices of every negatively oriented tetrahedron
        (meshers such as fTetWild emit them all negatively oriented); ``"require"`` raises instead.
    rtol : float
        A tetrahedron with ``|vol| <= rtol · L³`` (``L`` its longest edge) is degenerate.

    Returns
    -------
    TetMesh
        The mesh in compact vertex numbers, every tetrahedron positively oriented.

    Raises
    ------
    InvalidParameterError
        ``orientation`` is not ``"fix"`` or ``"require"``, or ``rtol`` is not a finite number >= 0.
    ShapeError, NonFiniteError, InvalidSimplexError
        ``V`` not of shape (n, 3) or not finite; ``T`` not of shape (m, 4), repeating a vertex in a
        row or pointing past ``V`` (the row is named).
    DegenerateSimplexError
        A flat tetrahedron (the first one is named with its input row; ``err.element`` is the row).
    InconsistentOrientationError
        ``orientation="require"`` and a tetrahedron is negatively oriented; or two tetrahedra lie
        on the same side of their common triangle, i.e. the mesh folds over (both are named).
    NonManifoldError
        Not a combinatorial 3-manifold with boundary: a duplicated tetrahedron, a triangle in
        three or more tetrahedra, or an edge or vertex whose link is no disk/sphere (the element
        and a tetrahedron containing it are named).

    Warns
    -----
    UnreferencedVertexWarning
        Vertices used by no tetrahedron are dropped (``complex.vertex_labels`` keeps the map).

    Examples
    --------
    >>> from dhlb.mesh import check_tet_mesh
    >>> mesh = check_tet_mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], [[1, 0, 2, 3]])   # inverted
    >>> mesh.tets.tolist(), mesh.flipped.tolist(), mesh.volumes.round(6).tolist()
    ([[1, 0, 3, 2]], [True], [0.166667])
    """
    if orientation not in ("fix", "require"):
        raise InvalidParameterError(f"orientation must be 'fix' or 'require', got {orientation!r}")
    if not (np.isscalar(rtol) and np.isfinite(rtol) and rtol >= 0):
        raise InvalidParameterError(f"rtol must be a finite number >= 0, got {rtol!r}")
    Vin = as_points(V, "V", finite=False)  # mesh_complex names a non-finite vertex that is used
    check_row_lengths(T, 4, "tetrahedron", name="T")
    mc = mesh_complex(Vin, T, dim=3)  # parses T, checks finiteness and index range, drops unused vertices
    X, P = mc.complex, mc.points
    T_in = np.asarray(T).astype(np.int64)
    m = T_in.shape[0]
    uniq, first = np.unique(mc.index, return_index=True)
    if uniq.size < m:
        dup = np.setdiff1d(np.arange(m), first)[0]
        other = int(first[np.searchsorted(uniq, mc.index[dup])])
        raise NonManifoldError(f"{_name_tet(int(dup), T_in)} repeats {_name_tet(other, T_in)}; remove the duplicate")
    # compact vertex indices, input row order
    Tc = np.searchsorted(X.vertex_labels, T_in)
    vol = signed_volumes(P, Tc)
    L = _edge_lengths_max(P, Tc)
    flat = ~(np.abs(vol) > rtol * L**3)
    if np.any(flat):
        r = int(np.argmax(flat))
        err = DegenerateSimplexError(
            f"{_name_tet(r, T_in)} is degenerate: volume {vol[r]:.3g} with longest edge {L[r]:.3g} "
            f"(|vol|/L³ = {abs(vol[r]) / L[r] ** 3 if L[r] > 0 else 0:.3g} <= rtol = {rtol:.3g})"
            + (f"; {int(flat.sum())} tetrahedra are degenerate" if flat.sum() > 1 else "")
            + ". Remove it or move its vertices apart."
        )
        err.element = r
        raise err
    flipped = vol < 0
    if orientation == "require" and np.any(flipped):
        r = int(np.argmax(flipped))
        err = InconsistentOrientationError(
            f"{_name_tet(r, T_in)} is negatively oriented (signed volume {vol[r]:.3g}); "
            f"{int(flipped.sum())} of {m} tetrahedra are. Swap two of its vertices or pass orientation='fix'."
        )
        err.element = r
        raise err
    Tc = np.where(flipped[:, None], Tc[:, [0, 1, 3, 2]], Tc)
    _check_manifold(X, mc.index, T_in)
    _check_no_folds(X, P, mc.index, T_in)
    Tc.setflags(write=False)
    flipped.setflags(write=False)
    return TetMesh(P, Tc, X, mc.index, flipped)


def _tet_containing(X: SimplicialComplex, k: int, row: int, index: np.ndarray) -> int:
    """Input row of a tetrahedron containing the k-simplex ``row`` of X."""
    verts = X.simplices(k)[row]
    S = X.simplices(3)
    hit = np.nonzero(np.isin(S, verts).sum(axis=1) == k + 1)[0][0]
    return int(np.nonzero(index == hit)[0][0])


def _check_manifold(X: SimplicialComplex, index: np.ndarray, T_in: np.ndarray) -> None:
    rep = manifold_report(X, limit=1)
    if rep.is_manifold:
        return
    o = rep.first()
    r = _tet_containing(X, o.k, o.row, index)
    err = NonManifoldError(
        f"not a tetrahedral 3-manifold mesh: {o} (it lies in {_name_tet(r, T_in)}). "
        "Split the mesh there or remove the offending tetrahedra."
    )
    err.simplex, err.k, err.element = o.simplex, o.k, r
    raise err


_FACE_SIGN = np.array([1.0, -1.0, 1.0, -1.0])  # incidence of face i (opposite vertex i) of a sorted tet


def _triangle_sides(X: SimplicialComplex, sgn: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per triangle of ``X``: the number of tetrahedra containing it, and whether two of them are on one side.

    ``sgn`` is the orientation sign of each canonical (sorted) tetrahedron; neighbours induce opposite
    orientations on their common triangle exactly when the sum of the induced signs is 0.
    """
    F3 = X.faces(3)
    n2 = X.n_simplices(2)
    cnt = np.bincount(F3.ravel(), minlength=n2)
    side = np.bincount(F3.ravel(), weights=(sgn[:, None] * _FACE_SIGN).ravel(), minlength=n2)
    return cnt, (cnt == 2) & (side != 0)


def tet_signs(X: SimplicialComplex, P: ArrayLike) -> np.ndarray:
    """Orientation sign of every canonical (sorted) tetrahedron of ``X`` placed at ``P``.

    Parameters
    ----------
    X : SimplicialComplex
        A complex of dimension 3.
    P : (X.n_vertices, 3) float array
        Positions of the (compact) vertices of ``X``.

    Returns
    -------
    (X.n_simplices(3),) float array
        ``+1`` or ``-1``: the sign of the signed volume of ``X.simplices(3)[t]`` in sorted vertex order.

    Raises
    ------
    DegenerateSimplexError
        A tetrahedron has exactly zero volume (named by its vertex labels).

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1, 2, 3)])
    >>> tet_signs(X, [[0, 0, 0], [0, 1, 0], [1, 0, 0], [0, 0, 1]]).tolist()
    [-1.0]
    """
    T = X.simplices(3)
    vol = signed_volumes(P, T)
    if np.any(vol == 0):
        t = int(np.argmax(vol == 0))
        raise DegenerateSimplexError(f"the tetrahedron {tuple(int(v) for v in X.vertex_labels[T[t]])} has zero volume")
    return np.sign(vol)


def check_tet_complex(X: SimplicialComplex, P: ArrayLike, triangles: ArrayLike | None = None) -> np.ndarray:
    """Check that the triangles of a tetrahedral complex at ``P`` do not fold; return :func:`tet_signs`.

    Parameters
    ----------
    X : SimplicialComplex
        A complex of dimension 3.
    P : (X.n_vertices, 3) float array
        Positions of the (compact) vertices of ``X``.
    triangles : (k,) int array, optional
        Rows of ``X.simplices(2)`` to check; all triangles if None.

    Returns
    -------
    (X.n_simplices(3),) float array
        The orientation sign of every canonical tetrahedron.

    Raises
    ------
    DegenerateSimplexError
        A tetrahedron has zero volume.
    NonManifoldError
        A checked triangle lies in more than two tetrahedra (named by its vertex labels).
    InconsistentOrientationError
        The two tetrahedra at a checked triangle lie on the same side of it (the mesh folds over).

    Examples
    --------
    >>> from dhlb import SimplicialComplex
    >>> X = SimplicialComplex([(0, 1, 2, 3), (0, 1, 2, 4)])
    >>> check_tet_complex(X, [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0, 0, -1]]).tolist()
    [1.0, -1.0]
    >>> try:
    ...     check_tet_complex(X, [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0, 0, 2]])
    ... except InconsistentOrientationError as err:
    ...     print(str(err)[:60])
    the two tetrahedra at the triangle (0, 1, 2) lie on the same
    """
    sgn = tet_signs(X, P)
    cnt, fold = _triangle_sides(X, sgn)
    rows = np.arange(cnt.size) if triangles is None else np.asarray(triangles, dtype=np.int64)
    name = lambda f: tuple(int(v) for v in X.vertex_labels[X.simplices(2)[f]])  # noqa: E731
    if np.any(cnt[rows] > 2):
        f = rows[np.argmax(cnt[rows] > 2)]
        raise NonManifoldError(f"the triangle {name(f)} lies in {cnt[f]} tetrahedra; filaments need at most 2")
    if np.any(fold[rows]):
        f = rows[np.argmax(fold[rows])]
        raise InconsistentOrientationError(f"the two tetrahedra at the triangle {name(f)} lie on the same side of it "
                                           "(the mesh folds over); fix the mesh with dhlb.mesh.check_tet_mesh")
    return sgn


def _check_no_folds(X: SimplicialComplex, P: np.ndarray, index: np.ndarray, T_in: np.ndarray) -> None:
    """Neighbouring tetrahedra must induce opposite orientations on their common triangle."""
    _, fold = _triangle_sides(X, np.sign(signed_volumes(P, X.simplices(3))))
    if np.any(fold):
        f = int(np.argmax(fold))
        row_of = np.empty(index.size, np.int64)
        row_of[index] = np.arange(index.size)
        a, b = (int(row_of[t]) for t in np.nonzero((X.faces(3) == f).any(axis=1))[0])
        tri = tuple(int(v) for v in X.vertex_labels[X.simplices(2)[f]])
        err = InconsistentOrientationError(
            f"{_name_tet(a, T_in)} and {_name_tet(b, T_in)} lie on the same side of their common "
            f"triangle {tri}: the mesh folds over there ({int(fold.sum())} such triangles). Remove or "
            "re-mesh the overlapping tetrahedra."
        )
        err.element = (a, b)
        raise err


# ---------------------------------------------------------------------------- generators
BOX_BYTES_PER_CELL = 7_000
"""Peak bytes per cell of :func:`box_tet_mesh` (measured 5.8 kB at 52³ cells, rounded up)."""
VORTEX_BYTES_PER_CELL = 12_000
"""Peak bytes per cell of ``dhlb vortex --box`` end to end (measured 9.3–9.7 kB at 28³ … 52³ cells)."""
BALL_BYTES_PER_TET = 1_000
"""Peak bytes per tetrahedron of :func:`ball_tet_mesh` (measured 917–931 B at n = 8 … 40, rounded up)."""
_BASE_BYTES = 100_000_000  # the interpreter with numpy, scipy and dhlb imported (measured 66 MB)


def _cells(m) -> tuple[int, int]:
    """``(m as given, number of cells)`` for an int or 3 ints, checked to be integers >= 1."""
    ms = [m] if np.ndim(m) == 0 else list(np.asarray(m).ravel())
    if len(ms) not in (1, 3):
        raise InvalidParameterError(f"m must be one integer or three, got {m!r}")
    for v in ms:
        check_int(v, "the number of cells per axis", 1)
    cells = int(ms[0]) ** 3 if len(ms) == 1 else int(ms[0]) * int(ms[1]) * int(ms[2])
    return m, cells


def box_memory_estimate(m: int | Sequence[int], *, per_cell: int = BOX_BYTES_PER_CELL) -> int:
    """Estimated peak bytes of a box mesh with ``m`` cells per axis (``per_cell`` bytes a cell + imports).

    ``per_cell`` is :data:`BOX_BYTES_PER_CELL` for :func:`box_tet_mesh` alone and
    :data:`VORTEX_BYTES_PER_CELL` for the whole vortex pipeline on it (mesh, bundle, matrices,
    sparse factorization, extraction); both are measured peaks rounded up, the growth is linear
    in the number of cells in the measured range.

    Examples
    --------
    >>> box_memory_estimate(400) / 1e9 > 400                      # --box 400: hundreds of GB
    True
    >>> box_memory_estimate(12, per_cell=VORTEX_BYTES_PER_CELL) < 200e6
    True
    """
    _, cells = _cells(m)
    return _BASE_BYTES + int(per_cell) * cells


def _ball_tets(n: int) -> int:
    return 6 * n**3 + 36 * n**2 * max(1, -(-n // 2))


def _ball_bytes(n: int) -> int:
    """Estimated peak bytes of ``ball_tet_mesh(n)`` (:data:`BALL_BYTES_PER_TET` a tetrahedron + imports)."""
    return _BASE_BYTES + BALL_BYTES_PER_TET * _ball_tets(n)


def _available_bytes() -> int:
    try:
        from dhlb.linalg.memory import available_bytes
    except ImportError:  # pragma: no cover - the linear-algebra layer is always there
        import os

        return int(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_AVPHYS_PAGES"))
    return int(available_bytes())


def check_box_memory(m: int | Sequence[int], *, per_cell: int = BOX_BYTES_PER_CELL, name: str = "m",
                     available: int | None = None) -> int:
    """Refuse a box size whose estimated memory exceeds what is available; return the estimate.

    Parameters
    ----------
    m : int or 3 ints
        Cells per axis.
    per_cell : int
        Bytes per cell of the work planned (see :func:`box_memory_estimate`).
    name : str
        How the message calls the parameter (``"m"``, ``"--box"``).
    available : int, optional
        Bytes available (default: free memory, cgroup and ``RLIMIT_AS`` room, and the
        ``DHLB_MEMORY_LIMIT`` environment variable, whichever is least).

    Raises
    ------
    InvalidParameterError
        ``m`` is not a positive integer (or three).
    ResourceLimitError
        The estimate exceeds ``available``; the message gives both and the largest ``m`` that fits.

    Examples
    --------
    >>> check_box_memory(400, available=8 * 10**9)
    Traceback (most recent call last):
    ...
    dhlb.errors.ResourceLimitError: m = 400 needs about 450 GB of memory (estimate), more than the 8 GB allowed; ...
    """
    _, cells = _cells(m)
    need = box_memory_estimate(m, per_cell=per_cell)
    room = _available_bytes() if available is None else int(available)
    if need > room:
        largest = int(max(0.0, (room - _BASE_BYTES) / per_cell) ** (1 / 3))
        fits = f"at most {largest} cells per axis fit" if largest >= 1 else "not even one cell fits"
        raise ResourceLimitError(name, m if np.ndim(m) == 0 else list(np.asarray(m).ravel()), need, room,
                                 f"{fits} ({cells} cells asked; set DHLB_MEMORY_LIMIT to change the budget)")
    return need


def box_corners(lower: ArrayLike, upper: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """The corners ``(lower, upper)`` of a box as two 3-vectors, checked: finite, ``lower < upper`` on every axis.

    Parameters
    ----------
    lower, upper : 3 floats (or one number for all axes)
        Opposite corners.

    Returns
    -------
    lower, upper : (3,) float arrays

    Raises
    ------
    InvalidParameterError
        ``lower < upper`` fails on an axis.
    ShapeError, NonFiniteError
        Neither a number nor 3 numbers, or not finite.

    Examples
    --------
    >>> [c.tolist() for c in box_corners(-1, (1, 2, 3))]
    [[-1.0, -1.0, -1.0], [1.0, 2.0, 3.0]]
    """
    lo = as_vec3(np.broadcast_to(lower, 3) if np.ndim(lower) == 0 else lower, "lower")
    hi = as_vec3(np.broadcast_to(upper, 3) if np.ndim(upper) == 0 else upper, "upper")
    if np.any(hi <= lo):
        raise InvalidParameterError(f"the box needs lower < upper on every axis, got lower={lo.tolist()}, "
                                    f"upper={hi.tolist()}")
    return lo, hi


def box_tet_mesh(
    m: int | Sequence[int] = 4, lower: ArrayLike = (0.0, 0.0, 0.0), upper: ArrayLike = (1.0, 1.0, 1.0)
) -> TetMesh:
    """Freudenthal–Kuhn tetrahedral mesh of the box ``[lower, upper]`` with ``m`` cells per axis.

    The grid of :func:`dhlb.examples.cube_nd` (six tetrahedra per cell, all sharing the cell's
    diagonal) scaled to the box; grid point ``(i, j, k)`` is vertex ``(i (m_1+1) + j)(m_2+1) + k``.

    Parameters
    ----------
    m : int >= 1, or 3 ints
        Cells per axis.
    lower, upper : 3 floats (or one number for all axes)
        Opposite corners, ``lower < upper`` on every axis.

    Returns
    -------
    TetMesh
        The box mesh, ``6 m³`` positively oriented tetrahedra (``6 m_0 m_1 m_2`` for three ints).

    Raises
    ------
    InvalidParameterError, ResourceLimitError
        ``m`` is not a positive integer, or its estimated memory (:func:`check_box_memory`)
        exceeds what is available — refused before any work; or ``lower < upper`` fails on an axis.
    ShapeError, NonFiniteError
        ``lower`` or ``upper`` is neither a number nor 3 numbers, or is not finite.

    Examples
    --------
    >>> mesh = box_tet_mesh(3, lower=-1.0, upper=1.0)
    >>> mesh.tets.shape, float(mesh.points.min()), round(float(mesh.volumes.sum()), 12)
    ((162, 4), -1.0, 8.0)
    """
    check_box_memory(m)
    lo, hi = box_corners(lower, upper)
    X, U = cube_nd(3, m, return_points=True)
    return check_tet_mesh(lo + U * (hi - lo), X.simplices(3))


_CORE_RATIO = 0.4  # half-side of the core cube / radius (corner at 0.69 R); best min quality in a scan


def ball_tet_mesh(n: int = 4, radius: float = 1.0, center: ArrayLike = (0.0, 0.0, 0.0)) -> TetMesh:
    """Deterministic tetrahedral mesh of a ball: a Kuhn-triangulated core cube inside a graded shell.

    The core is the cube ``center + [−0.4 R, 0.4 R]³`` with ``n`` cells per axis
    (:func:`box_tet_mesh`). Its boundary triangles ``s`` are swept out to the sphere in
    ``K = ceil(n / 2)`` layers: layer ``k`` puts the core boundary point ``s`` at
    ``(1 − k/K) s + (k/K) R s/|s|`` (relative to the center); the prism between layers ``k`` and
    ``k+1`` over a boundary triangle ``a < b < c`` is cut into the three tetrahedra of its
    staircase triangulation ``(a_k b_k c_k c_{k+1})``, ``(a_k b_k b_{k+1} c_{k+1})``,
    ``(a_k a_{k+1} b_{k+1} c_{k+1})``, which agree on shared quadrilaterals because the
    diagonal always runs from the smaller vertex on layer ``k`` to the larger on layer ``k+1``.
    No tetrahedron has more than three vertices on the sphere, so none is flattened by the
    projection, and the shape quality does not degrade as ``n`` grows (measured minimum of
    ``6√2 vol / L³``: 0.059 for ``n = 1``, 0.067–0.069 for ``n = 2..12``; Kuhn cubes have 0.27).
    The boundary vertices lie on the sphere; the enclosed volume is ``4π R³/3 − O(R³/n²)``.

    This replaces the classical "clip a grid and project its boundary", whose output has
    flattened and non-manifold elements where the sphere grazes grid points.

    Parameters
    ----------
    n : int >= 1, optional
        Cells per axis of the core cube; there are ``6 n³ + 36 n² ceil(n/2)`` tetrahedra.
    radius : float > 0, optional
        Radius ``R`` of the ball.
    center : 3 floats, optional
        Center of the ball.

    Returns
    -------
    TetMesh
        The ball mesh; its boundary vertices lie on the sphere.

    Raises
    ------
    InvalidParameterError
        ``radius`` is not a finite number > 0, or ``n`` is not an integer >= 1.
    ResourceLimitError
        The mesh of ``n`` would need more memory than is available (about :data:`BALL_BYTES_PER_TET` bytes
        a tetrahedron; the free memory, the cgroup's and the address-space limit count, see
        :func:`dhlb.linalg.available_bytes`): refused before any work, with the estimate and the largest
        ``n`` that fits.
    ShapeError, NonFiniteError
        ``center`` is not 3 numbers (or one), or is not finite.

    Examples
    --------
    >>> import numpy as np
    >>> mesh = ball_tet_mesh(4, radius=2.0)
    >>> mesh.tets.shape[0], mesh.complex.euler_characteristic
    (1536, 1)
    >>> B = np.unique(mesh.boundary_faces)
    >>> bool(np.allclose(np.linalg.norm(mesh.points[B], axis=1), 2.0))
    True
    """
    c = as_vec3(center, "center")
    R = float(radius) if np.isscalar(radius) else np.nan
    if not (np.isfinite(R) and R > 0):
        raise InvalidParameterError(f"radius must be a finite number > 0, got {radius!r}")
    n = check_int(n, "n", 1)
    check_memory("n", n, _ball_bytes(n), largest=lambda room: largest_fitting(_ball_bytes, room, 1, n),
                 advice=f"ball_tet_mesh(n) has 6 n³ + 36 n² ceil(n/2) tetrahedra ({_ball_tets(n):,} here), "
                        f"about {BALL_BYTES_PER_TET:,} bytes each")
    X, U = cube_nd(3, n, return_points=True)
    N = U.shape[0]
    r0 = _CORE_RATIO * R
    core = (2 * U - 1) * r0
    T = np.asarray(X.simplices(3))
    cnt = np.bincount(X.faces(3).ravel(), minlength=X.n_simplices(2))
    S = X.simplices(2)[cnt == 1]  # boundary triangles, sorted rows a < b < c
    sv = np.unique(S)
    K = max(1, -(-n // 2))
    rank = np.full(N, -1, np.int64)
    rank[sv] = np.arange(sv.size)
    s = core[sv]
    t = (np.arange(1, K + 1) / K)[None, :, None]
    shell = (1 - t) * s[:, None, :] + t * (R * s / np.linalg.norm(s, axis=1)[:, None])[:, None, :]
    P = np.concatenate([core, shell.reshape(-1, 3)]) + c

    def vid(v: np.ndarray, k: int) -> np.ndarray:
        return v if k == 0 else N + rank[v] * K + (k - 1)

    a, b, cc = S[:, 0], S[:, 1], S[:, 2]
    blocks = [T]
    for k in range(K):
        blocks += [np.stack([vid(a, k), vid(b, k), vid(cc, k), vid(cc, k + 1)], axis=1),
                   np.stack([vid(a, k), vid(b, k), vid(b, k + 1), vid(cc, k + 1)], axis=1),
                   np.stack([vid(a, k), vid(a, k + 1), vid(b, k + 1), vid(cc, k + 1)], axis=1)]
    return check_tet_mesh(P, np.concatenate(blocks))
