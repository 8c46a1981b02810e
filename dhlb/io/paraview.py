"""The package's results as ParaView files: which arrays each result carries (through :mod:`dhlb.io.meshio_bridge`).

* :func:`field_to_vtu`: a direction field (:func:`dhlb.fields.direction_field`) as a surface with
  its n directions, ``u`` and the face indices;
* :func:`stripes_to_vtu`: a stripe pattern (:func:`dhlb.stripes.stripe_pattern`) with ψ and the
  per-corner texture (per face: ParaView has no per-corner arrays);
* :func:`vortex_to_vtu`: a vortex result (:func:`dhlb.vortex.vortex_filaments`) as the tet mesh with
  ψ, ``|ψ|`` and the velocity, the filaments beside it as ``.vtp``.

Results are taken by what they carry (duck typing), so this layer imports no application.

Examples
--------
>>> import os, tempfile, meshio
>>> from dhlb.io import example_path, read_surface
>>> from dhlb.fields import direction_field
>>> res = direction_field(*read_surface(example_path("torus.obj")), n=2)
>>> with tempfile.TemporaryDirectory() as d:
...     print(sorted(meshio.read(field_to_vtu(res, os.path.join(d, "f.vtu"))).cell_data))
['index', 'input_face']
"""

from __future__ import annotations

import os
from typing import Any

import numpy as np

from dhlb.errors import InvalidParameterError, NonFiniteError, ShapeError
from dhlb.io.meshio_bridge import write_vtp_curves, write_vtu_surface, write_vtu_volume

__all__ = ["field_to_vtu", "stripes_to_vtu", "vortex_to_vtu"]


def _check_result(result, attrs, what, fn):
    if not all(hasattr(result, a) for a in attrs):
        raise InvalidParameterError(f"{fn} needs the result of {what}, got {type(result).__name__}")


def field_to_vtu(result: Any, path: str | os.PathLike[str], *, binary: bool = True) -> str:
    """Write a :class:`~dhlb.fields.DirectionField` as a ``.vtu`` surface for ParaView.

    The mesh is the validated one (``result.mesh.points``, ``.faces``). Arrays:

    * point data ``d0`` … ``d{n-1}``: the n unit directions (``(N, 3)`` each, zero where u = 0),
      ``u`` (``(N, 2)``: Re, Im of the power representation), ``u_abs``, ``input_vertex`` (the row
      of the input V);
    * cell data ``index`` (the face index, mesh orientation), ``input_face`` (row of the input F);
    * field data ``n``, ``s``, ``index_sum``, ``euler_characteristic``.

    Parameters
    ----------
    result : DirectionField
    path : str or path-like
    binary : bool

    Returns
    -------
    str
        ``path``.

    Raises
    ------
    InvalidParameterError
        ``result`` is not a direction field.
    OutputError, ImportError
        As in :func:`write_vtu_surface`.

    Examples
    --------
    >>> import os, tempfile, meshio
    >>> from dhlb.io import read_surface, example_path
    >>> from dhlb.fields import direction_field
    >>> res = direction_field(*read_surface(example_path("torus.obj")), n=4)
    >>> with tempfile.TemporaryDirectory() as d:
    ...     m = meshio.read(field_to_vtu(res, os.path.join(d, "f.vtu")))
    >>> sorted(m.point_data), m.point_data["d3"].shape, int(m.cell_data["index"][0].sum()) == res.index_sum
    (['d0', 'd1', 'd2', 'd3', 'input_vertex', 'u', 'u_abs'], (288, 3), True)
    """
    _check_result(result, ("mesh", "directions", "u", "face_index", "n"), "dhlb.fields.direction_field",
                  "field_to_vtu")
    mesh = result.mesh
    pd = {f"d{k}": result.directions[:, k, :] for k in range(result.n)}
    pd.update(u=result.u, u_abs=np.abs(result.u), input_vertex=mesh.vertex_rows)
    cd = {"index": result.face_index, "input_face": mesh.face_rows}
    fd = {"n": np.array([result.n]), "s": np.array([float(result.s)]),
          "index_sum": np.array([result.index_sum]), "euler_characteristic": np.array([result.euler_characteristic])}
    return write_vtu_surface(path, mesh.points, mesh.faces, point_data=pd, cell_data=cd, field_data=fd, binary=binary)


def stripes_to_vtu(result: Any, path: str | os.PathLike[str], *, binary: bool = True) -> str:
    """Write a :class:`~dhlb.stripes.StripePattern` as a ``.vtu`` surface.

    Arrays: point data ``psi`` (``(N, 2)``: Re, Im), ``input_vertex``; cell data ``corner_alpha``
    (``(m, 3)``: α at the three corners of each face, the linear part — ParaView has no per-corner
    arrays, so the texture travels per face), ``zero_index``, ``branch`` (0/1), ``input_face``.

    Parameters
    ----------
    result : StripePattern
    path : str or path-like
    binary : bool

    Returns
    -------
    str
        ``path``.

    Raises
    ------
    InvalidParameterError
        ``result`` is not a stripe pattern.
    OutputError, ImportError
        As in :func:`write_vtu_surface`.

    Examples
    --------
    >>> import os, tempfile, meshio, numpy as np
    >>> from dhlb.stripes import stripe_pattern
    >>> V, F = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], [[0, 1, 2], [1, 3, 2]]
    >>> res = stripe_pattern(V, F, np.tile([1.0, 0, 0], (4, 1)), frequency=0.25)
    >>> with tempfile.TemporaryDirectory() as d:
    ...     m = meshio.read(stripes_to_vtu(res, os.path.join(d, "s.vtu")))
    >>> m.cell_data["corner_alpha"][0].shape, m.point_data["psi"].shape
    ((2, 3), (4, 2))
    """
    _check_result(result, ("mesh", "texture", "psi"), "dhlb.stripes.stripe_pattern", "stripes_to_vtu")
    mesh = result.mesh
    tex = result.texture
    pd = {"psi": result.psi, "input_vertex": mesh.vertex_rows}
    cd = {"corner_alpha": tex.corner_alpha, "zero_index": tex.zero_index, "branch": tex.is_branch,
          "input_face": mesh.face_rows}
    return write_vtu_surface(path, mesh.points, mesh.faces, point_data=pd, cell_data=cd,
                             field_data={"n": np.array([result.n])}, binary=binary)


