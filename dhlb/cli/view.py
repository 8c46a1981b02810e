"""``dhlb view``: show what ``dhlb field``, ``stripes``, ``vortex``, ``conformal`` or ``demo`` wrote, in polyscope.

The files are read back by :func:`dhlb.io.read_result` (one loader per kind) and drawn by
:func:`dhlb.render.view.scene_of`, the scene builder of ``result.show()``: a picture from the files is
the picture of the result in memory. Needs the extra ``dhlb[view]``.
"""

from __future__ import annotations

import json

from dhlb.cli._common import PIXEL_SIZE, UsageError, add_command, number_tuple

__all__ = ["NAME", "SUMMARY", "register", "run"]

NAME = "view"
SUMMARY = "show the output of field / stripes / vortex / conformal / demo in polyscope, or render it to a PNG"

_DESCRIPTION = """\
Show in polyscope (pip install "dhlb[view]") what a dhlb command or 'dhlb demo' wrote, as
result.show() shows the result in memory. OUT is an output base or one of its files:

  field      OUT.npz (dhlb field, dhlb demo; OUT.ply and OUT.json beside it are optional):
             the mesh with its n-direction glyphs and the singularities (red +, blue -)
  stripes    OUT.obj with its sidecar OUT.json: the stripe texture, the isolines, the zeros
             and branch points
  vortex     OUT.json (dhlb vortex), or OUT.obj / OUT.ply alone (dhlb demo): the filaments,
             inside the domain's boundary when the JSON names it
  conformal  OUT.mesh / OUT.vtk with OUT.json (dhlb conformal), or OUT.npz / OUT.json of
             result.save: the deformed boundary coloured by the distortion of its tets

With --screenshot FILE.png no window opens: the picture is rendered headless through EGL (no
display needed; Debian/Ubuntu: apt-get install libegl1 libegl-mesa0). --back adds FILE-back.png
seen from the opposite side. Without a display and without --screenshot the command says so."""

_EXAMPLES = """\
  dhlb field spot.obj --n 4 -o spot && dhlb view spot
  dhlb view spot --screenshot spot-view.png --back
  dhlb stripes spot.obj --spacing 6 -o spot-stripes && dhlb view spot-stripes --screenshot s.png
  dhlb vortex --box 16 --velocity linked-rings -o rings.ply && dhlb view rings --screenshot r.png
  dhlb conformal --ball 6 -o ball.mesh && dhlb view ball --screenshot b.png
  dhlb demo && dhlb view dhlb-demo/field-n4-s+0"""


def register(subparsers) -> None:
    """Add the ``view`` parser to ``subparsers``."""
    p = add_command(subparsers, NAME, SUMMARY, _DESCRIPTION, _EXAMPLES)
    p.add_argument("base", metavar="OUT", help="output base (or one of its files) of dhlb field / stripes / vortex / "
                   "conformal / demo")
    p.add_argument("--screenshot", metavar="FILE.png", help="render headless to this PNG instead of a window")
    p.add_argument("--back", action="store_true", help="with --screenshot: also FILE-back.png from the other side")
    p.add_argument("--size", type=PIXEL_SIZE, default=800, metavar="PX", help="picture size in pixels (default 800)")
    p.add_argument("--view", type=number_tuple("X,Y,Z"), default=None, metavar="X,Y,Z",
                   help="direction from the model to the camera (default: fitted as in the PNG pictures: "
                        "from above, across the model's thinner side)")
    p.add_argument("--up", default=None, metavar="AXIS", choices=("x", "y", "z", "-x", "-y", "-z"),
                   help="the world axis shown upward (default y, the convention of OBJ/PLY/OFF files)")
    p.add_argument("--no-isolines", action="store_true", help="stripes: do not draw the isolines")
    p.set_defaults(func=run)


def run(args) -> int:
    """Entry point of ``dhlb view``."""
    from dhlb.errors import InvalidParameterError, MeshParseError
    from dhlb.io import read_result
    from dhlb.render.view import ViewerUnavailableError, scene_of, show

    view = args.view
    if args.back and not args.screenshot:
        raise UsageError("--back needs --screenshot FILE.png")
    if args.screenshot and not args.screenshot.lower().endswith(".png"):
        raise UsageError(f"--screenshot must name a .png file, got {args.screenshot!r}")
    try:
        scene = scene_of(read_result(args.base), isolines=not args.no_isolines)
    except (InvalidParameterError, MeshParseError, OSError) as exc:
        raise UsageError(str(exc)) from None
    size = (args.size, args.size)
    try:
        written = []
        if args.screenshot:
            written.append(show(scene, screenshot=args.screenshot, view=view, up=args.up, size=size))
            if args.back:
                from dhlb.render import Camera
                from dhlb.render.view import camera_for

                position, target, _ = camera_for(scene, view, args.up)
                behind = Camera(view=tuple(position - target), up=args.up).behind(None).view
                back = args.screenshot[:-4] + "-back.png"
                written.append(show(scene, screenshot=back, view=behind, up=args.up, size=size))
        else:
            show(scene, view=view, up=args.up, size=size)
    except (ImportError, ViewerUnavailableError) as exc:
        raise UsageError(str(exc)) from None
    except InvalidParameterError as exc:
        raise UsageError(str(exc)) from None
    if args.json:
        print(json.dumps({"base": args.base, "written": written, "title": scene.title}))
    elif written and not args.quiet:
        print("wrote " + ", ".join(written))
    return 0
