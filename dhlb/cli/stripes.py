"""``dhlb stripes``: a stripe pattern on a surface mesh → OBJ with per-corner UVs, JSON sidecar, isolines, PNG."""

from __future__ import annotations

import json
import os

import numpy as np

from dhlb.cli._common import (
    PIXEL_SIZE,
    UsageError,
    add_command,
    add_repair_argument,
    backend_choice,
    finite_float,
    int_in_range,
    resolve_input,
)
from dhlb.cli._outputs import OutputSpec, output_plan

__all__ = ["NAME", "OUTPUTS", "SUMMARY", "register", "run"]

NAME = "stripes"
SUMMARY = "stripe pattern along a direction field: OBJ with texture coordinates, isolines, PNG"

_DESCRIPTION = """\
Compute a stripe pattern (seed part 2) on a triangle surface mesh (.obj .off .ply): stripes
orthogonal to a direction field, with --frequency stripes per unit length or a period of
--spacing mean edge lengths. The field is the smoothest one (--field smoothest, default), the
principal curvature lines (--field curvature) or read from FILE (one 3D vector per vertex row,
text or .npy). --n 2 treats the directions as lines (branch points at their ±1/2 singularities);
the default is 2 for curvature and 1 otherwise.

--section unit (default) keeps the stripe spacing everywhere: after the smallest eigenvector it
iterates towards the unit-modulus section of least energy (the seed's energy of a unit function,
part 2 section 2.1), so parts of different girth get their own number of stripes, joined by
dislocations. --section eigenvector gives the relaxed eigenvector (the seed's pattern), --section
power the seed's Algorithm 9 (--iterations inverse power steps from a random start, --seed).
Defects of the mesh other tools repair routinely (non-manifold vertices and edges, duplicate
faces, doubled sheets, zero-area faces, inconsistent orientation) are repaired, one warning line
each (--repair, default safe; --repair none refuses them).
Parameters that scale the work (--frequency/--spacing for the isolines, --size) are checked
against a memory estimate before the work starts (exit 2 with the estimate and the allowed range).
No output may be the input mesh or field file.

Writes, for -o OUT (a base name; default: the mesh name with -stripes):
  OUT.obj           the mesh with one texture coordinate per face corner, u = alpha/2pi
  OUT.json          sidecar: zero faces (index, lArg interpolation) and branch faces (cone values)
  OUT-isolines.obj  the isolines alpha = 0 (mod 2pi) as polylines ('l' records)
  OUT.png           a rendering of cos(alpha), fine enough to show lArg and branch points
and with --orthogonal OUT-orthogonal.obj and .json. -o OUT.obj, OUT.png or OUT.vtu writes
that format only (see below). --json prints one JSON object (zero_faces as [{"face", "index"}] in input face rows,
branch_faces, timings, eigenvalue, solver, the written files)."""

_EXAMPLES = """\
  dhlb stripes bunny.obj --spacing 6 -o bunny-stripes
  dhlb stripes spot.obj --frequency 8 --field curvature --json
  dhlb stripes torus.off --spacing 5 --field dirs.txt --n 2 --orthogonal --no-png
  dhlb stripes vase.obj --spacing 6 --section eigenvector -o vase-relaxed"""


OUTPUTS = OutputSpec(NAME, (".obj", ".json", "-isolines.obj", ".png"), {
    ".obj": "the mesh with one texture coordinate per face corner",
    ".png": "the picture",
    ".vtu": "psi, the corner angles, zero and branch faces, for ParaView",
}, companions={".obj": (".json",)}, switches={".png": "no_png", "-isolines.obj": "no_isolines"})
"""What ``dhlb stripes -o`` writes (``--orthogonal`` adds ``OUT-orthogonal.obj/.json/.vtu``)."""


