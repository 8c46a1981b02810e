"""``dhlb view``: show what ``dhlb field``, ``stripes`` or ``vortex`` wrote, in polyscope (extra ``dhlb[view]``).

Reads, for the output base OUT of those commands:

* field: ``OUT.ply`` (mesh + directions ``d{k}x d{k}y d{k}z``) and ``OUT.npz`` (singular points
  and indices);
* stripes: ``OUT.obj`` (one texture coordinate ``u`` per face corner), ``OUT.json`` (the sidecar:
  zeros, branch points) and ``OUT-isolines.obj`` when present;
* vortex: ``OUT.json`` (the filaments; the domain outline when it was ``--box N``).
"""

from __future__ import annotations

import json
import os

import numpy as np

from dhlb.cli._common import PIXEL_SIZE, UsageError, add_command, number_tuple
from dhlb.io.polylines import read_polylines_obj, read_uv_obj

__all__ = ["NAME", "SUMMARY", "register", "run", "scene_from_outputs", "read_uv_obj", "read_polylines_obj"]

NAME = "view"
SUMMARY = "show the output of field / stripes / vortex in polyscope, or render it headless to a PNG"

_DESCRIPTION = """\
Show in polyscope (pip install "dhlb[view]") what 'dhlb field', 'dhlb stripes' or 'dhlb vortex'
wrote for the output base OUT: the mesh with its n-direction glyphs and the singularities
(red +, blue -); the stripe texture of the per-corner coordinates, the isolines, zeros and
branch points; the vortex filaments as curves inside the domain's outline. The kind is found
from the files (OUT.npz: field; OUT.obj with a dhlb-stripes OUT.json: stripes; OUT.json with
filaments: vortex). A name with an extension (OUT.ply, OUT.obj, OUT.json) is accepted too.

With --screenshot FILE.png no window opens: the picture is rendered headless through EGL (no
display needed; Debian/Ubuntu: apt-get install libegl1 libegl-mesa0). --back adds FILE-back.png
seen from the opposite side. Without a display and without --screenshot the command says so."""

_EXAMPLES = """\
  dhlb field spot.obj --n 4 -o spot && dhlb view spot
  dhlb view spot --screenshot spot-view.png --back
  dhlb stripes spot.obj --spacing 6 -o spot-stripes && dhlb view spot-stripes --screenshot s.png
  dhlb vortex --box 16 --velocity linked-rings -o rings.ply && dhlb view rings --screenshot r.png"""


def register(subparsers) -> None:
    """Add the ``view`` parser to ``subparsers``."""
    p = add_command(subparsers, NAME, SUMMARY, _DESCRIPTION, _EXAMPLES)
    p.add_argument("base", metavar="OUT", help="output base of dhlb field / stripes / vortex")
    p.add_argument("--screenshot", metavar="FILE.png", help="render headless to this PNG instead of a window")
    p.add_argument("--back", action="store_true", help="with --screenshot: also FILE-back.png from the other side")
    p.add_argument("--size", type=PIXEL_SIZE, default=800, metavar="PX", help="picture size in pixels (default 800)")
    p.add_argument("--view", type=number_tuple("X,Y,Z"), default="1,-1.6,1", metavar="X,Y,Z",
                   help="camera direction (default 1,-1.6,1)")
    p.add_argument("--no-isolines", action="store_true", help="stripes: do not draw the isolines")
    p.set_defaults(func=run)


def _box_outline(lo=-1.0, hi=1.0):
    c = np.array([[x, y, z] for x in (lo, hi) for y in (lo, hi) for z in (lo, hi)], float)
    edges = [(a, b) for a in range(8) for b in range(a + 1, 8) if bin(a ^ b).count("1") == 1]
    return [c[list(e)] for e in edges]


def _base(path: str) -> str:
    for ext in (".ply", ".obj", ".json", ".npz", ".png"):
        if path.lower().endswith(ext):
            return path[: -len(ext)]
    return path


