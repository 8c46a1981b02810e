"""Fuzzing: mutated mesh files and CLI argument lists never cause an internal error, a hang or a memory blow-up.

Hypothesis strategies mutate small valid files of every format (truncate, duplicate a slice,
flip bytes, change a count or index, huge numbers, NaN/inf, a byte-order mark, CRLF line ends,
Unicode) and build command lines with hostile values (0, negative, huge, NaN, inf, empty,
non-numbers). Each input runs in a worker subprocess under ``RLIMIT_AS`` = 2 GB with a timeout;
the worker reports one of

* ``ok`` — read / exit code 0;
* ``typed`` — a :class:`dhlb.errors.DhlbError` (readers) or exit code 1/2 with a one-line
  ``dhlb ...: error: ...`` message (CLI);
* ``internal`` — any other exception (``MemoryError``, ``IndexError``, ...) or the CLI's
  "internal error" line: a bug;
* ``hang`` — no answer within the timeout (the worker is killed and restarted);
* ``crash`` — the worker died (segfault, killed by the memory limit).

The default test run tries a fast, derandomized subset (``FAST_EXAMPLES`` inputs per strategy, a
few seconds). The long run is opt-in with an environment variable::

    DHLB_FUZZ_LONG=10000 OPENBLAS_NUM_THREADS=1 python -m pytest -q tests/test_fuzz.py -s

runs 10,000 inputs per strategy (random seeds), keeps going after a failure so that it can
count them all, prints the summary table of ``docs/validation.md`` and writes it as JSON to
``$DHLB_FUZZ_REPORT`` if that is set.
"""

from __future__ import annotations

import json
import os
import select
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

MEMORY_LIMIT = 2 * 1024**3  # bytes, RLIMIT_AS of the worker
TIMEOUT = float(os.environ.get("DHLB_FUZZ_TIMEOUT", "60"))  # seconds per input
LONG = int(os.environ.get("DHLB_FUZZ_LONG", "0") or 0)
FAST_EXAMPLES = 60
EXAMPLES = LONG if LONG > 0 else FAST_EXAMPLES
REPO = Path(__file__).resolve().parents[1]

_WORKER = r"""
import contextlib, io, json, os, resource, sys, traceback, warnings
limit = int(sys.argv[1])
resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
os.chdir(sys.argv[2])
import numpy as np
from dhlb.errors import DhlbError
from dhlb.io import load
from dhlb.cli import main
warnings.simplefilter("ignore")
print(json.dumps({"ready": True}), flush=True)
for line in sys.stdin:
    task = json.loads(line)
    out, err = io.StringIO(), io.StringIO()
    res = {}
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            if task["kind"] == "read":
                mesh = load(task["path"], task.get("fmt"))
                if mesh.points is not None and len(mesh.points) < 5000:
                    mesh.to_complex()
                res = {"outcome": "ok"}
            else:
                code = main(task["argv"])
                lines = [s for s in err.getvalue().splitlines() if s.strip()]
                errors = [s for s in lines if ": error: " in s or "internal error" in s]
                if any("internal error" in s for s in lines):
                    res = {"outcome": "internal", "detail": lines[-1][:300]}
                elif code == 0:
                    res = {"outcome": "ok"}
                elif code in (1, 2) and len(errors) == 1 and lines[-1] == errors[0]:
                    res = {"outcome": "typed", "detail": errors[0][:300]}
                else:
                    res = {"outcome": "internal", "detail": f"exit {code}, stderr {lines[-3:]!r}"[:300]}
    except DhlbError as exc:
        res = {"outcome": "typed", "detail": f"{type(exc).__name__}: {exc}"[:300]}
    except BaseException as exc:
        tb = traceback.extract_tb(exc.__traceback__)[-1]
        res = {"outcome": "internal",
               "detail": f"{type(exc).__name__}: {str(exc)[:200]} at {tb.filename}:{tb.lineno}"}
    res["maxrss"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    print(json.dumps(res), flush=True)
"""


