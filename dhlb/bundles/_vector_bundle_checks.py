"""Input checks of :class:`dhlb.bundles.VectorBundle`: the transport matrices of a connection.

Private helper of :mod:`dhlb.bundles.vector_bundle`: :func:`checked_transports` validates one
invertible K×K matrix per canonical edge (orthogonal / unitary for metric bundles) in the
bundle's field and returns them with their inverses; errors name the edge in input labels.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import InvalidConnectionError
from dhlb.topology._names import simplex_name

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

    from dhlb.bundles.fields import ComplexOps, PrimeFieldOps, RealOps
    from dhlb.topology.complex import SimplicialComplex

__all__ = ["checked_transports"]


def checked_transports(
    X: SimplicialComplex, transports: ArrayLike, ops: RealOps | ComplexOps | PrimeFieldOps, metric: bool, atol: float
) -> tuple[np.ndarray, np.ndarray]:
    """``(η, η⁻¹)``, each ``(n_1, K, K)`` in the field of ``ops`` (rank-1 input ``(n_1,)`` is reshaped).

    Raises
    ------
    InvalidConnectionError
        wrong shape, a singular transport, or (``metric``) a non-orthogonal / non-unitary one
        or a metric over a finite field.
    """
    n1 = X.n_simplices(1)
    try:
        arr = np.asarray(transports)
    except (TypeError, ValueError):
        raise InvalidConnectionError("transports must be a rectangular array of shape (n_1, K, K)") from None
    if arr.ndim == 1 and arr.shape[0] == n1:
        arr = arr.reshape(n1, 1, 1)
    if arr.ndim != 3 or arr.shape[0] != n1 or arr.shape[1] != arr.shape[2] or arr.shape[1] == 0:
        raise InvalidConnectionError(
            f"transports must have shape (n_1, K, K) = ({n1}, K, K) with K >= 1 (one matrix per "
            f"canonical edge of X.simplices(1)), got shape {np.shape(transports)}"
        )
    arr = ops.asarray(arr, "transports")
    inv, bad = ops.inv(arr)
    if np.any(bad):
        e = int(np.argmax(bad))
        raise InvalidConnectionError(f"the transport on edge {simplex_name(X, 1, e)} (row {e}) is not invertible")
    if metric:
        if ops.exact:
            raise InvalidConnectionError("metric=True (orthogonal/unitary transports) needs field 'R' or 'C'")
        defect = ops.unitary_defect(arr) if n1 else np.zeros(0)
        badm = defect > atol * 10
        if np.any(badm):
            e = int(np.argmax(badm))
            kind = "orthogonal" if ops.name == "R" else "unitary"
            raise InvalidConnectionError(
                f"the transport on edge {simplex_name(X, 1, e)} (row {e}) is not {kind}: "
                f"max |ηᴴη − I| = {defect[e]:.3g} > {atol * 10:.3g}"
            )
    return arr, inv
