#!/usr/bin/env python3
"""Variants per second of a design study (issue 19): rayon, a Dask LocalCluster, a Python loop.

The five-folded-sheet guide of the paper (examples/paper_dynamic_5_sheets.toml), a Latin
hypercube over the sheet thickness and width; every variant runs the kinematic check, the
static path with the support stiffness of the platform c in y and z, and 10 modes. Timed in
the same run, on this machine:

- ``one core``: ``flexmbd.study.run(jobs=1)``;
- ``rayon``: ``flexmbd.study.run(jobs=2)`` (all cores of a 2-core machine);
- ``dask``: ``flexmbd.study.run(client=...)`` on a ``LocalCluster`` of 2 worker processes with
  1 thread each (the cluster started before the clock);
- ``python loop``: the same analyses called one variant after the other from Python
  (``Model.set``, ``check``, ``static``, ``modes``), one core;
- ``cli``: the whole process ``flexmbd study --jobs 2`` of the release binary (writing the
  records, without plots).

Targets (issue 19): rayon within 10 % of twice the one-core speed; Dask within 25 % of rayon.
The best of ROUNDS rounds is reported (the machine's load only slows a run down).

    python3 bench/study_throughput.py [--samples 200] [--rounds 2] [--out bench/results/study-DATE]

Needs the package installed (``pip install ./crates/flexmbd-py``), dask and distributed
(``pip install "dask[distributed]"``) and the release binary (``cargo build --release -p
flexmbd-cli``).
"""

import argparse
import json
import os
import pathlib
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
MODEL = ROOT / "examples" / "paper_dynamic_5_sheets.toml"

STUDY = """
[study]
name = "five folded sheets: thickness and width"
model = "{model}"
analyses = ["check", "stroke", "modes"]
support = ["c:y", "c:z"]
buckling = false
modes = 10
sampling = "latin"
samples = {samples}
seed = 1
[parameters]
"sections.sheet.t" = {{ from = 0.15e-3, to = 0.3e-3 }}
"sections.sheet.w" = {{ from = 0.015, to = 0.025 }}
"""


def timed(f):
    t = time.perf_counter()
    out = f()
    return time.perf_counter() - t, out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=200)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--out", default=None)
    ap.add_argument("--binary", default=str(ROOT / "target" / "release" / "flexmbd"), help="the flexmbd binary of the cli run (skipped if missing)")
    a = ap.parse_args()

    import flexmbd
    import flexmbd.study
    from distributed import Client, LocalCluster

    tmp = pathlib.Path(tempfile.mkdtemp(prefix="flexmbd-study-bench-"))
    study_file = tmp / "study.toml"
    study_file.write_text(STUDY.format(model=MODEL.as_posix(), samples=a.samples))
    s = flexmbd.study.load(study_file)
    variants = s.variants()
    n = len(variants)
    exe = pathlib.Path(a.binary)

    def python_loop():
        base = flexmbd.load(MODEL)
        out = []
        for _, values in variants:
            m = base.copy()
            for k, v in values.items():
                m.set(k, v)
            out.append((m.check(max_suggestions=0), m.static(compliance=["c"]), m.modes(count=10)))
        return out

    def cli():
        out = tmp / "cli_out"
        p = subprocess.run(
            [str(exe), "--quiet", "--force", "study", str(study_file), "--out", str(out), "--jobs", "2", "--no-plots"],
            capture_output=True,
            text=True,
        )
        if p.returncode != 0:
            sys.exit(f"flexmbd study failed: {p.stderr}")

    best = {}
    reference = None
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, Client(cluster) as client:
        client.run(lambda: __import__("flexmbd.study"))  # import on the workers before the clock
        for _ in range(a.rounds):
            runs = {
                "one core": lambda: flexmbd.study.run(s, jobs=1),
                "rayon": lambda: flexmbd.study.run(s, jobs=2),
                "dask": lambda: flexmbd.study.run(s, client=client),
                "python loop": python_loop,
            }
            if exe.exists():
                runs["cli"] = cli
            for name, f in runs.items():
                t, out = timed(f)
                best[name] = min(best.get(name, t), t)
                if name in ("one core", "rayon", "dask"):
                    if reference is None:
                        reference = out.lines
                    elif out.lines != reference:
                        sys.exit(f"{name}: the records differ from the first run")
    rate = {k: n / t for k, t in best.items()}
    print(f"{n} variants of {MODEL.name} (check + stroke with support stiffness + 10 modes), best of {a.rounds}")
    print(f"{'runner':<14}{'time [s]':>10}{'variants/s':>13}")
    for k in best:
        print(f"{k:<14}{best[k]:>10.3f}{rate[k]:>13.1f}")
    ratio_rayon = rate["rayon"] / (2 * rate["one core"])
    ratio_dask = rate["dask"] / rate["rayon"]
    print(f"rayon / (2 x one core) = {ratio_rayon:.3f}  (target >= 0.90)")
    print(f"dask / rayon           = {ratio_dask:.3f}  (target >= 0.75)")
    print(f"rayon / python loop    = {rate['rayon'] / rate['python loop']:.2f}")
    result = {
        "variants": n,
        "model": MODEL.name,
        "seconds": best,
        "variants_per_second": rate,
        "rayon_over_two_cores": ratio_rayon,
        "dask_over_rayon": ratio_dask,
        "cores": os.cpu_count(),
        "records_identical": True,
    }
    if a.out:
        out = pathlib.Path(a.out)
        out.mkdir(parents=True, exist_ok=True)
        (out / "study_throughput.json").write_text(json.dumps(result, indent=2) + "\n")


if __name__ == "__main__":
    main()
