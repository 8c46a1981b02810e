"""``dhlb stripes``: a stripe pattern on a surface mesh → OBJ with per-corner UVs, JSON sidecar, isolines, PNG."""

from __future__ import annotations

import json
import os

import numpy as np

from dhlb.commands._common import UsageError, add_command, resolve_input

__all__ = ["NAME", "SUMMARY", "register", "run", "output_paths"]

NAME = "stripes"
SUMMARY = "stripe pattern along a direction field: OBJ with texture coordinates, isolines, PNG"

_DESCRIPTION = """\
Compute a stripe pattern (seed part 2) on a triangle surface mesh (.obj .off .ply): stripes
orthogonal to a direction field, with --frequency stripes per unit length or a period of
--spacing mean edge lengths. The field is the smoothest one (--field smoothest, default), the
principal curvature lines (--field curvature) or read from FILE (one 3D vector per vertex row,
text or .npy). --n 2 treats the directions as lines (branch points at their ±1/2 singularities);
the default is 2 for curvature and 1 otherwise.

Writes, for -o OUT (default: the mesh name with -stripes):
  OUT.obj           the mesh with one texture coordinate per face corner, u = alpha/2pi
  OUT.json          sidecar: zero faces (index, lArg interpolation) and branch faces (cone values)
  OUT-isolines.obj  the isolines alpha = 0 (mod 2pi) as polylines ('l' records)
  OUT.png           a rendering of cos(alpha), fine enough to show lArg and branch points
--json prints one JSON object (zero_faces as [{"face", "index"}] in input face rows,
branch_faces, timings, eigenvalue, solver, the written files)."""

_EXAMPLES = """\
  dhlb stripes bunny.obj --spacing 6 -o bunny-stripes
  dhlb stripes spot.obj --frequency 8 --field curvature --json
  dhlb stripes torus.off --spacing 5 --field dirs.txt --n 2 --orthogonal --no-png"""


def register(subparsers) -> None:
    """Add the ``stripes`` parser to ``subparsers``."""
    p = add_command(subparsers, NAME, SUMMARY, _DESCRIPTION, _EXAMPLES)
    p.add_argument("file", metavar="MESH", help="triangle surface mesh (.obj .off .ply ...)")
    size = p.add_mutually_exclusive_group(required=True)
    size.add_argument("--frequency", type=float, metavar="F", help="stripes per unit length (period 1/F)")
    size.add_argument("--spacing", type=float, metavar="S", help="period in mean edge lengths (scale free)")
    p.add_argument("--field", default="smoothest", metavar="FIELD",
                   help="smoothest (default), curvature, or a FILE of per-vertex 3D vectors")
    p.add_argument("--n", type=int, choices=(1, 2), default=None, help="1: oriented directions, 2: lines")
    p.add_argument("--energy", choices=("cotan", "fem"), default="cotan",
                   help="the seed's cotangent energy (default) or the curvature-corrected FEM energy")
    p.add_argument("--backend", default=None, metavar="B", help="factorization backend (default superlu)")
    p.add_argument("--orthogonal", action="store_true", help="also the pattern of the field turned by 90 degrees")
    p.add_argument("--format", dest="fmt", metavar="FMT", help="mesh format if the extension does not say it")
    p.add_argument("--no-png", action="store_true", help="do not render the PNG")
    p.add_argument("--no-isolines", action="store_true", help="do not write the isolines")
    p.add_argument("--level", type=float, default=0.0, help="isoline level c of alpha = c (mod 2pi), default 0")
    p.add_argument("--size", type=int, default=800, metavar="PX", help="PNG size in pixels (default 800)")
    p.set_defaults(func=run)


def output_paths(base: str) -> dict:
    """The files written for the output base ``base`` (a trailing ``.obj`` is dropped)."""
    if base.lower().endswith(".obj"):
        base = base[:-4]
    return {"obj": base + ".obj", "sidecar": base + ".json", "isolines": base + "-isolines.obj", "png": base + ".png"}


