"""Generate the before/after pictures of ``docs/input-meshes.md`` (the beetle: repaired, then a field).

Run from the repository root (a few seconds)::

    MPLBACKEND=Agg OPENBLAS_NUM_THREADS=1 python docs/_repair_figure.py

It writes ``docs/_static/repair/beetle-before.png`` (the mesh as read, red dots on the non-manifold
edges and vertices that make ``--repair none`` refuse it) and ``beetle-after.png`` (the smoothest cross
field on the repaired mesh, with its singularities), 500 × 500 pixels with a 256-colour palette, and
prints what was repaired and the Poincaré–Hopf check. The pictures are committed; the docs build does
not run this script. The mesh is ``tests/data/beetle.obj`` (alecjacobson/common-3d-test-models).
"""

from __future__ import annotations

import os
import warnings

import numpy as np

from dhlb.fields import direction_field
from dhlb.io import read_surface
from dhlb.render import Camera, render_field_png

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "docs", "_static", "repair")
CAMERA = Camera(view=(1.0, 0.55, 0.9), up=(0.0, 1.0, 0.0), size=(500, 500))


def _palette(path: str) -> None:
    from PIL import Image

    with Image.open(path) as im:
        q = im.convert("RGB").quantize(colors=256, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
    q.save(path, optimize=True)


def _defects(V: np.ndarray, F: np.ndarray) -> np.ndarray:
    """Midpoints of the edges with three or more faces, and the vertices whose faces form several fans."""
    from dhlb.mesh.repair import repair_surface

    e = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    edges, count = np.unique(e, axis=0, return_counts=True)
    mids = V[edges[count > 2]].mean(axis=1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        mesh = repair_surface(V, F)
    split = next(r for r in mesh.repair.repairs if r.kind == "split" and r.vertices)
    copies = np.bincount(mesh.vertex_rows, minlength=len(V))
    rows = np.flatnonzero(copies > 1)
    assert split.count == rows.size
    return np.vstack([mids, V[rows]])


def main() -> None:
    os.makedirs(OUT, exist_ok=True)
    V, F = read_surface(os.path.join(ROOT, "tests", "data", "beetle.obj"))
    V, F = np.asarray(V, float), np.asarray(F)
    marks = _defects(V, F)
    before = os.path.join(OUT, "beetle-before.png")
    render_field_png(before, V, F, None, (marks, np.ones(len(marks), int)), camera=CAMERA,
                     title="beetle.obj as read: refused by --repair none")
    _palette(before)
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        res = direction_field(V, F, n=4)
    after = os.path.join(OUT, "beetle-after.png")
    mesh = res.mesh
    render_field_png(after, mesh.points, mesh.faces, res.directions, res.singularities, camera=CAMERA,
                     title=f"repaired (default): n = 4, Σ index = {res.index_sum}")
    _palette(after)
    for w in seen:
        print("repaired:", w.message)
    print(f"{before}: {len(marks)} marks; {after}: index sum {res.index_sum} = {res.poincare_hopf} "
          f"(Poincaré–Hopf with boundary)")


if __name__ == "__main__":
    main()