def register(subparsers) -> None:
    """Add the ``stripes`` parser to ``subparsers``."""
    p = add_command(subparsers, NAME, SUMMARY, _DESCRIPTION, _EXAMPLES, outputs=OUTPUTS)
    p.add_argument("file", metavar="MESH", help="triangle surface mesh (.obj .off .ply ...)")
    size = p.add_mutually_exclusive_group(required=True)
    size.add_argument("--frequency", type=finite_float(0, low_open=True), metavar="F",
                      help="stripes per unit length (period 1/F)")
    size.add_argument("--spacing", type=finite_float(0, low_open=True), metavar="S",
                      help="period in mean edge lengths (scale free)")
    p.add_argument("--field", default="smoothest", metavar="FIELD",
                   help="smoothest (default), curvature, or a FILE of per-vertex 3D vectors")
    p.add_argument("--n", type=int, choices=(1, 2), default=None, help="1: oriented directions, 2: lines")
    p.add_argument("--energy", choices=("cotan", "fem"), default="cotan",
                   help="the seed's cotangent energy (default) or the curvature-corrected FEM energy")
    p.add_argument("--section", choices=("unit", "eigenvector", "power"), default="unit",
                   help="unit (default): unit-modulus section after the eigenvector, keeps the spacing; "
                        "eigenvector: the relaxed eigenvector; power: the seed's Algorithm 9")
    p.add_argument("--iterations", type=int_in_range(0, MAX_ITERATIONS), default=None, metavar="K",
                   help="unit: maximum number of steps (default 200); power: number of steps (default 20)")
    p.add_argument("--energy-tol", type=finite_float(0), default=None, metavar="E",
                   help="unit: also stop when the unit energy changed by less than E (relative) over the last "
                        "5 steps (default 1e-3; 0: iterate to the fixed point)")
    p.add_argument("--seed", type=int_in_range(0, 2**63 - 1), default=None, help="random start of --section power")
    p.add_argument("--backend", type=backend_choice,
                   default=None, metavar="B", help="factorization backend (default: by size and memory)")
    p.add_argument("--orthogonal", action="store_true", help="also the pattern of the field turned by 90 degrees")
    p.add_argument("--format", dest="fmt", metavar="FMT", help="mesh format if the extension does not say it")
    add_repair_argument(p)
    p.add_argument("--no-png", action="store_true", help="do not render the PNG")
    p.add_argument("--no-isolines", action="store_true", help="do not write the isolines")
    p.add_argument("--level", type=float, default=0.0, help="isoline level c of alpha = c (mod 2pi), default 0")
    p.add_argument("--size", type=PIXEL_SIZE, default=800, metavar="PX", help="PNG size in pixels (default 800)")
    p.set_defaults(func=run)


def _directions(args, V, F, n):
    from dhlb.fields import FieldOptions, direction_field

    fld = args.field
    if fld in ("smoothest", "curvature"):
        if fld == "curvature" and n == 1:
            raise UsageError("--field curvature gives lines (principal directions have no orientation): use --n 2")
        return direction_field(V, F, n=n, align=None if fld == "smoothest" else "curvature", solver=args.backend,
                               options=FieldOptions(repair=args.repair))
    if not os.path.isfile(fld):
        raise UsageError(f"--field {fld}: not 'smoothest', 'curvature' or an existing file of per-vertex vectors")
    try:
        X = np.load(fld) if fld.lower().endswith(".npy") else np.loadtxt(fld, ndmin=2)
    except (OSError, ValueError) as exc:
        raise UsageError(f"--field {fld}: cannot read per-vertex vectors ({exc})") from None
    if X.ndim != 2 or X.shape[1] != 3:
        raise UsageError(f"--field {fld}: expected one 3D vector per line (shape (n, 3)), got shape {X.shape}")
    return X


MAX_ITERATIONS = 100_000
"""The most ``--iterations`` accepted."""
MAX_BYTES = 1_000_000_000
"""Memory budget of one ``dhlb stripes`` run's outputs (isolines, PNG), checked before the work."""


def _check_size(size):
    from dhlb.render._figure import PNG_BYTES_PER_PIXEL

    low = PIXEL_SIZE.bounds[0]
    est = size * size * PNG_BYTES_PER_PIXEL
    if est > MAX_BYTES:
        from dhlb.errors import ResourceLimitError

        allowed = int((MAX_BYTES / PNG_BYTES_PER_PIXEL) ** 0.5)
        raise ResourceLimitError("--size", size, est, MAX_BYTES, f"allowed: --size {low} to {allowed}")


