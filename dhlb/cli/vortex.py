"""``dhlb vortex``: vortex filaments of a velocity field on a tetrahedral mesh (:func:`dhlb.vortex.vortex_filaments`).

Also home of the demo fields of the command (:func:`demo_velocity`); the filaments are written by
:mod:`dhlb.io.polylines`.
"""

from __future__ import annotations

import json
import os

import numpy as np

from dhlb.cli._common import (
    UsageError,
    add_command,
    backend_choice,
    did_you_mean,
    finite_float,
    int_in_range,
    nonempty_text,
    report_table,
    resolve_input,
)
from dhlb.cli._outputs import OutputSpec, output_plan
from dhlb.errors import InvalidParameterError, ResourceLimitError
from dhlb.io.polylines import write_polylines_obj, write_polylines_ply

__all__ = ["NAME", "OUTPUTS", "SUMMARY", "demo_velocity", "format_report", "register", "run", "write_polylines_obj",
           "write_polylines_ply"]

NAME = "vortex"
SUMMARY = "vortex filaments of a velocity field in a tet mesh (zero set of the least-energy section)"

DEMOS = ("ring", "linked-rings", "trefoil")
MAX_FILAMENTS_PER_CURVE = 100  # |circulation| / (2 pi hbar) for a demo field; more cannot be resolved

_DESCRIPTION = """\
Compute the vortex filaments of a velocity field v on a tetrahedral mesh (Weissmann, Pinkall,
Schroeder, "Smoke rings from smoke"): the section psi of the line bundle with connection
d - i<v, .>/hbar of least Dirichlet energy (unit L2 norm) is computed with the curvature-corrected
finite elements of dhlb.fem, and its zero set is traced through the tetrahedra. Every filament
carries the circulation 2 pi hbar.

The mesh is TETMESH (.mesh .msh .vtk) or, with --box N, the cube [-1, 1]^3 cut into N^3 cells of
six tetrahedra (default: --box 12). The velocity is a demo field placed in the middle of the
domain's bounding box (half-size rho = smallest half-extent): 'ring' (radius 0.6 rho),
'linked-rings' (a Hopf link of two rings of radius 0.55 rho), 'trefoil' (the (2,3) torus knot on
the torus with radii 0.55 rho, 0.25 rho), each of circulation --circulation (default 2 pi) and core
radius --core (default 0.08 rho), regularized Biot-Savart; or FILE.npy with one velocity vector
per mesh vertex (per row of TETMESH's vertex list).

With -o OUT (a base name) the filaments are written as polylines to OUT.obj, the full result
(filaments, linking numbers, timings, statistics) to OUT.json and a picture to OUT.png (unless
--no-png); -o OUT.EXT writes that format only (see below). --json prints the result as JSON:
{"filaments": [{"points": [[x, y, z], ...], "closed": bool}], "linking_numbers": ..., "timings": ...}."""

_EXAMPLES = """\
  dhlb vortex                                   # a ring in the cube, --box 12, hbar 1
  dhlb vortex --box 16 --velocity linked-rings --hbar 1 -o rings   # rings.obj, .json, .png
  dhlb vortex --velocity ring --hbar 0.5 --json  # two filaments
  dhlb vortex domain.mesh --velocity v.npy --hbar 0.2 -o filaments.obj"""


OUTPUTS = OutputSpec(NAME, (".obj", ".json", ".png"), {
    ".obj": "the filaments as polylines ('l' records)",
    ".ply": "the filaments as polylines (edges)",
    ".json": "the result: filaments, linking numbers, statistics, timings",
    ".png": "the picture",
    ".vtu": "the tet mesh with psi, |psi| and the velocity, for ParaView",
}, companions={".vtu": ("-filaments.vtp",)}, switches={".png": "no_png"})
"""What ``dhlb vortex -o`` writes (nothing without ``-o``)."""


