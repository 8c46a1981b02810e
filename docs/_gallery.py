"""Generate the pictures of the documentation gallery (``docs/gallery.md``).

Run from the repository root (about half a minute)::

    MPLBACKEND=Agg OPENBLAS_NUM_THREADS=1 python docs/_gallery.py          # all pictures
    MPLBACKEND=Agg OPENBLAS_NUM_THREADS=1 python docs/_gallery.py tube     # only the stepped tube (Fig. 3)
    MPLBACKEND=Agg OPENBLAS_NUM_THREADS=1 python docs/_gallery.py fingerprint  # only the fingerprint (Fig. 5)

It writes ``docs/_static/gallery/*.png`` (500 × 500 pixels, re-saved with a 256-colour palette so
that each stays well under 150 KB) and prints
one line per picture: file, size, singularity count and the Poincaré–Hopf check. The pictures
are committed; the docs build does not run this script. Everything comes from the bundled
meshes (:func:`dhlb.io.example_path`) or the generated ones of :mod:`dhlb.examples`, so the result
is reproducible on any machine.
"""

from __future__ import annotations

import os
import sys
import time

import numpy as np

from dhlb.fields import direction_field
from dhlb.io import example_path, read_surface
from dhlb.render import Camera, StripeStyle, render_field_png
from dhlb.stripes import SectionOptions, StripeOptions

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "_static", "gallery")
SIZE = (500, 500)
MAX_BYTES = 150_000
SPOT_VIEW = Camera(view=(1.0, 0.6, 0.4), up=(0.0, 1.0, 0.0), size=SIZE)
SADDLE_VIEW = Camera(view=(0.3, -1.0, 1.2), up=(0.0, 0.0, 1.0), size=SIZE)


