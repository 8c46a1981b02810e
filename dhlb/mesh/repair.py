"""Repairing the triangle meshes people have: a soup in, a manifold oriented surface and a map back out.

Classic test models and real scans carry everyday defects: a vertex where two sheets touch, an edge
with three faces, a fin made of a triangle and its mirror image, a face of zero area. What other
tools repair routinely, :func:`repair_surface` repairs and reports, and the mesh it returns
remembers how to map every result back to the input's vertices and faces (:class:`MeshRepair`).
The applications reach it through ``validate_surface(..., repair=...)``: the options
``FieldOptions(repair=...)``, ``StripeOptions(repair=...)`` and the command line's ``--repair``.

The repairs, in the order they are made (:class:`RepairOptions` names each one):

``merge-vertices`` (only when asked: it changes the topology)
    Vertices at exactly the same position are merged into the lowest row.
``degenerate``
    A face that repeats a vertex (``[a, a, b]``) has no area and no topology: it is dropped.
``duplicates``
    Copies of a triangle with the same orientation are merged into the first. Copies with both
    orientations are a *doubled sheet*: as oriented 2-chains the two copies cancel (``f + f̄ = 0``),
    and a two-sided piece of zero thickness encloses nothing. Where it hangs on the rest of the
    surface (a fin or pocket, as on Suzanne and the beast) it is removed; a connected piece made
    only of doubled triangles (a two-sided sheet such as a leaf) keeps one side, the orientation of
    its first copies. Several copies count by their net orientation: two of one and one of the
    other orientation leave one copy.
``split``
    An edge with three or more faces is cut: its faces are sorted by angle around the edge and
    paired with their neighbours (a face meets the next one where their orientations agree, the
    pairing that keeps each outward-oriented solid whole), an odd face out is detached (a boundary
    edge). Then every vertex gets one copy per fan of faces around it: two cones meeting at their
    tips become two vertices. Topology changes, geometry does not: the copies sit where the vertex was.
``reorient``
    Faces are flipped into a consistent orientation, keeping the orientation of the majority of each
    component (an orientable surface only).
``drop-nonorientable`` (only when asked)
    A component that is not orientable (a Möbius band) is removed; otherwise it is refused with
    :class:`~dhlb.errors.NonOrientableError`: direction fields need an oriented surface.
``mollify``
    If some face has zero area (collinear vertices, or two vertices at one position), every edge is
    lengthened by the smallest ``δ`` that makes every triangle satisfy the triangle inequality by
    ``ε = tol · mean edge length`` (*intrinsic mollification*, Sharp & Crane, "A Laplacian for
    Nonmanifold Triangle Meshes", 2020, §4.5): ``δ = max(0, max_t (ε − min_k (l_i + l_j − l_k)))``.
    Adding ``δ`` to the three lengths of a triangle raises each of its triangle-inequality gaps by
    exactly ``δ`` (``proofs/derive_mollification.py``), so every triangle becomes valid with gap at
    least ``ε``; no vertex moves, every length changes by exactly ``δ``, and the cotangent weights
    stay finite. The mesh then carries its metric as :attr:`SurfaceMesh.edge_lengths`: corner
    angles, curvature, transports and the finite elements are those of the intrinsic triangles.
    A mesh with no zero-area face is not touched (``δ = 0``).

A mesh with none of these defects passes through unchanged (``validate_surface`` tries the strict
checks first: no repair, no warning, the same arrays). Each repair made is reported once as a
:class:`~dhlb.errors.MeshRepairWarning` with counts and the first input rows, and recorded in
``mesh.repair`` (``to_json()`` for the outputs).

**Back to the input.** ``mesh.face_rows`` gives the input row of each face; ``repair.face_of_input``
the face carrying each input row (a merged duplicate: the copy kept; -1 for a removed face).
``repair.vertex_rows`` gives the input row of each vertex (copies of a split vertex share it) and
``repair.vertex_of_input`` the vertex that speaks for each input row: of several copies, the one
whose fan has the largest area (lowest number on a tie), so that a per-vertex result is the value
on the sheet that carries most of the vertex; rows merged into one vertex all take its value.

Examples
--------
>>> import numpy as np
>>> from dhlb.mesh.repair import repair_surface
>>> V = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0]]
>>> F = [[0, 1, 2], [0, 3, 4]]                       # two triangles touching at vertex 0 (a bowtie)
>>> mesh = repair_surface(V, F, warn=False)
>>> mesh.n_vertices, mesh.repair.vertex_rows.tolist(), [r.kind for r in mesh.repair.repairs]
(6, [0, 1, 2, 3, 4, 0], ['split'])
"""

from __future__ import annotations

import json
import numbers
import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from dhlb.errors import (
    DegenerateSimplexError,
    DhlbError,
    DhlbWarning,
    EmptyComplexError,
    InconsistentOrientationError,
    InvalidParameterError,
    InvalidSimplexError,
    MeshRepairWarning,
    NonManifoldError,
    NonOrientableError,
    UnreferencedVertexWarning,
)
from dhlb.geometry.euclidean import EuclideanComplex
from dhlb.geometry.simplex import SimplexStack
from dhlb.mesh import _surface_checks as checks
from dhlb.mesh.compact import _renumber
from dhlb.mesh.halfedge import halfedge_pairs
from dhlb.topology._dual_graph import propagate_signs
from dhlb.topology._keys import argsort_keys
from dhlb.topology.complex import SimplicialComplex

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from dhlb.mesh.surface import SurfaceMesh

__all__ = ["MeshRepair", "Repair", "RepairOptions", "REPAIRS", "SAFE_REPAIRS", "repair_surface", "repaired_mesh"]

REPAIRS = ("merge-vertices", "degenerate", "duplicates", "split", "reorient", "drop-nonorientable", "mollify")
"""Every repair, in the order :func:`repair_surface` makes them (the names of ``--repair``)."""
SAFE_REPAIRS = ("degenerate", "duplicates", "split", "reorient", "mollify")
"""The repairs made by default (``repair="safe"``): they keep every vertex where it is and every face that
carries area; merging vertices and dropping non-orientable components change more and are only made when
asked."""
_FIELDS = {name: name.replace("-", "_") for name in REPAIRS}
_REPAIRABLE = (DegenerateSimplexError, InvalidSimplexError, NonManifoldError, InconsistentOrientationError,
               NonOrientableError)   # the strict checks' errors a repair may fix (the others are raised again)