class Worker:
    """A persistent subprocess running inputs under a memory limit; restarted after a hang or crash."""

    def __init__(self, workdir: str):
        self.workdir = workdir
        self.proc = None
        self.peak = 0

    def start(self):
        env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MPLBACKEND="Agg",
                   PYTHONPATH=str(REPO) + os.pathsep + os.environ.get("PYTHONPATH", ""))
        self.proc = subprocess.Popen(
            [sys.executable, "-c", _WORKER, str(MEMORY_LIMIT), self.workdir],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True, env=env,
        )
        ready = self._read(120)
        assert ready == {"ready": True}, f"fuzz worker did not start: {ready}"

    def _read(self, timeout):
        ready, _, _ = select.select([self.proc.stdout], [], [], timeout)
        if not ready:
            return None
        line = self.proc.stdout.readline()
        return json.loads(line) if line else {"outcome": "crash", "detail": f"exit {self.proc.wait()}"}

    def run(self, task: dict) -> dict:
        if self.proc is None or self.proc.poll() is not None:
            self.start()
        t0 = time.perf_counter()
        try:
            self.proc.stdin.write(json.dumps(task) + "\n")
            self.proc.stdin.flush()
        except BrokenPipeError:
            self.stop()
            return {"outcome": "crash", "detail": "worker gone", "seconds": 0.0}
        res = self._read(TIMEOUT)
        if res is None:
            self.stop()
            res = {"outcome": "hang", "detail": f"no answer in {TIMEOUT:.0f} s"}
        elif res.get("outcome") == "crash":
            self.stop()
        res["seconds"] = time.perf_counter() - t0
        self.peak = max(self.peak, int(res.get("maxrss", 0)))
        return res

    def stop(self):
        if self.proc is not None:
            if self.proc.poll() is None:
                self.proc.kill()
            self.proc.wait()
            self.proc = None


class Tally:
    """Outcome counts per strategy, the slowest input and the failures (for the summary table)."""

    def __init__(self):
        self.counts: dict[str, Counter] = {}
        self.failures: list[tuple[str, dict, dict]] = []
        self.slowest: dict[str, float] = {}
        self.peak: dict[str, int] = {}

    def add(self, name: str, task: dict, res: dict) -> None:
        self.counts.setdefault(name, Counter())[res["outcome"]] += 1
        self.slowest[name] = max(self.slowest.get(name, 0.0), res.get("seconds", 0.0))
        self.peak[name] = max(self.peak.get(name, 0), int(res.get("maxrss", 0)))
        if res["outcome"] not in ("ok", "typed"):
            self.failures.append((name, task, res))

    def table(self) -> str:
        head = ("| strategy | inputs | ok | typed error | internal error | hang | crash | input overwritten | "
                "slowest (s) | peak RSS (MB) |\n|---|---|---|---|---|---|---|---|---|---|\n")
        rows = []
        for name, c in sorted(self.counts.items()):
            n = sum(v for k, v in c.items() if k != "overwrote")
            rows.append(f"| {name} | {n} | {c['ok']} | {c['typed']} | {c['internal']} | {c['hang']} | "
                        f"{c['crash']} | {c['overwrote']} | {self.slowest[name]:.2f} | {self.peak[name] / 1e6:.0f} |")
        return head + "\n".join(rows)


TALLY = Tally()


def run_worker(worker_class, prefix: str, tally: Tally, long: int):
    """The module fixture of a fuzzer: a started worker; after the long run, the table and the report.

    With ``long`` (``DHLB_FUZZ_LONG``) it prints the table of outcomes and the first failures, and
    writes them as JSON to ``$DHLB_FUZZ_REPORT`` if that is set.
    """
    with tempfile.TemporaryDirectory(prefix=prefix) as d:
        w = worker_class(d)
        w.start()
        yield w
        w.stop()
        if long:
            print("\n" + tally.table())
            for name, task, res in tally.failures[:50]:
                print(name, json.dumps(task)[:300], res)
            report = os.environ.get("DHLB_FUZZ_REPORT")
            if report:
                Path(report).write_text(json.dumps(
                    {"inputs_per_strategy": long, "table": tally.table(),
                     "counts": {k: dict(v) for k, v in tally.counts.items()},
                     "failures": [[n, t, r] for n, t, r in tally.failures]}, indent=1))


@pytest.fixture(scope="module")
def worker():
    yield from run_worker(Worker, "dhlb-fuzz-", TALLY, LONG)


# ------------------------------------------------------------------------------------- seeds
def _octahedron():
    V = np.array([[1.0, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]])
    F = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
    return V, F


