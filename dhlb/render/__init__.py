"""Layer 6: pictures (need matplotlib).

Direction fields (:func:`render_field_png`), stripe patterns (:func:`render_stripes_png`), vortex
filaments (:func:`render_filaments_png`), conformal deformations (:func:`render_conformal_png`) and an
HTML gallery. Every picture takes a :class:`Camera` and the style of its kind (:class:`FieldStyle`,
:class:`StripeStyle`, :class:`FilamentStyle`, :class:`ConformalStyle`). Interactive 3-D views:
:mod:`dhlb.render.web` (plotly, ``dhlb[web]``) and :mod:`dhlb.render.view` (polyscope, ``dhlb[view]``),
both drawing the :class:`~dhlb.render.scene.Scene` of a result; :func:`set_notebook_display` chooses
what results show in notebooks.
"""

from dhlb._result import set_notebook_display
from dhlb.render._figure import Camera, ConformalStyle, FieldStyle, FilamentStyle, StripeStyle
from dhlb.render.conformal_png import CONFORMAL_CAMERA, boundary_distortion, render_conformal_png
from dhlb.render.filaments_png import FILAMENT_CAMERA, render_filaments_png
from dhlb.render.gallery import write_gallery
from dhlb.render.png import render_field_png
from dhlb.render.stripes_png import render_stripes_png

__all__ = ["render_field_png", "render_stripes_png", "render_filaments_png", "render_conformal_png",
           "boundary_distortion", "write_gallery", "Camera", "FieldStyle", "StripeStyle", "FilamentStyle",
           "ConformalStyle", "FILAMENT_CAMERA", "CONFORMAL_CAMERA", "set_notebook_display"]
