"""Fuzzing the result readers: mutated outputs of every kind give a typed error or a consistent result.

For every output kind (field ``.npz`` / ``.json`` / ``.ply``, stripes ``.obj`` + sidecar, vortex ``.json`` /
``.ply`` / ``.obj`` polylines, conformal ``.npz`` / ``.json`` + ``.mesh``), hypothesis mutates a small real
output — truncate, flip bytes, drop / duplicate / swap lines, replace a number by NaN / inf / huge /
negative; in a JSON file change a value's type; in an ``.npz`` negate, NaN, reshape, retype, pickle or drop
one array — and :func:`dhlb.io.read_result` reads it in a worker subprocess under ``RLIMIT_AS`` = 2 GB
(the harness of ``tests/test_fuzz.py``). Allowed outcomes:

* ``typed`` — a :class:`dhlb.errors.DhlbError`;
* ``ok`` — the result reads, its summary is JSON, and saving it again and reading that back (or, for a kind
  that is read but not written, reading it once more) gives the same summary (a mutated file that still
  reads must read to a consistent result, never a half-read one).

Anything else (``IndexError``, ``EOFError``, ``UnicodeDecodeError``, ``MemoryError``, a hang, a crash, an
inconsistent re-read) fails. The default run tries ``FAST_EXAMPLES`` inputs per output kind; the long run::

    DHLB_FUZZ_LONG=10000 OPENBLAS_NUM_THREADS=1 python -m pytest -q tests/test_fuzz_results.py -s

prints the table of outcomes (and writes it as JSON to ``$DHLB_FUZZ_REPORT``).
"""

from __future__ import annotations

import io
import json
import os
import re
import sys
import tempfile
import zipfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tests.test_fuzz import MEMORY_LIMIT, REPO, Tally, Worker, run_worker

LONG = int(os.environ.get("DHLB_FUZZ_LONG", "0") or 0)
FAST_EXAMPLES = int(os.environ.get("DHLB_FUZZ_RESULTS", "300"))
EXAMPLES = LONG if LONG > 0 else FAST_EXAMPLES

_WORKER = r"""
import contextlib, io, json, os, resource, sys, traceback, warnings
limit = int(sys.argv[1])
resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
os.chdir(sys.argv[2])
import numpy as np
from dhlb.errors import DhlbError
from dhlb.io import read_result
warnings.simplefilter("ignore")
print(json.dumps({"ready": True}), flush=True)
for line in sys.stdin:
    task = json.loads(line)
    res = {}
    try:
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            r = read_result(task["path"])
            summary = json.dumps(r.to_json(), sort_keys=True, allow_nan=True, default=str)
            folder = os.path.join(os.path.dirname(task["path"]), "again")
            os.makedirs(folder, exist_ok=True)
            again = os.path.join(folder, task["save"][-1])
            try:
                for name in task["save"]:
                    r.save(os.path.join(folder, name))
            except DhlbError as exc:    # a kind that is read but not written (a loaded conformal mesh)
                if "cannot save" not in str(exc):
                    raise
                again = task["path"]
            back = json.dumps(read_result(again).to_json(), sort_keys=True, allow_nan=True, default=str)
            strip = lambda s: {k: v for k, v in json.loads(s).items() if k not in task["volatile"]}
            def same(a, b):   # floats to 1e-9 (a re-read recomputes through the frames), NaN equal to NaN
                if isinstance(a, float) or isinstance(b, float):
                    try:
                        return (a == b or (a != a and b != b)
                                or abs(a - b) <= 1e-9 * max(abs(a), abs(b), 1e-300) + 1e-12)
                    except TypeError:
                        return False
                if isinstance(a, dict) and isinstance(b, dict):
                    return a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
                if isinstance(a, list) and isinstance(b, list):
                    return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
                return a == b
            if not same(strip(summary), strip(back)):
                res = {"outcome": "internal", "detail": "re-read differs: " + summary[:120] + " | " + back[:120]}
            else:
                res = {"outcome": "ok"}
    except DhlbError as exc:
        res = {"outcome": "typed", "detail": f"{type(exc).__name__}: {exc}"[:300]}
    except BaseException as exc:
        tb = traceback.extract_tb(exc.__traceback__)[-1]
        res = {"outcome": "internal",
               "detail": f"{type(exc).__name__}: {str(exc)[:200]} at {tb.filename}:{tb.lineno}"}
    res["maxrss"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    print(json.dumps(res), flush=True)
"""


class ResultWorker(Worker):
    """The worker of tests/test_fuzz.py running :func:`dhlb.io.read_result` instead of the mesh readers."""

    def start(self):
        import subprocess

        env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MPLBACKEND="Agg",
                   PYTHONPATH=str(REPO) + os.pathsep + os.environ.get("PYTHONPATH", ""))
        self.proc = subprocess.Popen(
            [sys.executable, "-c", _WORKER, str(MEMORY_LIMIT), self.workdir],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True, env=env)
        ready = self._read(120)
        assert ready == {"ready": True}, f"fuzz worker did not start: {ready}"