def _check_density(args, V, F, n, plan):
    """Refuse a frequency whose isolines cannot fit in MAX_BYTES, before any solve.

    A lower estimate of the isoline work: every face is crossed about ``f · perimeter / 2`` times
    per level (zero faces, found only after the solve, add more; :func:`dhlb.stripes.isolines`
    checks the exact count before allocating).
    """
    if not plan.wants("-isolines.obj"):
        return
    from dhlb.errors import ResourceLimitError
    from dhlb.stripes.isolines import BYTES_PER_SEGMENT, BYTES_PER_SUBTRIANGLE

    P = np.asarray(V, float)
    T = np.asarray(F, np.int64)
    if P.ndim != 2 or T.ndim != 2 or T.shape[1] != 3 or T.size == 0 or T.min() < 0 or T.max() >= len(P):
        return  # the mesh checks of stripe_pattern report it
    e = np.linalg.norm(P[T[:, [1, 2, 0]]] - P[T], axis=2)
    if not np.all(np.isfinite(e)):
        return
    mean_edge = float(e.mean())
    f = args.frequency if args.frequency is not None else 1.0 / (args.spacing * mean_edge)
    levels = 1 if n == 1 or abs(np.sin(args.level)) < 1e-6 else 2
    crossings = levels * f * float(e.sum()) / 2.0
    est = len(T) * BYTES_PER_SUBTRIANGLE + crossings * BYTES_PER_SEGMENT
    if est > MAX_BYTES:
        f_ok = f * (MAX_BYTES - len(T) * BYTES_PER_SUBTRIANGLE) / (crossings * BYTES_PER_SEGMENT)
        if args.frequency is not None:
            name, value, advice = "--frequency", args.frequency, f"allowed: 0 < --frequency <= {f_ok:.3g} on this mesh"
        else:
            name, value = "--spacing", args.spacing
            advice = f"allowed: --spacing >= {1.0 / (max(f_ok, 1e-300) * mean_edge):.3g} mean edge lengths"
        raise ResourceLimitError(name, value, est, MAX_BYTES,
                                 f"{advice} (isolines of ~{crossings:.3g} crossings), or --no-isolines")


def _write_isolines(path, iso_list) -> int:
    from dhlb.io.polylines import write_lines_obj

    points, polylines, offset = [], [], 0
    for iso in iso_list:
        points.append(np.asarray(iso.points, dtype=float).reshape(-1, 3))
        polylines += [np.asarray(poly) + offset for poly in iso.polylines]
        offset += len(iso.points)
    write_lines_obj(path, np.concatenate(points) if points else np.zeros((0, 3)), polylines,
                    comment="dhlb stripe isolines: one 'l' polyline per isoline")
    return len(polylines)


def _outputs(res, plan, stage, args) -> dict:
    """Write the files of ``plan`` (to the temporary paths ``stage(suffix)``); return their final names."""
    from dhlb.io.stripes import write_stripes_obj
    from dhlb.stripes import isolines

    written = {}
    iso = None
    if plan.wants("-isolines.obj"):  # computed first: refused (memory) before any file is written
        iso = [isolines(res.texture, level=args.level, max_bytes=MAX_BYTES)]
        if res.orthogonal is not None:
            iso.append(isolines(res.orthogonal.texture, level=args.level, max_bytes=MAX_BYTES))
    if plan.wants(".obj"):
        write_stripes_obj(stage(".obj"), res.texture)
        written.update(obj=plan.path(".obj"), sidecar=plan.path(".json"))
    if iso is not None:
        written["isolines"] = plan.path("-isolines.obj")
        written["n_isolines"] = _write_isolines(stage("-isolines.obj"), iso)
    if plan.wants(".png"):
        from dhlb.render import Camera, StripeStyle, render_stripes_png

        render_stripes_png(stage(".png"), res.texture, camera=Camera(size=(args.size, args.size)),
                           style=StripeStyle(mark_singularities=True))
        written["png"] = plan.path(".png")
    if plan.wants(".vtu"):
        from dhlb.io.paraview import stripes_to_vtu

        written["vtu"] = plan.path(".vtu")
        stripes_to_vtu(res, stage(".vtu"))
    if res.orthogonal is not None and plan.wants("-orthogonal.obj"):
        write_stripes_obj(stage("-orthogonal.obj"), res.orthogonal.texture)
        written.update(orthogonal_obj=plan.path("-orthogonal.obj"), orthogonal_sidecar=plan.path("-orthogonal.json"))
    if res.orthogonal is not None and plan.wants("-orthogonal.vtu"):
        from dhlb.io.paraview import stripes_to_vtu

        written["orthogonal_vtu"] = plan.path("-orthogonal.vtu")
        stripes_to_vtu(res.orthogonal, stage("-orthogonal.vtu"))
    return written


