"""Tetrahedralize the solid bounded by a closed triangle surface with fTetWild (``pytetwild``).

``pytetwild`` is an optional dependency (``pip install dhlb[tet]``). This wrapper hides its quirks:

* versions 0.3–0.4.x import ``pyvista`` when the package is imported, although the
  array-based mesher does not need it; without ``pyvista`` installed we load the compiled
  extension ``pytetwild.PyfTetWildWrapper`` directly (0.2.x imports fine);
* fTetWild writes a scratch file (``__tracked_surface.stl``) into the working directory: the call
  runs in a fresh temporary directory (under a lock, since the working directory is per process);
* the output tetrahedra are negatively oriented: they are re-oriented and validated by
  :func:`dhlb.mesh.check_tet_mesh` (degenerate, folded or non-manifold output raises);
* the output is **not deterministic** (it differs from run to run even with one thread, as
  measured with pytetwild 0.2.3 and 0.4.2): do not compare meshes, compare what they bound.

Examples
--------
>>> from dhlb.mesh import tetgen
>>> isinstance(tetgen.available(), bool)
True
"""

from __future__ import annotations

import contextlib
import glob
import importlib
import importlib.machinery
import importlib.util
import os
import tempfile
import threading
import warnings

import numpy as np

from dhlb._coerce import as_points, check_int
from dhlb._install import install_hint
from dhlb.errors import InvalidParameterError, NonManifoldError, UnreferencedVertexWarning
from dhlb.mesh.compact import _renumber
from dhlb.mesh.tet import TetMesh, check_tet_mesh

__all__ = ["available", "backend_version", "tetrahedralize"]

_LOCK = threading.Lock()
_BACKEND = None
_INSTALL = f"install the optional dependency: {install_hint('pytetwild', 'tet')}"


def _load_extension():
    """The compiled ``PyfTetWildWrapper`` module, bypassing ``pytetwild/__init__`` (which may need pyvista)."""
    spec = importlib.util.find_spec("pytetwild")
    if spec is None or not spec.submodule_search_locations:
        raise ModuleNotFoundError(f"pytetwild is not installed; {_INSTALL}")
    name = "pytetwild.PyfTetWildWrapper"
    for folder in spec.submodule_search_locations:
        for path in sorted(glob.glob(os.path.join(folder, "PyfTetWildWrapper*"))):
            if path.endswith(tuple(importlib.machinery.EXTENSION_SUFFIXES)):
                loader = importlib.machinery.ExtensionFileLoader(name, path)
                spec = importlib.util.spec_from_file_location(name, path, loader=loader)
                module = importlib.util.module_from_spec(spec)
                loader.exec_module(module)
                return module
    raise ModuleNotFoundError("pytetwild is installed but its compiled extension was not found; "
                              f"reinstall it ({_INSTALL})")


def _backend():
    """``(call, version)``: ``call(V, F, edge_length_fac, edge_length_abs, epsilon, optimize, threads)``."""
    global _BACKEND
    if _BACKEND is not None:
        return _BACKEND
    try:
        from importlib.metadata import version

        ver = version("pytetwild")
    except Exception:
        ver = "unknown"
    try:
        ext = importlib.import_module("pytetwild.PyfTetWildWrapper")  # runs pytetwild/__init__
    except ModuleNotFoundError as err:
        if err.name in ("pytetwild", None):
            raise ModuleNotFoundError(f"pytetwild is not installed; {_INSTALL}") from None
        ext = _load_extension()  # e.g. pyvista missing for pytetwild >= 0.3
    fn = ext.tetrahedralize_mesh
    extra = "arg15" in (fn.__doc__ or "")  # >= 0.4: background sizing-field arrays

    def call(V, F, fac, abs_len, eps, optimize, threads):
        args = [V, F, bool(optimize), False, float(fac), float(abs_len), float(eps), 10.0, False, int(threads),
                80, 6, True, False, False]
        if extra:
            args += [np.empty((0, 3)), np.empty((0, 4), np.int32), np.empty(0)]
        return fn(*args)

    _BACKEND = (call, ver)
    return _BACKEND


def available() -> bool:
    """True if pytetwild can be used (installed, with or without pyvista)."""
    try:
        _backend()
    except (ImportError, OSError, AttributeError):
        return False
    return True


def backend_version() -> str:
    """Version string of the installed pytetwild (raises ``ModuleNotFoundError`` if missing)."""
    return _backend()[1]


