"""How to install an optional part of dhlb, in words that work from a clone of the repository.

dhlb is installed from its source tree (``pip install .``), so ``pip install "dhlb[view]"`` would ask
the package index for a dhlb it does not have; the package itself always installs, and the extra
does from the clone.

Examples
--------
>>> print(install_hint("polyscope", "view"))
pip install polyscope (or dhlb's extra: pip install ".[view]" in a clone of dhlb)
"""

from __future__ import annotations

__all__ = ["install_hint"]


def install_hint(package: str, extra: str) -> str:
    """``pip install PACKAGE``, and dhlb's extra ``EXTRA`` as it installs from a clone."""
    return f'pip install {package} (or dhlb\'s extra: pip install ".[{extra}]" in a clone of dhlb)'