_STOPPED = {"converged": " (converged: the iterate stopped moving)",
            "stalled": " (stopped: the unit energy changed by less than --energy-tol over the last 5 steps, while "
                       "dislocations may still creep; --energy-tol 0 iterates to the fixed point)",
            "limit": " (step limit, not converged: raise --iterations)"}


def _check_args(args) -> None:
    """The checks that involve two options (each value alone is checked by its argparse type)."""
    if args.iterations == 0 and args.section == "power":
        raise UsageError(f"--iterations must be between 1 and {MAX_ITERATIONS} for --section power, got 0")
    if not args.no_png:
        _check_size(args.size)


def run(args) -> int:
    """Entry point of ``dhlb stripes``."""
    from dhlb.errors import OverwriteError, ResourceLimitError

    try:
        return _run(args)
    except (ResourceLimitError, OverwriteError) as exc:  # a bad choice of parameters: usage error (exit 2)
        raise UsageError(str(exc)) from None


def _run(args) -> int:
    from dhlb.io import read_surface
    from dhlb.stripes import SectionOptions, StripeOptions, stripe_pattern

    fmt = resolve_input(args.file, args.fmt)
    _check_args(args)
    also = {".obj": ("-orthogonal.obj", "-orthogonal.json"), ".vtu": ("-orthogonal.vtu",)} if args.orthogonal else {}
    plan = output_plan(OUTPUTS, args, also=also,  # before any work; never over the mesh or the field file
                       default_base=os.path.splitext(os.path.basename(args.file))[0] + "-stripes")
    n = args.n if args.n is not None else (2 if args.field == "curvature" else 1)
    V, F = read_surface(args.file, fmt)
    _check_density(args, V, F, n, plan)
    directions = _directions(args, V, F, n)
    section = SectionOptions(kind=args.section, iterations=args.iterations, seed=args.seed,
                             **({} if args.energy_tol is None else {"energy_tol": args.energy_tol}))
    options = StripeOptions(energy=args.energy, orthogonal=args.orthogonal, progress=not (args.quiet or args.json),
                            section=section, repair=args.repair)
    res = stripe_pattern(V, F, directions, args.frequency, spacing=args.spacing, n=n, options=options,
                         solver=args.backend)
    with plan.writing() as stage:  # all files or none
        written = _outputs(res, plan, stage, args)
    summary = res.to_json()
    summary["files"] = written
    summary["mesh"] = args.file
    if args.json:
        print(json.dumps(summary))
    elif not args.quiet:
        t = summary["timings"]
        print(f"{args.file}: {summary['n_vertices']} vertices, {summary['n_faces']} faces; n = {summary['n']}, "
              f"energy {summary['energy']}, eigenvalue {summary['eigenvalue']:.6g}")
        it = summary["iteration"]
        steps = ""
        if it:
            steps = f" after {it['iterations']} steps"
            if it["kind"] == "unit":
                steps += _STOPPED[it["stopped"]]
        print(f"section {summary['section']}{steps}: unit energy {summary['unit_energy']:.6g}")
        print(f"zeros: {len(summary['zero_faces'])} faces, branch faces: {len(summary['branch_faces'])}")
        print(f"time: setup {t['setup']:.3f} s, solve {t['solve']:.3f} s, texture {t['texture']:.3f} s")
        print("wrote " + ", ".join(plan.written))
    return 0
