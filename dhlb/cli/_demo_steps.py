"""The computations of ``dhlb demo`` (one function per step; each returns summary records).

A record is a dict with ``step``, ``mesh``, ``result``, ``check`` (human-readable), ``ok`` (the
check passed), ``seconds``, ``picture`` / ``caption`` and ``details`` (JSON-ready numbers).
"""

from __future__ import annotations

import json
import os
import time

import numpy as np

from dhlb._files import atomic_write
from dhlb.io.results import FIELD_NPZ_NOTE as NPZ_NOTE
from dhlb.io.results import write_field_npz
from dhlb.render import CONFORMAL_CAMERA, FILAMENT_CAMERA, Camera
from dhlb.render._figure import plural

__all__ = ["fields", "aligned", "boundary", "stripes", "vortex", "write_field_npz", "NPZ_NOTE"]

_SPOT_VIEW = Camera(view=(1.0, 0.6, 0.4), up=(0.0, 1.0, 0.0), size=(600, 600))


def _signed(s: float) -> str:
    """``s`` of the energy E_s for a caption: ``0``, ``+1``, ``-1`` (no ``+0``)."""
    return "0" if s == 0 else f"{s:+g}"


def _back_path(png: str) -> str:
    return png[:-4] + "-back.png"


def view_angles(points) -> dict:
    """Camera directions of the polyscope views of a result: the fitted view and three turns about ``up``.

    ``front`` is :meth:`dhlb.render.Camera.fitted` (as in the PNG pictures), ``back`` walks around
    the model, ``left`` and ``right`` a quarter turn; all from the same height above it.

    Parameters
    ----------
    points : (k, 3) float array

    Returns
    -------
    dict
        ``{"front": (3,), "back": (3,), "left": (3,), "right": (3,)}`` directions toward the camera.
    """
    from dhlb.render._figure import up_vector

    cam = Camera().fitted(points)
    v, u = np.asarray(cam.view, dtype=np.float64), up_vector(cam.up)
    height, across = (v @ u) * u, np.cross(u, v - (v @ u) * u)
    return {"front": v, "back": np.asarray(cam.behind(points).view), "left": height + across,
            "right": height - across}


def _views(res, out: str, name: str) -> str | None:
    """A page of polyscope renderings of ``res`` from several angles, where the environment allows it.

    Needs polyscope (``dhlb[view]``) and a headless OpenGL (EGL); returns the page's path, or None
    (then the demo page shows the matplotlib pictures only).
    """
    from dhlb.errors import DhlbError
    from dhlb.render.gallery import write_gallery

    try:
        from dhlb.render.view import show
    except ImportError:
        return None
    shots = []
    for label, view in view_angles(res.mesh.points).items():
        path = os.path.join(out, f"{name}-3d-{label}.png")
        try:
            shots.append((show(res, screenshot=path, view=view, size=(480, 480)), f"{name}: {label}"))
        except (ImportError, DhlbError, RuntimeError):
            return None
    return write_gallery(os.path.join(out, f"{name}-views.html"), f"{name}: polyscope views", shots)


def _web(res, out: str, name: str, camera=None) -> str | None:
    """The interactive view of ``res`` beside its PNG (``NAME.html``, sharing ``plotly.min.js``), if plotly is there.

    It opens with the camera of the PNG. Without the extra ``dhlb[web]`` the demo page shows the
    pictures only (and says so).
    """
    try:
        from dhlb.render.web import to_html

        return to_html(res, os.path.join(out, f"{name}.html"), plotlyjs="directory", camera=camera)
    except ImportError:
        return None


def _spot():
    from dhlb.io import example_path, read_surface

    return read_surface(example_path("spot.obj"))


def _field_record(step, res, png, caption, seconds, mesh_name) -> dict:
    ok = res.index_sum == round(res.poincare_hopf)
    closed = res.mesh.is_closed
    expected = res.n * res.euler_characteristic if closed else res.poincare_hopf
    ok = ok and (not closed or res.index_sum == expected)
    check = (f"Σ index = {res.index_sum} = nχ = {res.n}·{res.euler_characteristic}" if closed else
             f"Σ index = {res.index_sum} = (ΣΩ + rotation)/2π = {res.poincare_hopf:.6f}")
    step = f"{step} n={res.n} s={_signed(res.s)}"
    return {"step": step, "mesh": f"{mesh_name} ({res.mesh.n_vertices} v, {res.mesh.n_faces} f)",
            "result": plural(len(res.singularities.faces), "singularity", "singularities"), "check": check,
            "ok": bool(ok),
            "seconds": seconds, "picture": png, "caption": caption,
            "details": {k: v for k, v in res.to_json().items() if k != "singularities"}}


