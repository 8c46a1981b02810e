"""What a result looks like in 3-D, as plain data: the :class:`Scene` of the viewer and of the web views.

A :class:`Scene` holds meshes with vector, scalar and per-corner texture quantities, coloured
point sets with labels, and curve networks. :func:`scene_of` builds it from a result, and is the
one scene builder of dhlb: the polyscope viewer (:mod:`dhlb.render.view`) and the web views
(:mod:`dhlb.render.web`) draw what it returns, and a result in memory and the same result read
back from its files (:func:`dhlb.io.read_result`) give the same scene.

- direction fields: the n directions as vector quantities, the singularities coloured by index
  (red +, blue −) and labelled with their face and index;
- stripe patterns: the per-corner texture coordinate ``u = α/2π`` (and the texture itself), the
  isolines as a curve network, the zeros and branch points;
- vortex results: the filaments as curves inside the translucent boundary of the domain and its
  outline (feature edges);
- conformal deformations: the input boundary and the deformed one side by side, both coloured by
  the distortion of their tetrahedra.

Examples
--------
>>> from dhlb.io import read_surface, example_path
>>> from dhlb.fields import direction_field
>>> scene = scene_of(direction_field(*read_surface(example_path("torus.obj")), n=4))
>>> [m.name for m in scene.meshes], sorted(scene.meshes[0].vectors), [p.name for p in scene.points]
(['mesh'], ['direction 0', 'direction 1', 'direction 2', 'direction 3'], ['singularities'])
>>> scene.points[0].labels[0]
'face 60, index -1/4'
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import TYPE_CHECKING, Any

import numpy as np

from dhlb.errors import InvalidParameterError, ShapeError
from dhlb.render._figure import (
    BRANCH,
    FACE_COLOR,
    FILAMENT_COLORS,
    GLYPH_COLOR,
    NEGATIVE,
    OUTLINE_COLOR,
    POSITIVE,
    Camera,
    face_normals,
    plural,
)
from dhlb.render.filaments_png import feature_edges

if TYPE_CHECKING:
    from collections.abc import Sequence

    from numpy.typing import ArrayLike

__all__ = ["Scene", "SceneCurves", "SceneMesh", "ScenePoints", "bounding_sphere", "index_colors", "index_label",
           "scene_of"]


def index_label(k: int, n: int) -> str:
    """The index ``k/n`` of a singularity of an n-direction field, as a signed reduced fraction.

    Examples
    --------
    >>> index_label(1, 4), index_label(-2, 4), index_label(3, 1)
    ('+1/4', '-1/2', '+3')
    """
    q = Fraction(int(k), int(n))
    return f"{'+' if q > 0 else '-' if q < 0 else ''}{abs(q)}"


@dataclass
class SceneMesh:
    """A triangle mesh of a :class:`Scene` and its quantities (see :meth:`Scene.add_mesh`)."""

    name: str
    points: np.ndarray
    faces: np.ndarray
    vectors: dict = field(default_factory=dict)
    scalars: dict = field(default_factory=dict)
    corner_uv: np.ndarray | None = None
    color: tuple = FACE_COLOR
    transparency: float = 1.0
    shown_scalar: str | None = None
    texture: Any = None
    colormap: str = "coolwarm"
    scalar_range: tuple | None = None
    scalar_label: str = ""

    def show_scalar(self, name: str, *, colormap: str = "coolwarm", limits: tuple[float, float] | None = None,
                    label: str = "") -> None:
        """Draw the scalar ``name`` with ``colormap`` (a matplotlib name) over ``limits`` (default: its range).

        ``label`` is the colour bar's title (default: the scalar's name).
        """
        if name not in self.scalars:
            raise ShapeError(f"mesh {self.name!r}: {name!r} is not one of its scalars {sorted(self.scalars)}")
        self.shown_scalar, self.colormap, self.scalar_label = name, str(colormap), str(label)
        self.scalar_range = None if limits is None else (float(limits[0]), float(limits[1]))


@dataclass
class ScenePoints:
    """Coloured points of a :class:`Scene` (see :meth:`Scene.add_points`)."""

    name: str
    points: np.ndarray
    colors: np.ndarray
    radius: float
    labels: list | None = None
    normals: np.ndarray | None = None
    two_sided: bool = False


@dataclass
class SceneCurves:
    """A curve network of a :class:`Scene` (see :meth:`Scene.add_curves`)."""

    name: str
    nodes: np.ndarray
    edges: np.ndarray
    color: tuple
    radius: float
    label: str | None = None
    normals: np.ndarray | None = None


@dataclass
class Scene:
    """What :func:`show` draws: meshes, point sets and curve networks (plain numpy data).

    Attributes
    ----------
    meshes : list of SceneMesh
    points : list of ScenePoints
    curves : list of SceneCurves
    title : str
    view : (3,) float or None
        The direction toward the camera the scene is arranged for (conformal maps: before and after
        side by side across it); None: fitted to the scene (:meth:`dhlb.render.Camera.fitted`).

    Examples
    --------
    >>> s = Scene()
    >>> _ = s.add_mesh("tri", [[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], vectors={"x": [[1, 0, 0]] * 3})
    >>> s.add_curves("edge", [(np.eye(3), True)])
    >>> s.meshes[0].vectors["x"].shape, s.curves[0].edges.tolist(), s.bounds()[1].tolist()
    ((3, 3), [[0, 1], [1, 2], [2, 0]], [1.0, 1.0, 1.0])
    """

    meshes: list = field(default_factory=list)
    points: list = field(default_factory=list)
    curves: list = field(default_factory=list)
    title: str = ""
    view: tuple | None = None

    def add_mesh(self, name: str, V: ArrayLike, F: ArrayLike, *, vectors: dict | None = None,
                 scalars: dict | None = None, corner_uv: ArrayLike | None = None,
                 color: Sequence[float] = FACE_COLOR, shown_scalar: str | None = None) -> SceneMesh:
        """Add a triangle mesh with ``vectors`` per vertex, ``scalars`` per vertex or face, ``corner_uv`` per corner.

        ``corner_uv`` is (m, 3) or (m, 3, 2); ``color`` is RGB or RGBA (alpha: the opacity, 1 = opaque);
        ``shown_scalar`` names the scalar drawn (none by default; :meth:`SceneMesh.show_scalar` sets its
        colours). Returns the :class:`SceneMesh` (its ``texture`` may be set to a
        :class:`~dhlb.stripes.StripeTexture` on these faces, which the web view evaluates on a refined
        copy of the mesh; the viewer draws ``corner_uv``).
        """
        P = np.asarray(V, dtype=np.float64)
        T = np.asarray(F, dtype=np.int64)
        if P.ndim != 2 or P.shape[1] != 3 or T.ndim != 2 or T.shape[1] != 3:
            raise ShapeError(f"mesh {name!r}: V must be (N, 3) and F (m, 3), got {P.shape} and {T.shape}")
        if T.size and (T.min() < 0 or T.max() >= len(P)):
            raise ShapeError(f"mesh {name!r}: a face refers to a vertex outside 0 .. {len(P) - 1}")
        vec = {}
        for k, v in (vectors or {}).items():
            A = np.nan_to_num(np.asarray(v, dtype=np.float64))
            if A.shape != P.shape:
                raise ShapeError(f"mesh {name!r}: vector quantity {k!r} must have shape {P.shape}, got {A.shape}")
            vec[k] = A
        sca = {}
        for k, v in (scalars or {}).items():
            A = np.asarray(v, dtype=np.float64)
            if A.shape not in ((len(P),), (len(T),)):
                raise ShapeError(f"mesh {name!r}: scalar {k!r} needs one value per vertex or face, got {A.shape}")
            sca[k] = A
        uv = None
        if corner_uv is not None:
            uv = np.asarray(corner_uv, dtype=np.float64)
            if uv.shape == T.shape:  # stripes: u only; v = 1/8 keeps polyscope's checker off its cell border
                uv = np.stack([uv, np.full_like(uv, 0.125)], axis=-1)
            if uv.shape != T.shape + (2,):
                raise ShapeError(f"mesh {name!r}: corner_uv must have shape {T.shape} or {T.shape + (2,)}, "
                                 f"got {np.shape(corner_uv)}")
        if shown_scalar is not None and shown_scalar not in sca:
            raise ShapeError(f"mesh {name!r}: shown_scalar {shown_scalar!r} is not one of its scalars")
        rgba = tuple(float(c) for c in color)
        if len(rgba) not in (3, 4):
            raise ShapeError(f"mesh {name!r}: color must be RGB or RGBA, got {color!r}")
        mesh = SceneMesh(name, P, T, vec, sca, uv, rgba[:3], rgba[3] if len(rgba) == 4 else 1.0, shown_scalar)
        self.meshes.append(mesh)
        return mesh

    def add_points(self, name: str, P: ArrayLike, colors: ArrayLike, *, radius: float = 0.01,
                   labels: Sequence[str] | None = None, normals: ArrayLike | None = None,
                   two_sided: bool = False) -> None:
        """Add points ``(k, 3)`` with one RGB colour each (or one for all); radius relative to the scene.

        ``labels`` (one string per point) is what the web view shows when the pointer is over a point.
        ``normals`` ``(k, 3)``: the normal of the surface the points lie on, along which the web view
        lifts their markers off it (on both sides with ``two_sided``, for a surface with boundary).
        """
        X = np.asarray(P, dtype=np.float64).reshape(-1, 3)
        C = np.broadcast_to(np.asarray(colors, dtype=np.float64), (len(X), 3)).copy()
        if labels is not None and len(labels) != len(X):
            raise ShapeError(f"points {name!r}: {len(X)} points but {len(labels)} labels")
        N = None if normals is None else _unit_rows(normals, len(X), f"points {name!r}")
        self.points.append(ScenePoints(name, X, C, float(radius), None if labels is None else list(labels), N,
                                       bool(two_sided)))

    def add_curves(self, name: str, curves: Sequence[Any], *, color: Sequence[float] = GLYPH_COLOR,
                   radius: float = 0.004, label: str | None = None, normals: Sequence[Any] | None = None) -> None:
        """Add polylines: Filaments (``.points``, ``.closed``), ``(points, closed)`` pairs or (m, 3) arrays.

        ``label`` is what the web view shows when the pointer is over the curves (nothing by default).
        ``normals`` (one ``(m, 3)`` array per curve): the normal of the surface the curves lie on, along
        which the web view lifts them off it.
        """
        nodes, edges, base = [], [], 0
        for c in curves:
            if hasattr(c, "points") and hasattr(c, "closed"):
                X, closed = np.asarray(c.points, float), bool(c.closed)
            elif isinstance(c, tuple) and len(c) == 2 and np.ndim(c[1]) == 0:
                X, closed = np.asarray(c[0], float), bool(c[1])
            else:
                X, closed = np.asarray(c, float), False
            if X.ndim != 2 or X.shape[1] != 3:
                raise ShapeError(f"curves {name!r}: a curve must be an (m, 3) array, got shape {X.shape}")
            m = len(X)
            nxt = np.arange(1, m + (1 if closed and m > 2 else 0)) % max(m, 1)
            edges.append(np.column_stack([base + np.arange(len(nxt)), base + nxt]))
            nodes.append(X)
            base += m
        N = np.concatenate(nodes) if nodes else np.zeros((0, 3))
        E = np.concatenate(edges).astype(np.int64) if edges else np.zeros((0, 2), np.int64)
        up = None
        if normals is not None:
            parts = [np.asarray(n, float).reshape(-1, 3) for n in normals]
            up = _unit_rows(np.concatenate(parts or [np.zeros((0, 3))]), len(N), f"curves {name!r}")
        self.curves.append(SceneCurves(name, N, E, tuple(color), float(radius), label, up))

    def drawn_points(self) -> np.ndarray:
        """Every point drawn, ``(k, 3)``: the vertices the faces use, the points, the curves' nodes."""
        drawn = [m.points[np.unique(m.faces)] if len(m.faces) else m.points for m in self.meshes]
        parts = drawn + [p.points for p in self.points] + [c.nodes for c in self.curves]
        return np.concatenate([p for p in parts if len(p)] or [np.zeros((1, 3))])

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """``(lower, upper)`` corners of the bounding box of everything drawn (:meth:`drawn_points`)."""
        X = self.drawn_points()
        return X.min(axis=0), X.max(axis=0)


def _unit_rows(normals, k: int, what: str) -> np.ndarray:
    N = np.asarray(normals, dtype=np.float64).reshape(-1, 3)
    if len(N) != k:
        raise ShapeError(f"{what}: {k} points but {len(N)} normals")
    length = np.linalg.norm(N, axis=1, keepdims=True)
    return np.nan_to_num(N / np.where(length > 0, length, 1.0))


def _face_normals(mesh, faces) -> np.ndarray:
    return face_normals(mesh.points, mesh.faces[np.asarray(faces, dtype=np.int64).reshape(-1)])


def index_colors(index: ArrayLike) -> np.ndarray:
    """RGB per index: :data:`POSITIVE` for > 0, :data:`NEGATIVE` for < 0, grey for 0.

    Examples
    --------
    >>> index_colors([1, -2, 0]).round(2).tolist()
    [[0.85, 0.12, 0.1], [0.1, 0.25, 0.85], [0.5, 0.5, 0.5]]
    """
    k = np.asarray(index).reshape(-1)
    out = np.full((len(k), 3), 0.5)
    out[k > 0] = POSITIVE
    out[k < 0] = NEGATIVE
    return out


def _field_scene(res) -> Scene:
    mesh = res.mesh
    s = Scene(title=f"n = {res.n}, s = {res.s:g}, index sum {res.index_sum}")
    s.add_mesh("mesh", mesh.points, mesh.faces,
               vectors={f"direction {k}": res.directions[:, k] for k in range(res.n)},
               scalars={"index": res.face_index})
    sing = res.singularities
    if len(sing.faces):
        s.add_points("singularities", sing.points, index_colors(sing.index), radius=0.012,
                     labels=[f"face {f}, index {index_label(k, res.n)}"
                             for f, k in zip(np.asarray(sing.input_faces).tolist(), np.asarray(sing.index).tolist())],
                     normals=_face_normals(mesh, sing.faces), two_sided=not mesh.is_closed)
    return s


def _stripes_scene(res, isolines: bool = True) -> Scene:
    from dhlb.stripes import isolines as trace

    tex = res.texture
    mesh = res.mesh
    s = Scene(title=f"stripes n = {res.n}: {plural(tex.zero_faces.size, 'zero')}, "
                    f"{plural(tex.branch_faces.size, 'branch face')}")
    # The per-corner α is defined per face up to α → α + 2π and, for line fields (n = 2), α → −α (the
    # sheet of the double cover): draw the distance of u = α/2π to the nearest integer, which both leave
    # alone; checker cells of 1/4 then show the bands cos α > 0 and cos α < 0, the stripes.
    u = tex.corner_alpha / (2 * np.pi)
    s.add_mesh("mesh", mesh.points, mesh.faces, corner_uv=np.abs(u - np.round(u)),
               scalars={"zero index": tex.zero_index}).texture = tex
    if isolines:
        iso = trace(tex)
        up = _face_normals(tex.mesh, iso.faces)
        s.add_curves("isolines", [iso.points[p] for p in iso.polylines], color=(0.05, 0.05, 0.08), radius=0.0015,
                     normals=[up[p] for p in iso.polylines])
    if tex.zero_faces.size:
        k = tex.zero_index[tex.zero_faces]
        s.add_points("zeros", tex.zero_points, index_colors(k), radius=0.01,
                     labels=[f"zero in face {f}, index {i:+d}" for f, i in zip(tex.zero_faces.tolist(), k.tolist())],
                     normals=_face_normals(tex.mesh, tex.zero_faces), two_sided=not tex.mesh.is_closed)
    if tex.branch_faces.size:
        s.add_points("branch points", tex.branch_points, BRANCH, radius=0.01,
                     labels=[f"branch point in face {f}" for f in tex.branch_faces.tolist()],
                     normals=_face_normals(tex.mesh, tex.branch_faces), two_sided=not tex.mesh.is_closed)
    return s


def _vortex_scene(res) -> Scene:
    s = Scene(title=plural(len(res.filaments), "filament"))
    mesh = res.mesh
    if mesh is not None:  # a result read back from curves alone has no domain
        s.add_mesh("domain", mesh.points, mesh.boundary_faces, color=(*FACE_COLOR, 0.25))
        outline = feature_edges(mesh.points, mesh.boundary_faces)
        if len(outline):
            s.add_curves("outline", [mesh.points[e] for e in outline], color=OUTLINE_COLOR, radius=0.002)
    for k, f in enumerate(res.filaments):
        kind = "closed" if f.closed else "open"
        s.add_curves(f"filament {k}", [f], color=FILAMENT_COLORS[k % len(FILAMENT_COLORS)], radius=0.006,
                     label=f"filament {k}: {kind}, {len(f.points)} points")
    return s


def _conformal_scene(res) -> Scene:
    from dhlb.render.conformal_png import boundary_distortion, distortion_range, rigid_fit

    s = Scene(title=f"λ₁ = {res.eigenvalue:.3g}")
    if res.distortion is None:  # read back from the deformed mesh alone: no distortion, no 'before'
        s.add_mesh("deformed", res.points, res.mesh.boundary_faces)
        return s
    F, dF = boundary_distortion(res)
    shown = {"colormap": "viridis", "limits": distortion_range(dF), "label": "distortion of the tet (1 = conformal)"}
    if not getattr(res, "input_known", True):  # the .json of result.save: the deformed mesh and its distortion
        s.add_mesh("deformed", res.points, F, scalars={"distortion": dF}).show_scalar("distortion", **shown)
        return s
    before = np.asarray(res.mesh.points, dtype=np.float64)
    after = rigid_fit(res.points, before)
    # side by side as in the PNG picture: the input on the left, the deformation on the right, their bounding
    # spheres apart (with a gap of a fifth of the larger), so that they cannot overlap however the view turns
    fitted = Camera().fitted(before)
    s.view = fitted.view
    right = fitted.frame()[0]
    (cb, rb), (ca, ra) = (bounding_sphere(X[np.unique(F)]) for X in (before, after))
    gap = 0.2 * max(rb, ra, 1e-12)
    mid = 0.5 * (cb + ca)
    s.title += ": the input (left), deformed (right)"
    for name, X, c, at in (("before", before, cb, -(rb + 0.5 * gap)), ("deformed", after, ca, ra + 0.5 * gap)):
        s.add_mesh(name, X - c + mid + at * right, F, scalars={"distortion": dF}).show_scalar("distortion", **shown)
    return s


def bounding_sphere(points: ArrayLike) -> tuple[np.ndarray, float]:
    """A sphere holding every point: the centre of their bounding box and the largest distance from it.

    Parameters
    ----------
    points : (k, 3) float array

    Returns
    -------
    centre : (3,) float array
    radius : float

    Examples
    --------
    >>> c, r = bounding_sphere([[0, 0, 0], [2, 0, 0], [1, 1, 0]])
    >>> c.tolist(), r
    ([1.0, 0.5, 0.0], 1.118033988749895)
    """
    X = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    if not len(X):
        return np.zeros(3), 0.0
    c = 0.5 * (X.min(axis=0) + X.max(axis=0))
    return c, float(np.linalg.norm(X - c, axis=1).max())


def scene_of(result: Any, *, isolines: bool = True) -> Scene:
    """The :class:`Scene` of a result (a Scene is returned as is): the one scene builder of dhlb.

    A result read back from its files (:func:`dhlb.io.read_result`) has the attributes used here,
    so it gives the scene of the result that was written.

    Parameters
    ----------
    result : object
        A DirectionField, StripePattern, VortexResult, ConformalResult, a result of
        :func:`dhlb.io.read_result`, or a Scene.
    isolines : bool
        Stripe patterns: trace the isolines α = 0 (mod 2π) as a curve network.

    Returns
    -------
    Scene

    Raises
    ------
    InvalidParameterError
        Another kind of object.

    Examples
    --------
    >>> from dhlb.mesh import box_tet_mesh
    >>> from dhlb.vortex import uniform_flow, vortex_filaments
    >>> s = scene_of(vortex_filaments(box_tet_mesh(2), None, uniform_flow([0.1, 0, 0]), hbar=1.0))
    >>> s.title, s.meshes[0].name, s.meshes[0].transparency
    ('0 filaments', 'domain', 0.25)
    """
    if isinstance(result, Scene):
        return result
    if all(hasattr(result, a) for a in ("directions", "singularities", "face_index")):
        return _field_scene(result)
    if all(hasattr(result, a) for a in ("texture", "mesh", "n")):
        return _stripes_scene(result, isolines)
    if all(hasattr(result, a) for a in ("filaments", "mesh")):
        return _vortex_scene(result)
    if all(hasattr(result, a) for a in ("points", "distortion", "mesh", "eigenvalue")):
        return _conformal_scene(result)
    raise InvalidParameterError(f"cannot show a {type(result).__name__}: give a direction field, a stripe pattern, "
                                "a vortex or conformal result (or one read back by dhlb.io.read_result) or a "
                                "dhlb.render.view.Scene")
