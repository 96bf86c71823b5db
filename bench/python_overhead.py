#!/usr/bin/env python3
"""The overhead of a Python call against the Rust call (issue 16).

Times `Model.check()` and `Model.modes(count=10)` of the installed `flexmbd` package on the
five-folded-sheet guide of the paper (examples/paper_dynamic_5_sheets.toml) against the same
library calls made from Rust in process (crates/flexmbd-py/benches/rust_calls.rs, built by
`cargo bench` in release mode, as the wheel is). Both sides: the model read once, then the
fastest of REPEAT calls (the machine's load adds to single calls, never takes away), in
ROUNDS alternating rounds; the fastest over the rounds is reported. Prints a table and the
overhead in per cent of the Rust time.

    python3 bench/python_overhead.py [--model examples/….toml] [--repeat 200]

Needs the package installed (`pip install ./crates/flexmbd-py`) and cargo.
"""

import argparse
import json
import pathlib
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]


def fastest_time(f, repeat):
    f()
    ts = []
    for _ in range(repeat):
        t = time.perf_counter()
        f()
        ts.append(time.perf_counter() - t)
    return min(ts)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--model", default="examples/paper_dynamic_5_sheets.toml")
    ap.add_argument("--repeat", type=int, default=200)
    ap.add_argument("--rounds", type=int, default=3)
    a = ap.parse_args()

    import flexmbd

    model = flexmbd.load(str(ROOT / a.model))
    best = {"check_s": [], "modes_s": [], "py_check": [], "py_modes": []}
    for _ in range(a.rounds):
        rust = subprocess.run(
            ["cargo", "bench", "-q", "-p", "flexmbd-py", "--bench", "rust_calls", "--", str(ROOT / a.model), str(a.repeat)],
            cwd=ROOT,
            capture_output=True,
            text=True,
        )
        if rust.returncode != 0:
            sys.exit(f"the Rust side failed:\n{rust.stderr}")
        r = json.loads(rust.stdout.strip().splitlines()[-1])
        best["check_s"].append(r["check_s"])
        best["modes_s"].append(r["modes_s"])
        best["py_check"].append(fastest_time(lambda: model.check(), a.repeat))
        best["py_modes"].append(fastest_time(lambda: model.modes(count=10), a.repeat))

    rows = [
        ("check", min(best["check_s"]), min(best["py_check"])),
        ("modes (count=10)", min(best["modes_s"]), min(best["py_modes"])),
    ]
    print(f"model: {a.model}, fastest of {a.rounds} x {a.repeat} calls each")
    print(f"{'call':<18} {'Rust [ms]':>10} {'Python [ms]':>12} {'overhead':>9}")
    for name, rs, ps in rows:
        print(f"{name:<18} {rs * 1e3:>10.3f} {ps * 1e3:>12.3f} {100 * (ps - rs) / rs:>8.1f}%")


if __name__ == "__main__":
    main()
