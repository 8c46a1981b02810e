"""Side-by-side benchmark (issue 41): dhlb's smoothest n = 4 direction field against fieldgen, in one run.

fieldgen (GeometryCollective/fieldgen, C++, CHOLMOD; Knöppel, Crane, Pinkall, Schröder 2013) computes
the same thing as :func:`dhlb.fields.direction_field` with its defaults: the smoothest n-direction field
(here n = 4, s = 0), its singular faces and their indices.  It is run from the binary built with
timers by ``/work/shared/anchors/fieldgen/build.sh`` (it prints one line ``PERF {json}`` with its
phases ``[wall, cpu]`` in seconds, and ``PERFEIG {json}`` with the eigenpair's backward error).

Run::

    FIELDGEN=/path/to/fieldgen OPENBLAS_NUM_THREADS=1 python benchmarks/bench_fieldgen.py [--quick]
        [--meshes spot,stanford-bunny] [--repeat 3] [--equal-answer] [--json out.json]

What is measured
----------------
* Meshes: ``rounded_cube.obj``, ``spot.obj``, ``kitten.obj``, ``stanford-bunny.obj``,
  ``bunny-watertight.off``, ``fertility.off`` from ``/work/shared/meshes`` and the icosphere of
  ``benchmarks/bench_scale.py`` at level 8 (1,310,720 faces; skipped with ``--quick``).  Each is
  read once by dhlb, compacted (fieldgen crashes on unreferenced vertices: the Stanford bunny has
  1,113) and written to a temporary OBJ with exact coordinates; both tools read that same file.
* For each mesh, ``--repeat`` rounds (default 3), interleaved: fieldgen, dhlb with
  ``OPENBLAS_NUM_THREADS=1``, dhlb with no thread variable set (the default install), each run
  in a fresh process.  The medians are reported.
* fieldgen (``fieldgen in.obj out.obj --degree=4``, with ``OPENBLAS_NUM_THREADS=1``): ``read``
  (parse + half-edge mesh), ``init``, ``assemble``, ``analyze``, ``factor`` (CHOLMOD), ``solves``
  (its fixed 20 inverse iterations, or ``FG_ITERS``), ``indices``; ``total = read + init +
  smoothest`` (writing its output file is not counted).
* dhlb (``dhlb field MESH --n 4`` without the output files): ``read``
  (:func:`dhlb.io.read_surface`) and the phases of :attr:`DirectionField.timings` — ``setup``
  (validation, repairs, tangent bundle, matrices), ``solve`` (eigen solve at the default tolerance
  :func:`dhlb.linalg.default_tol`), ``indices`` (directions and singularities); ``total = read +
  setup + solve + indices``.  ``import`` (dhlb and its libraries) is shown apart.
* ``wall``: the child process from start to exit, seen by this script (interpreter start-up,
  imports and fieldgen's output file included).  ``MB``: the peak resident memory of that child
  (``ru_maxrss`` from ``os.wait4``; dhlb's includes the interpreter and its libraries, ~150 MB).
* ``ratio``: dhlb total ÷ fieldgen total (> 1: dhlb slower).  The load average is printed before
  and after each mesh: the machine may be shared.
* ``--equal-answer``: the singularities (faces and indices) of fieldgen's output file (lines
  ``# singularity FACE INDEX/n``, 1-based face rows) and of dhlb's default solve are compared with
  a reference dhlb solve at ``SolverOptions(tol=1e-14)``.  Reported: the number of faces whose index
  differs at fieldgen's default 20 iterations, and the smallest ``FG_ITERS`` of ``--fg-iters``
  (default 20, 40, 60, 90, 120) at which fieldgen's singularities equal the reference, with its
  median time.

The script needs only the standard library in this process; ``--help`` works without ``FIELDGEN``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
MESHES = "/work/shared/meshes"
FILES = ["rounded_cube.obj", "spot.obj", "kitten.obj", "stanford-bunny.obj", "bunny-watertight.off", "fertility.off"]
ICO = "icosphere-8"
ICO_LEVEL = 8
THREAD_VARS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS",
               "VECLIB_MAXIMUM_THREADS", "NUMEXPR_NUM_THREADS", "GOTO_NUM_THREADS")
BASE_ENV = dict(os.environ)    # as given (no thread variable is set by this script)


# ---------------------------------------------------------------------------------------------- children


def child_prep(outdir, names):
    """Write each mesh, compacted, as an exact OBJ in ``outdir``; print their paths and sizes."""
    import warnings

    from dhlb.io import compact_mesh, read_surface, write_obj

    out = {}
    for name in names:
        t = time.perf_counter()
        if name == ICO:
            sys.path.insert(0, HERE)
            from bench_scale import icosphere

            V, F = icosphere(ICO_LEVEL)
            dropped = 0
        else:
            V, F = read_surface(os.path.join(MESHES, name))
            with warnings.catch_warnings():   # the Stanford bunny has unreferenced vertices
                warnings.simplefilter("ignore")
                V2, F, _ = compact_mesh(V, F)
            dropped, V = len(V) - len(V2), V2
        path = os.path.join(outdir, os.path.splitext(name)[0] + ".obj")
        write_obj(path, V, F)
        out[name] = {"path": path, "faces": len(F), "vertices": len(V), "dropped": int(dropped),
                     "seconds": time.perf_counter() - t}
    print(json.dumps(out))


def child_dhlb(path, tol):
    """The smoothest n = 4 field by dhlb of the OBJ ``path`` (what ``dhlb field PATH --n 4`` computes); print JSON."""
    t0 = time.perf_counter()
    import warnings

    from dhlb.fields import direction_field
    from dhlb.io import read_surface
    from dhlb.linalg import SolverOptions

    t1 = time.perf_counter()
    V, F = read_surface(path)
    t2 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = direction_field(V, F, n=4, solver=None if tol == "default" else SolverOptions(tol=float(tol)))
    T = res.timings
    s = res.singularities
    out = {"import": t1 - t0, "read": t2 - t1, "setup": T["setup"], "solve": T["solve"], "indices": T["indices"],
           "compute": T["total"], "total": t2 - t1 + T["total"], "backend": res.solver["backend"],
           "solves": res.solver["solves"],
           "factorizations": res.solver["factorizations"], "residual": res.solver["residual"],
           "index_sum": int(res.index_sum), "singular_faces": len(s.index),
           "singularities": [[int(f), int(k)] for f, k in zip(s.input_faces, s.index)]}
    print(json.dumps(out))


# ------------------------------------------------------------------------------------------------ runner


def run_process(cmd, env, timeout):
    """Run ``cmd``; return its exit code, output, wall seconds and peak resident memory (MB, ``os.wait4``)."""
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        t = time.perf_counter()
        p = subprocess.Popen(cmd, stdout=out, stderr=err, env=env)
        timer = threading.Timer(timeout, p.kill)
        timer.start()
        try:
            _, status, usage = os.wait4(p.pid, 0)
        finally:
            timer.cancel()
        wall = time.perf_counter() - t
        p.returncode = os.waitstatus_to_exitcode(status)   # reaped here: Popen must not wait again
        out.seek(0)
        err.seek(0)
        return {"rc": p.returncode, "stdout": out.read(), "stderr": err.read(), "wall": wall,
                "mb": usage.ru_maxrss / 1024.0, "timed_out": wall >= timeout}


def _fail(r, what):
    last = (r["stderr"].strip().splitlines() or r["stdout"].strip().splitlines() or ["?"])[-1]
    why = f"timeout after {r['wall']:.0f} s" if r["timed_out"] else f"exit {r['rc']}: {last[:200]}"
    return {"error": f"{what}: {why}", "wall": r["wall"], "mb": r["mb"]}


def run_child(args, env, timeout):
    cmd = [sys.executable, os.path.abspath(__file__), "--child", *map(str, args)]
    r = run_process(cmd, env, timeout)
    if r["rc"] != 0:
        return _fail(r, "dhlb child")
    out = json.loads(r["stdout"].strip().splitlines()[-1])
    out.update(wall=r["wall"], mb=r["mb"])
    return out


def parse_perf(stderr):
    """The ``PERF`` and ``PERFEIG`` JSON lines of the instrumented fieldgen, merged (``eta``, ``eigenvalue``)."""
    out = {}
    for line in stderr.splitlines():
        if line.startswith("PERF {") or line.startswith("PERFEIG {"):
            out.update(json.loads(line.split(" ", 1)[1]))
    return out


def fieldgen_singularities(path, n=4):
    """``{face row (0-based): index (integer, units of 1/n)}`` from fieldgen's output OBJ."""
    sing = {}
    with open(path) as fh:
        for line in fh:
            if line.startswith("# singularity "):
                parts = line.split()
                if len(parts) == 4 and parts[2].isdigit():
                    sing[int(parts[2]) - 1] = round(float(parts[3]) * n)
    return sing


