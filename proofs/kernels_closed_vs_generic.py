"""The closed-form element kernels (n = 2, 3) are the generic kernel: the code, checked numerically.

Run: python proofs/kernels_closed_vs_generic.py   (asserts; exits non-zero on failure).

``proofs/fast_local_closed_forms.py`` proves symbolically that the compact expressions of
``dhlb/fem/kernels_closed.py`` (``_block_2d`` / ``_block_3d``: pair reduction, diagonal, moment
series, recurrence and shift of ``dhlb/fem/_fast_moments.py``) equal Theorem 17 with the moments as
free symbols.  This script ties those expressions to the code: the registered kernels of n = 2, 3
(``dhlb.fem.kernels.KERNELS``) agree with the generic kernel (Theorem 17 with the moments as
divided differences, ``dhlb.fem.kernels.generic_kernel``) to 1e-13 relative on random simplices,
at ω -> 0 (1e-12 .. 1e-300), at near-cancelling phases and at large curvature (up to 60), and
mass-only / Dirichlet-only calls give the same entries.
"""

from __future__ import annotations

import sys
from math import factorial


def check_code():
    import numpy as np

    from dhlb.fem.kernels import KERNELS, dense, generic_kernel

    rng = np.random.default_rng(16)
    worst = 0.0
    for n in (2, 3):
        m = 60
        base = np.vstack([np.zeros(n), np.eye(n)])
        P = base + 0.3 * rng.standard_normal((m, n + 1, n))
        D = P[:, 1:] - P[:, :1]
        grads = np.concatenate([np.zeros((m, n, 1)), np.transpose(np.linalg.inv(D), (0, 2, 1))], axis=2)
        grads = np.swapaxes(grads, 1, 2)
        grads[:, 0] = -grads[:, 1:].sum(axis=1)
        gram = grads @ np.swapaxes(grads, 1, 2)
        vol = np.abs(np.linalg.det(D)) / factorial(n)
        scale = np.concatenate([10.0 ** -rng.uniform(12, 300, 20), rng.uniform(0.1, 3, 20), rng.uniform(4, 60, 20)])
        if n == 2:
            om = (scale * rng.uniform(-1, 1, m))[:, None]
        else:
            o = scale[:, None] * rng.uniform(-1, 1, (m, 3))
            o[::3, 1] = -o[::3, 0] * (1 + 1e-9)                       # near-cancelling phases
            om = np.column_stack([o[:, 0], o[:, 1], o[:, 2], o[:, 0] - o[:, 1] + o[:, 2]])
        got = KERNELS[n](gram, vol, om)
        ref = generic_kernel(gram, vol, om)
        for (xo, xd), (ro, rd) in ((got[:2], ref[:2]), (got[2:], ref[2:])):
            X, R = dense(xo, xd), dense(ro, rd)
            err = (np.abs(X - R).max(axis=(1, 2)) / np.abs(R).max(axis=(1, 2))).max()
            worst = max(worst, err)
        only_m = KERNELS[n](None, vol, om, dirichlet=False)
        only_a = KERNELS[n](gram, vol, om, mass=False)
        assert only_m[2] is None and only_a[0] is None
        assert np.abs(only_m[0] - got[0]).max() <= 1e-15 * np.abs(got[0]).max()
        assert np.array_equal(only_a[2], got[2])
    assert worst < 1e-13, worst
    print(f"registered kernels n = 2, 3 against the generic kernel: max rel. error {worst:.1e} (< 1e-13): OK")


if __name__ == "__main__":
    check_code()
    sys.exit(0)
