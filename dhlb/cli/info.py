"""``dhlb info``: counts, Euler characteristic, manifoldness, orientability, boundary and homology of a file."""

from __future__ import annotations

import json

import numpy as np

from dhlb.cli._common import UsageError, add_command, check_output_file, report_table, resolve_input, write_output
from dhlb.errors import DhlbError, EmptyComplexError

__all__ = ["NAME", "SUMMARY", "register", "run", "describe", "format_report"]

NAME = "info"
SUMMARY = "topology of a mesh or simplex list: counts, Euler characteristic, boundary, homology"

_DESCRIPTION = """\
Read a mesh (.obj .off .ply .mesh .msh .vtk) or a plain text simplex list (.txt .simplices:
one simplex per line, integer vertex labels, '#' comments) and report the number of simplices
of each dimension, the Euler characteristic, connected components, whether the complex is a
manifold and orientable, its boundary (number of boundary faces and their components) and its
integer homology groups with torsion.

Without FILE, the bundled example torus.obj (a triangulated torus) is used; --example picks
another bundled mesh."""

_EXAMPLES = """\
  dhlb info                           # the bundled torus
  dhlb info --example solid-torus.mesh
  dhlb info bunny.off
  dhlb info hand.mesh --json -o hand-info.json
  dhlb info complex.dat --format simplices --no-homology"""

_SIMPLEX_NAMES = {0: ("vertex", "vertices"), 1: ("edge", "edges"), 2: ("triangle", "triangles"),
                  3: ("tetrahedron", "tetrahedra")}  # fmt: skip


def _count(n: int, k: int) -> str:
    """``"1 triangle"``, ``"2 triangles"``, ``"3 4-simplices"``."""
    one, many = _SIMPLEX_NAMES.get(k, (f"{k}-simplex", f"{k}-simplices"))
    return f"{n} {one if n == 1 else many}"


def register(subparsers) -> None:
    """Add the ``info`` parser to ``subparsers``."""
    from dhlb.io.examples import EXAMPLES

    p = add_command(subparsers, NAME, SUMMARY, _DESCRIPTION, _EXAMPLES)
    p.add_argument("file", nargs="?", metavar="FILE", help="mesh or simplex-list file (default: bundled torus.obj)")
    p.add_argument(
        "--example", choices=sorted(EXAMPLES), metavar="NAME",
        help=f"use a bundled example instead of FILE ({', '.join(sorted(EXAMPLES))})",
    )  # fmt: skip
    p.add_argument(
        "--format", dest="fmt", metavar="FMT",
        help="file format if the extension does not say it (obj, off, ply, mesh, msh, vtk, simplices)",
    )  # fmt: skip
    p.add_argument("--no-homology", action="store_true", help="skip the homology computation (large complexes)")
    p.set_defaults(func=run)


def run(args) -> int:
    """Entry point of ``dhlb info``."""
    from dhlb.io import example_path, load

    if args.file is not None and args.example is not None:
        raise UsageError("give either FILE or --example, not both")
    path = args.file if args.file is not None else example_path(args.example or "torus.obj")
    fmt = resolve_input(path, args.fmt)
    check_output_file(args)   # before the work: a missing folder is a usage error (exit 2)
    info = describe(load(path, fmt), homology=not args.no_homology)
    write_output(args, json.dumps(info, indent=2) if args.json else format_report(info))
    return 0


def _component_count(labels) -> int:
    """Number of components from :meth:`SimplicialComplex.connected_components`.

    Accepts its ``(count, labels)`` result, a bare count or a label per vertex.
    """
    if isinstance(labels, tuple) and len(labels) == 2 and isinstance(labels[0], (int, np.integer)):
        return int(labels[0])
    if isinstance(labels, (int, np.integer)):
        return int(labels)
    return int(np.unique(np.asarray(labels)).size)


def _maybe(fn):
    """``fn()`` as a plain bool, or None when the property is undefined for this complex."""
    try:
        return bool(fn())
    except DhlbError:
        return None


def _boundary(X):
    """{"faces": number of boundary (dim-1)-simplices, "components": their connected components}."""
    if X.dim == 0:
        return {"faces": 0, "components": 0}
    try:
        B = X.boundary_complex()
    except EmptyComplexError:
        return {"faces": 0, "components": 0}
    except DhlbError:
        return None
    if B is None or B.n_vertices == 0 or B.dim < X.dim - 1:
        return {"faces": 0, "components": 0}
    return {"faces": int(B.n_simplices(X.dim - 1)), "components": _component_count(B.connected_components())}