_EXAMPLES = 5  # first input rows named in a message and kept in the report


@dataclass(frozen=True)
class RepairOptions:
    """Which repairs :func:`repair_surface` may make (see :mod:`dhlb.mesh.repair` for each).

    Parameters
    ----------
    degenerate, duplicates, split, reorient, mollify : bool
        The safe repairs (default on): drop faces repeating a vertex; merge duplicate faces and remove
        doubled sheets; split non-manifold edges and vertices; reorient faces consistently; mollify
        zero-area faces.
    merge_vertices, drop_nonorientable : bool
        Merge vertices at the same position; drop non-orientable components (default off).
    mollify_tol : float
        ``ε / mean edge length`` of the mollification (default 1e-6, as Sharp & Crane).

    Raises
    ------
    InvalidParameterError
        A switch that is not a bool, or ``mollify_tol`` outside ``(0, 0.1)``.

    Examples
    --------
    >>> RepairOptions.parse("none").enabled, RepairOptions.parse("safe,merge-vertices").enabled[0]
    ((), 'merge-vertices')
    >>> RepairOptions.parse("split,reorient")
    RepairOptions(split, reorient)
    """

    merge_vertices: bool = False
    degenerate: bool = True
    duplicates: bool = True
    split: bool = True
    reorient: bool = True
    drop_nonorientable: bool = False
    mollify: bool = True
    mollify_tol: float = 1e-6

    def __post_init__(self) -> None:
        for name in _FIELDS.values():
            if not isinstance(getattr(self, name), (bool, np.bool_)):
                raise InvalidParameterError(f"RepairOptions.{name} must be True or False, got "
                                            f"{getattr(self, name)!r}")
        tol = self.mollify_tol
        if isinstance(tol, bool) or not isinstance(tol, numbers.Real) or not (0 < tol < 0.1):
            raise InvalidParameterError(f"RepairOptions.mollify_tol must be a number in (0, 0.1) (ε relative to the "
                                        f"mean edge length), got {tol!r}")

    @property
    def enabled(self) -> tuple[str, ...]:
        """The names of the repairs switched on, in :data:`REPAIRS` order."""
        return tuple(name for name in REPAIRS if getattr(self, _FIELDS[name]))

    @property
    def any(self) -> bool:
        """True if at least one repair is switched on."""
        return bool(self.enabled)

    @classmethod
    def parse(cls, value: Any) -> RepairOptions:
        """The options named by ``value``.

        Parameters
        ----------
        value : RepairOptions, bool, None or str
            A :class:`RepairOptions`; ``"safe"`` or True (the default repairs, :data:`SAFE_REPAIRS`);
            ``"none"``, False or None (none: the strict checks of ``validate_surface``); ``"all"``; or a
            comma-separated list of names from :data:`REPAIRS`, optionally starting with ``safe``
            (``"safe,merge-vertices"``).

        Returns
        -------
        RepairOptions

        Raises
        ------
        InvalidParameterError
            An unknown name (the message lists the known ones).
        """
        if isinstance(value, RepairOptions):
            return value
        if value is None or value is False:
            return cls(**{f: False for f in _FIELDS.values()})
        if value is True:
            return cls()
        if not isinstance(value, str):
            raise InvalidParameterError(f"repair must be 'safe', 'none', 'all', a comma-separated list of "
                                        f"{', '.join(REPAIRS)} or a RepairOptions, got {value!r}")
        words = [w.strip().lower() for w in value.split(",") if w.strip()]
        chosen: set[str] = set()
        for w in words or ["none"]:
            if w == "safe":
                chosen |= set(SAFE_REPAIRS)
            elif w == "all":
                chosen |= set(REPAIRS)
            elif w == "none":
                continue
            elif w in _FIELDS:
                chosen.add(w)
            else:
                from dhlb._deprecation import did_you_mean

                raise InvalidParameterError(f"unknown repair {w!r}: give safe, none, all or a comma-separated list of "
                                            f"{', '.join(REPAIRS)}{did_you_mean(w, [*REPAIRS, 'safe', 'none', 'all'])}")
        if "none" in words and len(words) > 1:
            raise InvalidParameterError(f"repair 'none' cannot be combined with other repairs, got {value!r}")
        return cls(**{_FIELDS[name]: name in chosen for name in REPAIRS})

    def __repr__(self) -> str:
        extra = "" if self.mollify_tol == 1e-6 else f", mollify_tol={self.mollify_tol!r}"
        return f"RepairOptions({', '.join(self.enabled) or 'none'}{extra})"


@dataclass(frozen=True)
class Repair:
    """One kind of repair made, as reported (one :class:`~dhlb.errors.MeshRepairWarning` each).

    Parameters
    ----------
    kind : str
        The repair (a name of :data:`REPAIRS`, or ``"doubled"`` for removed doubled sheets).
    count : int
        How many vertices, faces or edges it concerned (the message says which).
    message : str
        What was done, in words, with the first input rows.
    faces : tuple of int
        The first input rows of F concerned.
    vertices : tuple of int
        The first input rows of V concerned.
    value : float or None
        A number the repair chose (the mollification's δ), else None.
    """

    kind: str
    count: int
    message: str
    faces: tuple = ()
    vertices: tuple = ()
    value: float | None = None

    def to_json(self) -> dict:
        """A JSON-ready dict (``kind``, ``count``, ``message``, ``faces``, ``vertices`` and ``value`` if any)."""
        out = {"kind": self.kind, "count": int(self.count), "message": self.message,
               "faces": [int(f) for f in self.faces], "vertices": [int(v) for v in self.vertices]}
        if self.value is not None:
            out["value"] = float(self.value)
        return out