def _directions(args, V, F, n):
    from dhlb.surface import direction_field

    fld = args.field
    if fld in ("smoothest", "curvature"):
        if fld == "curvature" and n == 1:
            raise UsageError("--field curvature gives lines (principal directions have no orientation): use --n 2")
        return direction_field(V, F, n=n, align=None if fld == "smoothest" else "curvature", backend=args.backend)
    if not os.path.isfile(fld):
        raise UsageError(f"--field {fld}: not 'smoothest', 'curvature' or an existing file of per-vertex vectors")
    try:
        X = np.load(fld) if fld.lower().endswith(".npy") else np.loadtxt(fld, ndmin=2)
    except (OSError, ValueError) as exc:
        raise UsageError(f"--field {fld}: cannot read per-vertex vectors ({exc})") from None
    if X.ndim != 2 or X.shape[1] != 3:
        raise UsageError(f"--field {fld}: expected one 3D vector per line (shape (n, 3)), got shape {X.shape}")
    return X


def _write_isolines(path, iso_list) -> int:
    lines = ["# dhlb stripe isolines: one 'l' polyline per isoline"]
    offset, count = 0, 0
    for iso in iso_list:
        lines += [f"v {p[0]:.17g} {p[1]:.17g} {p[2]:.17g}" for p in iso.points]
        for poly in iso.polylines:
            lines.append("l " + " ".join(str(int(i) + 1 + offset) for i in poly))
            count += 1
        offset += len(iso.points)
    with open(path, "w", encoding="utf-8") as fh:
        fh.write("\n".join(lines) + "\n")
    return count


def _outputs(res, paths, args) -> dict:
    from dhlb.stripes import isolines, write_stripes_obj

    written = {}
    obj, side = write_stripes_obj(paths["obj"], res.texture)
    written.update(obj=obj, sidecar=side)
    if not args.no_isolines:
        iso = [isolines(res.texture, level=args.level)]
        if res.orthogonal is not None:
            iso.append(isolines(res.orthogonal.texture, level=args.level))
        written["isolines"] = paths["isolines"]
        written["n_isolines"] = _write_isolines(paths["isolines"], iso)
    if not args.no_png:
        from dhlb.render.stripes_png import render_stripes_png

        written["png"] = render_stripes_png(paths["png"], res.texture, size=(args.size, args.size),
                                            mark_singularities=True)
    if res.orthogonal is not None:
        o = output_paths(paths["obj"][:-4] + "-orthogonal")
        written["orthogonal_obj"], written["orthogonal_sidecar"] = write_stripes_obj(o["obj"], res.orthogonal.texture)
    return written


def run(args) -> int:
    """Entry point of ``dhlb stripes``."""
    from dhlb.io import read_surface
    from dhlb.stripes import stripe_pattern

    fmt = resolve_input(args.file, args.fmt)
    for name in ("frequency", "spacing"):
        v = getattr(args, name)
        if v is not None and not (np.isfinite(v) and v > 0):
            raise UsageError(f"--{name} must be a positive number, got {v}")
    base = args.output or os.path.splitext(os.path.basename(args.file))[0] + "-stripes"
    paths = output_paths(base)
    n = args.n if args.n is not None else (2 if args.field == "curvature" else 1)
    V, F = read_surface(args.file, fmt)
    directions = _directions(args, V, F, n)
    res = stripe_pattern(V, F, directions, args.frequency, spacing=args.spacing, n=n, energy=args.energy,
                         backend=args.backend, orthogonal=args.orthogonal)
    written = _outputs(res, paths, args)
    summary = res.to_json()
    summary["files"] = written
    summary["mesh"] = args.file
    if args.json:
        print(json.dumps(summary))
    elif not args.quiet:
        t = summary["timings"]
        print(f"{args.file}: {summary['n_vertices']} vertices, {summary['n_faces']} faces; n = {summary['n']}, "
              f"energy {summary['energy']}, eigenvalue {summary['eigenvalue']:.6g}")
        print(f"zeros: {len(summary['zero_faces'])} faces, branch faces: {len(summary['branch_faces'])}")
        print(f"time: setup {t['setup']:.3f} s, solve {t['solve']:.3f} s, texture {t['texture']:.3f} s")
        print("wrote " + ", ".join(str(v) for k, v in written.items() if isinstance(v, str)))
    return 0
