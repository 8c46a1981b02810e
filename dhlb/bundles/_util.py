"""Deprecated home of three helpers, kept as plain re-exports for callers outside dhlb.bundles.

``simplex_name`` lives in :mod:`dhlb.topology._names`, ``coboundary`` is
:func:`dhlb.topology._incidence.coboundary_values`, ``wrap_angle`` is :func:`dhlb.forms.wrap_angle`.
Nothing in dhlb.bundles imports this module; delete it once dhlb/surface/prescribed.py does not.
"""

from dhlb.forms.groups import wrap_angle
from dhlb.topology._incidence import coboundary_values as coboundary
from dhlb.topology._names import simplex_name

__all__ = ["coboundary", "simplex_name", "wrap_angle"]