def run_fieldgen(exe, obj, outdir, timeout, iters=None, singularities=False):
    env = {k: v for k, v in BASE_ENV.items() if k != "FG_ITERS"}
    env["OPENBLAS_NUM_THREADS"] = "1"
    if iters is not None:
        env["FG_ITERS"] = str(iters)
    out = os.path.join(outdir, "fieldgen-out.obj")
    r = run_process([exe, obj, out, "--degree=4"], env, timeout)
    perf = parse_perf(r["stderr"])
    if r["rc"] != 0 or "read" not in perf:
        return _fail(r, "fieldgen")
    ph = {k: v[0] for k, v in perf.items() if isinstance(v, list)}   # wall seconds of each phase
    res = {"read": ph["read"], "init": ph.get("init", 0.0), "assemble": ph.get("assemble", 0.0),
           "analyze": ph.get("analyze", 0.0), "factor": ph.get("factor", 0.0), "solves": ph.get("solves", 0.0),
           "indices": ph.get("indices", 0.0), "smoothest": ph.get("smoothest_total", 0.0),
           "write": ph.get("write", 0.0), "nsolves": perf.get("nsolves"), "eta": perf.get("eta"),
           "singular_faces": perf.get("singular_faces"), "index_sum": perf.get("index_sum"),
           "faces": perf.get("faces"), "wall": r["wall"], "mb": r["mb"]}
    res["compute"] = res["init"] + res["smoothest"]
    res["total"] = res["read"] + res["compute"]
    if singularities:
        res["singularities"] = fieldgen_singularities(out)
    return res