@dataclass(frozen=True, eq=False)
class MeshRepair:
    """What :func:`repair_surface` did, and the maps from the repaired mesh back to the input.

    Parameters
    ----------
    repairs : tuple of Repair
        The repairs made, in order (empty if the mesh needed none).
    options : RepairOptions
        The repairs that were allowed.
    vertex_rows : (N,) int array
        Input row in V of each vertex of the mesh (copies of a split vertex share it).
    vertex_of_input : (n_V,) int array
        For each input row of V, the mesh vertex that speaks for it (-1: used by no face kept).
    face_of_input : (n_F,) int array
        For each input row of F, the mesh face that carries it (a merged duplicate: the copy kept; -1:
        removed).
    delta : float
        The mollification's δ (0 if no face needed it), in the units of V.
    source : str
        A fingerprint of the input arrays and ``components`` (:meth:`is_repair_of`).
    """

    repairs: tuple
    options: RepairOptions
    vertex_rows: np.ndarray
    vertex_of_input: np.ndarray
    face_of_input: np.ndarray
    delta: float = 0.0
    source: str = ""

    def is_repair_of(self, V, F, components: str = "all", repair: Any = "safe") -> bool:
        """Whether repairing ``(V, F)`` with these options gives this repair again (same arrays, same options)."""
        try:
            return (RepairOptions.parse(repair) == self.options
                    and _fingerprint(np.asarray(V, np.float64), np.asarray(F, np.int64), components) == self.source)
        except (DhlbError, TypeError, ValueError):
            return False

    def __post_init__(self) -> None:
        for a in (self.vertex_rows, self.vertex_of_input, self.face_of_input):
            a.setflags(write=False)

    def __bool__(self) -> bool:
        return bool(self.repairs)

    @property
    def kinds(self) -> tuple[str, ...]:
        """The kinds of the repairs made."""
        return tuple(r.kind for r in self.repairs)

    def to_json(self) -> list:
        """The repairs as a JSON-ready list (empty if none was needed)."""
        return [r.to_json() for r in self.repairs]

    def to_json_text(self) -> str:
        """:meth:`to_json` as a JSON string (stored in ``.npz`` outputs under the key ``repairs``)."""
        return json.dumps(self.to_json())

    def to_arrays(self) -> dict:
        """The repair as arrays for an ``.npz`` output (:meth:`from_arrays` reads them back).

        Keys ``repairs`` (:meth:`to_json_text`), ``repair_options`` (the names allowed), ``repair_delta``,
        ``vertex_of_input`` and ``face_of_input``; the vertex rows are the caller's ``vertex_rows``.
        """
        return {"repairs": np.array(self.to_json_text()), "repair_options": np.array(",".join(self.options.enabled)
                                                                                      or "none"),
                "repair_delta": np.float64(self.delta), "vertex_of_input": self.vertex_of_input,
                "face_of_input": self.face_of_input}

    @classmethod
    def from_arrays(cls, data: dict, vertex_rows: np.ndarray) -> MeshRepair:
        """The repair stored by :meth:`to_arrays` (``data`` a dict of the ``.npz`` arrays).

        Raises
        ------
        ValueError
            The arrays do not describe a repair (wrong types or shapes); the reader names the file.
        """
        try:
            items = json.loads(str(data["repairs"]))
            repairs = tuple(Repair(str(r["kind"]), int(r["count"]), str(r["message"]),
                                   tuple(int(f) for f in r.get("faces", ())),
                                   tuple(int(v) for v in r.get("vertices", ())),
                                   None if r.get("value") is None else float(r["value"])) for r in items)
            opts = RepairOptions.parse(str(data["repair_options"]))
            delta = float(np.asarray(data.get("repair_delta", 0.0), dtype=np.float64))
        except (KeyError, TypeError, AttributeError, OverflowError, json.JSONDecodeError, InvalidParameterError) as exc:
            raise ValueError(f"the repair record is not readable ({exc})") from None
        if not (np.isfinite(delta) and delta >= 0):
            raise ValueError(f"repair_delta must be a finite number >= 0, got {delta!r}")
        voi = np.asarray(data["vertex_of_input"])
        foi = np.asarray(data["face_of_input"])
        rows = np.asarray(vertex_rows)
        if voi.ndim != 1 or foi.ndim != 1 or voi.dtype.kind not in "iu" or foi.dtype.kind not in "iu":
            raise ValueError("vertex_of_input and face_of_input must be 1-d integer arrays")
        if voi.size and (voi.min() < -1 or voi.max() >= rows.size):
            raise ValueError(f"vertex_of_input refers to vertices outside 0 .. {rows.size - 1}")
        if foi.size and foi.min() < -1:
            raise ValueError(f"face_of_input holds {int(foi.min())}: faces are numbered from 0 (-1: removed)")
        return cls(repairs, opts, rows.astype(np.int64), voi.astype(np.int64), foi.astype(np.int64), delta)


# ---------------------------------------------------------------------------- the steps
def _fingerprint(P: np.ndarray, T: np.ndarray, components: str) -> str:
    import hashlib

    h = hashlib.blake2b(digest_size=16)
    for a in (P, T):
        h.update(str(a.shape).encode())
        h.update(np.ascontiguousarray(a).tobytes())
    h.update(components.encode())
    return h.hexdigest()


def _rows(rows, what="face", plural=None) -> str:
    rows = [int(r) for r in rows]
    head = ", ".join(str(r) for r in rows[:_EXAMPLES])
    name = what if len(rows) == 1 else (plural or what + "s")
    return f"{name} {head}{', ...' if len(rows) > _EXAMPLES else ''}"


def _plural(k: int, word: str, plural: str | None = None) -> str:
    return f"{k} {word if k == 1 else (plural or word + 's')}"


class _Soup:
    """The faces being repaired: rows ``T`` of ``P``, their input rows, and what was done so far."""

    def __init__(self, P: np.ndarray, T: np.ndarray, opts: RepairOptions):
        self.P, self.T, self.opts = P, T, opts
        self.n_input = len(P)
        self.n_input_faces = len(T)
        self.rows = np.arange(len(T), dtype=np.int64)
        self.carrier = np.arange(len(T), dtype=np.int64)  # input row whose kept face carries each input row
        self.repairs: list[Repair] = []
        self.merged = np.arange(len(P), dtype=np.int64)  # input row -> row it was merged into
        self.flipped = None   # per face: flipped by the reorientation
        self.nm_edges = 0     # edges with three or more faces (see _edge_pairs)
        self.nm_rows = self.detached_rows = np.zeros(0, np.int64)

    def keep(self, mask: np.ndarray) -> None:
        self.T, self.rows = self.T[mask], self.rows[mask]

    def report(self, kind: str, count: int, message: str, faces=(), vertices=(), value=None) -> None:
        self.repairs.append(Repair(kind, int(count), message, tuple(int(f) for f in list(faces)[:_EXAMPLES]),
                                   tuple(int(v) for v in list(vertices)[:_EXAMPLES]), value))


