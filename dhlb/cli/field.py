"""``dhlb field``: the globally optimal n-direction field of a triangle mesh (smoothest or aligned).

For a base name OUT (:data:`OUTPUTS`) writes ``OUT.ply`` (the mesh with the n unit directions as vertex
properties ``d{k}x d{k}y d{k}z``), ``OUT.npz`` (``u``, ``directions``, ``frames``, ``face_index`` and the
singularities, all in the input numbering: rows of the file's vertices and faces), ``OUT.json`` (the
summary of :meth:`dhlb.fields.DirectionField.to_json` plus output timings) and ``OUT.png`` (the shaded
mesh, direction glyphs, singularities red (+) / blue (−)); ``-o OUT.EXT`` writes that one file
(``.vtu``: ParaView).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time

import numpy as np

from dhlb.cli._common import (
    UsageError,
    add_command,
    add_repair_argument,
    backend_choice,
    did_you_mean,
    finite_float,
    int_in_range,
    resolve_input,
    write_output,
)
from dhlb.cli._outputs import OutputSpec, output_plan

__all__ = ["NAME", "OUTPUTS", "SUMMARY", "index_sum_label", "read_alignment", "parse_singularity", "register", "run",
           "write_field"]

NAME = "field"
MAX_N = 1000
"""The largest symmetry ``--n`` accepted."""
SUMMARY = "smoothest or aligned n-direction field of a triangle mesh, its singularities and a picture"

_DESCRIPTION = """\
Compute the globally optimal n-direction field of an oriented triangle mesh (.obj .off .ply):
the smoothest field for the energy E_s = E_D - s (E_A - E_H) (s = 0 Dirichlet, +1 holomorphic,
-1 anti-holomorphic), or with --align a field aligned to principal curvature (even n), to the
boundary, or to user vectors. Unreferenced vertices are dropped with a warning; each connected
component gets its own field. Defects other tools repair routinely (a non-manifold vertex or
edge, duplicate faces, a doubled sheet, a zero-area face, faces oriented inconsistently) are
repaired, one warning line each, and every output is given on the rows of the input file;
--repair none refuses them instead.

Outputs (-o, see below): OUT.ply (mesh + directions as vertex properties), OUT.npz (u,
directions, frames, face_index, singularities), OUT.json (singularities, index sum, Euler
characteristic, eigenvalue, timings) and OUT.png (picture). --json prints the summary (with no -o,
the summary alone: no files).