@contextlib.contextmanager
def _scratch_directory():
    with _LOCK, tempfile.TemporaryDirectory(prefix="dhlb-tetwild-") as tmp:
        old = os.getcwd()
        os.chdir(tmp)
        try:
            yield tmp
        finally:
            os.chdir(old)


def _closed_surface(V, F) -> tuple[np.ndarray, np.ndarray]:
    from dhlb.mesh.arrays import mesh_complex

    Vin = as_points(V, "V", finite=False)  # finiteness: mesh_complex names the vertex
    with warnings.catch_warnings():  # vertices no triangle uses are dropped below, silently
        warnings.simplefilter("ignore", UnreferencedVertexWarning)
        mc = mesh_complex(Vin, F, dim=2)  # parses F, checks finiteness and ranges (names the row)
    X = mc.complex
    cnt = np.bincount(X.faces(2).ravel(), minlength=X.n_simplices(1))
    if np.any(cnt != 2):
        e = int(np.argmax(cnt != 2))
        edge = tuple(int(v) for v in X.vertex_labels[X.simplices(1)[e]])
        raise NonManifoldError(f"the surface must be closed: its edge {edge} "
                               f"lies in {cnt[e]} triangle(s), not 2; close or repair the surface first")
    Fc = np.searchsorted(X.vertex_labels, np.asarray(F, dtype=np.int64))
    return mc.points, Fc


def tetrahedralize(V, F, *, edge_length=None, edge_length_fac: float = 0.05, epsilon: float = 1e-3,
                   optimize: bool = True, threads: int = 0) -> TetMesh:
    """Tetrahedral mesh of the solid bounded by the closed triangle surface ``(V, F)``.

    Parameters
    ----------
    V : (n, 3) float array
    F : (f, 3) int array
        A closed surface: every edge in exactly two triangles (checked).
    edge_length : float, optional
        Target edge length (absolute); overrides ``edge_length_fac``.
    edge_length_fac : float in (0, 1]
        Target edge length relative to the bounding-box diagonal.
    epsilon : float
        Envelope: the output boundary stays within ``epsilon`` × diagonal of the input surface.
    optimize : bool
        Let fTetWild improve element quality (slower, better meshes).
    threads : int
        Threads used by fTetWild (0, the default: all cores; one thread is not deterministic either).
        fTetWild is slow: the 3.5k-vertex ``bunny-watertight.off`` with ``edge_length_fac=0.08``
        took 44 s on one thread.

    Returns
    -------
    TetMesh
        Positively oriented and validated (:func:`dhlb.mesh.check_tet_mesh`).

    Raises
    ------
    ModuleNotFoundError
        pytetwild is not installed (``pip install dhlb[tet]``).
    ShapeError, NonFiniteError, InvalidSimplexError
        Malformed ``V``/``F`` (the row is named).
    NonManifoldError
        The surface is not closed (an edge in one triangle or in three, named), or the output is not
        a 3-manifold mesh.
    InvalidParameterError
        Out-of-range mesher parameters.
    """
    Vs, Fs = _closed_surface(V, F)
    if not (np.isfinite(edge_length_fac) and 0 < edge_length_fac <= 1):
        raise InvalidParameterError(f"edge_length_fac must lie in (0, 1], got {edge_length_fac!r}")
    if edge_length is not None and not (np.isfinite(edge_length) and edge_length > 0):
        raise InvalidParameterError(f"edge_length must be a finite number > 0, got {edge_length!r}")
    if not (np.isfinite(epsilon) and epsilon > 0):
        raise InvalidParameterError(f"epsilon must be a finite number > 0, got {epsilon!r}")
    threads = check_int(threads, "threads", 0)
    call, _ = _backend()
    with _scratch_directory():
        P, T = call(np.ascontiguousarray(Vs), np.ascontiguousarray(Fs, dtype=np.uint32), edge_length_fac,
                    0.0 if edge_length is None else edge_length, epsilon, optimize, threads)
    P = np.asarray(P, dtype=np.float64)
    T = np.asarray(T, dtype=np.int64)
    kept, new = _renumber(P.shape[0], T)
    if kept.size < P.shape[0]:  # drop vertices of the background mesh that no tetrahedron uses
        P, T = P[kept], new[T]
    return check_tet_mesh(P, T)
