"""Memory in one place: what is still available, refusing a parameter before the work, translating MemoryError.

A ``MemoryError`` that escapes the numeric core is turned into dhlb's own error.

* :func:`memory_budget` / :func:`available_bytes`: the least of the free memory (``MemAvailable``), the room
  under the memory limit of the process's cgroup (v2 ``memory.max`` or v1 ``memory.limit_in_bytes``, of its
  own cgroup and every ancestor, less the usage without the reclaimable file cache), the room under the
  address-space limit (``ulimit -v``, ``RLIMIT_AS``, less the address space in use, ``VmSize``) — what a
  batch scheduler sets — and a budget set by :func:`set_limit` (``dhlb.linalg.set_memory_limit``) or the
  environment variable ``DHLB_MEMORY_LIMIT``.
* :func:`check_memory`: every guard of a parameter that scales work (cells, cliques, subdivisions, the
  symmetry n, ...) compares its estimate with that budget *before* the work and raises
  :class:`~dhlb.errors.ResourceLimitError` with the estimate and the largest value that fits.
* :func:`translate_memory_errors`: a decorator for the public entry points; a ``MemoryError`` that still
  escapes (numpy's ``Unable to allocate 1.2 GiB for an array with shape ...``, a bare one from scipy) becomes
  :class:`~dhlb.errors.InsufficientMemoryError` naming the entry point, what it needed (an estimate when one
  is cheaply known, else the failed allocation), the memory available and what to do.

This module is a leaf (it imports :mod:`dhlb.errors` only), so that every layer can use it.

Examples
--------
>>> available_bytes() > 0
True
>>> check_memory("n", 10, 1e6, available=10**9)        # fits: the estimate is returned
1000000
>>> check_memory("n", 10**6, 1e14, largest=lambda room: room // 10**8, available=10**9)
Traceback (most recent call last):
...
dhlb.errors.ResourceLimitError: n = 1000000 needs about 100 TB of memory (estimate), more than the 1 GB allowed; ...
"""

from __future__ import annotations

import functools
import os
import re
import resource
from typing import TYPE_CHECKING

from dhlb.errors import InsufficientMemoryError, ResourceLimitError, format_bytes

if TYPE_CHECKING:
    from collections.abc import Callable

__all__ = ["available_bytes", "check_memory", "largest_fitting", "memory_budget", "set_limit",
           "translate_memory_errors"]

_LIMIT: int | None = None
_SMALL = 16 * 10**6   # an estimate below this never needs the look-ups (unless a budget was set)
_UNLIMITED = 2**60    # cgroup v1 writes "no limit" as a huge number (PAGE_COUNTER_MAX pages)
_CGROUP = "/sys/fs/cgroup"
_PROC_CGROUP = "/proc/self/cgroup"


def set_limit(nbytes: int | None) -> None:
    """Pretend that at most ``nbytes`` are available (``None``: drop that budget).

    Parameters
    ----------
    nbytes : int or None
        The budget in bytes, or ``None``.

    Examples
    --------
    >>> set_limit(10**6); available_bytes() <= 10**6
    True
    >>> set_limit(None)
    """
    global _LIMIT
    _LIMIT = None if nbytes is None else int(nbytes)


def env_limit() -> int | None:
    """The budget of the environment variable ``DHLB_MEMORY_LIMIT`` (bytes, or with a suffix K, M, G).

    Returns
    -------
    int or None
        The budget in bytes, or ``None`` when the variable is unset or not a number.
    """
    text = os.environ.get("DHLB_MEMORY_LIMIT", "").strip().upper().removesuffix("B")
    if not text:
        return None
    scale = {"K": 2**10, "M": 2**20, "G": 2**30, "T": 2**40}.get(text[-1], 1)
    try:
        return int(float(text.rstrip("KMGT")) * scale)
    except ValueError:
        return None


def budget_is_set() -> bool:
    """Whether :func:`set_limit` or ``DHLB_MEMORY_LIMIT`` gave a budget.

    Returns
    -------
    bool
        True when a budget was set.
    """
    return _LIMIT is not None or env_limit() is not None