def shrink(path: str) -> None:
    """Re-save the PNG with a 256-colour palette (median cut, no dithering): about a third of the size."""
    from PIL import Image  # a dependency of matplotlib, which the renderer needs anyway

    with Image.open(path) as im:
        q = im.convert("RGB").quantize(colors=256, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
    q.save(path, optimize=True)


def picture(name: str, mesh: str, view: Camera, **kw) -> dict:
    """Compute ``direction_field(mesh, **kw)``, render it to ``OUT/name.png`` and check it."""
    t0 = time.perf_counter()
    res = direction_field(*read_surface(example_path(mesh)), **kw)
    m = res.mesh
    path = render_field_png(os.path.join(OUT, f"{name}.png"), m.points, m.faces, res.directions,
                            res.singularities, camera=view)
    shrink(path)
    shrink(render_field_png(os.path.join(OUT, f"{name}-back.png"), m.points, m.faces, res.directions,
                            res.singularities, camera=view.behind(m.points)))
    nbytes = os.path.getsize(path)
    if nbytes > MAX_BYTES:
        raise SystemExit(f"{path}: {nbytes} bytes > {MAX_BYTES}")
    if res.index_sum != round(res.poincare_hopf):
        raise SystemExit(f"{path}: index sum {res.index_sum} != Poincaré–Hopf {res.poincare_hopf}")
    if m.is_closed and res.index_sum != res.n * res.euler_characteristic:
        raise SystemExit(f"{path}: index sum {res.index_sum} != nχ = {res.n * res.euler_characteristic}")
    rec = {"file": os.path.basename(path), "bytes": nbytes, "n": res.n, "s": res.s,
           "singularities": len(res.singularities.faces), "index_sum": res.index_sum,
           "positive": int(np.sum(res.singularities.index > 0)),
           "negative": int(np.sum(res.singularities.index < 0)),
           "seconds": time.perf_counter() - t0}
    print("{file:28s} {bytes:7d} B  n={n} s={s:+.0f}  {singularities:3d} singularities "
          "(+{positive}/-{negative}), index sum {index_sum:+d}  {seconds:5.1f} s".format(**rec))
    return rec


def stripes(name: str, view: Camera, *, n: int, spacing: float, **field_kw) -> None:
    """A stripe pattern on Spot along a direction field (``orthogonal`` pictures: both directions)."""
    from dhlb.render import render_stripes_png
    from dhlb.stripes import stripe_pattern

    t0 = time.perf_counter()
    V, F = read_surface(example_path("spot.obj"))
    field = direction_field(V, F, n=n, **field_kw)
    res = stripe_pattern(V, F, field, spacing=spacing)
    path = render_stripes_png(os.path.join(OUT, f"{name}.png"), res.texture, camera=view)
    shrink(path)
    shrink(render_stripes_png(os.path.join(OUT, f"{name}-back.png"), res.texture, camera=view.behind(res.mesh.points)))
    info = res.to_json()
    print(f"{os.path.basename(path):28s} {os.path.getsize(path):7d} B  {len(info['zero_faces'])} zero faces, "
          f"{len(info['branch_faces'])} branch faces  {time.perf_counter() - t0:5.1f} s")


def tube_stripes(section: str) -> list:
    """The seed's part 2 Fig. 3: a stepped tube (radii 1, 1.5, 2; 8, 12, 16 stripes) with ``section``."""
    from dhlb.render import render_stripes_png
    from dhlb.stripes import stripe_pattern
    from dhlb.stripes.revolution import stepped_tube

    t0 = time.perf_counter()
    tube = stepped_tube((1.0, 1.5, 2.0), stripes=8, around=96, jitter=0.25, seed=1)
    res = stripe_pattern(tube.points, tube.faces, tube.directions, frequency=tube.frequency,
                         options=StripeOptions(section=SectionOptions(kind=section)))
    counts = np.round(tube.winding(res.psi, res.mesh.vertex_labels)[tube.middle_rings()]).astype(int).tolist()
    tube_view = Camera(view=(1.0, -1.2, 0.35), up=(0.0, 0.0, 1.0), size=SIZE)
    marked = StripeStyle(mark_singularities=True)
    path = render_stripes_png(os.path.join(OUT, f"stripes-tube-{section}.png"), res.texture, camera=tube_view,
                              style=marked)
    shrink(path)
    shrink(render_stripes_png(os.path.join(OUT, f"stripes-tube-{section}-back.png"), res.texture,
                              camera=tube_view.behind(res.mesh.points), style=marked))
    print(f"{os.path.basename(path):28s} {os.path.getsize(path):7d} B  stripes per level {counts} "
          f"(want {tube.stripes_per_level.astype(int).tolist()}), {res.zero_faces.size} zeros, "
          f"unit energy {res.unit_energy:.3g} (λ₁ = {res.eigenvalue:.3g})  {time.perf_counter() - t0:5.1f} s")
    return counts


def fingerprint() -> None:
    """The seed's part 2 Fig. 5: stripes along the line field with a prescribed core (+1/2) and delta (−1/2)."""
    from dhlb.examples import fingerprint_pad
    from dhlb.fields import prescribed_field
    from dhlb.render import render_stripes_png
    from dhlb.stripes import stripe_pattern

    t0 = time.perf_counter()
    V, F, singularities = fingerprint_pad(rings=40)
    field = prescribed_field(V, F, 2, singularities)
    res = stripe_pattern(field, spacing=4.0)
    branch = sorted(res.mesh.face_rows[res.branch_faces].tolist())
    if branch != sorted(singularities):
        raise SystemExit(f"fingerprint: branch faces {branch} != prescribed faces {sorted(singularities)}")
    path = render_stripes_png(os.path.join(OUT, "fingerprint.png"), res.texture,
                              camera=Camera(view=(0.0, -0.25, 1.0), up=(0.0, 1.0, 0.0), size=SIZE))
    shrink(path)
    nbytes = os.path.getsize(path)
    if nbytes > MAX_BYTES:
        raise SystemExit(f"{path}: {nbytes} bytes > {MAX_BYTES}")
    print(f"{os.path.basename(path):28s} {nbytes:7d} B  branch faces {branch} = prescribed {singularities}, "
          f"{res.zero_faces.size} zero faces  {time.perf_counter() - t0:5.1f} s")


def filaments(name: str, kind: str) -> None:
    """Vortex filaments of a demo velocity field (``ring``/``linked-rings``/``trefoil``) in a tet cube."""
    from dhlb.cli.vortex import demo_velocity
    from dhlb.mesh import box_tet_mesh
    from dhlb.render import FILAMENT_CAMERA, render_filaments_png
    from dhlb.vortex import vortex_filaments

    t0 = time.perf_counter()
    mesh = box_tet_mesh(14, lower=(-1.0, -1.0, -1.0), upper=(1.0, 1.0, 1.0))
    field, _ = demo_velocity(kind, mesh.points)
    res = vortex_filaments(mesh, None, field, 1.0)
    camera = FILAMENT_CAMERA.replace(size=SIZE)
    path = render_filaments_png(os.path.join(OUT, f"{name}.png"), res.filaments, res.mesh.points,
                                res.mesh.boundary_faces, camera=camera)
    shrink(path)
    shrink(render_filaments_png(os.path.join(OUT, f"{name}-back.png"), res.filaments, res.mesh.points,
                                res.mesh.boundary_faces, camera=camera.behind(res.mesh.points)))
    print(f"{os.path.basename(path):28s} {os.path.getsize(path):7d} B  {len(res.filaments)} filaments  "
          f"{time.perf_counter() - t0:5.1f} s")


def main() -> int:
    os.makedirs(OUT, exist_ok=True)
    if sys.argv[1:] == ["tube"]:  # only the stepped-tube pictures
        for section in ("eigenvector", "unit"):
            tube_stripes(section)
        return 0
    if sys.argv[1:] == ["fingerprint"]:  # only the fingerprint
        fingerprint()
        return 0
    for n in (1, 2, 4):
        for s in (-1.0, 0.0, 1.0):
            picture(f"spot-n{n}-s{s:+.0f}", "spot.obj", SPOT_VIEW, n=n, s=s)
    picture("spot-n4-curvature", "spot.obj", SPOT_VIEW, n=4, align="curvature")
    picture("saddle-n4-boundary", "saddle.obj", SADDLE_VIEW, n=4, align="boundary", lam=-10.0)
    picture("torus-n4-s+1", "torus.obj", Camera(view=(0.4, -1.0, 1.4), up=(0.0, 0.0, 1.0), size=SIZE), n=4, s=1.0)
    stripes("stripes-spot-smoothest", SPOT_VIEW, n=2, spacing=6.0)
    stripes("stripes-spot-curvature", SPOT_VIEW, n=2, spacing=8.0, align="curvature")
    for section in ("eigenvector", "unit"):
        tube_stripes(section)
    fingerprint()
    for kind in ("ring", "linked-rings", "trefoil"):
        filaments(f"vortex-{kind}", kind)
    return 0


if __name__ == "__main__":
    sys.exit(main())