def _merge_vertices(s: _Soup) -> None:
    used = np.zeros(len(s.P), bool)
    used[s.T.ravel()] = True
    rows = np.flatnonzero(used)
    _, first, inv = np.unique(s.P[rows], axis=0, return_index=True, return_inverse=True)
    target = rows[first][inv.ravel()]
    moved = rows[target != rows]
    if moved.size == 0:
        return
    s.merged[rows] = target
    s.T = s.merged[s.T]
    s.report("merge-vertices", moved.size,
             f"merged {_plural(moved.size, 'vertex', 'vertices')} at the same position as a "
             f"lower row into that row ({', '.join(f'{int(v)} → {int(s.merged[v])}' for v in moved[:_EXAMPLES])}"
             f"{', ...' if moved.size > _EXAMPLES else ''})", vertices=moved)


def _degenerate(s: _Soup) -> None:
    srt = np.sort(s.T, axis=1)
    rep = np.any(srt[:, 1:] == srt[:, :-1], axis=1)
    if not np.any(rep):
        return
    if not s.opts.degenerate:
        checks.check_faces(s.P, s.T)  # raises the strict message
    gone = s.rows[rep]
    s.carrier[gone] = -1
    s.keep(~rep)
    s.report("degenerate", gone.size, f"dropped {_plural(gone.size, 'face')} that repeat a vertex (no area, no "
             f"topology): {_rows(gone)}", faces=gone)


def _face_components(T: np.ndarray, n: int) -> np.ndarray:
    """Component of each face, faces joined when they share an (undirected) edge."""
    m = len(T)
    a, b = T.ravel(), np.roll(T, -1, axis=1).ravel()
    key = np.minimum(a, b) * n + np.maximum(a, b)
    order = argsort_keys(key, n * n)
    sk = key[order]
    edge = np.empty(key.size, np.int64)
    edge[order] = np.cumsum(np.r_[True, sk[1:] != sk[:-1]]) - 1
    face = np.repeat(np.arange(m), 3)
    g = sp.csr_matrix((np.ones(face.size, np.int8), (face, edge)), shape=(m, int(edge.max()) + 1))
    _, lab = connected_components(sp.bmat([[None, g], [g.T, None]]), directed=False)
    return lab[:m]


def _duplicates(s: _Soup) -> None:
    T, n = s.T, max(len(s.P), 1)
    srt = np.sort(T, axis=1)
    if n < 2_000_000:
        key = (srt[:, 0] * n + srt[:, 1]) * n + srt[:, 2]
        sk = np.sort(key)
        if not np.any(sk[1:] == sk[:-1]):   # the common case: one value sort, no duplicate
            return
        _, first, inv, cnt = np.unique(key, return_index=True, return_inverse=True, return_counts=True)
    else:
        _, first, inv, cnt = np.unique(srt, axis=0, return_index=True, return_inverse=True, return_counts=True)
    inv = inv.ravel()
    if np.all(cnt == 1):
        return
    if not s.opts.duplicates:
        checks.check_faces(s.P, T)  # raises the strict message
    sign = SimplicialComplex.orientation_of(T)
    net = np.bincount(inv, weights=sign, minlength=cnt.size).astype(np.int64)
    m = len(T)
    idx = np.arange(m)
    # the copy kept of a group: its first face with the orientation of the net count
    want = np.sign(net)[inv]
    pick = np.full(cnt.size, m, np.int64)
    np.minimum.at(pick, inv, np.where((sign == want) & (want != 0), idx, m))
    doubled = (net == 0)[inv]  # every copy of a triangle present with both orientations equally often
    keep = np.zeros(m, bool)
    keep[pick[pick < m]] = True
    if np.any(doubled):
        comp = _face_components(T, n)
        all_doubled = np.bincount(comp, weights=~doubled, minlength=comp.max() + 1) == 0
        sheet = doubled & all_doubled[comp]  # a piece made only of doubled triangles: keep one side
        keep[first[inv[sheet]]] = True
        removed = doubled & ~sheet
        if np.any(removed):
            r = s.rows[removed]
            s.report("doubled", int(removed.sum()),
                     f"removed {_plural(int(np.unique(inv[removed]).size), 'doubled triangle')} "
                     f"({_plural(int(removed.sum()), 'face')}: a triangle and its mirror image, a fin or pocket of "
                     f"zero thickness that cancels as a 2-chain): {_rows(r)}", faces=r)
        if np.any(sheet):
            r = s.rows[sheet & ~keep]
            s.report("doubled", int(sheet.sum()),
                     f"kept one side of {_plural(int(np.unique(comp[sheet]).size), 'two-sided sheet')} "
                     f"({_plural(int(r.size), 'mirror face')} dropped): {_rows(r)}", faces=r)
    # where each input row's triangle is carried now: the kept copy of its group, or nothing
    carrier_face = np.full(cnt.size, -1, np.int64)
    carrier_face[inv[keep]] = idx[keep]
    car = carrier_face[inv]
    merged = ~keep & (car >= 0) & ~doubled
    s.carrier[s.rows] = np.where(car >= 0, s.rows[np.maximum(car, 0)], -1)
    if np.any(merged):
        r = s.rows[merged]
        s.report("duplicates", int(merged.sum()), f"merged {_plural(int(merged.sum()), 'duplicate face')} into the "
                 f"first copy of the same triangle: {_rows(r)}", faces=r)
    s.keep(keep)


