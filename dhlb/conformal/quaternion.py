r"""Quaternions as float arrays ``(..., 4)`` = ``w + x i + y j + z k``, and their matrix pictures.

* algebra: :func:`qmul` (Hamilton product), :func:`qconj`, :func:`qnorm`, :func:`qnormalize`,
  :func:`qexp` / :func:`qlog` (exponential of any quaternion, principal logarithm of a unit one);
* R³ = Im H: :func:`imag` (``v ↦ 0 + v``), :func:`sandwich_matrix` (the rotation ``X ↦ q̄ X q``);
* H ≅ C² with the **right** complex structure (``J q = q i``): :func:`to_c2` writes
  ``q = z₁ + j z₂`` with ``z₁ = w + x i``, ``z₂ = y − z i``; then left multiplication by
  ``p = α + j β`` is the C-linear map with matrix :func:`su2_matrix` ``[[α, −β̄], [β, ᾱ]]`` ∈ SU(2)
  (``proofs/derive_conformal_quaternion.py``);
* H ≅ R⁴: :func:`left_matrix`, :func:`right_matrix` (``q ↦ p q``, ``q ↦ q p``), and
  :func:`so4_matrix` (``q ↦ p q r̄``, every element of SO(4) is one, for unit ``p``, ``r``).

For imaginary ``a, b``: ``a b = −a·b + a × b``, so ``a b − b a = 2 a × b``.

Examples
--------
>>> import numpy as np
>>> from dhlb.conformal.quaternion import qmul, qexp, to_c2, su2_matrix
>>> i, j = np.array([0., 1, 0, 0]), np.array([0., 0, 1, 0])
>>> qmul(i, j).tolist()                                        # i j = k
[0.0, 0.0, 0.0, 1.0]
>>> bool(np.allclose(qexp([0, np.pi / 2, 0, 0]), i))           # exp(π i / 2) = i
True
>>> p, q = np.array([0.5, 0.5, 0.5, 0.5]), np.array([1.0, 2, 3, 4])
>>> bool(np.allclose(su2_matrix(p) @ to_c2(q), to_c2(qmul(p, q))))
True
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from dhlb.errors import NonFiniteError, ShapeError

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["as_quaternions", "imag", "left_matrix", "qconj", "qexp", "qlog", "qmul", "qnorm", "qnormalize",
           "right_matrix", "sandwich_matrix", "so4_matrix", "su2_matrix", "from_c2", "to_c2"]


def as_quaternions(q: ArrayLike, name: str = "q") -> np.ndarray:
    """``q`` as a float64 array of shape ``(..., 4)``; raises on a wrong last axis or NaN/inf.

    The other functions of this module do not check their input; call this one first on user data.

    Parameters
    ----------
    q : (..., 4) float array
        Quaternions ``(w, x, y, z)``.
    name : str, optional
        How the error message calls ``q``.

    Returns
    -------
    (..., 4) float array
        ``q`` as float64.

    Raises
    ------
    ShapeError
        ``q`` is a scalar or its last axis does not have length 4.
    NonFiniteError
        ``q`` contains NaN or inf.

    Examples
    --------
    >>> as_quaternions([1, 0, 0, 0]).dtype
    dtype('float64')
    >>> as_quaternions([1, 0, 0])
    Traceback (most recent call last):
    ...
    dhlb.errors.ShapeError: q must have shape (..., 4) (w, x, y, z), got (3,)
    """
    a = np.asarray(q, dtype=np.float64)
    if a.ndim == 0 or a.shape[-1] != 4:
        raise ShapeError(f"{name} must have shape (..., 4) (w, x, y, z), got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise NonFiniteError(f"{name} contains NaN or inf")
    return a


def qmul(p: ArrayLike, q: ArrayLike) -> np.ndarray:
    """Hamilton product ``p q`` (broadcasting over leading axes).

    Parameters
    ----------
    p : (..., 4) float array
        The left factors.
    q : (..., 4) float array
        The right factors.

    Returns
    -------
    (..., 4) float array
        The products, over the broadcast leading axes.

    Examples
    --------
    >>> qmul([0, 0, 1, 0], [0, 1, 0, 0]).tolist()               # j i = −k
    [0.0, 0.0, 0.0, -1.0]
    """
    p, q = np.asarray(p, dtype=np.float64), np.asarray(q, dtype=np.float64)
    pw, px, py, pz = np.moveaxis(p, -1, 0)
    qw, qx, qy, qz = np.moveaxis(q, -1, 0)
    return np.stack([pw * qw - px * qx - py * qy - pz * qz,
                     pw * qx + px * qw + py * qz - pz * qy,
                     pw * qy - px * qz + py * qw + pz * qx,
                     pw * qz + px * qy - py * qx + pz * qw], axis=-1)


def qconj(q: ArrayLike) -> np.ndarray:
    """Conjugate ``q̄ = w − x i − y j − z k``.

    Parameters
    ----------
    q : (..., 4) float array
        Quaternions.

    Returns
    -------
    (..., 4) float array
        Their conjugates.

    Examples
    --------
    >>> qconj([1.0, 2.0, 3.0, 4.0]).tolist()
    [1.0, -2.0, -3.0, -4.0]
    """
    q = np.asarray(q, dtype=np.float64)
    return q * np.array([1.0, -1.0, -1.0, -1.0])


def qnorm(q: ArrayLike) -> np.ndarray:
    """``|q| = sqrt(q q̄)``.

    Parameters
    ----------
    q : (..., 4) float array
        Quaternions.

    Returns
    -------
    (...) float array
        Their norms (a float array of shape ``()`` for one quaternion).

    Examples
    --------
    >>> float(qnorm([1.0, 2.0, 2.0, 4.0]))
    5.0
    """
    return np.linalg.norm(np.asarray(q, dtype=np.float64), axis=-1)


def qnormalize(q: ArrayLike) -> np.ndarray:
    """``q / |q|`` (a zero quaternion raises :class:`~dhlb.errors.NonFiniteError`).

    Parameters
    ----------
    q : (..., 4) float array
        Nonzero quaternions.

    Returns
    -------
    (..., 4) float array
        The unit quaternions ``q / |q|``.

    Raises
    ------
    NonFiniteError
        Some ``q`` is zero.

    Examples
    --------
    >>> qnormalize([0.0, 3.0, 0.0, 4.0]).tolist()
    [0.0, 0.6, 0.0, 0.8]
    """
    q = np.asarray(q, dtype=np.float64)
    n = qnorm(q)
    if np.any(n == 0):
        raise NonFiniteError("cannot normalize the zero quaternion")
    return q / n[..., None]


def imag(v: ArrayLike) -> np.ndarray:
    """The imaginary quaternion ``0 + v`` of vectors ``v`` of shape ``(..., 3)``.

    Parameters
    ----------
    v : (..., 3) float array
        Vectors of R³.

    Returns
    -------
    (..., 4) float array
        ``(0, v_x, v_y, v_z)``.

    Raises
    ------
    ShapeError
        ``v`` is a scalar or its last axis does not have length 3.

    Examples
    --------
    >>> imag([1.0, 2.0, 3.0]).tolist()
    [0.0, 1.0, 2.0, 3.0]
    """
    v = np.asarray(v, dtype=np.float64)
    if v.ndim == 0 or v.shape[-1] != 3:
        raise ShapeError(f"v must have shape (..., 3), got {v.shape}")
    return np.concatenate([np.zeros(v.shape[:-1] + (1,)), v], axis=-1)


def _sinc(t: np.ndarray) -> np.ndarray:
    """``sin t / t`` (1 at 0; Taylor series below 1e-4, where it is exact to round-off)."""
    small = np.abs(t) < 1e-4
    ts = np.where(small, 1.0, t)
    return np.where(small, 1.0 - t * t / 6.0, np.sin(ts) / ts)


def qexp(q: ArrayLike) -> np.ndarray:
    """``exp(q) = e^w (cos|v| + sin|v| v/|v|)`` for ``q = w + v`` (v imaginary).

    For imaginary ``v`` the result is a unit quaternion; ``t ↦ exp(t v) p`` solves ``ψ' = v ψ``.

    Parameters
    ----------
    q : (..., 4) float array
        Quaternions.

    Returns
    -------
    (..., 4) float array
        Their exponentials.

    Examples
    --------
    >>> import numpy as np
    >>> bool(np.allclose(qexp([0.0, 0.0, 0.0, np.pi]), [-1, 0, 0, 0]))   # exp(π k) = −1
    True
    >>> qexp([0.0, 0.0, 0.0, 0.0]).tolist()
    [1.0, 0.0, 0.0, 0.0]
    """
    q = np.asarray(q, dtype=np.float64)
    v = q[..., 1:]
    t = np.linalg.norm(v, axis=-1)
    s = _sinc(t)
    out = np.concatenate([np.cos(t)[..., None], s[..., None] * v], axis=-1)
    return np.exp(q[..., 0])[..., None] * out


def qlog(q: ArrayLike) -> np.ndarray:
    """Principal logarithm of a nonzero quaternion: ``log|q| + θ v/|v|`` with ``θ ∈ [0, π]``.

    Parameters
    ----------
    q : (..., 4) float array
        Nonzero quaternions.

    Returns
    -------
    (..., 4) float array
        Their principal logarithms, ``qexp(qlog(q)) = q``. A negative real ``q`` (``v = 0``,
        ``θ = π``) has a logarithm ``log|q| + π u`` for every unit imaginary ``u``; the one returned
        is ``u = i``, as for complex numbers (``log(−1) = iπ``, with ``w + x i`` the complex plane).

    Raises
    ------
    NonFiniteError
        Some ``q`` is zero.

    Examples
    --------
    >>> import numpy as np
    >>> bool(np.allclose(qlog(qexp([0.3, 0.1, -0.2, 0.4])), [0.3, 0.1, -0.2, 0.4]))
    True
    >>> (qlog([-2.0, 0, 0, 0]) - [np.log(2), np.pi, 0, 0]).round(12).tolist()
    [0.0, 0.0, 0.0, 0.0]
    """
    q = np.asarray(q, dtype=np.float64)
    n = qnorm(q)
    if np.any(n == 0):
        raise NonFiniteError("the logarithm of the zero quaternion is undefined")
    v = q[..., 1:]
    s = np.linalg.norm(v, axis=-1)
    theta = np.arctan2(s, q[..., 0])
    scale = np.where(s > 0, theta / np.where(s > 0, s, 1.0), 1.0 / n)
    out = np.concatenate([np.log(n)[..., None], scale[..., None] * v], axis=-1)
    out[..., 1] += np.where((s == 0) & (q[..., 0] < 0), np.pi, 0.0)   # log(−r) = log r + iπ
    return out


def to_c2(q: ArrayLike) -> np.ndarray:
    """``(z₁, z₂)`` with ``q = z₁ + j z₂``: ``z₁ = w + x i``, ``z₂ = y − z i`` (shape ``(..., 2)`` complex).

    Right multiplication by ``i`` becomes multiplication of ``(z₁, z₂)`` by ``i``, and
    ``|q|² = |z₁|² + |z₂|²``.

    Parameters
    ----------
    q : (..., 4) float array
        Quaternions.

    Returns
    -------
    (..., 2) complex array
        ``(z₁, z₂)``.

    Examples
    --------
    >>> to_c2([1.0, 2.0, 3.0, 4.0]).tolist()
    [(1+2j), (3-4j)]
    """
    q = np.asarray(q, dtype=np.float64)
    return np.stack([q[..., 0] + 1j * q[..., 1], q[..., 2] - 1j * q[..., 3]], axis=-1)


def from_c2(z: ArrayLike) -> np.ndarray:
    """Inverse of :func:`to_c2`.

    Parameters
    ----------
    z : (..., 2) complex array
        Pairs ``(z₁, z₂)``.

    Returns
    -------
    (..., 4) float array
        The quaternions ``z₁ + j z₂``.

    Raises
    ------
    ShapeError
        ``z`` is a scalar or its last axis does not have length 2.

    Examples
    --------
    >>> from_c2([1 + 2j, 3 - 4j]).tolist()
    [1.0, 2.0, 3.0, 4.0]
    """
    z = np.asarray(z, dtype=np.complex128)
    if z.ndim == 0 or z.shape[-1] != 2:
        raise ShapeError(f"z must have shape (..., 2), got {z.shape}")
    return np.stack([z[..., 0].real, z[..., 0].imag, z[..., 1].real, -z[..., 1].imag], axis=-1)


def su2_matrix(p: ArrayLike) -> np.ndarray:
    """The complex 2×2 matrix of ``q ↦ p q`` in the coordinates of :func:`to_c2`: ``[[α, −β̄], [β, ᾱ]]``.

    ``p = α + j β`` (``α = w + x i``, ``β = y − z i``); for unit ``p`` the matrix is in SU(2).

    Parameters
    ----------
    p : (..., 4) float array
        Quaternions.

    Returns
    -------
    (..., 2, 2) complex array
        The matrix of left multiplication by each ``p``.

    Examples
    --------
    >>> su2_matrix([0.0, 0.0, 1.0, 0.0]).real.tolist()     # p = j: α = 0, β = 1
    [[0.0, -1.0], [1.0, 0.0]]
    """
    ab = to_c2(p)
    a, b = ab[..., 0], ab[..., 1]
    return np.stack([np.stack([a, -b.conj()], axis=-1), np.stack([b, a.conj()], axis=-1)], axis=-2)


def left_matrix(p: ArrayLike) -> np.ndarray:
    """Real 4×4 matrix of ``q ↦ p q`` (orthogonal for unit ``p``).

    Parameters
    ----------
    p : (..., 4) float array
        Quaternions.

    Returns
    -------
    (..., 4, 4) float array
        The matrix of left multiplication by each ``p``.

    Examples
    --------
    >>> import numpy as np
    >>> p, q = np.array([1.0, 2, 3, 4]), np.array([0.5, -1, 2, 0])
    >>> bool(np.allclose(left_matrix(p) @ q, qmul(p, q)))
    True
    """
    w, x, y, z = np.moveaxis(np.asarray(p, dtype=np.float64), -1, 0)
    return np.stack([np.stack([w, -x, -y, -z], -1), np.stack([x, w, -z, y], -1),
                     np.stack([y, z, w, -x], -1), np.stack([z, -y, x, w], -1)], axis=-2)


def right_matrix(p: ArrayLike) -> np.ndarray:
    """Real 4×4 matrix of ``q ↦ q p``.

    Parameters
    ----------
    p : (..., 4) float array
        Quaternions.

    Returns
    -------
    (..., 4, 4) float array
        The matrix of right multiplication by each ``p``.

    Examples
    --------
    >>> import numpy as np
    >>> p, q = np.array([1.0, 2, 3, 4]), np.array([0.5, -1, 2, 0])
    >>> bool(np.allclose(right_matrix(p) @ q, qmul(q, p)))
    True
    """
    w, x, y, z = np.moveaxis(np.asarray(p, dtype=np.float64), -1, 0)
    return np.stack([np.stack([w, -x, -y, -z], -1), np.stack([x, w, z, -y], -1),
                     np.stack([y, -z, w, x], -1), np.stack([z, y, -x, w], -1)], axis=-2)


def so4_matrix(p: ArrayLike, r: ArrayLike) -> np.ndarray:
    """Real 4×4 matrix of ``q ↦ p q r̄``; for unit ``p, r`` it lies in SO(4) (and every rotation of R⁴ is one).

    Parameters
    ----------
    p : (..., 4) float array
        The left factors.
    r : (..., 4) float array
        The right factors (conjugated).

    Returns
    -------
    (..., 4, 4) float array
        The matrices, over the broadcast leading axes.

    Examples
    --------
    >>> import numpy as np
    >>> R = so4_matrix(qnormalize([1.0, 2, 0, 1]), qnormalize([0.0, 1, 1, 3]))
    >>> bool(np.allclose(R @ R.T, np.eye(4))), round(float(np.linalg.det(R)), 12)
    (True, 1.0)
    """
    return left_matrix(p) @ right_matrix(qconj(r))


def sandwich_matrix(q: ArrayLike) -> np.ndarray:
    """3×3 matrix of ``X ↦ q̄ X q / |q|²`` on imaginary quaternions (a rotation, SO(3)).

    Parameters
    ----------
    q : (..., 4) float array
        Nonzero quaternions (a zero one gives NaN entries).

    Returns
    -------
    (..., 3, 3) float array
        The rotation matrices, acting on ``(x, y, z)`` column vectors.

    Examples
    --------
    >>> import numpy as np
    >>> q = qexp([0.0, 0.0, 0.0, np.pi / 4])                  # X ↦ q̄ X q turns by −π/2 about k
    >>> sandwich_matrix(q).round(12).tolist()
    [[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
    """
    q = np.asarray(q, dtype=np.float64)
    M = right_matrix(q) @ left_matrix(qconj(q))
    return M[..., 1:, 1:] / (qnorm(q) ** 2)[..., None, None]
