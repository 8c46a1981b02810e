"""Safe output files: :func:`atomic_write`, :func:`atomic_path`, :func:`refuse_overwrite` (from :mod:`dhlb._files`).

The primitives live at layer 0 so that every layer that writes a file uses the same one; this module is
their public name in the io layer.
"""

from dhlb._files import atomic_path, atomic_write, output_error, refuse_overwrite

__all__ = ["atomic_path", "atomic_write", "refuse_overwrite", "output_error"]