def _seed_files(folder: Path) -> dict[str, tuple[bytes, str]]:
    """name -> (bytes, format) of small valid files of every format the readers know."""
    from dhlb.io import write_obj, write_off, write_ply, write_simplices, write_volume

    V, F = _octahedron()
    Vt = np.vstack([V, [[0.0, 0, 0]]])
    T = np.array([[6, *f] for f in F])
    out = {}
    writers = {
        "oct.obj": lambda p: write_obj(p, V, F),
        "oct.off": lambda p: write_off(p, V, F),
        "oct-ascii.ply": lambda p: write_ply(p, V, F),
        "oct-le.ply": lambda p: write_ply(p, V, F, binary=True),
        "oct-be.ply": lambda p: write_ply(p, V, F, binary=True, byteorder=">"),
        "ball.mesh": lambda p: write_volume(p, Vt, T),
        "ball.msh": lambda p: write_volume(p, Vt, T),
        "ball.vtk": lambda p: write_volume(p, Vt, T),
        "cx.txt": lambda p: write_simplices(p, [tuple(f) for f in F.tolist()] + [(6, 7)]),
    }
    for name, write in writers.items():
        path = folder / name
        write(path)
        out[name] = (path.read_bytes(), name.rsplit(".", 1)[1])
    return out


SEEDS = _seed_files(Path(tempfile.mkdtemp(prefix="dhlb-fuzz-seeds-")))
_HOSTILE_NUMBERS = [b"0", b"-1", b"-5", b"1", b"2", b"3", b"4", b"255", b"256", b"65536", b"2147483648",
                    b"4294967296", b"18446744073709551616", str(2**70).encode(), b"1e400", b"-1e400",
                    b"nan", b"NaN", b"inf", b"-inf", b"1e-320", b"0.5", b"-0", b"1e308", b"9" * 40]
_UNICODE = ["\ufeff", "\u00e9", "\u2212", "\u00a0", "\u200b", "\U0001f600", "\x00", "\r", "\t", "\u2028"]


@st.composite
def mutated_file(draw):
    """(name, format, bytes): a seed file after 1-4 hostile edits."""
    name = draw(st.sampled_from(sorted(SEEDS)))
    data, fmt = SEEDS[name]
    data = bytearray(data)
    for _ in range(draw(st.integers(1, 4))):
        op = draw(st.sampled_from(["truncate", "duplicate", "flip", "number", "bom", "crlf", "unicode",
                                   "delete_line", "duplicate_line", "swap_lines"]))
        n = len(data)
        if op == "truncate" and n:
            data = data[: draw(st.integers(0, n - 1))]
        elif op == "duplicate" and n:
            a = draw(st.integers(0, n - 1))
            b = draw(st.integers(a, min(n, a + 64)))
            data[b:b] = data[a:b]
        elif op == "flip" and n:
            for _ in range(draw(st.integers(1, 3))):
                i = draw(st.integers(0, len(data) - 1))
                data[i] ^= 1 << draw(st.integers(0, 7))
        elif op == "number":
            import re

            spans = [m.span() for m in re.finditer(rb"-?\d+(\.\d*)?(e-?\d+)?", bytes(data))]
            if spans:
                a, b = spans[draw(st.integers(0, len(spans) - 1))]
                data[a:b] = draw(st.sampled_from(_HOSTILE_NUMBERS))
        elif op == "bom":
            data[0:0] = b"\xef\xbb\xbf"
        elif op == "crlf":
            data = bytearray(bytes(data).replace(b"\n", b"\r\n"))
        elif op == "unicode" and n:
            i = draw(st.integers(0, n))
            data[i:i] = draw(st.sampled_from(_UNICODE)).encode("utf-8")
        elif op in ("delete_line", "duplicate_line", "swap_lines"):
            lines = bytes(data).split(b"\n")
            i = draw(st.integers(0, len(lines) - 1))
            j = draw(st.integers(0, len(lines) - 1))
            if op == "delete_line":
                del lines[i]
            elif op == "duplicate_line":
                lines.insert(i, lines[j])
            else:
                lines[i], lines[j] = lines[j], lines[i]
            data = bytearray(b"\n".join(lines))
    return name, fmt, bytes(data)


def _check(worker, name: str, task: dict) -> None:
    res = worker.run(task)
    TALLY.add(name, task, res)
    if not LONG:
        assert res["outcome"] in ("ok", "typed"), f"{name}: {task} -> {res}"
        assert res.get("maxrss", 0) < MEMORY_LIMIT


_SETTINGS = settings(max_examples=EXAMPLES, deadline=None, derandomize=not LONG, database=None,
                     suppress_health_check=list(HealthCheck))


