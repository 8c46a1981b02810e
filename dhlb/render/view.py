"""Interactive and headless 3D views with `polyscope <https://polyscope.run>`_ (extra ``dhlb[view]``).

:func:`show` hands the :class:`~dhlb.render.scene.Scene` of a result (:func:`~dhlb.render.scene.scene_of`,
the one scene builder, re-exported here) to polyscope: the stripe texture as a per-corner
parameterization quantity, vectors as glyphs, points and curves as point clouds and curve networks;
a window, or
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
>>> position, target, up = camera_for(scene)          # the PNG's fitted view, framed for polyscope
>>> up.tolist(), bool(position[1] > target[1])        # +y up, from above
([0.0, 1.0, 0.0], True)
"""

from __future__ import annotations

import contextlib
import os
import sys
from typing import TYPE_CHECKING, Any

import numpy as np

from dhlb._install import install_hint
from dhlb.errors import InvalidParameterError, OutputError, ViewerUnavailableError
from dhlb.render._figure import GLYPH_COLOR, STRIPE_DARK, STRIPE_LIGHT, mean_edge_length, thin_out  # the one palette
from dhlb.render.scene import Scene, index_colors, scene_of  # the one scene builder (re-exported)

if TYPE_CHECKING:
    from collections.abc import Sequence

__all__ = [
    "VIEW_EXTRA",
    "ViewerUnavailableError",
    "Scene",
    "scene_of",
    "index_colors",
    "show",
    "camera_for",
]

MAX_GLYPHS = 3000
"""At most this many vertices carry direction glyphs in the viewer (an evenly spread subset of a finer mesh)."""
VIEW_EXTRA = f"polyscope is not installed: {install_hint('polyscope', 'view')}"
"""The message of the ``ImportError`` raised when polyscope is missing."""



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


_NO_INI = ""   # kept alive here: ImGui keeps the pointer (the empty string: nothing is saved)


def _no_imgui_ini() -> None:
    """Keep ImGui from writing ``imgui.ini`` into the working folder (window layout we never read back)."""
    try:
        import polyscope.imgui as psim

        psim.GetIO().IniFilename = _NO_INI
    except Exception:  # an older polyscope without these bindings: the file is harmless
        pass


def _no_prefs_file(ps) -> None:
    """Keep polyscope from reading and writing ``.polyscope.ini`` (its window size and place) in the working folder.

    Called before ``polyscope.init``, which reads the file, and whose shutdown writes it.
    """
    try:
        ps.set_use_prefs_file(False)
    except AttributeError:  # an older polyscope without the option
        pass


@contextlib.contextmanager
def _logs_to_stderr():
    """Send what the C++ side prints to standard output (polyscope's ``[polyscope] EGL: …`` lines) to stderr.

    Standard output carries results (``dhlb view --json`` prints one JSON line there); polyscope logs to
    ``std::cout``.  File descriptor 1 is pointed at descriptor 2 for the duration, after both the
    Python and the C buffers were flushed, and restored afterwards.
    """
    try:
        out = sys.stdout.fileno()
    except (AttributeError, OSError, ValueError):   # no real stdout (a notebook, a captured stream): leave it
        yield
        return
    sys.stdout.flush()
    saved = os.dup(out)
    target = sys.stderr.fileno() if _has_fileno(sys.stderr) else os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(target, out)
        yield
    finally:
        _flush_c_stdio()
        os.dup2(saved, out)
        os.close(saved)
        if not _has_fileno(sys.stderr):   # the devnull descriptor opened above
            os.close(target)


def _has_fileno(stream) -> bool:
    try:
        stream.fileno()
    except (AttributeError, OSError, ValueError):
        return False
    return True


def _flush_c_stdio() -> None:
    """``fflush(NULL)``: what the C library still buffers is written (to where it was meant to go)."""
    import ctypes

    try:
        ctypes.CDLL(None).fflush(None)
    except (OSError, AttributeError):   # no C library by that name (Windows): nothing buffered to lose
        pass


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
        _no_prefs_file(ps)
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
    _no_imgui_ini()
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
    given = scene.view if view is None else tuple(float(x) for x in d)   # else: as the scene is arranged
    cam = Camera(view=given, up=up).fitted(np.vstack([lo, hi]))
    w = np.asarray(cam.view, dtype=np.float64)
    if distance is None:
        distance = 1.04 / np.sin(np.radians(FIELD_OF_VIEW / 2))
    return c + w / np.linalg.norm(w) * distance * r, c, up_vector(cam.up)


def _register(ps, scene: Scene) -> None:
    for m in scene.meshes:
        sm = ps.register_surface_mesh(m.name, m.points, m.faces, color=m.color, smooth_shade=True)
        if m.transparency < 1.0:
            sm.set_transparency(m.transparency)
        e, scale = mean_edge_length(m.points, m.faces), np.ones(len(m.points))
        sites = np.nonzero(np.any([np.any(v != 0, axis=1) for v in m.vectors.values()], axis=0))[0] \
            if m.vectors else np.zeros(0, np.int64)
        if sites.size > MAX_GLYPHS:   # a fine mesh: glyphs on an evenly spread subset, as far apart (no moiré)
            kept, e = thin_out(m.points, sites, 0.5 * e, MAX_GLYPHS)
            scale = np.zeros(len(m.points))
            scale[kept] = 1.0
        for k, v in m.vectors.items():  # glyphs of 0.45 mean edge lengths, as in the PNG pictures
            sm.add_vector_quantity(k, 0.45 * e * scale[:, None] * v, defined_on="vertices", enabled=True,
                                   vectortype="ambient", radius=0.0012, color=GLYPH_COLOR)
        for k, v in m.scalars.items():
            rng = {} if m.scalar_range is None or k != m.shown_scalar else {"vminmax": m.scalar_range}
            sm.add_scalar_quantity(k, v, defined_on="vertices" if len(v) == len(m.points) else "faces",
                                   enabled=k == m.shown_scalar, cmap=m.colormap, **rng)
        if m.corner_uv is not None:
            sm.add_parameterization_quantity("stripes", m.corner_uv.reshape(-1, 2), defined_on="corners",
                                             coords_type="unit", viz_style="checker", checker_size=0.25,
                                             checker_colors=(STRIPE_DARK, STRIPE_LIGHT), enabled=True)
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
    polyscope is not installed: pip install polyscope (or dhlb's extra: pip install ".[view]" in a clone of dhlb)
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
    with _logs_to_stderr():    # stdout carries results only (dhlb view --json)
        _init(ps, headless=screenshot is not None)
        ps.remove_all_structures()
        ps.set_window_size(w, h)
        _register(ps, scene)
        ps.look_at_dir(tuple(camera), tuple(target), tuple(float(x) for x in upv))
    if out is None:
        ps.show()
        return None
    try:
        with _logs_to_stderr():
            ps.screenshot(out, transparent_bg=False)
    except Exception as exc:
        raise OutputError(out, f"polyscope could not save the screenshot ({exc})") from None
    if not os.path.isfile(out):
        raise OutputError(out, "polyscope did not write the screenshot")
    return out