TALLY = Tally()


# ------------------------------------------------------------------------------------------ seeds
def _seed_outputs(folder: Path) -> dict[str, dict[str, bytes]]:
    """kind -> {file name: bytes} of small real outputs of every command (one result each)."""
    import warnings

    from dhlb.conformal import conformal_deformation, point_charge_factor
    from dhlb.fields import direction_field
    from dhlb.mesh import ball_tet_mesh, box_tet_mesh
    from dhlb.stripes import stripe_pattern
    from dhlb.vortex import FilamentField, vortex_filaments, vortex_ring
    from tests.surface_meshes import icosphere

    V, F = icosphere(1)
    out: dict[str, dict[str, bytes]] = {}

    def keep(kind, base, suffixes):
        out[kind] = {base + s: (folder / (base + s)).read_bytes() for s in suffixes}

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fld = direction_field(V, F, n=2)
        fld.save(folder / "f.npz")
        fld.save(folder / "f.json")
        keep("field-npz", "f", [".npz", ".json"])
        stripes = stripe_pattern(V, F, fld, spacing=4.0, n=2)
        stripes.save(folder / "s.obj")
        keep("stripes", "s", [".obj", ".json"])
        mesh = box_tet_mesh(8, lower=(-1, -1, -1), upper=(1, 1, 1))
        vort = vortex_filaments(mesh, None, FilamentField([vortex_ring(0.6, center=(0.01, 0.005, 0.01))],
                                                          circulation=6.283185, core_radius=0.1), hbar=1.0)
        assert len(vort.filaments) == 1
        for ext in (".json", ".ply", ".obj"):
            vort.save(folder / f"v{ext[1:]}{ext}")
            keep(f"vortex-{ext[1:]}", f"v{ext[1:]}", [ext])
        ball = ball_tet_mesh(2)
        conf = conformal_deformation(ball.points, ball.tets, point_charge_factor([(2.0, 0.0, 0.0, 0.5)]))
        conf.save(folder / "c.npz")
        keep("conformal-npz", "c", [".npz"])
        conf.save(folder / "m.json")
        conf.save(folder / "m.mesh")
        keep("conformal-mesh", "m", [".json", ".mesh"])
    return out


SEEDS = _seed_outputs(Path(tempfile.mkdtemp(prefix="dhlb-fuzz-results-")))
READ = {"field-npz": "f.npz", "stripes": "s.obj", "vortex-json": "vjson.json", "vortex-ply": "vply.ply",
        "vortex-obj": "vobj.obj", "conformal-npz": "c.npz", "conformal-mesh": "m.json"}
SAVE = {"field-npz": ["f.json", "f.npz"], "stripes": ["s.obj"], "vortex-json": ["v.json"], "vortex-ply": ["v.ply"],
        "vortex-obj": ["v.json"], "conformal-npz": ["c.npz"], "conformal-mesh": ["c.npz"]}
VOLATILE = ["timings", "files", "solver", "input", "mesh", "note"]   # what a re-save may change by design
_HOSTILE = [b"0", b"-1", b"-7", b"1", b"2", b"99999", b"2147483648", b"18446744073709551616", b"1e400", b"-1e400",
            b"nan", b"NaN", b"inf", b"-inf", b"1e-320", b"0.5", b"1e308", b"9" * 40, b'"x"', b"null", b"[]", b"{}"]


def _mutate_bytes(draw, data: bytes) -> bytes:
    data = bytearray(data)
    op = draw(st.sampled_from(["truncate", "flip", "number", "delete_line", "duplicate_line", "swap_lines",
                               "garbage"]))
    n = len(data)
    if op == "truncate" and n:
        data = data[: draw(st.integers(0, n - 1))]
    elif op == "flip" and n:
        for _ in range(draw(st.integers(1, 3))):
            i = draw(st.integers(0, len(data) - 1))
            data[i] ^= 1 << draw(st.integers(0, 7))
    elif op == "number":
        spans = [m.span() for m in re.finditer(rb"-?\d+(\.\d*)?(e-?\d+)?", bytes(data))]
        if spans:
            a, b = spans[draw(st.integers(0, len(spans) - 1))]
            data[a:b] = draw(st.sampled_from(_HOSTILE))
    elif op == "garbage":
        i = draw(st.integers(0, n))
        data[i:i] = draw(st.binary(min_size=1, max_size=16))
    else:
        lines = bytes(data).split(b"\n")
        i, j = draw(st.integers(0, len(lines) - 1)), draw(st.integers(0, len(lines) - 1))
        if op == "delete_line":
            del lines[i]
        elif op == "duplicate_line":
            lines.insert(i, lines[j])
        else:
            lines[i], lines[j] = lines[j], lines[i]
        data = bytearray(b"\n".join(lines))
    return bytes(data)


