"""Benchmark of the interactive views of ``dhlb demo`` (dhlb[web]): their cost in time and in bytes.

Runs ``dhlb demo`` in fresh child processes, alternately without plotly (``sys.modules["plotly"] =
None`` before dhlb is imported: pictures only) and with it (every result also gets ``NAME.html``),
``--repeat`` times each; polyscope is hidden in both, so the runs measure the README's main job and
not the polyscope renderings. Prints the wall time of each child (interpreter, imports and the
demo; the demo's own total in brackets), the ratio of the best web run to the best run without
(target <= 1.20), the size of the demo folder, of its interactive part (every ``*.html`` and
``plotly.min.js``) and the largest view. The machine load (``os.getloadavg()``) is printed at the
start and the end: on a shared machine compare runs of similar load.

With ``--shots DIR`` a headless Chromium (network off, tests/browser.py) opens three views of the
last web run, a field (``field-n4-s+0``), the stripe pattern (``stripes``) and the linked filaments
(``vortex-linked``), and saves each as ``NAME-0.png`` and, after turning the camera by 60° about its
up vector, ``NAME-60.png``.

Run:  OPENBLAS_NUM_THREADS=1 python benchmarks/bench_web.py [--out DIR] [--shots DIR] [--repeat N]
"""
from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # before numpy is imported (also in the children)

import argparse
import json
import pathlib
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

TARGET = 1.20
"""Most the demo may slow down by writing the interactive views (web / no web)."""
SHOTS = ("field-n4-s+0", "stripes", "vortex-linked")
TURN = 60.0

_CHILD = """
import json, sys, time
sys.modules["polyscope"] = None
if {hide_plotly!r}:
    sys.modules["plotly"] = None
sys.path.insert(0, {root!r})
t0 = time.perf_counter()
from dhlb.cli import main
import contextlib, io
buf = io.StringIO()
with contextlib.redirect_stdout(buf):
    code = main(["demo", "-o", {out!r}, "-q", "--json"])
summary = json.loads(buf.getvalue())
print(json.dumps({{"code": code, "demo": summary["seconds"], "child": time.perf_counter() - t0,
                   "checks": summary["checks_passed"]}}))
"""


def run_demo(out: str, web: bool) -> dict:
    """One ``dhlb demo -o out`` in a fresh process; its wall time and the demo's own."""
    env = dict(os.environ, OMP_NUM_THREADS="1", MPLBACKEND="Agg", PYTHONPATH=str(ROOT))
    code = _CHILD.format(hide_plotly=not web, root=str(ROOT), out=out)
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, cwd=str(ROOT))
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        raise SystemExit(f"dhlb demo failed ({'web' if web else 'no web'}):\n{proc.stderr[-3000:]}")
    info = json.loads(proc.stdout.strip().splitlines()[-1])
    views = sorted(pathlib.Path(out).glob("*.html"))
    return {"wall": wall, **info, "html": len(views)}


def sizes(out: str) -> dict:
    """Bytes of the folder, of its interactive part (``*.html`` and plotly.min.js) and of the largest view."""
    files = [p for p in pathlib.Path(out).rglob("*") if p.is_file()]
    interactive = [p for p in files if p.suffix == ".html" or p.name == "plotly.min.js"]
    views = [p for p in interactive if p.suffix == ".html" and p.name != "index.html"
             and not p.name.endswith("-views.html")]
    largest = max(views, key=lambda p: p.stat().st_size) if views else None
    return {"total": sum(p.stat().st_size for p in files), "interactive": sum(p.stat().st_size for p in interactive),
            "views": len(views), "largest": (largest.name, largest.stat().st_size) if largest else None}


def shots(folder: str, dest: str) -> list[str]:
    """Screenshots of :data:`SHOTS` before and after a turn of :data:`TURN` degrees; their paths."""
    from tests.browser import chromium_driver, missing

    reason = missing()
    if reason is not None:
        print(f"no screenshots: {reason}")
        return []
    os.makedirs(dest, exist_ok=True)
    written = []
    with chromium_driver(800, 800) as browser:
        for name in SHOTS:
            browser.open(os.path.join(folder, f"{name}.html"))
            browser.wait_ready()
            for angle in (0.0, TURN):
                if angle:
                    browser.rotate(angle)
                browser.settled_screenshot()
                path = os.path.join(dest, f"{name}-{angle:.0f}.png")
                with open(path, "wb") as fh:
                    fh.write(browser.view().screenshot_as_png)
                written.append(path)
            errors = browser.console_errors()
            if errors:
                print(f"{name}: console errors {errors}")
        browser.assert_local()
    return written


def _mb(n: int) -> str:
    return f"{n / 2**20:.2f} MB"


def main(argv=None) -> int:
    """Run the benchmark; print the figures."""
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", default=None, help="folder for the demo runs (default: a temporary one)")
    p.add_argument("--shots", default=None, metavar="DIR", help="save screenshots of three views into DIR")
    p.add_argument("--repeat", type=int, default=2, help="runs of each kind (alternating; default 2)")
    args = p.parse_args(argv)
    print(f"load average at start: {' '.join(f'{x:.2f}' for x in os.getloadavg())} ({os.cpu_count()} cores)")
    with tempfile.TemporaryDirectory(prefix="bench-web-") as tmp:
        base = args.out or tmp
        runs: dict[bool, list[dict]] = {False: [], True: []}
        for i in range(args.repeat):
            for web in (False, True):
                out = os.path.join(base, f"{'web' if web else 'noweb'}-{i + 1}")
                r = run_demo(out, web)
                runs[web].append(r)
                print(f"{'web   ' if web else 'no web'} run {i + 1}: {r['wall']:6.2f} s wall "
                      f"(demo {r['demo']:.2f} s), {r['html']} html files, checks {'ok' if r['checks'] else 'FAILED'}")
        best = {web: min(r["wall"] for r in rs) for web, rs in runs.items()}
        ratio = best[True] / best[False]
        print(f"best wall: no web {best[False]:.2f} s, web {best[True]:.2f} s; ratio web/no web {ratio:.3f} "
              f"(target <= {TARGET:.2f}: {'met' if ratio <= TARGET else 'NOT met'})")
        s = sizes(out)
        s0 = sizes(os.path.join(base, f"noweb-{args.repeat}"))
        print(f"demo folder: {_mb(s['total'])} with the views, {_mb(s0['total'])} without; "
              f"interactive part ({s['views']} views + index + plotly.min.js): {_mb(s['interactive'])}; "
              f"largest view: {s['largest'][0]} {_mb(s['largest'][1])}")
        if args.shots:
            t0 = time.perf_counter()
            paths = shots(out, args.shots)
            if paths:
                print(f"screenshots ({time.perf_counter() - t0:.1f} s):")
                print("\n".join(f"  {q}" for q in paths))
    print(f"load average at end: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
