"""Benchmark of mesh repair (issue 38): what ``repair="safe"`` costs next to the field it serves.

For each mesh it prints, measured in one run (best of ``REPEAT``, ``OPENBLAS_NUM_THREADS=1``):

* ``field``: ``direction_field(V, F, n=4)`` end to end with the default options (repair included);
* ``strict``: ``validate_surface(V, F)``, the checks every field ran before repair existed;
* ``default``: ``repair_surface(V, F)``, what the default options run: the strict checks, and the
  repairs only when a check fails (on a clean mesh this is ``strict`` plus nothing);
* ``forced``: ``repair_surface(V, F, force=True)``, the whole repair pipeline even on a clean mesh
  (pairing the edges, orienting, fans, the mollification test, the maps back);
* ``checks``: ``validate_surface`` of the repaired mesh's own arrays — the half-edges, the complex,
  the geometry and the fans that every field builds (the repaired mesh keeps them for the field);
* ``repair``: what repair adds to that: ``forced − checks`` on a clean mesh (the whole pipeline run
  although nothing needed it: the pessimistic figure; the default path adds nothing there),
  ``default − checks`` on a defective one (the strict attempt that fails, then the repairs), and
  ``repair / field``. Issue 38's target: at most 10 % on the bunny (69k faces).

The defective public models (``tests/data``: Suzanne, the beetle, the cow, the teapot; and, when the
folder is there, the whole beast and ogre from a clone of alecjacobson/common-3d-test-models given as
``COMMON3D=path/to/data``) are measured the same way; there ``default`` is the repair itself.

Run:  python benchmarks/bench_repair.py          (reads ../shared/meshes and tests/data)
"""
from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import sys
import time
import warnings

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

from dhlb.errors import DhlbError
from dhlb.fields import direction_field
from dhlb.io import read_surface
from dhlb.mesh import repair_surface, validate_surface

HERE = os.path.dirname(os.path.abspath(__file__))
SHARED = os.path.join(HERE, "..", "..", "shared", "meshes")
DATA = os.path.join(HERE, "..", "tests", "data")
REPEAT = 3


def best(fn, repeat=REPEAT):
    out, t = None, np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        try:
            out = fn()
        except DhlbError as exc:
            out = exc
        t = min(t, time.perf_counter() - t0)
    return out, t


def row(path: str) -> str:
    V, F = read_surface(path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res, t_field = best(lambda: direction_field(V, F, n=4))
        strict, t_strict = best(lambda: validate_surface(V, F))
        mesh, t_default = best(lambda: repair_surface(V, F))
        _, t_forced = best(lambda: repair_surface(V, F, force=True))
        _, t_checks = best(lambda: validate_surface(mesh.points, mesh.faces))
    kinds = ", ".join(dict.fromkeys(mesh.repair.kinds)) if mesh.repair else "none needed"
    strict_s = f"{t_strict:.3f}" if not isinstance(strict, DhlbError) else f"refused ({type(strict).__name__})"
    t_repair = (t_default if mesh.repair else t_forced) - t_checks
    return (f"| {os.path.basename(path)} | {len(F)} | {kinds} | {t_field:.3f} | {strict_s} | {t_default:.3f} | "
            f"{t_forced:.3f} | {t_checks:.3f} | {t_repair:.3f} | {t_repair / t_field:.1%} | "
            f"{res.index_sum} = {res.poincare_hopf:g} |")


def main() -> None:
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"mesh repair, n = 4 fields, best of {REPEAT}, OPENBLAS_NUM_THREADS={os.environ['OPENBLAS_NUM_THREADS']}, "
          f"load {load:.2f}")
    print("| mesh | faces | repairs | field s | strict s | default s | forced s | checks s | repair s | repair/field "
          "| Σ index = PH |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    paths = [os.path.join(SHARED, f) for f in ("stanford-bunny.obj", "kitten.obj", "spot.obj")]
    paths += [os.path.join(DATA, f) for f in ("suzanne.obj", "beetle.obj", "cow.obj", "teapot.obj")]
    extra = os.environ.get("COMMON3D")
    if extra:
        paths += [os.path.join(extra, f) for f in ("beast.obj", "ogre.obj")]
    for p in paths:
        if os.path.isfile(p):
            print(row(p), flush=True)


if __name__ == "__main__":
    main()