def _field(out, progress, name, V, F, mesh_name, caption, view, **kw):
    from dhlb.fields import direction_field
    from dhlb.render import render_field_png

    def work():
        t0 = time.perf_counter()
        res = direction_field(V, F, **kw)
        m = res.mesh
        png = render_field_png(os.path.join(out, f"{name}.png"), m.points, m.faces, res.directions,
                               res.singularities, title=caption, camera=view)
        render_field_png(_back_path(png), m.points, m.faces, res.directions, res.singularities,
                         title=caption + " (back)", camera=view.behind(m.points))
        write_field_npz(os.path.join(out, f"{name}.npz"), res)  # the layout of dhlb field
        return res, png, time.perf_counter() - t0

    res, png, sec = progress.run(caption, work)
    return {**_field_record(name.split("-")[0], res, png, caption, sec, mesh_name), "views": _views(res, out, name),
            "web": _web(res, out, name, view)}


def fields(out, progress, *, backend=None) -> list[dict]:
    """Smoothest fields on Spot for n = 1, 2, 4 and s = −1, 0, +1."""
    V, F = _spot()
    recs = []
    for n in (1, 2, 4):
        for s in (-1.0, 0.0, 1.0):
            recs.append(_field(out, progress, f"field-n{n}-s{s:+.0f}", V, F, "spot",
                               f"smoothest {n}-direction field, s = {_signed(s)}", _SPOT_VIEW, n=n, s=s,
                               solver=backend))
    return recs


def aligned(out, progress, *, backend=None) -> list[dict]:
    """The curvature-aligned cross field on Spot (λ = 0)."""
    V, F = _spot()
    return [_field(out, progress, "aligned-curvature-n4", V, F, "spot",
                   "cross field aligned to principal curvature (λ = 0)", _SPOT_VIEW, n=4, align="curvature",
                   solver=backend)]


def boundary(out, progress, *, backend=None) -> list[dict]:
    """A boundary-aligned cross field on the saddle disk: Poincaré–Hopf with boundary."""
    from dhlb.io import example_path, read_surface

    V, F = read_surface(example_path("saddle.obj"))
    view = Camera(view=(0.3, -1.0, 1.2), up=(0.0, 0.0, 1.0), size=(600, 600))
    caption = "cross field aligned to the boundary (λ = −10), saddle disk"
    return [_field(out, progress, "boundary-n4", V, F, "saddle", caption, view, n=4, align="boundary", lam=-10.0,
                   solver=backend)]


def stripes(out, progress, *, backend=None) -> list[dict]:
    """A stripe pattern on Spot following its smoothest line field."""
    from dhlb.fields import direction_field
    from dhlb.io.stripes import write_stripes_obj
    from dhlb.render.stripes_png import render_stripes_png
    from dhlb.stripes import stripe_pattern

    V, F = _spot()
    caption = "stripe pattern along the smoothest line field (spacing 6 mean edge lengths)"

    def work():
        t0 = time.perf_counter()
        field = direction_field(V, F, n=2, solver=backend)
        res = stripe_pattern(V, F, field, spacing=6.0, solver=backend)
        png = render_stripes_png(os.path.join(out, "stripes.png"), res.texture, title=caption, camera=_SPOT_VIEW)
        render_stripes_png(_back_path(png), res.texture, title=caption + " (back)",
                           camera=_SPOT_VIEW.behind(res.mesh.points))
        write_stripes_obj(os.path.join(out, "stripes.obj"), res.texture)
        return res, png, time.perf_counter() - t0

    res, png, sec = progress.run(caption, work)
    info = res.to_json()
    n_zero, n_branch = len(info["zero_faces"]), len(info["branch_faces"])
    return [{"step": "stripes", "mesh": f"spot ({len(V)} v, {len(F)} f)",
             "result": f"{n_zero} zero faces, {n_branch} branch faces", "check": "continuous texture",
             "ok": True, "seconds": sec, "picture": png, "caption": caption, "views": _views(res, out, "stripes"),
             "web": _web(res, out, "stripes", _SPOT_VIEW),
             "details": {"zero_faces": n_zero, "branch_faces": n_branch, "timings": info.get("timings", {})}}]


