"""``dhlb view``: show what ``dhlb field``, ``stripes``, ``vortex``, ``conformal`` or ``demo`` wrote.

The files are read back by :func:`dhlb.io.read_result` (one loader per kind) and drawn by
:func:`dhlb.render.scene.scene_of`, the scene builder of ``result.show()``: a picture from the files is
the picture of the result in memory. In polyscope (a window or ``--screenshot``; extra ``dhlb[view]``)
or, with ``--html``, as a page with the interactive web view (extra ``dhlb[web]``).
"""

from __future__ import annotations

import json

from dhlb.cli._common import PIXEL_SIZE, UsageError, add_command, number_tuple

__all__ = ["NAME", "SUMMARY", "register", "run"]

NAME = "view"
SUMMARY = "show the output of field / stripes / vortex / conformal / demo in polyscope, a PNG or a web page"

_DESCRIPTION = """\
Show in polyscope (pip install polyscope, or the extra: pip install ".[view]" in a clone of dhlb)
what a dhlb command or 'dhlb demo' wrote, as
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
seen from the opposite side. Without a display and without --screenshot the command says so.

With --html FILE.html the command writes a page with the interactive 3-D view (rotate, zoom,
hover over a singularity for its face and index; pip install plotly, or the extra ".[web]"). The page opens from
the file system without network: plotly's script is inside it (about 5 MB), or with
--shared-script one copy of plotly.min.js beside it serves every page of the folder."""

_EXAMPLES = """\
  dhlb field spot.obj --n 4 -o spot && dhlb view spot
  dhlb view spot --screenshot spot-view.png --back
  dhlb stripes spot.obj --spacing 6 -o spot-stripes && dhlb view spot-stripes --screenshot s.png
  dhlb vortex --box 16 --velocity linked-rings -o rings.ply && dhlb view rings --screenshot r.png
  dhlb conformal --ball 6 -o ball && dhlb view ball --screenshot b.png
  dhlb view spot --html spot.html          # open spot.html in any browser
  dhlb demo && dhlb view dhlb-demo/field-n4-s+0"""


def register(subparsers) -> None:
    """Add the ``view`` parser to ``subparsers``."""
    p = add_command(subparsers, NAME, SUMMARY, _DESCRIPTION, _EXAMPLES, output=False)   # writes only --screenshot
    p.add_argument("base", metavar="OUT", help="output base (or one of its files) of dhlb field / stripes / vortex / "
                   "conformal / demo")
    p.add_argument("--screenshot", metavar="FILE.png", help="render headless to this PNG instead of a window")
    p.add_argument("--back", action="store_true", help="with --screenshot: also FILE-back.png from the other side")
    p.add_argument("--html", metavar="FILE.html", help="write a page with the interactive web view (dhlb[web])")
    p.add_argument("--shared-script", action="store_true",
                   help="with --html: one copy of plotly.min.js beside the page instead of inside it")
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
    if args.html and not args.html.lower().endswith((".html", ".htm")):
        raise UsageError(f"--html must name a .html file, got {args.html!r}")
    if args.html and args.screenshot:
        raise UsageError("give --html or --screenshot, not both (run the command twice for both)")
    if args.shared_script and not args.html:
        raise UsageError("--shared-script needs --html FILE.html")
    try:
        scene = scene_of(read_result(args.base), isolines=not args.no_isolines)
    except (InvalidParameterError, MeshParseError, OSError) as exc:
        raise UsageError(str(exc)) from None
    size = (args.size, args.size)
    if args.html:
        return _write_html(args, scene)
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


def _write_html(args, scene) -> int:
    """``dhlb view OUT --html FILE.html``: the interactive web view of the scene, as a page."""
    import os

    from dhlb._files import refuse_overwrite
    from dhlb.errors import InvalidParameterError, OutputError, OverwriteError
    from dhlb.render import Camera
    from dhlb.render.web import to_html

    try:
        refuse_overwrite([args.html], [args.base])
        camera = Camera(view=None if args.view is None else tuple(args.view), up=args.up)
        path = to_html(scene, args.html, plotlyjs="directory" if args.shared_script else "inline", camera=camera,
                       isolines=not args.no_isolines)
    except (ImportError, InvalidParameterError, OutputError, OverwriteError) as exc:
        raise UsageError(str(exc)) from None
    size = os.path.getsize(path)
    if args.json:
        print(json.dumps({"base": args.base, "written": [path], "title": scene.title, "bytes": size}))
    elif not args.quiet:
        print(f"wrote {path} ({size / 1e6:.1f} MB); open it in a browser")
    return 0
