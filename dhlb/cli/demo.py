"""``dhlb demo``: the main job on the bundled data — fields, stripes, vortex filaments, conformal maps.

Runs every application of the package on meshes shipped inside it (the cow Spot, a saddle disk
with boundary, a tetrahedral cube and ball generated on the fly, a real tet mesh), prints a summary
table with the checks (Poincaré–Hopf, filament counts and linking, λ₁) and timings, and writes
the pictures, the results and an ``index.html`` page that shows every picture with a caption.
"""

from __future__ import annotations

import json
import os
import sys
import threading
import time

from dhlb._install import install_hint
from dhlb.cli._common import UsageError, add_command, backend_choice

__all__ = ["NAME", "SUMMARY", "register", "run"]

NAME = "demo"
SUMMARY = "run every application on bundled data; write pictures, meshes and index.html"

_DESCRIPTION = """\
The main job: on meshes bundled with dhlb, compute smoothest direction fields for n = 1, 2, 4 and
s = -1, 0, +1 (the cow Spot, closed, genus 0), a curvature-aligned cross field, a boundary-aligned
cross field on a saddle disk (Poincaré–Hopf with boundary), a stripe pattern, the vortex
filaments of a vortex ring and of two linked rings in a tetrahedral cube, and close-to-conformal
deformations of a tetrahedral ball and of a real tet mesh. Prints a summary table and writes PNG
pictures, the results (each opens with 'dhlb view') and a self-contained index.html into OUT."""

_EXAMPLES = """\
  dhlb demo                      # writes ./dhlb-demo/index.html
  dhlb demo -o /tmp/demo --json  # summary as JSON
  dhlb demo --backend superlu"""


def register(subparsers) -> None:
    """Add the ``demo`` parser to ``subparsers``."""
    p = add_command(subparsers, NAME, SUMMARY, _DESCRIPTION, _EXAMPLES,
                    output="the folder to write the demo's page, pictures and files into (default: dhlb-demo)")
    next(a for a in p._actions if "--output" in a.option_strings).metavar = "DIR"
    p.set_defaults(output="dhlb-demo")
    p.add_argument("--backend", type=backend_choice,
                   default=None, metavar="NAME", help="linear-algebra backend (default: automatic)")
    p.add_argument("--only", default=None, metavar="LIST",
                   help="comma-separated subset of: fields, aligned, boundary, stripes, vortex, conformal")
    p.set_defaults(func=run)


class _Progress:
    """Prints a step's name once it has run for a second, and its time when done (stderr)."""

    def __init__(self, quiet: bool):
        self.quiet = quiet

    def run(self, name: str, fn):
        shown = threading.Event()

        def announce():
            if not self.quiet:
                print(f"  {name} ...", file=sys.stderr, flush=True)
                shown.set()

        timer = threading.Timer(1.0, announce)
        t0 = time.perf_counter()
        timer.start()
        try:
            return fn()
        finally:
            timer.cancel()
            if shown.is_set():
                print(f"  {name}: done in {time.perf_counter() - t0:.1f} s", file=sys.stderr, flush=True)


STEPS = ("fields", "aligned", "boundary", "stripes", "vortex", "conformal")


def run(args) -> int:
    """Entry point of ``dhlb demo``."""
    from dhlb.cli import _demo_steps as steps
    from dhlb.render.gallery import write_gallery

    only = STEPS if args.only is None else tuple(s.strip() for s in args.only.split(","))
    if not any(only) or not all(only):
        raise UsageError(f"--only {args.only!r} names no step (or has an empty item); give a comma-separated "
                         f"list of {', '.join(STEPS)}")
    bad = [s for s in only if s not in STEPS]
    if bad:
        raise UsageError(f"unknown step(s) {', '.join(bad)}; choose from {', '.join(STEPS)}")
    out = args.output
    if out in (None, "-"):
        raise UsageError("dhlb demo writes files: give a directory with -o OUT")
    if os.path.exists(out) and not os.path.isdir(out):
        raise UsageError(f"{out}: exists and is not a directory")
    os.makedirs(out, exist_ok=True)
    progress = _Progress(args.quiet or args.json)
    t0 = time.perf_counter()
    records = []
    for name in STEPS:
        if name in only:
            records += getattr(steps, name)(out, progress, backend=args.backend)
    total = time.perf_counter() - t0
    pictures = []  # every result front and back
    for r in records:
        if r.get("picture"):
            back = r["picture"][:-4] + "-back.png"
            link = r.get("views")  # polyscope views from several angles, where the environment allows it
            pictures += [(r["picture"], r["caption"], link, r.get("web"))] + (
                [(back, r["caption"] + " (back)", link)] if os.path.exists(back) else [])
    table = [["step", "mesh", "result", "check", "seconds"]] + [
        [r["step"], r["mesh"], r["result"], r["check"], f"{r['seconds']:.2f}"] for r in records]
    web = any(r.get("web") for r in records)
    intro = f"dhlb demo: {len(records)} computations in {total:.1f} s. " + (
        "Rotate any result in 3-D with the button on its picture (drag to turn, scroll to zoom, hover over a "
        "singularity for its face and index); the views need no network: plotly's script is in this folder."
        if web else f"Interactive 3-D views need plotly: {install_hint('plotly', 'web')}.")
    page = write_gallery(os.path.join(out, "index.html"), "dhlb demo", pictures, table=table, intro=intro)
    views = [r["web"] for r in records if r.get("web")]
    script = os.path.join(out, "plotly.min.js")
    web_bytes = sum(os.path.getsize(v) for v in views) + (os.path.getsize(script) if views else 0)
    summary = {"output": os.path.abspath(out), "index": os.path.abspath(page), "seconds": total,
               "web": {"views": len(views), "bytes": web_bytes, "folder_bytes": _folder_bytes(out)},
               "steps": [{k: v for k, v in r.items() if k != "details"} | {"details": r.get("details", {})}
                         for r in records],
               "checks_passed": all(r["ok"] for r in records)}
    if args.json:
        sys.stdout.write(json.dumps(summary, indent=2, default=_json_default) + "\n")
    else:
        sys.stdout.write(_format(table, total, page, summary["web"]))
    return 0 if summary["checks_passed"] else 1


def _json_default(obj):
    import numpy as np

    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    raise TypeError(type(obj).__name__)


def _folder_bytes(folder: str) -> int:
    return sum(e.stat().st_size for e in os.scandir(folder) if e.is_file())


def _format(table, total: float, page: str, web: dict) -> str:
    widths = [max(len(str(row[i])) for row in table) for i in range(len(table[0]))]
    lines = ["  ".join(str(c).ljust(w) for c, w in zip(row, widths)).rstrip() for row in table]
    lines.insert(1, "  ".join("-" * w for w in widths))
    views = (f"{web['views']} interactive views, {web['bytes'] / 1e6:.1f} MB with plotly's script" if web["views"]
             else f"no interactive views: {install_hint('plotly', 'web')}")
    lines.append(f"\ntotal {total:.1f} s; {views}; folder {web['folder_bytes'] / 1e6:.1f} MB; open {page}")
    return "\n".join(lines) + "\n"