def register(subparsers) -> None:
    """Add the ``vortex`` parser to ``subparsers``."""
    p = add_command(subparsers, NAME, SUMMARY, _DESCRIPTION, _EXAMPLES, outputs=OUTPUTS)
    p.add_argument("mesh", nargs="?", metavar="TETMESH", help="tetrahedral mesh file (.mesh .msh .vtk)")
    p.add_argument("--box", type=int_in_range(1, 100_000), metavar="N",
                   help="use the cube [-1, 1]^3 with N cells per axis instead (memory is checked first)")
    p.add_argument("--format", dest="fmt", metavar="FMT", help="mesh format if the extension does not say it")
    p.add_argument("--velocity", default="ring", metavar="FIELD", type=nonempty_text,
                   help="ring, linked-rings, trefoil, or FILE.npy with one vector per vertex (default: ring)")
    p.add_argument("--hbar", type=finite_float(0, low_open=True), default=1.0, metavar="H",
                   help="hbar > 0: circulation per filament / 2 pi")
    p.add_argument("--circulation", type=float, default=2 * np.pi, metavar="G",
                   help="circulation of each demo curve (default 2 pi)")
    p.add_argument("--core", type=finite_float(0, low_open=True), metavar="A",
                   help="core radius of the demo fields (default 0.08 rho)")
    p.add_argument("--order", type=int_in_range(1, 64), default=4, metavar="Q",
                   help="Gauss-Legendre nodes per edge (default 4)")
    p.add_argument("--backend", type=backend_choice,
                   metavar="B", help="linear-algebra backend of the eigen solver (default: dhlb's)")
    p.add_argument("--tol", type=finite_float(0, 1, low_open=True, high_open=True), default=1e-9, metavar="TOL",
                   help="eigen solver tolerance (default 1e-9)")
    p.add_argument("--no-png", action="store_true", help="with -o: do not render the PNG picture")
    p.set_defaults(func=run)


# ---------------------------------------------------------------------------- demo fields and writers
def demo_velocity(name: str, points, *, circulation: float = 2 * np.pi, core_radius: float | None = None):
    """A demo field centred in the bounding box of ``points``; returns ``(field, curves)``.

    ``rho`` is the smallest half-extent of the box; the curves are shifted off the box centre by
    ``(0.013, 0.007, 0.011) rho`` so that they do not meet a symmetric mesh symmetrically.

    Examples
    --------
    >>> import numpy as np
    >>> field, curves = demo_velocity("linked-rings", np.array([[-1.0, -1, -1], [1, 1, 1]]))
    >>> len(curves), field.core_radius
    (2, 0.08)
    """
    from dhlb.vortex import FilamentField, hopf_link, torus_knot, vortex_ring

    P = np.asarray(points, dtype=float)
    lo, hi = P.min(axis=0), P.max(axis=0)
    rho = 0.5 * float((hi - lo).min())
    if not rho > 0:
        raise InvalidParameterError("the domain is flat: its bounding box has zero extent along some axis")
    c = 0.5 * (lo + hi) + np.array([0.013, 0.007, 0.011]) * rho
    if name == "ring":
        curves = [vortex_ring(0.6 * rho, center=c, n=96)]
    elif name == "linked-rings":
        R = 0.55 * rho
        curves = [C + c - [0.5 * R, 0.0, 0.0] for C in hopf_link(R, n=96)]
    elif name == "trefoil":
        curves = [torus_knot(2, 3, major=0.55 * rho, minor=0.25 * rho, n=240) + c]
    else:
        raise InvalidParameterError(
            f"unknown demo field {name!r}; choose one of {', '.join(DEMOS)} or give a .npy file"
        )
    a = 0.08 * rho if core_radius is None else float(core_radius)
    return FilamentField(curves, circulation=circulation, core_radius=a), curves


# ---------------------------------------------------------------------------- the command
def _mesh(args):
    """``(V, T, name)``: the box as a TetMesh (``T`` None), or the arrays of TETMESH (validated later)."""
    from dhlb.mesh import box_tet_mesh
    from dhlb.mesh.tet import VORTEX_BYTES_PER_CELL, check_box_memory

    if args.mesh is not None and args.box is not None:
        raise UsageError("give either TETMESH or --box N, not both")
    if args.mesh is None:
        n = 12 if args.box is None else args.box
        try:  # the whole run's memory, estimated before any work
            check_box_memory(n, per_cell=VORTEX_BYTES_PER_CELL, name="--box")
        except ResourceLimitError as exc:
            raise UsageError(str(exc)) from None
        return box_tet_mesh(n, lower=-1.0, upper=1.0), None, f"box {n}"
    from dhlb.io import read_volume

    fmt = resolve_input(args.mesh, args.fmt)
    V, T = read_volume(args.mesh, fmt)
    return V, T, args.mesh


