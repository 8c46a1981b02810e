"""``dhlb conformal``: close-to-conformal deformation of a tet mesh (:func:`dhlb.conformal.conformal_deformation`).

Its picture, :func:`dhlb.render.render_conformal_png`, is importable from here too.
"""

from __future__ import annotations

import json
import os

import numpy as np

from dhlb.cli._common import (
    UsageError,
    add_command,
    backend_choice,
    int_in_range,
    number_tuple,
    report_table,
    resolve_input,
)
from dhlb.cli._outputs import OutputSpec, output_plan
from dhlb.render.conformal_png import boundary_distortion, render_conformal_png

__all__ = ["NAME", "OUTPUTS", "SUMMARY", "boundary_distortion", "format_report", "register",
           "render_conformal_png", "run"]

NAME = "conformal"
SUMMARY = "close-to-conformal deformation of a tet mesh with a target conformal factor (point charges or u.npy)"

_DESCRIPTION = """\
Deform the tetrahedral mesh TETMESH (.mesh .msh .vtk) so that it scales every direction by about e^u
(seed part 3, section 2.4; Chern, Pinkall, Schroeder 2015): the smallest eigenvector psi of the
quaternionic connection d + 1/2 (grad u x dx) on M x H gives unit quaternions phi = psi/|psi|, and the
map f solves the least-squares problem df(X) = e^u conj(phi) X phi (one Poisson solve).

u is the potential of point charges, u(x) = sum q / |x - a| (--charge x,y,z,q, repeatable; the
charges must lie outside the solid), or one value per mesh vertex (--u FILE.npy). Without --charge or
--u the default is one charge at distance 0.3 diam above the top of the bounding box, q = 0.5 diam or
less on a coarse mesh: at most 0.5 rad phase change per edge (dhlb.conformal.default_charge).

With -o OUT (a base name) the deformed mesh is written to OUT.mesh and OUT.vtk, the result
(statistics, timings) to OUT.json and a picture of the boundary before and after, coloured by the
distortion of each tetrahedron (sigma_max / sigma_min of the deformation gradient), to OUT.png
(unless --no-png); -o OUT.EXT writes that format only (see below)."""

_EXAMPLES = """\
  dhlb conformal solid.mesh --charge 0,0,2,1 --charge 1.5,0,0,-0.5 -o deformed   # .mesh .vtk .json .png
  dhlb conformal solid.vtk --u u.npy -o out.vtk --json                          # out.vtk only
  dhlb conformal --ball 6 -o ball                # a tetrahedralised ball, default charge: dhlb view ball"""

OUTPUTS = OutputSpec("conformal", (".mesh", ".vtk", ".json", ".png"), {
    ".mesh": "the deformed tets (Medit)",
    ".msh": "the deformed tets (Gmsh)",
    ".vtk": "the deformed tets (legacy VTK)",
    ".vtu": "the deformed tets with phi, u, distortion, for ParaView",
    ".npz": "points, tets, phi, u, distortion, scale error, eigenvalue",
    ".json": "the summary: eigenvalue, statistics, timings",
    ".png": "the boundary before and after, coloured by distortion",
}, switches={".png": "no_png"})
"""What ``dhlb conformal -o`` writes (nothing without ``-o``)."""


def register(subparsers) -> None:
    """Add the ``conformal`` parser to ``subparsers``."""
    p = add_command(subparsers, NAME, SUMMARY, _DESCRIPTION, _EXAMPLES, outputs=OUTPUTS)
    p.add_argument("mesh", nargs="?", metavar="TETMESH", help="tetrahedral mesh file (.mesh .msh .vtk)")
    p.add_argument("--ball", type=int_in_range(1, 100_000), metavar="N",
                   help="use the unit ball (dhlb.mesh.ball_tet_mesh(N)) instead")
    p.add_argument("--format", dest="fmt", metavar="FMT", help="mesh format if the extension does not say it")
    p.add_argument("--charge", action="append", default=[], type=number_tuple("X,Y,Z,Q"), metavar="X,Y,Z,Q",
                   help="a point charge at (X, Y, Z) with charge Q (repeatable; default: one charge scaled to "
                        "the mesh, dhlb.conformal.default_charge)")
    p.add_argument("--u", dest="u_file", metavar="FILE.npy", help="one value of u per mesh vertex")
    p.add_argument("--backend", type=backend_choice, metavar="B", help="linear-algebra backend (default: dhlb's)")
    p.add_argument("--no-png", action="store_true", help="with -o: do not render the PNG picture")
    p.set_defaults(func=run)


