"""Wall time and peak resident memory of each phase of a run (the per-rank figures of the MPI drivers).

On Linux the peak resident set size (``VmHWM``) can be reset (``/proc/self/clear_refs``, value 5), so
the peak *within* each phase is measured, not only the peak since the process started; elsewhere the
process peak so far (``getrusage``) is reported for every phase.

Examples
--------
>>> import gc
>>> _ = gc.collect(); trim_heap()  # pending frees would lower the resident size inside the phase
>>> meter = PhaseMeter()
>>> x = b"x" * (50 * 2**20)         # written, so resident (a zeroed bytearray may be mapped lazily)
>>> meter.mark("allocate")
>>> sorted(meter.seconds), meter.peak_mb["allocate"] >= 50, meter.peak_mb["allocate"] - meter.start_mb["allocate"] >= 50
(['allocate'], True, True)
"""

from __future__ import annotations

import resource
import time

__all__ = ["PhaseMeter", "peak_mb", "rss_mb", "trim_heap"]


def peak_mb() -> float:
    """The peak resident memory of this process so far, in MB (``getrusage``; Linux reports kilobytes).

    Examples
    --------
    >>> peak_mb() > 0
    True
    """
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def trim_heap() -> None:
    """Return the heap's free memory to the operating system (glibc ``malloc_trim``; elsewhere nothing).

    Validating a mesh allocates many small and medium blocks; after they are freed, glibc keeps the
    memory in its arenas, so the process stays as large as at its peak (measured: 820 MB resident
    after validating and dropping a 1.3M-face mesh, 140 MB after the trim). The MPI drivers call this
    after the phases whose temporaries are large, so that the next phase starts small.

    Examples
    --------
    >>> trim_heap()
    """
    import ctypes
    import ctypes.util

    name = ctypes.util.find_library("c")
    try:
        libc = ctypes.CDLL(name) if name else None
        trim = getattr(libc, "malloc_trim", None)
    except OSError:
        trim = None
    if trim is not None:
        trim(0)


def rss_mb() -> float:
    """The resident memory now, in MB (``VmRSS``; the process peak where ``/proc`` is missing).

    Examples
    --------
    >>> 0 < rss_mb() <= peak_mb() + 1
    True
    """
    try:
        with open("/proc/self/status", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    return peak_mb()


def _hwm_mb() -> float | None:
    try:
        with open("/proc/self/status", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        return None
    return None


def _reset_hwm() -> bool:
    try:
        with open("/proc/self/clear_refs", "w", encoding="ascii") as fh:
            fh.write("5")
        return True
    except OSError:
        return False


class PhaseMeter:
    """Times phases and measures the peak resident memory within each (MB); :meth:`mark` ends a phase.

    ``peak_mb[name]`` is the largest resident memory during the phase, ``start_mb[name]`` the resident
    memory when it began (what it inherited), so ``peak_mb - start_mb`` is what the phase itself added.
    """

    def __init__(self):
        self.seconds: dict[str, float] = {}
        self.peak_mb: dict[str, float] = {}
        self.start_mb: dict[str, float] = {}    # resident memory when each phase began (what it inherited)
        self._resettable = _reset_hwm() and _hwm_mb() is not None
        self._start = rss_mb()
        self._t0 = self._t = time.perf_counter()

    def mark(self, name: str) -> None:
        """End the phase ``name`` (begun at the previous mark, or at construction) and begin the next."""
        now = time.perf_counter()
        self.seconds[name] = self.seconds.get(name, 0.0) + now - self._t
        peak = _hwm_mb() if self._resettable else peak_mb()
        self.peak_mb[name] = max(self.peak_mb.get(name, 0.0), peak if peak is not None else peak_mb())
        self.start_mb.setdefault(name, self._start)
        if self._resettable:
            _reset_hwm()
        self._start = rss_mb()
        self._t = time.perf_counter()

    @property
    def total(self) -> float:
        """Seconds since construction."""
        return time.perf_counter() - self._t0
