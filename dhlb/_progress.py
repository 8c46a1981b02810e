"""Progress bars for long steps: tqdm on stderr when installed and the step is expected to take > ~2 s.

Silent when ``progress`` is False, when tqdm is missing, or when the estimate is short; the API
default is silent (callers pass ``progress=True``; the CLI passes ``not (args.quiet or args.json)``).

Examples
--------
>>> with progress_bar(10, "assembly", progress=False) as bar:
...     for _ in range(10):
...         bar.update(1)
>>> bar.n
10
"""

from __future__ import annotations

import sys

__all__ = ["MIN_SECONDS", "progress_bar"]

MIN_SECONDS = 2.0
"""Steps estimated to take less than this many seconds show no bar."""


class _Silent:
    """The no-op bar: counts, prints nothing."""

    def __init__(self, total):
        self.total, self.n = total, 0

    def update(self, k: int = 1) -> None:
        """Advance by ``k``."""
        self.n += k

    def set_postfix_str(self, s: str) -> None:
        """Ignored."""

    def close(self) -> None:
        """Nothing to close."""

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False


def progress_bar(total: int | None, desc: str, *, progress: bool = False, estimate_seconds: float | None = None,
                 unit: str = "it"):
    """A context-manager bar with ``update(k)``: tqdm on stderr, or a silent counter.

    Parameters
    ----------
    total : int or None
        Number of steps (None: unknown).
    desc : str
        Label, e.g. ``"factorization"``.
    progress : bool
        False: always silent.
    estimate_seconds : float, optional
        Expected duration (from the problem size); below :data:`MIN_SECONDS` the bar is silent.
        None means "long enough".
    unit : str

    Returns
    -------
    object
        With ``update(k)``, ``n`` and the context-manager protocol.

    Examples
    --------
    >>> type(progress_bar(5, "x", progress=True, estimate_seconds=0.1)).__name__   # too short to show
    '_Silent'
    """
    if not progress or (estimate_seconds is not None and estimate_seconds < MIN_SECONDS):
        return _Silent(total)
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return _Silent(total)
    return tqdm(total=total, desc=desc, unit=unit, file=sys.stderr, leave=False, dynamic_ncols=True)
