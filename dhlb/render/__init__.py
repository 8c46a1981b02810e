"""Layer 6: pictures (need matplotlib).

Direction fields (:func:`render_field_png`), stripe patterns (:func:`render_stripes_png`), vortex
filaments (:func:`render_filaments_png`) and an HTML gallery.
"""

from dhlb.render.filaments_png import render_filaments_png
from dhlb.render.gallery import write_gallery
from dhlb.render.png import render_field_png
from dhlb.render.stripes_png import render_stripes_png

__all__ = ["render_field_png", "render_stripes_png", "render_filaments_png", "write_gallery"]