def _mesh(args):
    from dhlb.mesh import ball_tet_mesh, check_tet_mesh

    if args.mesh is not None and args.ball is not None:
        raise UsageError("give either TETMESH or --ball N, not both")
    if args.mesh is None:
        from dhlb.errors import ResourceLimitError

        n = 6 if args.ball is None else args.ball
        try:   # refused before any work when it cannot fit (a usage error naming the option)
            m = ball_tet_mesh(n)
        except ResourceLimitError as exc:
            raise UsageError(f"argument --ball: {exc} (ball_tet_mesh's n is --ball)") from None
        return m, m.points.shape[0], f"ball {n}"
    from dhlb.io import read_volume

    fmt = resolve_input(args.mesh, args.fmt)
    V, T = read_volume(args.mesh, fmt)
    return check_tet_mesh(V, T), np.shape(V)[0], args.mesh


def _factor(args, mesh, n_rows):
    from dhlb.conformal import default_charge, point_charge_factor

    if args.charge and args.u_file:
        raise UsageError("give either --charge ... or --u FILE.npy, not both")
    if args.u_file:
        if not args.u_file.endswith(".npy"):
            raise UsageError(f"--u must name a .npy file, got {args.u_file!r}")
        if not os.path.isfile(args.u_file):
            raise UsageError(f"{args.u_file}: no such file")
        try:
            arr = np.load(args.u_file, allow_pickle=False)
        except (ValueError, OSError) as exc:
            raise UsageError(f"{args.u_file}: not a readable .npy array ({exc})") from None
        return arr, f"{args.u_file} (per vertex)"
    if args.charge:
        C = [list(c) for c in args.charge]
    else:
        C = default_charge(mesh)
    u = point_charge_factor(C)
    return u, "; ".join(u.labels)


def _outputs(plan, result, meta) -> None:
    """Write the files of ``plan`` (all or none); :attr:`OutputPlan.written` lists them."""
    with plan.writing() as stage:
        for suffix in plan.suffixes:
            if suffix == ".json":
                with open(stage(suffix), "w", encoding="utf-8") as fh:
                    json.dump({**meta, **_summary(result)}, fh, indent=1)
            elif suffix == ".png":
                F, dF = boundary_distortion(result)
                title = f"{meta['u']}: distortion (colour) 1 .. {result.distortion.max():.3g}"
                render_conformal_png(stage(suffix), result.mesh.points, result.points, F, dF, title=title)
            else:  # the formats of dhlb.io.results.write
                result.save(stage(suffix))


def _summary(result) -> dict:
    return {"eigenvalue": float(result.eigenvalue), "statistics": result.statistics, "timings": result.timings}


def format_report(meta: dict, data: dict) -> str:
    """Human-readable summary of a run.

    Examples
    --------
    >>> print(format_report({"mesh": "m", "u": "u"}, {"eigenvalue": 0.0, "statistics": {"n_vertices": 1,
    ...       "n_tets": 0, "distortion_mean": 1.0, "distortion_max": 1.0, "scale_error_rms": 0.0,
    ...       "inverted_tets": 0, "solver": {"backend": "superlu"}}, "timings": {"total": 0.1}}).splitlines()[0])
    mesh           m (1 vertices, 0 tetrahedra)
    """
    s, t = data["statistics"], data["timings"]
    rows = [
        ("mesh", f"{meta['mesh']} ({s['n_vertices']} vertices, {s['n_tets']} tetrahedra)"),
        ("u", meta["u"]),
        ("eigenvalue", f"{data['eigenvalue']:.6g}"),
        ("distortion", f"mean {s['distortion_mean']:.4g}, max {s['distortion_max']:.4g}"),
        ("scale error", f"rms {s['scale_error_rms']:.3g}"),
        ("inverted", f"{s['inverted_tets']} tetrahedra"),
        ("solver", s["solver"]["backend"]),
    ]
    return report_table(rows, timings=t, written=meta.get("written"))


def run(args) -> int:
    """Entry point of ``dhlb conformal``."""
    from dhlb.conformal import conformal_deformation

    plan = output_plan(OUTPUTS, args)  # before any work; never over the input mesh or the u file
    mesh, n_rows, mesh_name = _mesh(args)
    u, uname = _factor(args, mesh, n_rows)
    if isinstance(u, np.ndarray) and u.shape != (n_rows,):
        raise UsageError(f"--u: the array must have one value per mesh vertex, shape ({n_rows},), got {u.shape}")
    if isinstance(u, np.ndarray):
        u = u[np.asarray(mesh.complex.vertex_labels)]
    result = conformal_deformation(mesh, None, u, backend=args.backend)
    meta = {"mesh": mesh_name, "u": uname}
    if plan:
        _outputs(plan, result, meta)
        meta["written"] = plan.written
    data = _summary(result)
    if args.json or not args.quiet:
        print(json.dumps({**data, **meta}, indent=1) if args.json else format_report(meta, data))
    return 0