def _velocity(velocity, mesh, path):
    if velocity is None:
        return None
    if callable(velocity):
        v = np.asarray(velocity(mesh.points), dtype=np.float64)
    else:
        arr = np.asarray(velocity, dtype=np.float64)
        labels = np.asarray(mesh.complex.vertex_labels)
        if arr.ndim != 2 or arr.shape[1] != 3 or len(arr) <= labels.max(initial=-1):
            raise ShapeError(f"{path}: the velocity must have one 3D vector per vertex row of the input mesh, "
                             f"got shape {arr.shape}")
        v = arr[labels]
    if v.shape != mesh.points.shape:
        raise ShapeError(f"{path}: the velocity field returned shape {v.shape}, expected {mesh.points.shape}")
    bad = ~np.isfinite(v).all(axis=1)
    if np.any(bad):
        raise NonFiniteError(f"{path}: the velocity is not finite at vertex {int(np.argmax(bad))}")
    return v


def vortex_to_vtu(result: Any, path: str | os.PathLike[str], velocity: Any = None, *,
                  filaments: str | os.PathLike[str] | None = "auto", binary: bool = True) -> list[str]:
    """Write a :class:`~dhlb.vortex.VortexResult`: the tet mesh as ``.vtu`` and the filaments beside it.

    Arrays of the ``.vtu``: point data ``psi`` (``(N, 2)``: Re, Im of ψ in the frames of the
    result's bundle), ``psi_abs`` (``|ψ|``), ``velocity`` (``(N, 3)``, when ``velocity`` is given)
    and ``input_vertex``; field data ``hbar``, ``eigenvalue``, ``n_filaments``. The filaments go to
    ``STEM-filaments.vtp`` (:func:`write_vtp_curves`).

    Parameters
    ----------
    result : VortexResult
    path : str or path-like
        The ``.vtu`` file.
    velocity : callable, (n, 3) array or None
        The velocity given to :func:`~dhlb.vortex.vortex_filaments`: a callable is evaluated at the
        mesh points, an array has one row per input vertex. The result does not keep it.
    filaments : str or path-like, "auto" or None
        Where to write the filaments: ``"auto"`` is ``STEM-filaments.vtp``, None writes none.
    binary : bool

    Returns
    -------
    list of str
        The files written (the ``.vtu`` first).

    Raises
    ------
    InvalidParameterError
        ``result`` is not a vortex result.
    ShapeError, NonFiniteError
        A velocity of the wrong shape or not finite.
    OutputError, ImportError
        As in :func:`write_vtu_volume`.

    Examples
    --------
    >>> import os, tempfile, meshio
    >>> from dhlb.mesh import box_tet_mesh
    >>> from dhlb.vortex import uniform_flow, vortex_filaments
    >>> v = uniform_flow([0.3, 0.0, 0.0])
    >>> res = vortex_filaments(box_tet_mesh(3), None, v, hbar=1.0)
    >>> with tempfile.TemporaryDirectory() as d:
    ...     paths = vortex_to_vtu(res, os.path.join(d, "v.vtu"), v)
    ...     m = meshio.read(paths[0])
    ...     names = [os.path.basename(p) for p in paths]
    >>> names, sorted(m.point_data), m.cells_dict["tetra"].shape
    (['v.vtu', 'v-filaments.vtp'], ['input_vertex', 'psi', 'psi_abs', 'velocity'], (162, 4))
    """
    _check_result(result, ("mesh", "psi", "filaments", "statistics"), "dhlb.vortex.vortex_filaments",
                  "vortex_to_vtu")
    where = os.fspath(path)
    mesh = result.mesh
    pd = {"psi": result.psi, "psi_abs": np.abs(result.psi)}
    v = _velocity(velocity, mesh, where)
    if v is not None:
        pd["velocity"] = v
    pd["input_vertex"] = np.asarray(mesh.complex.vertex_labels)
    fd = {"hbar": np.array([float(result.statistics.get("hbar", np.nan))]),
          "eigenvalue": np.array([float(result.eigenvalue)]), "n_filaments": np.array([len(result.filaments)])}
    written = [write_vtu_volume(where, mesh.points, mesh.tets, point_data=pd, field_data=fd, binary=binary)]
    if filaments is not None:
        fpath = os.path.splitext(where)[0] + "-filaments.vtp" if filaments == "auto" else os.fspath(filaments)
        written.append(write_vtp_curves(fpath, result.filaments))
    return written