def _angle_pairs(s: _Soup, hs: np.ndarray, outward: bool) -> list[tuple[int, int]]:
    """Pair the half-edges ``hs`` around one edge by the angles of their faces around it."""
    T, P = s.T, s.P
    f, k = hs // 3, hs % 3
    a, b = T[f[0], k[0]], T[f[0], (k[0] + 1) % 3]
    axis = P[b] - P[a]
    nrm = np.linalg.norm(axis)
    axis = axis / nrm if nrm > 0 else np.array([1.0, 0.0, 0.0])
    tip = P[T[f, (k + 2) % 3]] - P[a]
    radial = tip - np.outer(tip @ axis, axis)
    ref = radial[np.argmax(np.linalg.norm(radial, axis=1))]
    ref_n = np.linalg.norm(ref)
    ref = ref / ref_n if ref_n > 0 else np.cross(axis, [0.0, 0.0, 1.0] if abs(axis[2]) < 0.9 else [1.0, 0.0, 0.0])
    ang = np.arctan2(radial @ np.cross(axis, ref), radial @ ref)
    order = np.argsort(ang, kind="stable")
    forward = T[f, k] == a  # the face traverses a → b: its normal turns towards increasing angle
    q = len(hs)
    best, best_score = None, -1
    for start in range(q if q > 2 else 1):
        pairs, score = [], 0
        for i in range(start, start + q - 1, 2):
            x, y = order[i % q], order[(i + 1) % q]
            # an outward-oriented solid between angles x < y: its face at x turns away (b → a), at y towards
            good = (not forward[x]) and forward[y] if outward else forward[x] and not forward[y]
            score += 2 if good else (1 if forward[x] != forward[y] else 0)
            pairs.append((int(hs[x]), int(hs[y])))
        if score > best_score:
            best, best_score = pairs, score
    return best


