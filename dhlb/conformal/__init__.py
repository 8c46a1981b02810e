"""Close-to-conformal deformations of volumes (seed part 3 §2.4): a quaternionic bundle on tet meshes.

Layer 5 (an application beside :mod:`dhlb.fields`, :mod:`dhlb.stripes` and :mod:`dhlb.vortex`);
imports only the layers below (topology, bundles, geometry, fem) and the tet meshes of
:mod:`dhlb.vortex`.

* :func:`conformal_deformation` → :class:`ConformalResult` (deformed points, unit quaternions φ,
  λ₁, per-tet distortion and scale error);
* target factors: :func:`point_charge_factor`, :func:`mobius_factor`, :class:`ConformalFactor`;
* building blocks: :func:`quaternion_bundle` (the SU(2) connection as a
  :class:`dhlb.bundles.VectorBundle`), :func:`tet_connection_laplacian` (its energy, PSD on every
  mesh), :func:`edge_gradients`, :func:`tet_distortion`;
* :func:`default_charge`: a point charge scaled to the mesh (at most :data:`MAX_EDGE_ANGLE` per edge);
* :mod:`dhlb.conformal.quaternion`: quaternion algebra, H ≅ C², H ≅ R⁴ (SO(4)).

Examples
--------
>>> from dhlb.mesh import ball_tet_mesh
>>> from dhlb.conformal import conformal_deformation, mobius_factor
>>> res = conformal_deformation(ball_tet_mesh(3), None, mobius_factor((0.0, 0.0, 3.0), 2.5))
>>> res.statistics["inverted_tets"], bool(abs(res.eigenvalue) < 1e-4), bool(res.statistics["distortion_mean"] < 1.3)
(0, True, True)
"""
from dhlb.conformal import quaternion
from dhlb.conformal.deformation import (
    MAX_EDGE_ANGLE,
    ConformalResult,
    conformal_deformation,
    default_charge,
    edge_gradients,
    quaternion_bundle,
    tet_connection_laplacian,
    tet_distortion,
)
from dhlb.conformal.factors import ConformalFactor, mobius_factor, point_charge_factor

__all__ = [
    "MAX_EDGE_ANGLE", "ConformalFactor", "ConformalResult", "conformal_deformation", "default_charge",
    "edge_gradients", "mobius_factor", "point_charge_factor", "quaternion", "quaternion_bundle",
    "tet_connection_laplacian", "tet_distortion",
]