_BOX_CORNERS = np.array([[-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]])  # the domain of --box


def _velocity(args, V, T):
    """The velocity of ``--velocity`` on the mesh ``(V, T)`` (``V`` None: the ``--box`` cube ``[-1, 1]^3``)."""
    spec = args.velocity
    if spec in DEMOS:
        per_curve = abs(args.circulation) / (2 * np.pi * args.hbar)
        if per_curve > MAX_FILAMENTS_PER_CURVE:
            raise UsageError(
                f"--circulation {args.circulation:g} with --hbar {args.hbar:g} asks for about {per_curve:.3g} "
                f"filaments per demo curve (|circulation| / 2 pi hbar); at most {MAX_FILAMENTS_PER_CURVE} are "
                "allowed: lower --circulation or raise --hbar")
        P = _BOX_CORNERS if V is None else V.points if T is None else np.asarray(V)[np.unique(np.asarray(T))]
        field, _ = demo_velocity(spec, P, circulation=args.circulation, core_radius=args.core)
        return field, f"{spec} (circulation {args.circulation:.6g}, core radius {field.core_radius:.4g})"
    if not spec.endswith(".npy"):
        raise UsageError(f"--velocity must be one of {', '.join(DEMOS)} or a .npy file, got {spec!r}"
                         f"{did_you_mean(spec, DEMOS)}")
    if not os.path.isfile(spec):
        raise UsageError(f"{spec}: no such file")
    try:
        arr = np.load(spec, allow_pickle=False)
    except (ValueError, OSError) as exc:
        raise UsageError(f"{spec}: not a readable .npy array ({exc})") from None
    return arr, f"{spec} (per-vertex)"  # checked against the mesh's rows by vortex_filaments


def _outputs(plan, result, meta, velocity=None) -> None:
    """Write the files of ``plan`` (all or none); :attr:`OutputPlan.written` lists them."""
    with plan.writing() as stage:
        for ext in (".obj", ".ply"):
            if plan.wants(ext):
                (write_polylines_ply if ext == ".ply" else write_polylines_obj)(stage(ext), result.filaments)
        if plan.wants(".vtu"):
            from dhlb.io.paraview import vortex_to_vtu

            vortex_to_vtu(result, stage(".vtu"), velocity)
        if plan.wants(".json"):
            with open(stage(".json"), "w", encoding="utf-8") as fh:
                json.dump({**meta, **result.to_json()}, fh, indent=1)
        if plan.wants(".png"):
            from dhlb.render._figure import plural
            from dhlb.render.filaments_png import render_filaments_png

            title = f"{meta['velocity']}, ħ = {meta['hbar']:g}: {plural(len(result.filaments), 'filament')}"
            mesh = result.mesh
            render_filaments_png(stage(".png"), result.filaments, mesh.points, mesh.boundary_faces, title=title)