def vortex(out, progress, *, backend=None) -> list[dict]:
    """Vortex filaments of a vortex ring and of two linked rings in a tetrahedral cube (ħ = 1)."""
    from dhlb.cli.vortex import demo_velocity
    from dhlb.io.polylines import write_polylines_obj
    from dhlb.mesh import box_tet_mesh
    from dhlb.render.filaments_png import render_filaments_png
    from dhlb.vortex import vortex_filaments

    recs = []
    mesh = box_tet_mesh(12, lower=-1.0, upper=1.0)      # what "box 12" names (dhlb vortex --box 12)
    cases = [("vortex-ring", "ring", "a vortex ring (ħ = 1): one closed filament", 1, None),
             ("vortex-linked", "linked-rings", "two linked rings (ħ = 1): two filaments, linking number ±1", 2, 1)]
    for name, kind, caption, n_expected, link_expected in cases:
        def work(name=name, kind=kind, caption=caption):
            t0 = time.perf_counter()
            field, _ = demo_velocity(kind, mesh.points)
            res = vortex_filaments(mesh, None, field, 1.0, solver=backend)
            write_polylines_obj(os.path.join(out, f"{name}.obj"), res.filaments)
            with atomic_write(os.path.join(out, f"{name}.json")) as fh:   # as dhlb vortex: names the domain
                json.dump({"mesh": "box 12", "velocity": kind, "hbar": 1.0, **res.to_json()}, fh, indent=1)
            png = render_filaments_png(os.path.join(out, f"{name}.png"), res.filaments, res.mesh.points,
                                       res.mesh.boundary_faces, title=caption)
            render_filaments_png(_back_path(png), res.filaments, res.mesh.points, res.mesh.boundary_faces,
                                 title=caption + " (back)", camera=FILAMENT_CAMERA.behind(res.mesh.points))
            return res, png, time.perf_counter() - t0

        res, png, sec = progress.run(caption, work)
        closed = [f for f in res.filaments if f.closed]
        L = np.asarray(res.linking_numbers)
        ok = len(closed) == n_expected and (link_expected is None or (L.shape == (2, 2) and abs(int(L[0, 1])) == 1))
        check = f"{n_expected} closed" + ("" if link_expected is None else ", |linking number| = 1")
        result = f"{plural(len(res.filaments), 'filament')} ({len(closed)} closed)"
        if L.shape == (2, 2):
            result += f", linking {int(L[0, 1])}"
        recs.append({"step": "vortex " + kind, "mesh": f"cube ({len(mesh.points)} v, {len(mesh.tets)} tets)",
                     "result": result, "check": check, "ok": bool(ok), "seconds": sec, "picture": png,
                     "views": _views(res, out, name), "web": _web(res, out, name, FILAMENT_CAMERA),
                     "caption": caption, "details": {"filaments": len(res.filaments), "linking_numbers": L.tolist(),
                                                     "timings": res.timings}})
    return recs


def conformal(out, progress, *, backend=None) -> list[dict]:
    """Close-to-conformal deformations (seed part 3, §2.4): a ball (Möbius, charges) and a real tet mesh (default).

    The ball is :func:`dhlb.mesh.ball_tet_mesh` under a Möbius factor and two point charges; the
    real mesh is the bundled solid Spot (``spot-tet.mesh``) under the default charge of ``dhlb conformal``.
    """
    from dhlb.conformal import conformal_deformation, default_charge, mobius_factor, point_charge_factor
    from dhlb.io import example_path, read_volume
    from dhlb.mesh import ball_tet_mesh, check_tet_mesh
    from dhlb.render import boundary_distortion, render_conformal_png

    ball = ball_tet_mesh(6)
    spot = check_tet_mesh(*read_volume(example_path("spot-tet.mesh")))
    cases = [("conformal-mobius", ball, "ball", mobius_factor((2.5, 0.0, 0.0), 1.5),
              "a Möbius factor log(R²/|x − a|²): an exactly conformal map, λ₁ ≈ 0", "Möbius"),
             ("conformal-charges", ball, "ball", point_charge_factor([(2.0, 0.0, 0.0, 0.5), (0.0, -2.0, 0.0, -0.4)]),
              "two point charges: close to conformal, λ₁ > 0", "charges"),
             ("conformal-spot", spot, "spot-tet.mesh", point_charge_factor(default_charge(spot)),
              "a real tet mesh (the solid cow Spot), the default charge of dhlb conformal", "default charge")]
    recs = []
    for name, mesh, label, u, caption, kind in cases:
        def work(name=name, mesh=mesh, u=u, caption=caption):
            t0 = time.perf_counter()
            res = conformal_deformation(mesh.points, mesh.tets, u, backend=backend)
            res.save(os.path.join(out, f"{name}.npz"))               # opens with dhlb view
            F, dF = boundary_distortion(res)
            png = render_conformal_png(os.path.join(out, f"{name}.png"), mesh.points, res.points, F, dF,
                                       title=caption)
            render_conformal_png(_back_path(png), mesh.points, res.points, F, dF, title=caption + " (back)",
                                 camera=CONFORMAL_CAMERA.behind(mesh.points))
            return res, png, time.perf_counter() - t0

        res, png, sec = progress.run(caption, work)
        if kind == "Möbius":
            ok, check = abs(res.eigenvalue) < 1e-6, "λ₁ ≈ 0 (|λ₁| < 1e-6)"
        elif kind == "charges":
            ok, check = res.eigenvalue > 1e-6 and res.distortion.min() >= 1.0, "λ₁ > 0, distortion >= 1"
        else:
            ok = res.eigenvalue > 0 and res.statistics["max_edge_angle"] <= 0.5 and np.median(res.distortion) < 1.2
            check = "λ₁ > 0, ≤ 0.5 rad per edge, median distortion < 1.2"
        recs.append({"step": "conformal " + kind,
                     "mesh": f"{label} ({len(mesh.points)} v, {len(mesh.tets)} tets)",
                     "result": f"λ₁ = {res.eigenvalue:.2g}, distortion {res.distortion.mean():.3f} mean",
                     "check": check, "ok": bool(ok),
                     "seconds": sec, "picture": png, "caption": caption,
                     "web": _web(res, out, name, CONFORMAL_CAMERA),
                     "details": {"eigenvalue": float(res.eigenvalue), "timings": res.timings}})
    return recs