def dhlb_env(threads):
    env = {k: v for k, v in BASE_ENV.items() if k not in THREAD_VARS}
    if threads:
        env["OPENBLAS_NUM_THREADS"] = "1"
    return env


def median(rows, key):
    vals = [r[key] for r in rows if "error" not in r and r.get(key) is not None]
    return statistics.median(vals) if vals else float("nan")


def load():
    a = os.getloadavg()
    return f"{a[0]:.2f} {a[1]:.2f} {a[2]:.2f}"


def differing(a, b):
    """Number of faces whose index differs between two ``{face: index}`` maps (a face absent has index 0)."""
    return sum(a.get(f, 0) != b.get(f, 0) for f in set(a) | set(b))


# ------------------------------------------------------------------------------------------------ tables


def timing(meshes, info, exe, outdir, repeat, timeout):
    """The interleaved runs of every mesh; prints the two tables, returns the rows."""
    head = (f"{'mesh':<22}{'faces':>9}{'fg total':>10}{'dhlb 1t':>9}{'dhlb':>9}{'ratio 1t':>9}{'ratio':>7}"
            f"{'comp 1t':>8}{'fg wall':>9}{'d 1t wall':>10}{'d wall':>8}{'fg MB':>8}{'d 1t MB':>9}{'d MB':>7}"
            "  load before/after")
    print(f"\nmedians of {repeat} interleaved runs (fieldgen; dhlb with OPENBLAS_NUM_THREADS=1 '1t'; dhlb with no "
          "thread variable), seconds. total: read + compute; ratio: dhlb total / fieldgen total; comp 1t: the same "
          "without reading the file; wall: the whole child process; MB: its peak resident memory")
    print(head + "\n" + "-" * len(head), flush=True)
    rows = []
    for name in meshes:
        obj = info[name]["path"]
        before = load()
        runs = {"fg": [], "d1": [], "d0": []}
        for _ in range(repeat):
            runs["fg"].append(run_fieldgen(exe, obj, outdir, timeout))
            runs["d1"].append(run_child(["dhlb", obj, "default"], dhlb_env(True), timeout))
            runs["d0"].append(run_child(["dhlb", obj, "default"], dhlb_env(False), timeout))
        after = load()
        errors = [r["error"] for k in runs for r in runs[k] if "error" in r]
        med = {k: {key: median(v, key) for key in ("read", "init", "assemble", "analyze", "factor", "solves",
                                                     "indices", "compute", "total", "wall", "mb", "setup", "solve",
                                                     "import", "eta")}
               for k, v in runs.items()}
        last = {k: next((r for r in reversed(v) if "error" not in r), {}) for k, v in runs.items()}
        fg, d1, d0 = med["fg"], med["d1"], med["d0"]
        label = os.path.splitext(name)[0]
        print(f"{label:<22}{info[name]['faces']:>9}{fg['total']:>10.3f}{d1['total']:>9.3f}{d0['total']:>9.3f}"
              f"{d1['total'] / fg['total']:>9.2f}{d0['total'] / fg['total']:>7.2f}"
              f"{d1['compute'] / fg['compute']:>8.2f}{fg['wall']:>9.3f}"
              f"{d1['wall']:>10.3f}{d0['wall']:>8.3f}{fg['mb']:>8.0f}{d1['mb']:>9.0f}{d0['mb']:>7.0f}  "
              f"{before} / {after}", flush=True)
        for e in errors:
            print(f"  FAILED: {e}", flush=True)
        rows.append({"mesh": name, "faces": info[name]["faces"], "vertices": info[name]["vertices"],
                     "medians": med, "load_before": before, "load_after": after, "errors": errors,
                     "fieldgen": {k: last["fg"].get(k) for k in ("nsolves", "singular_faces", "index_sum", "eta")},
                     "dhlb": {k: last["d1"].get(k) for k in ("backend", "factorizations", "solves", "singular_faces",
                                                             "index_sum", "residual")}})
    head2 = (f"{'mesh':<22}{'fg read':>8}{'init':>7}{'assem':>7}{'analyz':>7}{'factor':>7}{'solves':>7}{'indic':>7}"
             f"{'eta':>9}{'sing':>6}  |{'d read':>7}{'setup':>7}{'solve':>7}{'indic':>7}{'import':>7}"
             f"{'1t wall-total':>14}{'sing':>6}  backend, solves")
    print("\nphases (medians, seconds): fieldgen | dhlb with OPENBLAS_NUM_THREADS=1")
    print(head2 + "\n" + "-" * len(head2))
    for row in rows:
        fg, d1, f, d = row["medians"]["fg"], row["medians"]["d1"], row["fieldgen"], row["dhlb"]
        eta = f"{f['eta']:.1e}" if f["eta"] is not None else "-"
        print(f"{os.path.splitext(row['mesh'])[0]:<22}{fg['read']:>8.3f}{fg['init']:>7.3f}{fg['assemble']:>7.3f}"
              f"{fg['analyze']:>7.3f}{fg['factor']:>7.3f}{fg['solves']:>7.3f}{fg['indices']:>7.3f}{eta:>9}"
              f"{f['singular_faces'] or 0:>6}  |{d1['read']:>7.3f}{d1['setup']:>7.3f}{d1['solve']:>7.3f}"
              f"{d1['indices']:>7.3f}{d1['import']:>7.3f}{d1['wall'] - d1['total']:>14.3f}{d['singular_faces'] or 0:>6}"
              f"  {d['backend']}, {d['factorizations']} fact. / {d['solves']} solves")
    print("fg total = read + init + smoothest (assemble, analyze, factor, solves, Rayleigh quotient, indices); "
          f"{'fieldgen iterations: ' + str(rows[0]['fieldgen']['nsolves']) if rows else ''}; eta = backward error "
          "of fieldgen's eigenpair; dhlb total = read + setup + solve + indices; wall - total = interpreter start-up, "
          "imports, exit", flush=True)
    return rows


