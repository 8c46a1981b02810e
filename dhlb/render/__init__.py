"""Layer 6: pictures. :func:`render_field_png` draws a mesh with a direction field (needs matplotlib)."""

from dhlb.render.png import render_field_png

__all__ = ["render_field_png"]
