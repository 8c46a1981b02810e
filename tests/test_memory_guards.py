"""No public entry point can be driven out of memory by one parameter (issue 39, point 3).

Every parameter that scales work is estimated before the work against the memory actually available —
the free memory, the room under the cgroup's memory limit and under an address-space limit
(``ulimit -v``, ``RLIMIT_AS``, as batch schedulers set it) — and refused with
:class:`~dhlb.errors.ResourceLimitError` naming the estimate and the largest value that fits; a
``MemoryError`` that still escapes the numeric core becomes :class:`~dhlb.errors.InsufficientMemoryError`
at the public entry point, with the figure.

Each guarded parameter is driven in a worker subprocess under ``RLIMIT_AS`` = 2.5 GB: the worker reports
the class of the error and its message; a raw ``MemoryError``, another exception or a crash fails. The
guard cases share one worker (one interpreter start); the 1.3M-face field runs in its own, under a lower
limit so that it runs out early (a few seconds).
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from dhlb import _memory_errors as mem
from dhlb.errors import InsufficientMemoryError, ResourceLimitError

REPO = Path(__file__).resolve().parents[1]
LIMIT = 2_500_000_000  # bytes, RLIMIT_AS of the workers (as a batch scheduler sets it)

_WORKER = r"""
import json, resource, sys, traceback, warnings
limit = int(sys.argv[1])
resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
warnings.simplefilter("ignore")
import numpy as np

def complete_edges(n):
    i, j = np.triu_indices(n, 1)
    return np.column_stack([i, j])

import networkx as nx
import dhlb
from tests.surface_meshes import icosphere
import dhlb.examples, dhlb.fields, dhlb.mesh, dhlb.topology.cliques
from dhlb.errors import DhlbError
names = {"np": np, "nx": nx, "dhlb": dhlb, "icosphere": icosphere, "complete_edges": complete_edges}
for line in sys.stdin:
    case = json.loads(line)
    try:
        value = eval(compile(case["code"], case["name"], "eval"), names)
        res = {"outcome": "ok", "value": repr(value)[:200]}
    except DhlbError as exc:
        res = {"outcome": type(exc).__name__, "message": str(exc), "needed": getattr(exc, "needed", None),
               "available": getattr(exc, "available", None), "estimate": getattr(exc, "estimate_bytes", None),
               "limit": getattr(exc, "limit_bytes", None)}
    except BaseException as exc:
        res = {"outcome": "internal", "message": f"{type(exc).__name__}: {str(exc)[:300]}",
               "where": traceback.format_exc(limit=-3)[-1500:]}
    print(json.dumps(res), flush=True)