def equal_answer(meshes, info, exe, outdir, iters_list, repeat, timeout):
    """Singularities of fieldgen (by iterations) and of dhlb's default solve against dhlb at tol = 1e-14."""
    print("\nequal answer: singular faces whose index differs from dhlb's tol = 1e-14 solve (n = 4)")
    out = []
    for name in meshes:
        obj = info[name]["path"]
        ref = run_child(["dhlb", obj, "1e-14"], dhlb_env(True), timeout)
        dfl = run_child(["dhlb", obj, "default"], dhlb_env(True), timeout)
        label = os.path.splitext(name)[0]
        if "error" in ref or "error" in dfl:
            print(f"{label}: FAILED: {ref.get('error') or dfl.get('error')}")
            continue
        R = {f: k for f, k in ref["singularities"]}
        D = {f: k for f, k in dfl["singularities"]}
        print(f"{label}: reference {len(R)} singular faces (index sum {ref['index_sum']}, {ref['solves']} solves, "
              f"{ref['total']:.2f} s); dhlb default tol: {differing(D, R)} differ ({dfl['total']:.2f} s, "
              f"{dfl['solves']} solves)  [load {load()}]", flush=True)
        row = {"mesh": name, "reference_singular_faces": len(R), "dhlb_default_differs": differing(D, R),
               "fieldgen": []}
        found = None
        for k in iters_list:
            r = run_fieldgen(exe, obj, outdir, timeout, iters=k, singularities=True)
            if "error" in r:
                print(f"  FG_ITERS={k}: FAILED: {r['error']}", flush=True)
                break
            diff = differing(r["singularities"], R)
            row["fieldgen"].append({"iters": k, "differ": diff, "singular_faces": len(r["singularities"]),
                                    "eta": r["eta"], "total": r["total"]})
            print(f"  fieldgen FG_ITERS={k:<4} ({r['nsolves']} solves): {len(r['singularities']):>5} singular faces, "
                  f"{diff:>4} differ, eta {r['eta']:.1e}, total {r['total']:.3f} s", flush=True)
            if diff == 0:
                found = (k, [r] + [run_fieldgen(exe, obj, outdir, timeout, iters=k) for _ in range(repeat - 1)])
                break
        if found:
            k, runs = found
            t, w = median(runs, "total"), median(runs, "wall")
            row["equal_iters"], row["equal_total"] = k, t
            print(f"  smallest FG_ITERS with the reference's singularities: {k}, fieldgen total {t:.3f} s "
                  f"(wall {w:.3f} s, median of {len(runs)}) vs dhlb default {dfl['total']:.3f} s "
                  f"(ratio {dfl['total'] / t:.2f})", flush=True)
        else:
            print(f"  fieldgen never gave the reference's singularities for FG_ITERS in {iters_list}", flush=True)
        out.append(row)
    return out