def _edge_pairs(s: _Soup) -> np.ndarray:
    """Half-edge pairs ``(h, h')``, one per interior edge (the non-manifold edges' pairs chosen by angle).

    Sets ``s.nm_edges`` (the number of edges with three or more faces), ``s.nm_rows`` (the input rows of
    their faces) and ``s.detached_rows`` (those of the faces left without a partner there).
    """
    T, n = s.T, max(len(s.P), 1)
    a, b = T.ravel(), np.roll(T, -1, axis=1).ravel()
    key = np.minimum(a, b) * n + np.maximum(a, b)
    order = argsort_keys(key, n * n)
    sk = key[order]
    starts = np.flatnonzero(np.r_[True, sk[1:] != sk[:-1]])
    counts = np.diff(np.r_[starts, sk.size])
    two = starts[counts == 2]
    pairs = [np.stack([order[two], order[two + 1]], axis=1)]
    detached = []
    many = np.flatnonzero(counts > 2)
    if many.size:
        if not s.opts.split:
            X = SimplicialComplex(T)
            checks.check_manifold(X, T, s.rows)  # raises the strict message
        outward = _outward(s.P, T, n)
        extra = []
        for e in many:
            hs = order[starts[e]:starts[e] + counts[e]]
            got = _angle_pairs(s, hs, bool(outward[hs[0] // 3]))
            extra.extend(got)
            paired = {h for p in got for h in p}
            detached.extend(int(h) for h in hs if h not in paired)
        pairs.append(np.array(extra, np.int64).reshape(-1, 2))
        s.nm_edges = int(many.size)
        s.nm_rows = s.rows[np.unique(np.concatenate([order[starts[e]:starts[e] + counts[e]] // 3 for e in many]))]
        s.detached_rows = np.unique(s.rows[np.array(detached, np.int64) // 3])
    return np.concatenate(pairs)


def _outward(P: np.ndarray, T: np.ndarray, n: int) -> np.ndarray:
    """Per face: whether its component (faces joined by edges) encloses a positive signed volume.

    The signed volume is taken about the component's centroid (translation invariant when closed), so a
    solid touching another one is judged by its own orientation, not by the whole soup's.
    """
    comp = _face_components(T, n)
    nc = int(comp.max()) + 1
    cent = P[T].mean(axis=1)
    w = np.bincount(comp, minlength=nc).astype(float)
    c = np.stack([np.bincount(comp, weights=cent[:, k], minlength=nc) for k in range(3)], axis=1) / w[:, None]
    A, B, C = (P[T[:, k]] - c[comp] for k in range(3))
    vol = np.bincount(comp, weights=np.einsum("ij,ij->i", A, np.cross(B, C)), minlength=nc)
    return (vol >= 0)[comp]


def _edge_of(T: np.ndarray, h: int) -> tuple[int, int]:
    """The vertices ``(a, b)`` of half-edge ``h = 3f + k`` (``T[f, k] → T[f, k + 1]``)."""
    f, k = divmod(int(h), 3)
    return int(T[f, k]), int(T[f, (k + 1) % 3])


def _orient(s: _Soup, pairs: np.ndarray) -> np.ndarray:
    """Flip faces into a consistent orientation (majority kept per component); returns the pairs after."""
    T = s.T
    m = len(T)
    f0, f1 = pairs[:, 0] // 3, pairs[:, 1] // 3
    same = T.ravel()[pairs[:, 0]] == T.ravel()[pairs[:, 1]]  # both traverse the edge the same way
    if not np.any(same):   # consistently oriented already (all signs +1 satisfy every pair)
        return pairs
    o, lab, clash = propagate_signs(m, np.stack([f0, f1], axis=1), same.astype(np.int64))
    if np.any(clash):
        bad = np.unique(lab[f0[clash]])
        if not s.opts.drop_nonorientable:
            e = int(np.argmax(clash))
            edge = _edge_of(T, pairs[e, 0])
            raise NonOrientableError(
                f"the surface is not orientable: it contains a Möbius band (carrying an orientation of the faces "
                f"around it comes back reversed, e.g. at edge {edge}, faces {int(s.rows[f0[e]])} and "
                f"{int(s.rows[f1[e]])}). Direction fields are sections of the tangent bundle of an oriented surface; "
                "n-direction fields on non-orientable surfaces (a twisted bundle) are future work. Pass "
                "repair='safe,drop-nonorientable' (--repair safe,drop-nonorientable) to drop such components")
        drop = np.isin(lab, bad)
        r = s.rows[drop]
        s.carrier[np.isin(s.carrier, r)] = -1
        s.report("drop-nonorientable", int(bad.size), f"dropped {_plural(int(bad.size), 'non-orientable component')} "
                 f"({_plural(int(drop.sum()), 'face')}: {_rows(r)})", faces=r)
        keepf = ~drop
        new_index = np.cumsum(keepf) - 1
        ok = keepf[f0] & keepf[f1]
        pairs = 3 * new_index[pairs[ok] // 3] + pairs[ok] % 3
        s.keep(keepf)
        if len(s.T) == 0:
            raise EmptyComplexError("no faces are left after dropping the non-orientable components")
        return _orient(s, pairs)
    votes = np.bincount(lab, weights=o)
    flip = o * np.where(votes >= 0, 1, -1)[lab] < 0
    if not np.any(flip):
        return pairs
    if not s.opts.reorient:
        e = int(np.argmax(same))
        edge = _edge_of(T, pairs[e, 0])
        raise InconsistentOrientationError(
            f"faces {int(s.rows[f0[e]])} and {int(s.rows[f1[e]])} traverse their common edge {edge} in the same "
            "direction: the faces are not consistently oriented. Allow the repair 'reorient' to flip faces into a "
            "consistent orientation (the majority orientation of each component is kept)")
    r = s.rows[flip]
    s.flipped = flip
    s.T = np.where(flip[:, None], T[:, [0, 2, 1]], T)
    s.report("reorient", int(flip.sum()), f"flipped {_plural(int(flip.sum()), 'face')} into a consistent orientation "
             f"(the majority orientation of each component kept): {_rows(r)}", faces=r)
    # half-edge k of a flipped face [a, c, b] is its old half-edge 2 - k, reversed
    h = pairs.copy()
    fl = flip[h // 3]
    h[fl] = 3 * (h[fl] // 3) + (2 - h[fl] % 3)
    return h


def _split(s: _Soup, pairs: np.ndarray) -> np.ndarray:
    """One vertex per fan: ``(new T, vertex row of each new vertex)``; copies numbered after the input rows."""
    T = s.T
    nc = 3 * len(T)
    nxt = lambda h: 3 * (h // 3) + (h % 3 + 1) % 3  # noqa: E731  the corner at the head of half-edge h
    isolated = 0
    for _ in range(8):
        # h0: a → b, h1: b → a (consistent after _orient); corners at a: tail of h0, head of h1; at b: the others
        h0, h1 = pairs[:, 0], pairs[:, 1]
        links = np.concatenate([np.stack([h0, nxt(h1)], 1), np.stack([nxt(h0), h1], 1)])
        g = sp.csr_matrix((np.ones(len(links), np.int8), (links[:, 0], links[:, 1])), shape=(nc, nc))
        _, fan = connected_components(g, directed=False)
        vert = T.ravel()
        # the fan with the lowest corner keeps the row; other fans of the vertex become new vertices
        first_corner = np.full(fan.max() + 1, nc, np.int64)
        np.minimum.at(first_corner, fan, np.arange(nc))
        fan_vertex = vert[first_corner]
        lowest = np.full(len(s.P), nc, np.int64)
        np.minimum.at(lowest, fan_vertex, first_corner)
        extra = np.flatnonzero(first_corner != lowest[fan_vertex])
        new_id = fan_vertex.copy()
        new_id[extra] = len(s.P) + np.arange(extra.size)
        T2 = new_id[fan].reshape(-1, 3)
        if not s.nm_edges:   # every edge had at most two faces: splitting cannot overfill one
            break
        n2 = len(s.P) + extra.size
        a, b = T2.ravel(), np.roll(T2, -1, axis=1).ravel()
        key = np.minimum(a, b) * n2 + np.maximum(a, b)
        _, inv, cnt = np.unique(key, return_inverse=True, return_counts=True)
        over = cnt[inv.ravel()] > 2
        if not np.any(over):
            break
        # an edge still has faces beyond its pair (their fans join around both of its ends again):
        # detach those faces from all their neighbours (each becomes a triangle of its own)
        in_pair = np.zeros(nc, bool)
        in_pair[pairs.ravel()] = True
        bad = np.unique(np.flatnonzero(over & ~in_pair) // 3)
        if bad.size == 0:
            bad = np.unique(np.flatnonzero(over) // 3)
        isolated += bad.size
        pairs = pairs[~(np.isin(pairs[:, 0] // 3, bad) | np.isin(pairs[:, 1] // 3, bad))]
    else:
        raise NonManifoldError("could not split the non-manifold edges and vertices of the mesh into a surface; "
                               "repair it with another tool (e.g. PyMeshFix) first")
    split_rows = np.unique(fan_vertex[extra])
    s.vertex_row = np.concatenate([np.arange(len(s.P)), fan_vertex[extra]])
    if s.nm_edges:
        r = s.detached_rows if s.detached_rows.size else s.nm_rows
        s.report("split", s.nm_edges,
                 f"cut {_plural(s.nm_edges, 'non-manifold edge')} (three or more faces) by pairing the faces "
                 f"around each edge ({_plural(int(s.detached_rows.size), 'face')} detached"
                 + (f", {_plural(isolated, 'face')} cut off from all neighbours" if isolated else "")
                 + f"): {_rows(r)}",
                 faces=r)
    if split_rows.size:
        if not s.opts.split:
            raise NonManifoldError(f"non-manifold vertex {int(split_rows[0])}: its faces form more than one fan (e.g. "
                                   "two surfaces touching at a point); allow the repair 'split' to split the vertex")
        s.report("split", int(split_rows.size),
                 f"split {_plural(int(split_rows.size), 'non-manifold vertex', 'non-manifold vertices')} into one copy "
                 f"per fan of faces ({_plural(int(extra.size), 'new vertex', 'new vertices')}): "
                 f"{_rows(split_rows, 'vertex', 'vertices')}",
                 vertices=split_rows)
    return T2


def _mollify(s: _Soup, X: SimplicialComplex, Pc: np.ndarray, Fc: np.ndarray, edge_of_half: np.ndarray):
    """``(geometry, edge_lengths or None, δ)``: the geometry of the points, or the intrinsic mollification.

    Mollified when some face has zero area (the criterion of :class:`~dhlb.geometry.SimplexStack`, in mesh
    units).
    """
    try:
        with np.errstate(all="ignore"):
            return EuclideanComplex(X, points=Pc), None, 0.0
    except DhlbError:
        pass
    scale = checks.length_scale(Pc)
    U = Pc / scale
    st = SimplexStack.from_points(U[Fc])
    deg = np.flatnonzero(~st.positive_definite)
    if deg.size == 0:   # refused only in the units of V (1e-150 or 1e+150): as validate_surface, no geometry yet
        return None, None, 0.0
    if not s.opts.mollify:
        checks.check_geometry(Pc, Fc, s.rows)  # raises the strict message
    a, b = Fc.ravel(), np.roll(Fc, -1, axis=1).ravel()
    d = U[b] - U[a]
    L_half = np.sqrt(np.einsum("ij,ij->i", d, d))
    L = np.empty(X.n_simplices(1))
    L[edge_of_half] = L_half
    tri = L[edge_of_half].reshape(-1, 3)
    gap = tri.sum(axis=1)[:, None] - 2 * tri  # l_i + l_j − l_k for each k
    eps = s.opts.mollify_tol * float(L.mean())
    delta = max(0.0, float(eps - gap.min()))
    L = L + delta
    r = s.rows[deg]
    s.report("mollify", deg.size,
             f"mollified {_plural(int(deg.size), 'zero-area face')} intrinsically: every edge lengthened by "
             f"δ = {delta * scale:.3g} ({delta / float(L.mean() - delta):.2g} of the mean edge length) so that every "
             f"triangle is strictly valid; no vertex moved: {_rows(r)}", faces=r, value=delta * scale)
    L = L * scale
    return EuclideanComplex(X, edge_lengths=L), L, delta * scale


# ---------------------------------------------------------------------------- the function
def repair_surface(V: ArrayLike, F: ArrayLike, repair: Any = "safe", *, reorient: bool = False,
                   components: str = "all", warn: bool = True, force: bool = False) -> SurfaceMesh:
    """Turn a triangle soup into a manifold, consistently oriented :class:`~dhlb.mesh.SurfaceMesh`.

    The repairs are described in :mod:`dhlb.mesh.repair`. The strict checks of
    :func:`~dhlb.mesh.validate_surface` run first: a mesh that passes them is returned exactly as
    ``validate_surface`` returns it (``mesh.repair`` is None, no warning). Otherwise (or when
    ``merge-vertices`` is asked for, which changes valid meshes too) the repairs build the mesh, and
    ``mesh.repair`` says what was done.

    Parameters
    ----------
    V : (n, 3) float array
        Vertex positions (or ``(n, 2)``).
    F : (m, 3) int array
        Triangles as rows of V.
    repair : str, bool or RepairOptions, optional
        Which repairs may be made (:meth:`RepairOptions.parse`; default ``"safe"``). A defect whose
        repair is not allowed raises the error :func:`~dhlb.mesh.validate_surface` raises for it.
    reorient : bool, optional
        With ``repair="none"``: flip faces into a consistent orientation (as ``validate_surface``).
    components : {"all", "largest"}, optional
        Keep every component of the repaired surface, or only the one with most faces (warning).
    warn : bool, optional
        Issue one :class:`~dhlb.errors.MeshRepairWarning` per repair made (default True).
    force : bool, optional
        Run the repairs even when the strict checks pass (``mesh.repair`` is then an empty record):
        for tests and for measuring their cost.

    Returns
    -------
    SurfaceMesh
        With ``mesh.repair`` (:class:`MeshRepair`) and, where faces were mollified, ``mesh.edge_lengths``.

    Raises
    ------
    InvalidParameterError
        An unknown repair or ``components`` value.
    NonOrientableError
        A non-orientable component (unless ``drop-nonorientable`` is allowed).
    EmptyComplexError
        No face is left.
    DhlbError
        The errors of :func:`~dhlb.mesh.validate_surface` for bad arrays and for defects whose repair is
        not allowed.

    Warns
    -----
    MeshRepairWarning
        One per kind of repair made.
    UnreferencedVertexWarning
        Rows of V used by no face are dropped.

    Examples
    --------
    >>> from dhlb.mesh.repair import repair_surface
    >>> V = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
    >>> mesh = repair_surface(V, [[0, 1, 2], [1, 2, 3], [0, 1, 2]], warn=False)  # one duplicate, one flipped face
    >>> mesh.repair.kinds, mesh.faces.tolist(), mesh.repair.face_of_input.tolist()
    (('duplicates', 'reorient'), [[0, 1, 2], [1, 3, 2]], [0, 1, 0])
    """
    from dhlb.mesh.surface import SurfaceMesh, _surface_complex, _validate

    opts = RepairOptions.parse(repair)
    if components not in ("all", "largest"):
        raise InvalidParameterError(f"components must be 'all' or 'largest', got {components!r}")
    if not opts.any:
        return _validate(V, F, reorient, components)
    if not (force or opts.merge_vertices):   # merging vertices is asked for even on a valid mesh
        with warnings.catch_warnings(record=True) as seen:
            warnings.simplefilter("always")
            try:
                mesh = _validate(V, F, reorient, components)
            except _REPAIRABLE:
                mesh = None
        if mesh is not None:
            for w in seen:   # the strict path's own warnings (unreferenced vertices, components dropped)
                warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
            return mesh
    P, T = checks.parse(V, F)
    s = _Soup(P, T, opts)
    used0 = np.zeros(len(P), bool)
    used0[T.ravel()] = True
    if opts.merge_vertices:
        _merge_vertices(s)
    _degenerate(s)
    if len(s.T) == 0:
        raise EmptyComplexError("no faces are left: every face repeats a vertex")
    _duplicates(s)
    pairs = _edge_pairs(s)
    pairs = _orient(s, pairs)
    flipped = s.flipped if s.flipped is not None else np.zeros(len(s.T), bool)
    s.flipped = flipped
    T2 = _split(s, pairs)
    rows = s.rows
    if components == "largest":
        comp = _face_components(T2, int(T2.max()) + 1)
        ncomp = int(comp.max()) + 1
        if ncomp > 1:
            keepc = comp == np.argmax(np.bincount(comp))
            warnings.warn(f"kept the largest of {ncomp} components ({int(keepc.sum())} faces); "
                          f"{int((~keepc).sum())} faces dropped", DhlbWarning, stacklevel=2)
            s.carrier[np.isin(s.carrier, rows[~keepc])] = -1
            T2, rows, flipped = T2[keepc], rows[keepc], flipped[keepc]
            s.rows = rows
    unused = np.flatnonzero(~used0)
    if unused.size:
        warnings.warn(UnreferencedVertexWarning(
            f"{unused.size} vertices of V are used by no face and were dropped (first: "
            f"{', '.join(str(int(v)) for v in unused[:5])}); mesh.vertex_rows maps vertices to rows of V",
            dropped=unused, cell="face"), stacklevel=2)
    kept, compact = _renumber(len(s.vertex_row), T2)
    Fc = compact[T2]
    Pc = np.ascontiguousarray(P[s.vertex_row[kept]])
    bad = ~np.isfinite(Pc).all(axis=1)
    if np.any(bad):
        checks.check_geometry(P, T[rows], rows)  # names the vertex
    pairs_c = halfedge_pairs(Fc, kept.size)
    X, tri = _surface_complex(Fc, kept, pairs_c)
    geometry, lengths, delta = _mollify(s, X, Pc, Fc, pairs_c[1])
    # the vertex that speaks for each input row: of its copies, the one with the largest fan area
    vrows = s.vertex_row[kept]
    area = np.bincount(Fc.ravel(), weights=np.repeat(_face_areas(Pc, Fc) if geometry is None
                                                     else geometry.volumes(2)[tri], 3), minlength=kept.size)
    order = np.lexsort((np.arange(kept.size), -area, vrows))
    best = order[np.r_[True, vrows[order][1:] != vrows[order][:-1]]]
    vertex_of_input = np.full(len(P), -1, np.int64)
    vertex_of_input[vrows[best]] = best
    merged_rows = np.flatnonzero(s.merged != np.arange(len(P)))
    vertex_of_input[merged_rows] = vertex_of_input[s.merged[merged_rows]]
    face_of_row = np.full(len(T), -1, np.int64)
    face_of_row[rows] = np.arange(len(rows))
    face_of_input = np.where(s.carrier >= 0, face_of_row[np.maximum(s.carrier, 0)], -1)
    info = MeshRepair(tuple(s.repairs), opts, vrows, vertex_of_input, face_of_input, float(delta),
                      _fingerprint(P, T, components))
    mesh = SurfaceMesh(Pc, Fc, X, rows, flipped, len(P), repair=info, edge_lengths=lengths)
    mesh.__dict__.update(_pairs=pairs_c, triangle_of_face=tri)
    if geometry is not None:
        mesh.__dict__["geometry"] = geometry
    _ = mesh.fans  # one fan per vertex, by construction
    if warn:
        for r in s.repairs:
            warnings.warn(MeshRepairWarning(r.message, kind=r.kind, count=r.count), stacklevel=2)
    return mesh


def _face_areas(P: np.ndarray, F: np.ndarray) -> np.ndarray:
    """Areas of the faces (only to rank the copies of a split vertex when the geometry is not built)."""
    return 0.5 * np.linalg.norm(np.cross(P[F[:, 1]] - P[F[:, 0]], P[F[:, 2]] - P[F[:, 0]]), axis=1)


def _geometry(X: SimplicialComplex, P: np.ndarray, lengths: np.ndarray | None) -> EuclideanComplex:
    if lengths is not None:
        return EuclideanComplex(X, edge_lengths=lengths)
    with np.errstate(all="ignore"):
        return EuclideanComplex(X, points=P)


def repaired_mesh(points: ArrayLike, faces: ArrayLike, face_rows: ArrayLike, repair: MeshRepair | None,
                  edge_lengths: ArrayLike | None = None, flipped: ArrayLike | None = None) -> SurfaceMesh:
    """A repaired :class:`~dhlb.mesh.SurfaceMesh` again from its parts (reading a result back).

    Parameters
    ----------
    points : (N, 3) float array
        The mesh's vertices (``mesh.points``).
    faces : (m, 3) int array
        Its faces in its own numbering (``mesh.faces``: manifold and consistently oriented).
    face_rows : (m,) int array
        The input row of each face.
    repair : MeshRepair or None
        The repair record (:meth:`MeshRepair.from_arrays`); None: the mesh is its own input (a mesh file
        written from a repaired mesh, with its metric).
    edge_lengths : (n_1,) float array, optional
        The intrinsic lengths of a mollified mesh (``mesh.edge_lengths``), else None.
    flipped : (m,) bool array, optional
        The faces flipped by the repair (default none).

    Returns
    -------
    SurfaceMesh

    Raises
    ------
    DhlbError
        The parts do not make a manifold, consistently oriented mesh (the messages of the checks).
    """
    from dhlb.mesh.surface import SurfaceMesh, _surface_complex

    P, Fc = checks.parse(points, faces)
    N = len(P)
    rows = np.asarray(face_rows, np.int64)
    if rows.shape != (len(Fc),):
        raise InvalidParameterError(f"face_rows has shape {rows.shape}, the mesh has {len(Fc)} faces")
    pairs = halfedge_pairs(Fc, N)
    X, tri = _surface_complex(Fc, np.arange(N, dtype=np.int64), pairs)
    lengths = None if edge_lengths is None else np.asarray(edge_lengths, np.float64)
    if lengths is not None and lengths.shape != (X.n_simplices(1),):
        raise InvalidParameterError(f"edge_lengths has shape {lengths.shape}, the mesh has {X.n_simplices(1)} edges")
    geometry = _geometry(X, P, lengths)
    flip = np.zeros(len(Fc), bool) if flipped is None else np.asarray(flipped)
    if flip.shape != (len(Fc),) or flip.dtype != bool:
        raise InvalidParameterError(f"flipped must be one bool per face ({len(Fc)}), got {flip.dtype} {flip.shape}")
    if repair is not None and repair.face_of_input.size and repair.face_of_input.max() >= len(Fc):
        raise InvalidParameterError(f"face_of_input refers to faces outside 0 .. {len(Fc) - 1}")
    n_input = N if repair is None else int(repair.vertex_of_input.size)
    mesh = SurfaceMesh(np.ascontiguousarray(P), Fc, X, rows, flip, n_input, repair=repair, edge_lengths=lengths)
    mesh.__dict__.update(_pairs=pairs, triangle_of_face=tri, geometry=geometry)
    _ = mesh.fans
    return mesh