"""

# name -> (code, expected error class, texts the message must contain)
GUARDS = {
    "ball_tet_mesh-400": ("dhlb.mesh.ball_tet_mesh(400)", "ResourceLimitError",
                          ["n = 400 needs about 1.5 TB", "at most n = ", "address-space limit of 2.5 GB"]),
    "ball_tet_mesh-3000": ("dhlb.mesh.ball_tet_mesh(3000)", "ResourceLimitError",
                           ["n = 3000 needs about 650 TB", "at most n = "]),
    "direction_field-n": ("dhlb.fields.direction_field(*icosphere(3), n=10**6)", "ResourceLimitError",
                          ["n = 1000000 needs about 82 GB", "at most n = ", "642 vertices"]),
    "prescribed_field-n": ("dhlb.fields.prescribed_field(*icosphere(3), n=10**6, singularities={0: 1})",
                           "ResourceLimitError", ["n = 1000000 needs about 82 GB", "at most n = "]),
    "from_graph-30-clique": ("dhlb.SimplicialComplex.from_graph(nx.complete_graph(30))", "ResourceLimitError",
                             ["max_dim = None needs about", "at most max_dim = ", "candidates"]),
    "maximal_cliques-30-clique": ("dhlb.topology.cliques.maximal_cliques(30, complete_edges(30))",
                                  "ResourceLimitError", ["max_dim = None needs about", "at most max_dim = "]),
    "from_graph-max_dim": ("dhlb.SimplicialComplex.from_graph(nx.complete_graph(60), max_dim=6)",
                           "ResourceLimitError", ["max_dim = 6 needs about", "at most max_dim = "]),
    "barycentric_subdivision-12-simplex": ("dhlb.examples.simplex(12).barycentric_subdivision()", "ResourceLimitError",
                                           ["X.dim = 12 needs about", "at most X.dim = ", "6,227,020,800"]),
    "Camera-size": ("dhlb.render.Camera(size=(8192, 8192))", "ResourceLimitError",
                    ["size = (8192, 8192) needs about 2.7 GB", "address-space limit of 2.5 GB", "fits"]),
    "write_stripes_obj-expand": (
        "__import__('dhlb.io.stripes').io.stripes.write_stripes_obj("
        "__import__('tempfile').gettempdir() + '/dhlb-guard-expand.obj', dhlb.stripes.stripe_pattern("
        "*icosphere(2), dhlb.fields.direction_field(*icosphere(2), n=1), spacing=4.0).texture, expand=10**4)",
        "ResourceLimitError", ["expand = 10000 needs about", "zero faces", "allowed: expand 0 to"]),
}


def _env() -> dict:
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1",
               PYTHONPATH=str(REPO) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    env.pop("DHLB_MEMORY_LIMIT", None)
    return env


def _run(cases: list[tuple[str, str]], limit: int, timeout: float = 120) -> list[dict]:
    stdin = "".join(json.dumps({"name": name, "code": code}) + "\n" for name, code in cases)
    proc = subprocess.run([sys.executable, "-c", _WORKER, str(limit)], input=stdin, capture_output=True, text=True,
                          env=_env(), timeout=timeout, cwd=str(REPO))
    lines = [json.loads(s) for s in proc.stdout.splitlines() if s.startswith("{")]
    assert len(lines) == len(cases), f"the worker crashed (exit {proc.returncode}): {proc.stderr[-2000:]}"
    return lines


@pytest.fixture(scope="module")
def guarded():
    """Every guard case, run once in one worker under RLIMIT_AS = 2.5 GB."""
    names = list(GUARDS)
    return dict(zip(names, _run([(n, GUARDS[n][0]) for n in names], LIMIT)))


@pytest.mark.parametrize("name", list(GUARDS))
def test_parameter_refused_under_address_space_limit(guarded, name):
    """The parameter is refused before the work: the estimate, the memory allowed and the largest value that fits."""
    res = guarded[name]
    _, expected, texts = GUARDS[name]
    assert res["outcome"] == expected, res
    for text in texts:
        assert text in res["message"], (text, res["message"])
    assert res["estimate"] > res["limit"] > 0
    assert res["limit"] < LIMIT   # the room under the address-space limit, not the machine's memory


def test_cli_conformal_ball_refused_under_address_space_limit(tmp_path):
    """``dhlb conformal --ball 400`` (was: MemoryError, an internal error): a one-line error with the estimate."""
    code = ("__import__('dhlb.cli').cli.main(['conformal', '--ball', '400', '-o', "
            f"{str(tmp_path / 'ball.mesh')!r}])")
    script = ("import contextlib, io, sys\nerr = io.StringIO()\nwith contextlib.redirect_stderr(err):\n"
              f"    code = {code}\nprint(code, err.getvalue().strip().replace(chr(10), ' | '))")
    proc = subprocess.run([sys.executable, "-c", f"import resource; resource.setrlimit(resource.RLIMIT_AS, "
                           f"({LIMIT}, {LIMIT}))\n" + script], capture_output=True, text=True, env=_env(), timeout=120)
    out = proc.stdout.strip()
    assert out.startswith("2 ") and "argument --ball" in out, (out, proc.stderr[-2000:])   # a usage error
    assert "internal error" not in out and "MemoryError" not in out, out
    assert "needs about 1.5 TB" in out and "at most n = " in out, out
    assert not (tmp_path / "ball.mesh").exists()


def test_field_of_1_3m_faces_runs_out_with_dhlb_error():
    """A 1.3M-face field under an address-space limit (was: numpy's MemoryError): InsufficientMemoryError with figures.

    The limit (1 GB here, 2.5 GB in the report) only decides where the work runs out; 1 GB makes it
    early (a few seconds). The message says what the field needs and what is available.
    """
    (res,) = _run([("field-1.3M", "__import__('dhlb.fields').fields.direction_field(*icosphere(8), n=4)")],
                  1_000_000_000)
    assert res["outcome"] == "InsufficientMemoryError", res
    msg = res["message"]
    assert msg.startswith("direction_field ran out of memory: a field of 1,310,720 faces"), msg
    assert "needs about 4.9 GB (estimate)" in msg and "address-space limit of 1 GB" in msg, msg
    assert res["needed"] > res["available"] > 0


# ---------------------------------------------------------------------------- in-process units
def test_translation_of_numpy_memory_error():
    """numpy's message gives the size of the failed allocation; an InsufficientMemoryError passes unchanged."""
    @mem.translate_memory_errors("grow")
    def grow(kind):
        if kind == "numpy":
            np.empty((2**40, 2**10))   # 8 PiB: numpy refuses with "Unable to allocate 8.00 PiB ..."
        raise InsufficientMemoryError("refused by its own estimate", needed=5, available=1)

    with pytest.raises(InsufficientMemoryError) as info:
        grow("numpy")
    assert info.value.needed == 8 * 2**50 and info.value.available > 0
    assert str(info.value).startswith("grow ran out of memory with ")
    assert "numpy could not allocate 8.00 PiB (an array of shape (1099511627776, 1024), float64)" in str(info.value)
    assert info.value.__cause__ is None and info.value.__context__ is None   # the frames (and arrays) are gone
    with pytest.raises(InsufficientMemoryError, match="refused by its own estimate"):
        grow("own")


def test_translation_with_estimate_and_bare_memory_error():
    """A bare MemoryError (scipy, C code) is translated too; an estimate above the room is the figure."""
    @mem.translate_memory_errors("work", lambda size: (size, f"a problem of size {size:,}"))
    def work(size):
        raise MemoryError()

    with pytest.raises(InsufficientMemoryError, match=r"work ran out of memory: a problem of size [0-9,]+ needs "
                                                      r"about 100 TB \(estimate\), but only") as info:
        work(10**14)
    assert info.value.needed == 10**14
    with pytest.raises(InsufficientMemoryError, match="work ran out of memory with"):
        work(10)   # a small estimate is no explanation: the room is the figure


def test_check_memory_names_largest_value_that_fits():
    """The refusal names the estimate, the budget and the largest value that fits, which the guard accepts."""
    estimate = lambda n: 1000 * n**3  # noqa: E731
    with pytest.raises(ResourceLimitError, match=r"n = 400 needs about 64 GB .* at most n = 200 fits in 8 GB") as info:
        mem.check_memory("n", 400, estimate(400), largest=lambda room: mem.largest_fitting(estimate, room, 1, 400),
                         available=8 * 10**9)
    assert info.value.parameter == "n" and info.value.value == 400
    assert mem.check_memory("n", 200, estimate(200), available=8 * 10**9) == estimate(200)


def test_budget_from_set_memory_limit_and_environment(monkeypatch):
    """dhlb.linalg.set_memory_limit and DHLB_MEMORY_LIMIT lower the figure every guard uses."""
    from dhlb.linalg import available_bytes, set_memory_limit
    from dhlb.mesh import ball_tet_mesh

    set_memory_limit(110 * 10**6)
    try:
        assert mem.memory_budget() == (110 * 10**6, "the budget of dhlb.linalg.set_memory_limit")
        assert available_bytes() == 110 * 10**6
        with pytest.raises(ResourceLimitError, match=r"n = 20 needs about 290 MB .* at most n = 7 fits in 110 MB"):
            ball_tet_mesh(20)
        assert ball_tet_mesh(7).tets.shape[0] == 9114    # the largest n that fits is accepted
    finally:
        set_memory_limit(None)
    monkeypatch.setenv("DHLB_MEMORY_LIMIT", "64M")
    assert mem.memory_budget() == (64 * 2**20, "the budget of DHLB_MEMORY_LIMIT")
    with pytest.raises(ResourceLimitError, match=r"X\.dim = 8 needs about"):
        __import__("dhlb.examples").examples.simplex(8).barycentric_subdivision()


def _cgroup_tree(tmp_path, v2: bool, limit: int, usage: int, inactive: int) -> None:
    """A fake /sys/fs/cgroup with this process in ``/jobs/job1`` (the limit on ``/jobs``)."""
    root = tmp_path / ("cg" if v2 else "cg/memory")
    leaf = root / "jobs" / "job1"
    leaf.mkdir(parents=True)
    if v2:
        (tmp_path / "cg" / "cgroup.controllers").write_text("cpu memory\n")
        (root / "jobs" / "memory.max").write_text(f"{limit}\n")
        (root / "jobs" / "memory.current").write_text(f"{usage}\n")
        (root / "jobs" / "memory.stat").write_text(f"anon 5\ninactive_file {inactive}\n")
        (leaf / "memory.max").write_text("max\n")
        (tmp_path / "proc").write_text("0::/jobs/job1\n")
    else:
        (root / "jobs" / "memory.limit_in_bytes").write_text(f"{limit}\n")
        (root / "jobs" / "memory.usage_in_bytes").write_text(f"{usage}\n")
        (root / "jobs" / "memory.stat").write_text(f"cache 7\ntotal_inactive_file {inactive}\n")
        (leaf / "memory.limit_in_bytes").write_text(f"{2**63 - 4096}\n")   # v1's "no limit"
        (tmp_path / "proc").write_text("4:memory:/jobs/job1\n3:cpu,cpuacct:/\n0::/\n")


@pytest.mark.parametrize("v2", [True, False], ids=["cgroup-v2", "cgroup-v1"])
def test_cgroup_limit_of_an_ancestor_counts(tmp_path, monkeypatch, v2):
    """The room under the memory limit of the process's cgroup or an ancestor, without the inactive file cache."""
    _cgroup_tree(tmp_path, v2, limit=3 * 10**9, usage=2 * 10**9, inactive=5 * 10**8)
    monkeypatch.setattr(mem, "_CGROUP", str(tmp_path / "cg"))
    monkeypatch.setattr(mem, "_PROC_CGROUP", str(tmp_path / "proc"))
    monkeypatch.setattr(mem, "_meminfo_available", lambda: 10**12)
    room, source = mem.memory_budget()
    if mem._rlimit_available() is None:
        assert room == 3 * 10**9 - (2 * 10**9 - 5 * 10**8)
        assert source.startswith("the room under the memory limit of the cgroup") and source.endswith("jobs")


def test_rlimit_room_is_limit_minus_address_space_in_use():
    """Under RLIMIT_AS the room is the limit less VmSize (run in a subprocess: the limit cannot be raised again)."""
    code = ("import resource; resource.setrlimit(resource.RLIMIT_AS, (3 * 10**9, 3 * 10**9))\n"
            "from dhlb import _memory_errors as m\n"
            "vm = int(open('/proc/self/status').read().split('VmSize:')[1].split()[0]) * 1024\n"
            "room, source = m.memory_budget()\nprint(room, vm, source)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=_env(), timeout=60).stdout
    room, vm, source = out.split(maxsplit=2)
    assert abs(int(room) - (3 * 10**9 - int(vm))) < 50 * 10**6
    assert source.startswith("the room under the address-space limit of 3 GB")


def test_from_graph_refuses_the_complex_of_cliques_that_fit():
    """The cliques of a 16-clique fit the budget but the complex built from them does not: refused before it is built.

    The largest max_dim that fits is named, and accepted under the same budget; the model is not monotone
    in max_dim (a 10-skeleton built from its C(16, 11) maximal cliques needs more than the whole simplex).
    """
    import networkx as nx

    from dhlb import SimplicialComplex
    from dhlb.linalg import set_memory_limit
    from dhlb.topology.subdivision import complex_bytes

    assert complex_bytes([(math.comb(16, 11), 10)]) > 10 * complex_bytes([(1, 15)])
    G = nx.complete_graph(16)
    set_memory_limit(9 * 10**6)
    try:
        with pytest.raises(ResourceLimitError, match=r"max_dim = None needs about 11 MB .* at most max_dim = 4 fits "
                                                     r"in 9 MB, .* the complex of the 1 maximal cliques"):
            SimplicialComplex.from_graph(G)
        assert SimplicialComplex.from_graph(G, max_dim=4).counts == tuple(math.comb(16, k + 1) for k in range(5))
    finally:
        set_memory_limit(None)