# -------------------------------------------------------------------------------------------------- main


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 epilog="Environment: FIELDGEN=path of the instrumented fieldgen binary (required); "
                                        "FG_ITERS is set by --equal-answer for fieldgen's iteration count.")
    ap.add_argument("--quick", action="store_true", help=f"skip the 1.31M-face icosphere ({ICO})")
    ap.add_argument("--meshes", help=f"comma-separated subset (file names or stems) of {', '.join(FILES)}, {ICO}")
    ap.add_argument("--repeat", type=int, default=3, help="interleaved rounds per mesh (default 3); medians")
    ap.add_argument("--equal-answer", action="store_true",
                    help="also compare singularities with dhlb at tol = 1e-14 and search fieldgen's FG_ITERS")
    ap.add_argument("--fg-iters", default="20,40,60,90,120", help="FG_ITERS searched by --equal-answer")
    ap.add_argument("--timeout", type=float, default=1800.0, help="seconds per child process (default 1800)")
    ap.add_argument("--json", help="also write the results to this JSON file")
    ap.add_argument("--child", nargs="+", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        kind, *rest = args.child
        if kind == "prep":
            child_prep(rest[0], rest[1:])
        else:
            child_dhlb(rest[0], rest[1])
        return 0
    exe = os.environ.get("FIELDGEN")
    if not exe:
        print("bench_fieldgen: set FIELDGEN to the instrumented fieldgen binary, e.g. FIELDGEN=/tmp/fg/fieldgen "
              "(built by /work/shared/anchors/fieldgen/build.sh)", file=sys.stderr)
        return 2
    if not (os.path.isfile(exe) and os.access(exe, os.X_OK)):
        print(f"bench_fieldgen: FIELDGEN={exe} is not an executable file", file=sys.stderr)
        return 2
    names = FILES + [ICO]
    if args.meshes:
        stems = {os.path.splitext(n)[0]: n for n in names}
        want = [m.strip() for m in args.meshes.split(",") if m.strip()]
        bad = [m for m in want if m not in names and m not in stems]
        if bad:
            print(f"bench_fieldgen: unknown mesh {', '.join(bad)}; choose from {', '.join(names)}", file=sys.stderr)
            return 2
        names = [stems.get(m, m) for m in want]
    if args.quick:
        names = [n for n in names if n != ICO]
    t_start = time.perf_counter()
    print(f"bench_fieldgen: fieldgen {exe}; python {sys.version.split()[0]}; {os.cpu_count()} cpus; "
          f"OPENBLAS_NUM_THREADS in this shell: {BASE_ENV.get('OPENBLAS_NUM_THREADS', 'unset')}; "
          f"load average before: {load()}", flush=True)
    with tempfile.TemporaryDirectory(prefix="bench_fieldgen-") as tmp:
        r = run_process([sys.executable, os.path.abspath(__file__), "--child", "prep", tmp, *names],
                        dhlb_env(True), args.timeout)
        if r["rc"] != 0:
            print(f"bench_fieldgen: preparing the meshes failed: {r['stderr'].strip()[-500:]}", file=sys.stderr)
            return 1
        info = json.loads(r["stdout"].strip().splitlines()[-1])
        for name in names:
            i = info[name]
            if i["dropped"]:
                print(f"  {name}: {i['dropped']} unreferenced vertices dropped for both tools", flush=True)
        rows = timing(names, info, exe, tmp, args.repeat, args.timeout)
        eq = None
        if args.equal_answer:
            iters = [int(k) for k in args.fg_iters.split(",")]
            eq = equal_answer(names, info, exe, tmp, iters, args.repeat, args.timeout)
    print(f"\nload average after: {load()}; {time.perf_counter() - t_start:.0f} s in all", flush=True)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"fieldgen": exe, "meshes": info, "timing": rows, "equal_answer": eq}, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