def _read(path: str) -> str | None:
    try:
        with open(path) as fh:
            return fh.read()
    except OSError:
        return None


def _int(path: str) -> int | None:
    text = _read(path)
    try:
        return None if text is None else int(text.split()[0])
    except (ValueError, IndexError):
        return None


def _meminfo_available() -> int | None:
    text = _read("/proc/meminfo") or ""
    for line in text.splitlines():
        if line.startswith("MemAvailable:"):
            return int(line.split()[1]) * 1024
    return None


def _stat_value(directory: str, keys: tuple[str, ...]) -> int:
    """The first of ``keys`` in ``memory.stat`` of a cgroup directory (0 if absent)."""
    values = {}
    for line in (_read(os.path.join(directory, "memory.stat")) or "").splitlines():
        parts = line.split()
        if len(parts) == 2 and parts[0] in keys:
            values[parts[0]] = int(parts[1])
    return next((values[k] for k in keys if k in values), 0)


def _cgroup_room(directory: str, v2: bool) -> int | None:
    """Room under the memory limit of one cgroup directory (``None``: no limit there)."""
    if v2:
        top = (_read(os.path.join(directory, "memory.max")) or "max").strip()
        if top == "max":
            return None
        limit, usage = int(top), _int(os.path.join(directory, "memory.current"))
        cache = _stat_value(directory, ("inactive_file",))
    else:
        limit = _int(os.path.join(directory, "memory.limit_in_bytes"))
        if limit is None or limit >= _UNLIMITED:
            return None
        usage = _int(os.path.join(directory, "memory.usage_in_bytes"))
        cache = _stat_value(directory, ("total_inactive_file", "inactive_file"))
    return limit - max(0, (usage or 0) - cache)


def _cgroup_dirs() -> list[tuple[str, bool]]:
    """The memory cgroup directories of this process and of its ancestors: ``(directory, is_v2)``."""
    out = []
    for line in (_read(_PROC_CGROUP) or "").splitlines():
        parts = line.split(":", 2)
        if len(parts) != 3:
            continue
        hier, controllers, rel = parts
        if hier == "0" and controllers == "":
            roots = [r for r in (_CGROUP, os.path.join(_CGROUP, "unified"))
                     if os.path.exists(os.path.join(r, "cgroup.controllers"))]
            v2 = True
        elif "memory" in controllers.split(","):
            roots, v2 = [os.path.join(_CGROUP, "memory")], False
        else:
            continue
        for root in roots:
            d = os.path.normpath(root + "/" + rel.strip())
            if not os.path.isdir(d):  # another cgroup namespace: only the mount's root is ours
                d = root
            while True:
                out.append((d, v2))
                if d == root or not d.startswith(root):
                    break
                d = os.path.dirname(d)
    return out


def _cgroup_available() -> tuple[int, str] | None:
    rooms = [(room, d) for d, v2 in _cgroup_dirs() if (room := _cgroup_room(d, v2)) is not None]
    return min(rooms) if rooms else None


def _rlimit_available() -> tuple[int, int, int] | None:
    """``(room, limit, in use)`` under the address-space limit, or ``None`` without one."""
    soft, _ = resource.getrlimit(resource.RLIMIT_AS)
    if soft == resource.RLIM_INFINITY:
        return None
    used = _int("/proc/self/statm")   # the first field is VmSize, in pages
    used = 0 if used is None else used * os.sysconf("SC_PAGE_SIZE")
    return soft - used, soft, used