def _mutate_json(draw, data: bytes) -> bytes:
    """Change the type or value of one entry of a JSON document (a leaf anywhere in it)."""
    doc = json.loads(data)
    paths = []

    def walk(node, path):
        paths.append(path)
        if isinstance(node, dict):
            for k, v in node.items():
                walk(v, path + (k,))
        elif isinstance(node, list) and node:
            for i in sorted({0, len(node) - 1}):
                walk(node[i], path + (i,))
    walk(doc, ())
    path = draw(st.sampled_from(paths[1:] or paths))
    new = draw(st.sampled_from(["x", None, [], {}, -1, -99999, 10**30, 0.5, True, [[1, 2]], float("nan"),
                                float("inf")]))
    if not path:
        return json.dumps(new).encode()
    node = doc
    for k in path[:-1]:
        node = node[k]
    if draw(st.booleans()) and isinstance(node, dict):
        del node[path[-1]]
    else:
        node[path[-1]] = new
    return json.dumps(doc, allow_nan=True).encode()


def _mutate_npz(draw, data: bytes) -> bytes:
    """Change one array of an ``.npz``: negate, NaN, reshape, retype, pickle, drop or empty it."""
    with np.load(io.BytesIO(data), allow_pickle=False) as z:
        arrays = {k: z[k] for k in z.files}
    key = draw(st.sampled_from(sorted(arrays)))
    a = arrays[key]
    op = draw(st.sampled_from(["negate", "nan", "reshape", "float", "object", "drop", "empty", "huge", "scalar"]))
    if op == "negate" and a.dtype.kind in "iufc":
        arrays[key] = -a - (1 if a.dtype.kind in "iu" else 0)
    elif op == "nan" and a.dtype.kind in "fc" and a.size:
        b = a.copy()
        b.flat[draw(st.integers(0, a.size - 1))] = np.nan
        arrays[key] = b
    elif op == "reshape" and a.size:
        arrays[key] = a.reshape(-1)[: max(a.size - 1, 0)]
    elif op == "float" and a.dtype.kind in "iu":
        arrays[key] = a.astype(float) + 0.5
    elif op == "object":
        arrays[key] = np.array([a, "x"], dtype=object)
    elif op == "drop":
        del arrays[key]
    elif op == "empty":
        arrays[key] = a.reshape(-1)[:0]
    elif op == "huge" and a.dtype.kind in "iu" and a.size:
        b = a.astype(np.int64)
        b.flat[draw(st.integers(0, a.size - 1))] = 2**40
        arrays[key] = b
    elif op == "scalar":
        arrays[key] = np.array(7)
    buf = io.BytesIO()
    np.savez(buf, **arrays)      # allow_pickle: an object array goes in pickled, the reader must refuse it
    return buf.getvalue()


@st.composite
def mutated_output(draw, kind: str):
    files = dict(SEEDS[kind])
    name = draw(st.sampled_from(sorted(files)))
    data = files[name]
    if name.endswith(".npz") and draw(st.booleans()):
        try:
            data = _mutate_npz(draw, data)
        except (ValueError, zipfile.BadZipFile):
            data = _mutate_bytes(draw, data)
    elif name.endswith(".json") and draw(st.booleans()):
        data = _mutate_json(draw, data)
    else:
        data = _mutate_bytes(draw, data)
    files[name] = data
    return files


@pytest.fixture(scope="module")
def worker():
    yield from run_worker(ResultWorker, "dhlb-fuzz-results-", TALLY, LONG)


_SETTINGS = settings(max_examples=EXAMPLES, deadline=None, derandomize=not LONG, database=None,
                     suppress_health_check=list(HealthCheck))


@pytest.mark.parametrize("kind", sorted(SEEDS))
def test_the_seeds_read_back(worker, kind):
    """The unmutated outputs read and re-read consistently (the fuzzer's reference point)."""
    folder = Path(worker.workdir) / f"seed-{kind}"
    folder.mkdir(exist_ok=True)
    for name, data in SEEDS[kind].items():
        (folder / name).write_bytes(data)
    res = worker.run({"path": str(folder / READ[kind]), "save": SAVE[kind], "volatile": VOLATILE})
    assert res["outcome"] == "ok", res


@pytest.mark.parametrize("kind", sorted(SEEDS))
def test_fuzz_result_readers(worker, kind):
    @_SETTINGS
    @given(files=mutated_output(kind))
    def run(files):
        folder = Path(tempfile.mkdtemp(dir=worker.workdir))
        for name, data in files.items():
            (folder / name).write_bytes(data)
        task = {"path": str(folder / READ[kind]), "save": SAVE[kind], "volatile": VOLATILE}
        res = worker.run(task)
        TALLY.add(kind, task, res)
        if not LONG:
            assert res["outcome"] in ("ok", "typed"), f"{kind}: {sorted(files)} -> {res}"
    run()