def format_report(meta: dict, data: dict) -> str:
    """Human-readable summary of a run (``meta``: mesh/velocity/hbar; ``data``: :meth:`VortexResult.to_json`)."""
    s, t = data["statistics"], data["timings"]
    lens = [len(f["points"]) for f in data["filaments"]]
    Lk = data["linking_numbers"]
    idx = data["linking_index"]
    pairs = [f"#{idx[a]}-#{idx[b]}: {Lk[a][b]}" for a in range(len(Lk)) for b in range(a + 1, len(Lk)) if Lk[a][b]]
    rows = [
        ("mesh", f"{meta['mesh']} ({s['n_vertices']} vertices, {s['n_tets']} tetrahedra)"),
        ("velocity", meta["velocity"]),
        ("hbar", f"{meta['hbar']:g}"),
        ("filaments", f"{s['n_filaments']} ({s['n_closed']} closed, {s['n_open']} open; points {lens})"),
        ("linking", ", ".join(pairs) if pairs else "none"),
        ("eigenvalue", f"{data['eigenvalue']:.6g}"),
        ("max flux", f"{s['max_flux']:.3g} per triangle ({s['n_unresolved_faces']} triangles above pi)"),
        ("crossed faces", f"{s['n_crossed_faces']}; tets by crossed faces {s['tets_by_crossed_faces']}"),
        ("solver", (f"{s['solver']['backend']}, {s['solver']['iterations']} iterations, "
                    f"backward error {s['solver']['residual']:.2g}")),
    ]
    return report_table(rows, timings=t, written=meta.get("written"))


def _run_distributed(args):
    """``dhlb vortex --backend petsc``: rank 0 builds or reads the mesh and the velocity, all ranks compute.

    Returns ``(result, mesh name, velocity name, velocity)``; the result is None on ranks other than 0.
    """
    from dhlb.linalg import SolverOptions
    from dhlb.mesh.distribute import root_first, world
    from dhlb.vortex import VortexOptions
    from dhlb.vortex.distributed import distributed_vortex_filaments

    comm = world()
    if args.mesh is None and args.velocity in DEMOS:  # --box: every rank builds its own slab, nothing is sent
        from dhlb.mesh.distribute import distribute_box
        from dhlb.mesh.tet import VORTEX_BYTES_PER_CELL, check_box_memory

        n = 12 if args.box is None else args.box
        try:  # the memory of the whole run over all ranks, estimated before any work
            check_box_memory(n, per_cell=VORTEX_BYTES_PER_CELL, name="--box")
        except ResourceLimitError as exc:
            raise UsageError(str(exc)) from None
        velocity, vname = _velocity(args, None, None)
        loc = distribute_box(n, -1.0, 1.0, comm=comm)
        result = distributed_vortex_filaments(loc, None, velocity, args.hbar, options=VortexOptions(order=args.order),
                                              solver=SolverOptions(tol=args.tol), comm=comm)
        return result, f"box {n}", vname, velocity

    def read():
        V, T, name = _mesh(args)
        velocity, vname = _velocity(args, V, T)
        return V, T, name, velocity, vname

    got = root_first(read, comm, what="dhlb vortex")
    V, T, name, velocity, vname = got if comm.rank == 0 else (None,) * 5
    # a velocity field v(x) is needed on every rank; per-vertex velocities travel with the mesh
    shared = comm.bcast((name, vname, velocity if callable(velocity) else None), root=0)
    name, vname = shared[:2]
    if comm.rank != 0:
        velocity = shared[2]
    result = distributed_vortex_filaments(V, T, velocity, args.hbar, options=VortexOptions(order=args.order),
                                          solver=SolverOptions(tol=args.tol), comm=comm)
    return result, name, vname, velocity


def run(args) -> int:
    """Entry point of ``dhlb vortex``."""
    from dhlb.linalg import SolverOptions
    from dhlb.vortex import VortexOptions, vortex_filaments

    plan = output_plan(OUTPUTS, args)  # before the computation; never over the mesh or the velocity file
    if args.backend == "petsc":
        result, mesh_name, vname, velocity = _run_distributed(args)
        if result is None:  # ranks other than 0: rank 0 writes and prints
            return 0
    else:
        V, T, mesh_name = _mesh(args)
        velocity, vname = _velocity(args, V, T)
        result = vortex_filaments(V, T, velocity, args.hbar, options=VortexOptions(order=args.order),
                                  solver=SolverOptions(backend=args.backend, tol=args.tol),
                                  progress=not (args.quiet or args.json))
    meta = {"mesh": mesh_name, "velocity": vname, "hbar": float(args.hbar)}
    if plan:
        _outputs(plan, result, meta, velocity)
        meta["written"] = plan.written
    data = result.to_json()
    text = json.dumps({**data, **meta}, indent=1) if args.json else format_report(meta, data)
    print(text)
    return 0