def memory_budget() -> tuple[int, str]:
    """The bytes this process can still allocate and what limits them.

    Returns
    -------
    nbytes : int
        The least of the figures that can be read here (at least 0); ``2**62`` when none can.
    source : str
        What gives that figure, for messages: ``"the room under the address-space limit (ulimit -v)
        of 2.5 GB"``, ``"the free memory of the machine"``, ...

    Examples
    --------
    >>> nbytes, source = memory_budget()
    >>> nbytes > 0 and isinstance(source, str)
    True
    """
    figures = []
    if (free := _meminfo_available()) is not None:
        figures.append((free, "the free memory of the machine, MemAvailable"))
    if (cg := _cgroup_available()) is not None:
        figures.append((cg[0], f"the room under the memory limit of the cgroup {cg[1]}"))
    if (rl := _rlimit_available()) is not None:
        figures.append((rl[0], f"the room under the address-space limit of {format_bytes(rl[1])} set by "
                               f"ulimit -v or RLIMIT_AS, {format_bytes(rl[2])} of it in use"))
    if _LIMIT is not None:
        figures.append((_LIMIT, "the budget of dhlb.linalg.set_memory_limit"))
    if (env := env_limit()) is not None:
        figures.append((env, "the budget of DHLB_MEMORY_LIMIT"))
    if not figures:
        return 2**62, "no figure could be read"
    nbytes, source = min(figures, key=lambda f: f[0])
    return max(0, int(nbytes)), source


def available_bytes() -> int:
    """Bytes this process can still allocate (:func:`memory_budget` without the explanation).

    Returns
    -------
    int
        The least of free memory, cgroup room, ``RLIMIT_AS`` room and a set budget, at least 0.

    Examples
    --------
    >>> isinstance(available_bytes(), int)
    True
    """
    return memory_budget()[0]


def largest_fitting(estimate: Callable[[int], float], room: float, low: int, high: int) -> int | None:
    """The largest integer ``v`` in ``[low, high]`` with ``estimate(v) <= room`` (``estimate`` increasing).

    Parameters
    ----------
    estimate : callable int -> float
        The estimated bytes of the work for a value, increasing in the value.
    room : float
        The bytes available.
    low, high : int
        The range searched.

    Returns
    -------
    int or None
        The largest fitting value, or ``None`` if not even ``low`` fits.

    Examples
    --------
    >>> largest_fitting(lambda n: 1000 * n**3, 8e9, 1, 10**6)
    200
    """
    if estimate(low) > room:
        return None
    while low < high:
        mid = (low + high + 1) // 2
        low, high = (mid, high) if estimate(mid) <= room else (low, mid - 1)
    return low


def check_memory(parameter: str, value, need: float, *, largest: Callable[[int], object] | None = None,
                 advice: str = "", available: int | None = None) -> int:
    """Refuse work whose estimated memory exceeds what is available; return the estimate.

    Parameters
    ----------
    parameter : str
        The name of the parameter that scales the work (as the caller spells it: ``"n"``, ``"max_dim"``).
    value : object
        Its value.
    need : float
        The estimated peak bytes of the work.
    largest : callable, optional
        ``largest(room)``: the largest value of ``parameter`` whose work fits in ``room`` bytes (``None``
        if none does), for the message.
    advice : str, optional
        What else to do, appended to the message.
    available : int, optional
        The bytes available (default :func:`memory_budget`).

    Returns
    -------
    int
        ``need``, as an int.

    Raises
    ------
    ResourceLimitError
        ``need`` exceeds the bytes available; the message names the parameter, its value, the estimate,
        the memory available and what limits it, and the largest value that fits.

    Examples
    --------
    >>> check_memory("m", 400, 4.5e11, largest=lambda room: 98, available=8 * 10**9)
    Traceback (most recent call last):
    ...
    dhlb.errors.ResourceLimitError: m = 400 needs about 450 GB of memory (estimate), ...; at most m = 98 fits in 8 GB...
    """
    need = int(need)
    if available is None and need < _SMALL and not budget_is_set():
        return need
    room, source = (int(available), "the budget given") if available is not None else memory_budget()
    if need <= room:
        return need
    parts = []
    fit = largest(room) if largest is not None else None
    where = f"{format_bytes(room)}, {source}"
    if largest is not None:
        parts.append(f"at most {parameter} = {fit} fits in {where}" if fit is not None
                     else f"no {parameter} fits in {where}")
    else:
        parts.append(f"{format_bytes(room)} is {source}")
    if advice:
        parts.append(advice)
    raise ResourceLimitError(parameter, value, need, room, "; ".join(parts))


_NUMPY = re.compile(r"Unable to allocate ([0-9.]+) (\w*B) for an array with shape (\(.*?\)) and data type (\S+)")
_UNITS = {"B": 1, "KiB": 2**10, "MiB": 2**20, "GiB": 2**30, "TiB": 2**40, "PiB": 2**50, "EiB": 2**60}