@_SETTINGS
@given(case=mutated_file())
def test_fuzz_readers(worker, case):
    name, _fmt, data = case
    path = Path(worker.workdir) / f"input.{name.rsplit('.', 1)[1]}"
    path.write_bytes(data)
    _check(worker, "readers", {"kind": "read", "path": str(path), "fmt": None, "seed": name})


# --------------------------------------------------------------------------------- CLI arguments
_HOSTILE_VALUES = ["0", "-5", "60000", "nan", "NaN", "inf", "-inf", "1e308", "1e400", "-1e-320", "", " ",
                   "x", "1,2", "0x10", str(2**70), "-0", "1e-300", "\u00e9", "--json", "3", "2", "0.5"]
_OPTIONS = {
    "info": ["--format", "--example", "--no-homology", "--json", "-o"],
    "vortex": ["--box", "--hbar", "--circulation", "--core", "--order", "--tol", "--velocity", "--format",
               "--backend", "-o"],
    "demo": ["--only", "--backend"],
    "field": ["--n", "--s", "--lambda", "--align", "--format", "--backend", "--repair", "--singularity"],
    "stripes": ["--spacing", "--n", "--iterations", "--seed", "--backend", "--repair", "--size", "--level",
                "--section", "--energy"],
    "conformal": ["--ball", "--charge", "--backend", "-o"],
}
_FLAGS = {"--no-homology", "--json", "--no-png", "--reorient", "--quiet", "--debug"}


@st.composite
def cli_argv(draw):
    """A dhlb command line: a command, its input, 1-3 options with hostile values."""
    command = draw(st.sampled_from(sorted(_OPTIONS)))
    argv = [command]
    if command in ("info", "field", "stripes"):
        argv.append(draw(st.sampled_from(["oct.obj", "oct.off", "oct-le.ply", "ball.mesh", "cx.txt",
                                          "missing.obj", "", "oct.stl", "."])))
    if command == "vortex":
        argv += ["--box", draw(st.sampled_from(["2", "3"]))]
    if command == "stripes":
        argv += ["--spacing", draw(st.sampled_from(["4", "6"])), "--no-png", "--no-isolines"]
    if command == "conformal":
        argv += ["--ball", draw(st.sampled_from(["1", "2"])), "--no-png"]
    if command == "demo":
        argv += ["-o", "demo-out"]
    for _ in range(draw(st.integers(1, 3))):
        opt = draw(st.sampled_from(_OPTIONS[command]))
        argv.append(opt)
        if opt not in _FLAGS:
            value = draw(st.sampled_from(_HOSTILE_VALUES + (["oct.obj", "out.ply", "oct-le.ply"]
                                                             if opt == "-o" else [])))
            argv.append(value)
    if command == "demo" and "--only" not in argv:
        argv += ["--only", draw(st.sampled_from(["", ",", " ", "x", "fields,x"]))]
    if command == "field" and "--no-png" not in argv:
        argv.append("--no-png")
    return argv


@pytest.fixture(scope="module")
def cli_files(worker):
    for name, (data, _) in SEEDS.items():
        (Path(worker.workdir) / name).write_bytes(data)
    return worker


@_SETTINGS
@given(argv=cli_argv())
def test_fuzz_cli(cli_files, argv):
    inputs = [a for i, a in enumerate(argv) if a in SEEDS and (i == 0 or argv[i - 1] not in ("-o", "--output"))]
    folder = Path(cli_files.workdir)
    before = {name: (folder / name).read_bytes() for name in inputs}
    _check(cli_files, "cli", {"kind": "cli", "argv": argv})
    changed = [name for name in inputs if (folder / name).read_bytes() != before[name]]
    for name, (data, _) in SEEDS.items():  # restore for the next input
        (folder / name).write_bytes(data)
    if changed:  # an input file was overwritten
        TALLY.add("cli", {"kind": "cli", "argv": argv}, {"outcome": "overwrote", "detail": changed})
    assert LONG or not changed, f"{argv} changed the input file(s) {changed}"


def test_worker_reports_internal_errors_and_memory_limit(worker):
    """The harness itself: a MemoryError under the 2 GB limit and a hang are both caught."""
    res = worker.run({"kind": "cli", "argv": ["info", "oct.obj"], "_": 0})
    assert res["outcome"] in ("ok", "typed")
    big = worker.run({"kind": "read", "path": "/dev/zero", "fmt": "obj"})  # reading /dev/zero: > 2 GB
    assert big["outcome"] in ("internal", "crash", "typed", "hang")
    assert big["outcome"] != "ok"
