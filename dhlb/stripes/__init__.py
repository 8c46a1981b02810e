"""Layer 5 application: stripe patterns on surfaces (seed part 2).

:func:`stripe_form` turns directions and frequencies into the edge 1-form ω̂, the relative
orientations ``s_ij`` of line-field representatives, the branch triangles and the double-cover
bundle (a real rank-2 :class:`~dhlb.bundles.VectorBundle` with rotation/reflection transports);
the finite-element engine (:mod:`dhlb.fem`) turns that bundle into ``A ψ = λ M ψ``.
:func:`texture_coordinates` turns a section ψ into per-corner coordinates α with the frequency
adjustment, zero indices, the nonlinear interpolant lArg and the subdivision of branch triangles
(§4.3); :func:`isolines` extracts the curves ``α ≡ c``; :mod:`dhlb.io.stripes` writes OBJ + JSON.
:func:`stripe_pattern` runs the whole pipeline (energy of :mod:`.energy`, smallest eigenpair, texture), its
method knobs in :class:`StripeOptions` (the section step in :class:`SectionOptions`).

Examples
--------
>>> import numpy as np
>>> from dhlb.mesh import validate_surface
>>> from dhlb.stripes import stripe_form, texture_coordinates
>>> V = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
>>> form = stripe_form(validate_surface(V, [[0, 1, 2], [1, 3, 2]]), np.tile([1.0, 0, 0], (4, 1)), frequency=0.25)
>>> tex = texture_coordinates(form, np.exp(0.5j * np.pi * np.array(V)[:, 0]))   # ψ = exp(i ν x), ν = 2π/4
>>> float(tex.evaluate([0], [[0.2, 0.5, 0.3]])[0] / (np.pi / 2))            # α = ν x at x = 0.5
0.5
"""

from dhlb.stripes.energy import stripe_matrices
from dhlb.stripes.isolines import Isolines, isolines
from dhlb.stripes.oneform import DoubleCover, StripeForm, stripe_form
from dhlb.stripes.options import SectionOptions, StripeOptions
from dhlb.stripes.pattern import StripePattern, stripe_pattern
from dhlb.stripes.texture import StripeTexture, Subdivision, larg, texture_coordinates

__all__ = ["DoubleCover", "StripeForm", "stripe_form", "StripeTexture", "Subdivision", "larg", "texture_coordinates",
           "Isolines", "isolines", "stripe_matrices", "StripePattern",
           "stripe_pattern", "StripeOptions", "SectionOptions"]


def __getattr__(name):
    # deprecated: the writers moved to the io layer (dhlb.io.stripes)
    if name in ("stripes_sidecar", "write_stripes_obj"):
        from dhlb.stripes import output

        return getattr(output, name)
    raise AttributeError(f"module 'dhlb.stripes' has no attribute {name!r}")
