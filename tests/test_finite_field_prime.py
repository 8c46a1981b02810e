"""The primality test of GF(p) bundles (dhlb no longer needs sympy at run time) agrees with sympy's."""

import sympy
from hypothesis import given, settings
from hypothesis import strategies as st

from dhlb.bundles.finite_field import MAX_PRIME, _is_prime


@settings(max_examples=300, deadline=None)
@given(st.one_of(st.integers(-5, 10_000), st.integers(0, MAX_PRIME - 1)))
def test_is_prime_agrees_with_sympy(q):
    assert _is_prime(q) == sympy.isprime(q)


def test_is_prime_on_hard_cases():
    for q in (2, 3, 2**31 - 1, 46337**2, 46337 * 46349, 65537 * 32749, 561, 2047, 1_373_653):
        assert _is_prime(q) == sympy.isprime(q)
