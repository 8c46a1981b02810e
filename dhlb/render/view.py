"""Interactive and headless 3D views with `polyscope <https://polyscope.run>`_ (extra ``dhlb[view]``).

A :class:`Scene` is plain data (meshes with vector, scalar and per-corner texture quantities,
coloured point sets, curve networks), built from a result by :func:`scene_of` (direction fields:
the n directions as vector quantities and the singularities coloured by index, red + / blue −;
stripe patterns: the per-corner texture coordinate ``u = α/2π`` as a parameterization quantity and
the isolines as a curve network; vortex results: the filaments as curve networks inside the
translucent boundary of the domain; conformal deformations: the deformed boundary coloured by the
distortion of its tetrahedra) or by hand. :func:`scene_of` is the one scene builder: a result in
memory and the same result read back from its files (:func:`dhlb.io.read_result`) give the same
scene. :func:`show` hands it to polyscope: a window, or
with ``screenshot=FILE.png`` a picture rendered without any display through EGL
(``polyscope.set_allow_headless_backends(True)``, ``polyscope.init("openGL3_egl")``).

Without polyscope :func:`show` raises an ``ImportError`` naming the extra; without a display (and
no screenshot asked for) or without a working EGL it raises :class:`ViewerUnavailableError`
saying what is missing and what to do.

Examples
--------
>>> from dhlb.io import read_surface, example_path
>>> from dhlb.fields import direction_field
>>> scene = scene_of(direction_field(*read_surface(example_path("torus.obj")), n=4))
>>> [m.name for m in scene.meshes], sorted(scene.meshes[0].vectors), [p.name for p in scene.points]
(['mesh'], ['direction 0', 'direction 1', 'direction 2', 'direction 3'], ['singularities'])
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from dhlb.errors import InvalidParameterError, OutputError, ShapeError, ViewerUnavailableError
from dhlb.render._figure import BRANCH, NEGATIVE, POSITIVE  # one colour per kind of point, PNGs and viewer

if TYPE_CHECKING:
    from collections.abc import Sequence

    from numpy.typing import ArrayLike

__all__ = [
    "VIEW_EXTRA",
    "ViewerUnavailableError",
    "Scene",
    "scene_of",
    "index_colors",
    "show",
    "camera_for",
]

VIEW_EXTRA = 'polyscope is not installed: pip install "dhlb[view]" (or: pip install polyscope)'
"""The message of the ``ImportError`` raised when polyscope is missing."""



# ---------------------------------------------------------------------------- the scene
@dataclass
class SceneMesh:
    """A triangle mesh of a :class:`Scene` and its quantities (see :meth:`Scene.add_mesh`)."""

    name: str
    points: np.ndarray
    faces: np.ndarray
    vectors: dict = field(default_factory=dict)
    scalars: dict = field(default_factory=dict)
    corner_uv: np.ndarray | None = None
    color: tuple = (0.78, 0.80, 0.86)
    transparency: float = 1.0
    shown_scalar: str | None = None


@dataclass
class ScenePoints:
    """Coloured points of a :class:`Scene` (see :meth:`Scene.add_points`)."""

    name: str
    points: np.ndarray
    colors: np.ndarray
    radius: float


@dataclass
class SceneCurves:
    """A curve network of a :class:`Scene` (see :meth:`Scene.add_curves`)."""

    name: str
    nodes: np.ndarray
    edges: np.ndarray
    color: tuple
    radius: float


@dataclass
class Scene:
    """What :func:`show` draws: meshes, point sets and curve networks (plain numpy data).

    Attributes
    ----------
    meshes : list of SceneMesh
    points : list of ScenePoints
    curves : list of SceneCurves
    title : str

    Examples
    --------
    >>> s = Scene()
    >>> s.add_mesh("tri", [[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], vectors={"x": [[1, 0, 0]] * 3})
    >>> s.add_curves("edge", [(np.eye(3), True)])
    >>> s.meshes[0].vectors["x"].shape, s.curves[0].edges.tolist(), s.bounds()[1].tolist()
    ((3, 3), [[0, 1], [1, 2], [2, 0]], [1.0, 1.0, 1.0])
    """

    meshes: list = field(default_factory=list)
    points: list = field(default_factory=list)
    curves: list = field(default_factory=list)
    title: str = ""

    def add_mesh(self, name: str, V: ArrayLike, F: ArrayLike, *, vectors: dict | None = None,
                 scalars: dict | None = None, corner_uv: ArrayLike | None = None,
                 color: Sequence[float] = (0.78, 0.80, 0.86), shown_scalar: str | None = None) -> None:
        """Add a triangle mesh with ``vectors`` per vertex, ``scalars`` per vertex or face, ``corner_uv`` per corner.

        ``corner_uv`` is (m, 3) or (m, 3, 2); ``color`` is RGB or RGBA (alpha: the opacity, 1 = opaque);
        ``shown_scalar`` names the scalar drawn (none by default).
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
        self.meshes.append(SceneMesh(name, P, T, vec, sca, uv, rgba[:3], rgba[3] if len(rgba) == 4 else 1.0,
                                     shown_scalar))

    def add_points(self, name: str, P: ArrayLike, colors: ArrayLike, *, radius: float = 0.01) -> None:
        """Add points ``(k, 3)`` with one RGB colour each (or one for all); radius relative to the scene."""
        X = np.asarray(P, dtype=np.float64).reshape(-1, 3)
        C = np.broadcast_to(np.asarray(colors, dtype=np.float64), (len(X), 3)).copy()
        self.points.append(ScenePoints(name, X, C, float(radius)))

    def add_curves(self, name: str, curves: Sequence[Any], *, color: Sequence[float] = (0.1, 0.1, 0.1),
                   radius: float = 0.004) -> None:
        """Add polylines: Filaments (``.points``, ``.closed``), ``(points, closed)`` pairs or (m, 3) arrays."""
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
        self.curves.append(SceneCurves(name, N, E, tuple(color), float(radius)))

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """``(lower, upper)`` corners of the bounding box of everything in the scene."""
        parts = [m.points for m in self.meshes] + [p.points for p in self.points] + [c.nodes for c in self.curves]
        X = np.concatenate([p for p in parts if len(p)] or [np.zeros((1, 3))])
        return X.min(axis=0), X.max(axis=0)


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
        s.add_points("singularities", sing.points, index_colors(sing.index), radius=0.012)
    return s


def _stripes_scene(res, isolines: bool = True) -> Scene:
    from dhlb.stripes import isolines as trace

    tex = res.texture
    mesh = res.mesh
    s = Scene(title=f"stripes n = {res.n}: {tex.zero_faces.size} zeros, {tex.branch_faces.size} branch faces")
    # The per-corner α is defined per face up to α → α + 2π and, for line fields (n = 2), α → −α (the
    # sheet of the double cover): draw the distance of u = α/2π to the nearest integer, which both leave
    # alone; checker cells of 1/4 then show the bands cos α > 0 and cos α < 0, the stripes.
    u = tex.corner_alpha / (2 * np.pi)
    s.add_mesh("mesh", mesh.points, mesh.faces, corner_uv=np.abs(u - np.round(u)),
               scalars={"zero index": tex.zero_index})
    if isolines:
        iso = trace(tex)
        s.add_curves("isolines", [iso.points[p] for p in iso.polylines], color=(0.05, 0.05, 0.08), radius=0.0015)
    if tex.zero_faces.size:
        s.add_points("zeros", tex.zero_points, index_colors(tex.zero_index[tex.zero_faces]), radius=0.01)
    if tex.branch_faces.size:
        s.add_points("branch points", tex.branch_points, BRANCH, radius=0.01)
    return s


_CURVE_COLORS = [(0.85, 0.12, 0.10), (0.10, 0.35, 0.85), (0.10, 0.60, 0.25), (0.80, 0.45, 0.05),
                 (0.55, 0.20, 0.70), (0.05, 0.60, 0.65)]


def _vortex_scene(res) -> Scene:
    s = Scene(title=f"{len(res.filaments)} filaments")
    mesh = res.mesh
    if mesh is not None:  # a result read back from curves alone has no domain
        s.add_mesh("domain", mesh.points, mesh.boundary_faces, color=(0.78, 0.80, 0.86, 0.25))
    for k, f in enumerate(res.filaments):
        s.add_curves(f"filament {k}", [f], color=_CURVE_COLORS[k % len(_CURVE_COLORS)], radius=0.006)
    return s


def _conformal_scene(res) -> Scene:
    from dhlb.render.conformal_png import boundary_distortion

    s = Scene(title=f"λ₁ = {res.eigenvalue:.3g}")
    if res.distortion is None:  # read back without its input mesh: the deformed boundary alone
        s.add_mesh("deformed", res.points, res.mesh.boundary_faces)
        return s
    F, dF = boundary_distortion(res)
    s.add_mesh("deformed", res.points, F, scalars={"distortion": dF}, shown_scalar="distortion")
    return s


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


# ---------------------------------------------------------------------------- polyscope
_STATE: dict = {}


def _polyscope():
    try:
        import polyscope
    except ImportError:
        raise ImportError(VIEW_EXTRA) from None
    return polyscope


def _has_display() -> bool:
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")) or os.name == "nt" or \
        os.uname().sysname == "Darwin"


def _init(ps, headless: bool) -> None:
    """Initialize polyscope once per process (headless EGL when asked or when there is no display)."""
    if _STATE.get("backend"):
        if headless or _STATE["backend"] != "openGL3_egl":
            return
        raise ViewerUnavailableError("polyscope was started headless (EGL) in this process: it cannot open a "
                                     "window now; restart Python, or pass screenshot=FILE.png")
    if not headless and not _has_display():
        raise ViewerUnavailableError("no display: $DISPLAY and $WAYLAND_DISPLAY are unset, so no window can open. "
                                     "Render a picture instead: show(result, screenshot='view.png') or "
                                     "'dhlb view OUT --screenshot view.png' (needs EGL: apt-get install libegl1 "
                                     "libegl-mesa0 libgl1-mesa-dri)")
    try:
        if headless:
            ps.set_allow_headless_backends(True)
            ps.init("openGL3_egl")
            _STATE["backend"] = "openGL3_egl"
        else:
            ps.init()
            _STATE["backend"] = "auto"
    except Exception as exc:  # polyscope raises RuntimeError when no backend starts
        what = "EGL (headless OpenGL)" if headless else "an OpenGL window"
        raise ViewerUnavailableError(f"polyscope could not start {what}: {exc}. Headless rendering needs the EGL "
                                     "and Mesa libraries (Debian/Ubuntu: apt-get install libegl1 libegl-mesa0 "
                                     "libgl1-mesa-dri); a window needs a display") from None
    ps.set_program_name("dhlb")
    ps.set_ground_plane_mode("none")


FIELD_OF_VIEW = 45.0
"""The vertical field of view of polyscope's camera, in degrees."""


def camera_for(scene: Scene, view: Sequence[float] | None = None, up=None, distance: float | None = None):
    """``(camera position, target, up)``: looking at the scene's centre as the PNG pictures do.

    The direction is :meth:`dhlb.render.Camera.fitted` to the scene's bounding box (``+y`` up,
    from above, across the thinner side) unless ``view`` / ``up`` are given; the distance fits the
    bounding sphere into polyscope's field of view, so nothing is clipped.

    Parameters
    ----------
    scene : Scene
        What is shown.
    view : (3,) float, optional
        Direction from the scene's centre toward the camera (default: fitted).
    up : (3,) float or {"x", "y", "z", "-x", "-y", "-z"}, optional
        The world direction shown upward (default ``+y``).
    distance : float, optional
        In units of the half-diagonal of the bounding box (default: the bounding sphere just fits the
        45° field of view, with a 4 % margin).

    Returns
    -------
    position, target, up : (3,) float arrays

    Raises
    ------
    InvalidParameterError
        ``view`` or ``up`` is not a nonzero 3D direction.

    Examples
    --------
    >>> s = Scene(); s.add_points("p", [[-1, -1, -1], [1, 1, 1]], (0, 0, 0))
    >>> [c.round(3).tolist() for c in camera_for(s, view=(0, 0, 1), up="y")]
    [[0.0, 0.0, 4.707], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    """
    from dhlb.render._figure import Camera, up_vector

    lo, hi = scene.bounds()
    c = 0.5 * (lo + hi)
    r = max(0.5 * float(np.linalg.norm(hi - lo)), 1e-12)
    if view is not None:
        d = np.asarray(view, dtype=np.float64).reshape(-1)
        if d.shape != (3,) or not np.all(np.isfinite(d)) or not np.any(d):
            raise InvalidParameterError(f"view must be a nonzero 3-vector, got {view!r}")
    cam = Camera(view=None if view is None else tuple(float(x) for x in d), up=up).fitted(np.vstack([lo, hi]))
    w = np.asarray(cam.view, dtype=np.float64)
    if distance is None:
        distance = 1.04 / np.sin(np.radians(FIELD_OF_VIEW / 2))
    return c + w / np.linalg.norm(w) * distance * r, c, up_vector(cam.up)


def _register(ps, scene: Scene) -> None:
    for m in scene.meshes:
        sm = ps.register_surface_mesh(m.name, m.points, m.faces, color=m.color, smooth_shade=True)
        if m.transparency < 1.0:
            sm.set_transparency(m.transparency)
        e = np.linalg.norm(m.points[m.faces[:, [1, 2, 0]]] - m.points[m.faces], axis=2).mean() if len(m.faces) else 0
        for k, v in m.vectors.items():  # glyphs of 0.45 mean edge lengths, as in the PNG pictures
            sm.add_vector_quantity(k, 0.45 * e * v, defined_on="vertices", enabled=True, vectortype="ambient",
                                   radius=0.0012, color=(0.1, 0.1, 0.1))
        for k, v in m.scalars.items():
            sm.add_scalar_quantity(k, v, defined_on="vertices" if len(v) == len(m.points) else "faces",
                                   enabled=k == m.shown_scalar, cmap="coolwarm")
        if m.corner_uv is not None:
            sm.add_parameterization_quantity("stripes", m.corner_uv.reshape(-1, 2), defined_on="corners",
                                             coords_type="unit", viz_style="checker", checker_size=0.25,
                                             checker_colors=((0.10, 0.10, 0.14), (0.96, 0.94, 0.88)), enabled=True)
    for p in scene.points:
        pc = ps.register_point_cloud(p.name, p.points, radius=p.radius)
        pc.add_color_quantity("index", p.colors, enabled=True)
    for c in scene.curves:
        if len(c.edges):
            ps.register_curve_network(c.name, c.nodes, c.edges, color=c.color, radius=c.radius)


def show(result: Any, *, screenshot: str | os.PathLike[str] | None = None,
         view: Sequence[float] | None = None, up=None, size: tuple[int, int] = (800, 800),
         isolines: bool = True) -> str | None:
    """Show a result in polyscope: a window, or a PNG rendered headless with ``screenshot=FILE.png``.

    Parameters
    ----------
    result : a result of the applications or of :func:`dhlb.io.read_result`, or Scene
        See :func:`scene_of`.
    screenshot : path, optional
        Render to this PNG without a window (EGL, no display needed) and return its path.
    view : (3,) float, optional
        Direction from the scene's centre to the camera (default: fitted as in the PNG pictures,
        :func:`camera_for`).
    up : (3,) float or {"x", "y", "z", "-x", "-y", "-z"}, optional
        The world direction shown upward (default ``+y``).
    size : (width, height)
        Window / picture size in pixels.
    isolines : bool
        Stripe patterns: draw the isolines.

    Returns
    -------
    str or None
        The screenshot path, or None after the window was closed.

    Raises
    ------
    ImportError
        polyscope is not installed (names the extra ``dhlb[view]``).
    ViewerUnavailableError
        No display for a window, or EGL/OpenGL does not start (says what to install).
    InvalidParameterError
        Not a result :func:`scene_of` knows; a bad ``view`` or ``size``.
    OutputError
        The screenshot cannot be written.

    Examples
    --------
    >>> import sys
    >>> sys.modules["polyscope"], saved = None, sys.modules.get("polyscope")   # as if polyscope were missing
    >>> try:
    ...     show(Scene(), screenshot="never.png")
    ... except ImportError as exc:
    ...     print(exc)
    ... finally:
    ...     _ = sys.modules.pop("polyscope") if saved is None else sys.modules.update(polyscope=saved)
    polyscope is not installed: pip install "dhlb[view]" (or: pip install polyscope)
    """
    scene = scene_of(result, isolines=isolines)
    w, h = (int(x) for x in size)
    if not (16 <= w <= 8192 and 16 <= h <= 8192):
        raise InvalidParameterError(f"size must be two integers between 16 and 8192 pixels, got {size!r}")
    camera, target, upv = camera_for(scene, view, up)
    out = None
    if screenshot is not None:
        out = os.fspath(screenshot)
        folder = os.path.dirname(os.path.abspath(out))
        if not os.path.isdir(folder):
            raise OutputError(out, "the folder does not exist")
    ps = _polyscope()
    _init(ps, headless=screenshot is not None)
    ps.remove_all_structures()
    ps.set_window_size(w, h)
    _register(ps, scene)
    ps.look_at_dir(tuple(camera), tuple(target), tuple(float(x) for x in upv))
    if out is None:
        ps.show()
        return None
    try:
        ps.screenshot(out, transparent_bg=False)
    except Exception as exc:
        raise OutputError(out, f"polyscope could not save the screenshot ({exc})") from None
    if not os.path.isfile(out):
        raise OutputError(out, "polyscope did not write the screenshot")
    return out