With --singularity (repeatable) the field has exactly the given singularities instead
(dualised trivial connections, dhlb.fields.prescribed_field): FACE:K puts index K/n on the
face with row FACE of the file, x,y,z:K on the face nearest to the point; K is an integer in
{-1, 0, 1} per face and on a closed surface the K sum to n * chi (Poincare-Hopf)."""

_EXAMPLES = """\
  dhlb field bunny.obj --n 4 -o bunny-cross            # smoothest cross field
  dhlb field kitten.obj --n 2 --s 1 --align curvature --lambda 0 -o kitten
  dhlb field part.off --n 4 --align boundary -o part --json
  dhlb field face.ply --n 1 --align guide.npy -o face   # guide.npy: (k, 3) vectors or complex (k,)
  dhlb field spot.obj --n 1 --singularity 0:1 --singularity 3000:1 -o spot-two
  dhlb field torus.obj --n 4 --singularity 0.5,0,1.2:1 --singularity 12:-1 -o torus-pair"""

_ALIGN = ("curvature", "min-curvature", "boundary", "boundary-normal")

OUTPUTS = OutputSpec(NAME, (".ply", ".npz", ".json", ".png"), {
    ".ply": "the mesh (input rows) with the directions as vertex properties",
    ".npz": "u, directions, frames, face_index, singularities (input rows)",
    ".json": "the summary: singularities, index sum, eigenvalue, timings",
    ".png": "the picture",
    ".vtu": "the mesh with directions and face indices, for ParaView",
}, switches={".png": "no_png"})
"""What ``dhlb field -o`` writes."""


def register(subparsers) -> None:
    """Add the ``field`` parser to ``subparsers``."""
    p = add_command(subparsers, NAME, SUMMARY, _DESCRIPTION, _EXAMPLES, outputs=OUTPUTS)
    p.add_argument("mesh", metavar="MESH", help="triangle mesh file (.obj, .off, .ply)")
    p.add_argument("--n", type=int_in_range(1, MAX_N), default=1,
                   help=f"symmetry: 1 vector, 2 line, 4 cross field, ... up to {MAX_N} (default 1)")
    p.add_argument("--s", type=finite_float(-1, 1), default=0.0,
                   help="energy parameter in [-1, 1] (default 0, Dirichlet)")
    p.add_argument("--align", metavar="WHAT",
                   help=f"alignment: {', '.join(_ALIGN)}, or a .npy file of (k, 3) vectors or complex (k,) values")
    p.add_argument("--lambda", dest="lam", type=float, default=0.0,
                   help="lambda_t of the aligned problem, below the smallest eigenvalue (default 0)")
    p.add_argument("--singularity", action="append", type=parse_singularity, metavar="FACE:K | x,y,z:K",
                   help="prescribe index K/n at a face (row of the file) or at the face nearest to a point; "
                        "repeatable; the result has exactly these singularities (write --singularity=-1,0,0:1 "
                        "when x is negative)")
    p.add_argument("--backend", type=backend_choice, default=None,
                   help="superlu, cholmod, cholespy, amg-lobpcg (default: by size, memory); petsc: distributed "
                        "over the ranks of mpirun (docs/mpi.md)")
    add_repair_argument(p)
    p.add_argument("--reorient", action="store_true",
                   help="flip inconsistently oriented faces (with --repair none; the default repairs do it)")
    p.add_argument("--format", dest="fmt", metavar="FMT", help="file format if the extension does not say it")
    p.add_argument("--no-png", action="store_true", help="do not render OUT.png")
    p.set_defaults(func=run)


def read_alignment(value):
    """The ``align`` argument of :func:`dhlb.fields.direction_field` for ``--align VALUE``.

    Examples
    --------
    >>> read_alignment("curvature"), read_alignment(None)
    ('curvature', None)
    """
    if value is None or value in _ALIGN:
        return value
    if not value.endswith(".npy"):
        raise UsageError(f"--align must be one of {', '.join(_ALIGN)} or a .npy file, got {value!r}"
                         f"{did_you_mean(value, _ALIGN)}")
    if not os.path.isfile(value):
        raise UsageError(f"{value}: no such file")
    try:
        arr = np.load(value, allow_pickle=False)
    except (OSError, ValueError) as exc:
        raise UsageError(f"{value}: not a readable .npy array ({exc})") from None
    return arr


def parse_singularity(text: str) -> tuple:
    """One ``--singularity`` value ``FACE:K`` or ``x,y,z:K`` as a key and index of :func:`dhlb.fields.prescribed_field`.

    An argparse ``type``: a malformed value, a negative face or a non-finite coordinate is a usage
    error (exit 2) naming the option; a face past the mesh is refused by the library (exit 1).

    Examples
    --------
    >>> parse_singularity("3:1"), parse_singularity("0.5,0,1:-1")
    ((3, 1), ((0.5, 0.0, 1.0), -1))
    >>> parse_singularity("nan,0,0:1")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: 'nan,0,0:1': the location must be a face number or three finite coordinates x,y,z
    """
    where, sep, k = text.rpartition(":")
    try:
        index = int(k)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: the index K after ':' must be an integer") from None
    if not sep or not where:
        raise argparse.ArgumentTypeError(f"{text!r}: expected FACE:K or x,y,z:K")
    parts = where.split(",")
    try:
        if len(parts) == 1 and int(parts[0]) >= 0:
            return int(parts[0]), index
        if len(parts) == 3:
            p = tuple(float(c) for c in parts)
            if all(np.isfinite(p)):
                return p, index
    except ValueError:
        pass
    raise argparse.ArgumentTypeError(f"{text!r}: the location must be a face number or three finite coordinates x,y,z")


def write_field(out: str, res, V, F, *, png: bool = True, kinds=None) -> dict:
    """Write the files of ``dhlb field`` for the field ``res`` under the base path ``out``.

    Parameters
    ----------
    out : str
        The base path (without extension).
    res : DirectionField
        The field.
    V : (n, 3) float array
        The input vertices.
    F : (m, 3) int array
        The input faces.
    png : bool
        Also draw ``OUT.png`` (when ``kinds`` is not given).
    kinds : sequence of str, optional
        The suffixes to write among ``.ply``, ``.npz`` (:func:`dhlb.io.results.write_field_files`),
        ``.png`` and ``.vtu``; default ``.ply``, ``.npz`` and, with ``png``, ``.png``.

    Returns
    -------
    dict
        Kind → path (``ply``, ``npz``, ``json`` — the JSON is written by :func:`run` — ``png``, ``vtu``).

    Examples
    --------
    >>> import os, tempfile
    >>> from dhlb.io import read_surface, example_path
    >>> from dhlb.fields import direction_field
    >>> V, F = read_surface(example_path("torus.obj"))
    >>> with tempfile.TemporaryDirectory() as d:
    ...     paths = write_field(os.path.join(d, "t"), direction_field(V, F, n=2), V, F, png=False)
    ...     sorted(os.path.basename(p) for p in paths.values() if os.path.exists(p))
    ['t.npz', 't.ply']
    """
    from dhlb.io.results import _field_ply, write_field_files, write_field_npz

    kinds = set((".ply", ".npz") + ((".png",) if png else ()) if kinds is None else kinds)
    paths = {"json": out + ".json"}
    if {".ply", ".npz"} <= kinds:
        paths.update(write_field_files(out, res, V, F))
    elif ".ply" in kinds:
        paths["ply"] = _field_ply(out + ".ply", res, V, F)
    elif ".npz" in kinds:
        paths["npz"] = write_field_npz(out + ".npz", res)
    if ".png" in kinds:
        from dhlb.render import render_field_png

        mesh = res.mesh
        paths["png"] = render_field_png(out + ".png", mesh.points, mesh.faces, res.directions, res.singularities,
                                        title=f"n = {res.n}, s = {res.s:g}, index sum {res.index_sum}")
    if ".vtu" in kinds:
        from dhlb.io.paraview import field_to_vtu

        paths["vtu"] = field_to_vtu(res, out + ".vtu")
    return paths


def index_sum_label(res) -> str:
    """What the index sum of the field ``res`` equals: ``nχ`` on a closed mesh, ``(ΣΩ + rotation)/2π`` otherwise.

    With boundary the sum is not ``nχ``: it is the total curvature plus the turning of the field along
    the boundary, over 2π (the row "boundary" of ``dhlb demo``).

    Examples
    --------
    >>> from dhlb.io import read_surface, example_path
    >>> from dhlb.fields import direction_field
    >>> index_sum_label(direction_field(*read_surface(example_path("torus.obj")), n=4))
    'Σ index = 0 = nχ = 4·0'
    """
    if res.mesh.is_closed:
        return f"Σ index = {res.index_sum} = nχ = {res.n}·{res.euler_characteristic}"
    return f"Σ index = {res.index_sum} = (ΣΩ + rotation)/2π = {res.poincare_hopf:.6f} (a mesh with boundary)"


def run(args) -> int:
    """Entry point of ``dhlb field``."""
    from dhlb.fields import FieldOptions, direction_field, prescribed_field
    from dhlb.io import read_surface

    t0 = time.perf_counter()
    fmt = resolve_input(args.mesh, args.fmt)  # every surface read_surface reads (also via meshio); see below
    plan = output_plan(OUTPUTS, args)  # before any work: the extension, the folder, the inputs, meshio
    if not plan and not args.json:   # nothing would be written and nothing printed that a script could read
        raise UsageError(f"give the output with -o OUT ({OUTPUTS.help()}), or --json for the summary alone")
    align = read_alignment(args.align)
    sing = args.singularity or []
    if args.singularity and (align is not None or args.s != 0.0):
        raise UsageError("--singularity prescribes the field; it does not combine with --align or --s")
    if args.backend == "petsc" and not sing and align is None:  # the smoothest field under MPI: distributed
        return _run_distributed(args, fmt, plan, t0)
    V, F = read_surface(args.mesh, fmt)
    t1 = time.perf_counter()
    for where, k in sing:   # a face number is checked against the file before any work (a usage error)
        if isinstance(where, int) and where >= len(F):
            raise UsageError(f"argument --singularity: {where}:{k}: face {where} is out of range; {args.mesh} has "
                             f"{len(F)} faces (rows 0 .. {len(F) - 1})")
    if args.singularity:
        res = prescribed_field(V, F, args.n, sing, options=FieldOptions(reorient=args.reorient, repair=args.repair),
                               solver=args.backend)
    else:
        res = direction_field(V, F, n=args.n, s=args.s, align=align, lam=args.lam, solver=args.backend,
                              options=FieldOptions(reorient=args.reorient, progress=not (args.quiet or args.json),
                                                   repair=args.repair))
    t2 = time.perf_counter()
    return _report(args, res, V, F, plan, t0, t1, t2)


def _run_distributed(args, fmt, plan, t0) -> int:
    """``dhlb field --backend petsc``: rank 0 reads the mesh, all ranks compute, rank 0 writes and prints."""
    from dhlb.fields import FieldOptions
    from dhlb.fields.distributed import distributed_direction_field
    from dhlb.io import read_surface
    from dhlb.mesh.distribute import root_first, world

    comm = world()
    VF = root_first(lambda: read_surface(args.mesh, fmt), comm, what=f"reading {args.mesh}")
    V, F = VF if comm.rank == 0 else (None, None)
    t1 = time.perf_counter()
    from dhlb.errors import (
        DegenerateSimplexError,
        InconsistentOrientationError,
        InvalidSimplexError,
        NonManifoldError,
    )

    try:
        res = distributed_direction_field(V, F, n=args.n, s=args.s, options=FieldOptions(reorient=args.reorient),
                                          comm=comm)
    except (NonManifoldError, DegenerateSimplexError, InvalidSimplexError, InconsistentOrientationError) as exc:
        if args.repair == "none":
            raise
        raise type(exc)(f"{exc}. The distributed field (--backend petsc) does not repair meshes: run dhlb field "
                        "without --backend petsc, which repairs it (--repair), or repair the mesh first") from None
    t2 = time.perf_counter()
    if res is None:  # ranks other than 0: rank 0 writes and prints
        return 0
    return _report(args, res, V, F, plan, t0, t1, t2)


def _report(args, res, V, F, plan, t0, t1, t2) -> int:
    """Write the outputs of ``dhlb field`` and print its summary."""
    note = (getattr(res, "solver", None) or {}).get("note")
    if note and not args.quiet:
        print(f"dhlb field: note: {note}", file=sys.stderr)
    summary = res.to_json()
    summary["files"] = {s.lstrip("."): plan.path(s) for s in plan.suffixes}
    summary["input"] = args.mesh
    if not plan:   # --json without -o: the summary alone
        t3 = time.perf_counter()
        summary["timings"] = dict(summary["timings"], io=t1 - t0, output=t3 - t2, end_to_end=t3 - t0)
    else:
        with plan.writing() as stage:  # all files or none
            write_field(stage(""), res, V, F, kinds=[s for s in plan.suffixes if s != ".json"])
            t3 = time.perf_counter()
            summary["timings"] = dict(summary["timings"], io=t1 - t0, output=t3 - t2, end_to_end=t3 - t0)
            if plan.wants(".json"):
                with open(stage(".json"), "w", encoding="utf-8") as fh:
                    json.dump(summary, fh, indent=2)
    if args.json:
        args.output = None  # the summary goes to stdout; -o named the output files
        write_output(args, json.dumps(summary, indent=2))
    elif not args.quiet:
        s = summary
        print(f"{args.mesh}: {s['n_vertices']} vertices, {s['n_faces']} faces, χ = {s['euler_characteristic']}; "
              f"n = {s['n']}, s = {s['s']:g}: {len(s['singularities'])} singularities, {index_sum_label(res)}; "
              f"wrote {', '.join(plan.written)}")
    return 0