def failed_allocation(err: BaseException) -> tuple[int, str]:
    """The size of the allocation that failed and a description, from numpy's message (``(0, "")`` if none).

    Parameters
    ----------
    err : MemoryError
        The error.

    Returns
    -------
    nbytes : int
        The bytes numpy could not allocate (rounded as numpy prints them), 0 when the message does not say.
    text : str
        ``"numpy could not allocate 1.2 GiB (an array of shape (1000, 160000), float64)"``, or the message
        of another ``MemoryError``, or ``""``.

    Examples
    --------
    >>> failed_allocation(MemoryError("Unable to allocate 1.5 GiB for an array with shape (200000000,) "
    ...                               "and data type float64"))[0] == int(1.5 * 2**30)
    True
    """
    text = str(err)
    m = _NUMPY.search(text)
    if m is None:
        return 0, (f"the error was: {text[:200]}" if text else "")
    nbytes = int(float(m.group(1)) * _UNITS.get(m.group(2), 1))
    return nbytes, f"numpy could not allocate {m.group(1)} {m.group(2)} (an array of shape {m.group(3)}, {m.group(4)})"


def translate_memory_errors(entry: str, estimate: Callable[..., tuple[float, str] | None] | None = None,
                            advice: str = "use a coarser input, raise the memory limit, or use a machine "
                                          "with more memory"):
    """Decorator for a public entry point: a ``MemoryError`` becomes :class:`~dhlb.errors.InsufficientMemoryError`.

    An :class:`~dhlb.errors.InsufficientMemoryError` raised inside (a factorization refused by its own
    estimate) passes unchanged. The new error is raised once the failed call's frames are gone, so the
    memory they held is free again and the figure available is that of the entry point.

    Parameters
    ----------
    entry : str
        The name of the entry point, for the message (``"direction_field"``).
    estimate : callable, optional
        ``estimate(*args, **kwargs)`` with the entry point's arguments: ``(bytes, what)`` — an estimate of
        the peak memory of the call and what it is for (``"a 1,310,720-face mesh (3.5 kB a face)"``) — or
        ``None``. It must be cheap; an exception inside it counts as ``None``.
    advice : str, optional
        What to do, the end of the message.

    Returns
    -------
    callable
        The decorator.

    Examples
    --------
    >>> @translate_memory_errors("grow")
    ... def grow():
    ...     raise MemoryError("Unable to allocate 8.0 EiB for an array with shape (2**60,) and data type int64")
    >>> try:
    ...     grow()
    ... except InsufficientMemoryError as err:
    ...     print(type(err).__name__, err.needed == 8 * 2**60)
    InsufficientMemoryError True
    """
    def decorate(func):
        @functools.wraps(func)
        def wrapper(*args, **kwargs):
            failed = None
            try:
                return func(*args, **kwargs)
            except InsufficientMemoryError:
                raise
            except MemoryError as err:   # keep only text: the traceback's frames (and arrays) go with `err`
                failed = failed_allocation(err)
            raise _translated(entry, failed, _safe(estimate, args, kwargs), advice) from None
        return wrapper
    return decorate


def _safe(estimate, args, kwargs):
    if estimate is None:
        return None
    try:
        return estimate(*args, **kwargs)
    except Exception:   # an estimate must never hide the memory error
        return None


def _translated(entry: str, failed: tuple[int, str], guess: tuple[float, str] | None,
                advice: str) -> InsufficientMemoryError:
    nbytes, what_failed = failed
    room, source = memory_budget()
    need = int(guess[0]) if guess else 0
    if need > room:
        head = (f"{entry} ran out of memory: {guess[1]} needs about {format_bytes(need)} (estimate), "
                f"but only {format_bytes(room)} is available, {source}")
    else:
        head = f"{entry} ran out of memory with {format_bytes(room)} available, {source}"
    details = "; ".join(p for p in (what_failed, advice) if p)
    return InsufficientMemoryError(head + (f"; {details}" if details else ""), needed=max(need, nbytes),
                                   available=room)
