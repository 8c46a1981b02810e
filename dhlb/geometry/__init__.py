"""Layer 4 (geometry + FEM): Euclidean simplicial complexes.

Discrete metrics, volumes, cotangent weights and P1 matrices.
"""
from dhlb.geometry.euclidean import EuclideanComplex
from dhlb.geometry.simplex import SimplexStack, metric_from_squared_lengths, squared_lengths_from_points

__all__ = ["EuclideanComplex", "SimplexStack", "metric_from_squared_lengths", "squared_lengths_from_points"]