def describe(mesh, homology: bool = True) -> dict:
    """The facts ``dhlb info`` reports, as a JSON-ready dict.

    Parameters
    ----------
    mesh : dhlb.io.MeshData
    homology : bool
        Compute the integer homology (``None`` in the result otherwise).

    Returns
    -------
    dict
        ``file``, ``format``, ``kind``, ``dim``, ``counts`` (simplices per dimension),
        ``euler_characteristic``, ``pure``, ``connected_components``, ``manifold``,
        ``orientable`` (``None`` if undefined), ``boundary`` (``{"faces", "components"}``),
        ``homology`` (list over k of ``{"rank", "torsion"}``), ``unreferenced_vertices``, and for a
        triangle surface ``repairs``: what ``dhlb field`` and ``dhlb stripes`` repair by default
        (:mod:`dhlb.mesh.repair`; a list of ``{"kind", "count", "message"}``, empty when none is needed,
        or ``{"refused": message}`` when the surface cannot be repaired), else None.

    Examples
    --------
    >>> from dhlb.io import load, example_path
    >>> info = describe(load(example_path("torus.obj")), homology=False)
    >>> info["counts"], info["euler_characteristic"]
    ([288, 864, 576], 0)
    """
    X = mesh.to_complex()
    info = {
        "file": mesh.path,
        "format": mesh.format,
        "kind": mesh.kind,
        "dim": int(X.dim),
        "counts": [int(c) for c in X.counts],
        "euler_characteristic": int(X.euler_characteristic),
        "pure": bool(X.is_pure),
        "connected_components": _component_count(X.connected_components()),
        "manifold": _maybe(X.is_manifold),
        "orientable": _maybe(X.is_orientable),
        "boundary": _boundary(X),
        "homology": None,
        "unreferenced_vertices": int(mesh.unreferenced_vertices().size),
        "repairs": _repairs(mesh) if mesh.kind == "surface" and X.dim == 2 else None,
    }
    if homology:
        from dhlb.topology.homology import homology as compute_homology

        info["homology"] = [
            {"rank": int(h.rank), "torsion": [int(t) for t in h.torsion]} for h in compute_homology(X)
        ]
    return info


def _repairs(mesh):
    """What the default repairs of ``dhlb field`` / ``dhlb stripes`` would do to the surface."""
    import warnings

    from dhlb.mesh.repair import repair_surface

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            surface = repair_surface(mesh.points, mesh.top_cells, warn=False)
    except DhlbError as exc:
        return {"refused": str(exc)}
    if surface.repair is None:
        return []
    return [{"kind": r.kind, "count": r.count, "message": r.message} for r in surface.repair.repairs]


def _group(h: dict) -> str:
    parts = []
    if h["rank"]:
        parts.append("Z" if h["rank"] == 1 else f"Z^{h['rank']}")
    parts += [f"Z/{t}" for t in h["torsion"]]
    return " + ".join(parts) if parts else "0"


def _yes_no(value) -> str:
    return {True: "yes", False: "no", None: "undefined"}[value]


def format_report(info: dict) -> str:
    """Human-readable text of :func:`describe`'s dict.

    Examples
    --------
    >>> print(format_report({"file": "t.obj", "format": "obj", "kind": "surface", "dim": 2,
    ...     "counts": [4, 6, 4], "euler_characteristic": 2, "pure": True, "connected_components": 1,
    ...     "manifold": True, "orientable": True, "boundary": {"faces": 0, "components": 0},
    ...     "homology": [{"rank": 1, "torsion": []}, {"rank": 0, "torsion": []}, {"rank": 1, "torsion": []}],
    ...     "unreferenced_vertices": 0}))
    file                  t.obj (obj, surface)
    simplices             4 vertices, 6 edges, 4 triangles
    dimension             2 (pure)
    Euler characteristic  2
    components            1
    manifold              yes
    orientable            yes
    boundary              none
    homology              H0 = Z, H1 = 0, H2 = Z
    """
    counts = ", ".join(_count(n, k) for k, n in enumerate(info["counts"]))
    rows = [
        ("file", f"{info['file']} ({info['format']}, {info['kind']})"),
        ("simplices", counts),
        ("dimension", f"{info['dim']} ({'pure' if info['pure'] else 'not pure'})"),
        ("Euler characteristic", str(info["euler_characteristic"])),
        ("components", str(info["connected_components"])),
        ("manifold", _yes_no(info["manifold"])),
        ("orientable", _yes_no(info["orientable"])),
    ]
    b = info["boundary"]
    if b is None:
        rows.append(("boundary", "undefined"))
    elif b["faces"] == 0:
        rows.append(("boundary", "none"))
    else:
        comps = f"{b['components']} component{'s' * (b['components'] != 1)}"
        rows.append(("boundary", f"{_count(b['faces'], info['dim'] - 1)} in {comps}"))
    if info["homology"] is not None:
        rows.append(("homology", ", ".join(f"H{k} = {_group(h)}" for k, h in enumerate(info["homology"]))))
    reps = info.get("repairs")
    if isinstance(reps, dict):
        rows.append(("repairs", f"refused: {reps['refused']}"))
    elif reps:
        rows += [("repairs" if i == 0 else "", r["message"]) for i, r in enumerate(reps)]
    elif reps is not None:
        rows.append(("repairs", "none needed"))
    if info["unreferenced_vertices"]:
        rows.append(("unreferenced", f"{info['unreferenced_vertices']} vertices of the file are in no cell (ignored)"))
    return report_table(rows, width=21)