def scene_from_outputs(base: str, *, isolines: bool = True):
    """The :class:`dhlb.render.view.Scene` of the files written for the output base ``base``.

    Examples
    --------
    >>> import os, tempfile
    >>> from dhlb.io import read_surface, example_path
    >>> from dhlb.fields import direction_field
    >>> from dhlb.cli.field import write_field
    >>> V, F = read_surface(example_path("torus.obj"))
    >>> with tempfile.TemporaryDirectory() as d:
    ...     _ = write_field(os.path.join(d, "t"), direction_field(V, F, n=2), V, F, png=False)
    ...     s = scene_from_outputs(os.path.join(d, "t"))
    >>> sorted(s.meshes[0].vectors), s.meshes[0].faces.shape
    (['direction 0', 'direction 1'], (576, 3))
    """
    from dhlb.render.view import BRANCH, Scene, index_colors

    base = _base(base)
    side = None
    if os.path.isfile(base + ".json"):
        try:
            with open(base + ".json", encoding="utf-8") as fh:
                side = json.load(fh)
        except (OSError, ValueError) as exc:
            raise UsageError(f"{base}.json: not readable JSON ({exc})") from None
    if os.path.isfile(base + ".npz") and os.path.isfile(base + ".ply"):  # dhlb field
        from dhlb.io import read_ply

        V, F = read_ply(base + ".ply")  # the directions come from OUT.npz (input numbering)
        with np.load(base + ".npz", allow_pickle=False) as z:
            D, sp, si = z["directions"], z["singular_points"], z["singular_index"]
        s = Scene(title=os.path.basename(base))
        s.add_mesh("mesh", V, F, vectors={f"direction {k}": D[:, k] for k in range(D.shape[1])})
        if len(sp):
            s.add_points("singularities", sp, index_colors(si), radius=0.012)
        return s
    if os.path.isfile(base + ".obj") and isinstance(side, dict) and side.get("format") == "dhlb-stripes":
        V, F, U = read_uv_obj(base + ".obj")
        s = Scene(title=os.path.basename(base))
        s.add_mesh("mesh", V, F, corner_uv=U)
        iso = base + "-isolines.obj"
        if isolines and os.path.isfile(iso):
            s.add_curves("isolines", read_polylines_obj(iso), color=(0.05, 0.05, 0.08), radius=0.0015)
        z, b = side.get("zeros", {}), side.get("branch", {})
        if z.get("points"):
            s.add_points("zeros", z["points"], index_colors(z["index"]), radius=0.01)
        if b.get("points"):
            s.add_points("branch points", b["points"], BRANCH, radius=0.01)
        return s
    if isinstance(side, dict) and "filaments" in side:
        s = Scene(title=os.path.basename(base))
        mesh = str(side.get("mesh", ""))
        if mesh.startswith("box "):
            s.add_curves("domain", _box_outline(), color=(0.55, 0.58, 0.64), radius=0.002)
        elif os.path.isfile(mesh):
            from dhlb.io import read_volume
            from dhlb.mesh import check_tet_mesh

            m = check_tet_mesh(*read_volume(mesh))
            s.add_mesh("domain", m.points, m.boundary_faces, transparency=0.25)
        from dhlb.render.view import _CURVE_COLORS

        for k, f in enumerate(side["filaments"]):
            s.add_curves(f"filament {k}", [(np.asarray(f["points"], float), bool(f["closed"]))],
                         color=_CURVE_COLORS[k % len(_CURVE_COLORS)], radius=0.006)
        return s
    raise UsageError(f"{base}: found no output of dhlb field (OUT.ply + OUT.npz), stripes (OUT.obj + OUT.json) "
                     "or vortex (OUT.json with filaments)")


def run(args) -> int:
    """Entry point of ``dhlb view``."""
    from dhlb.errors import InvalidParameterError
    from dhlb.render.view import ViewerUnavailableError, show

    view = args.view
    if args.back and not args.screenshot:
        raise UsageError("--back needs --screenshot FILE.png")
    if args.screenshot and not args.screenshot.lower().endswith(".png"):
        raise UsageError(f"--screenshot must name a .png file, got {args.screenshot!r}")
    scene = scene_from_outputs(args.base, isolines=not args.no_isolines)
    size = (args.size, args.size)
    try:
        written = []
        if args.screenshot:
            written.append(show(scene, screenshot=args.screenshot, view=view, size=size))
            if args.back:
                back = args.screenshot[:-4] + "-back.png"
                written.append(show(scene, screenshot=back, view=tuple(-x for x in view), size=size))
        else:
            show(scene, view=view, size=size)
    except (ImportError, ViewerUnavailableError) as exc:
        raise UsageError(str(exc)) from None
    except InvalidParameterError as exc:
        raise UsageError(str(exc)) from None
    if args.json:
        print(json.dumps({"base": _base(args.base), "written": written, "title": scene.title}))
    elif written and not args.quiet:
        print("wrote " + ", ".join(written))
    return 0
