#!/usr/bin/env python3
"""flexmbd simulate vs Exudyn on the peer kit's flexible pendulum (problem pendulum_sim, 3d).

Same model as the peer script pendulum_sim_exudyn.py --model 3d: an elastomer strip
L = 0.5 m, b = 10 mm, h = 2 mm, E = 1e8 Pa, nu = 0.3, rho = 1000 kg/m^3 in N beams, held at
x = 0 by a spherical joint (position fixed, rotation free), along +x, gravity -z (swinging about
the weak axis), initial velocity v_y = 0.5 x at every node but the first (spatial motion).
Both integrate with generalised-alpha (rho_inf = 0.9, index 3) at the fixed step h = 1e-3 s to
t_end = 1 s (N >= 1000: 0.2 s). flexmbd's accuracy: the tip at t_end against a flexmbd run with
h/8 (the step-size error of the h run) and its energy balance error; the two programs' tips
are listed side by side (their beam models differ: Exudyn's has shear, flexmbd's the
SPACAR beam with a consistent Hermite mass). Times: Exudyn's in-process solve (t_solve_s);
flexmbd's whole process (start-up, reading, JSON output) and in process (the library call that
`simulate --timings` reports), with a ratio for each.

Usage: sim_pendulum.py --flexmbd BIN [--peers DIR] [--python PY] [--n N ...] [--out FILE]
Prints a table; --out writes the records as JSON lines.
"""
import argparse
import json
import os
import re
import resource
import subprocess
import sys
import tempfile
import time

sys.dont_write_bytecode = True

L, E, RHO, H, B, NU = 0.5, 1e8, 1000.0, 0.002, 0.01, 0.3


def model_toml(n, t_end, dt, spatial=True):
    lines = [
        "[model]", f'name = "flexible pendulum N={n}"',
        "[nodes]", "p0 = [0.0, 0.0, 0.0]", f"p1 = [{L}, 0.0, 0.0]",
        "[fix]", 'p0 = ["x", "y", "z"]',
        "[[material]]", 'id = "rubber"', f"E = {E}", f"nu = {NU}", f"rho = {RHO}",
        "[[section]]", 'id = "strip"', 'shape = "rectangle"', f"w = {B}", f"t = {H}",
        "[[beam]]", 'id = "s"', 'nodes = ["p0", "p1"]', "orient = [0.0, 1.0, 0.0]",
        'section = "strip"', 'material = "rubber"', f"segments = {n}",
        "[static]", "gravity = [0.0, 0.0, -9.81]",
        "[simulate]", f"t_end = {t_end}", f"dt = {dt}", 'step = "fixed"', f"output_step = {t_end}",
    ]
    if spatial:
        # the pivot node starts at rest, as in the peer script (Exudyn's default)
        lines += ["[[velocity]]", 'node = "p0"', "v = [0.0, 0.0, 0.0]"]
        for k in range(1, n + 1):
            x = L * k / n
            name = "p1" if k == n else f"s:{k}"
            lines += ["[[velocity]]", f'node = "{name}"', f"v = [0.0, {0.5 * x}, 0.0]"]
    return "\n".join(lines) + "\n"


def run_flexmbd(binary, n, t_end, dt, tmp):
    path = os.path.join(tmp, f"pendulum_{n}_{dt}.toml")
    with open(path, "w") as f:
        f.write(model_toml(n, t_end, dt))
    t0 = time.perf_counter()
    p = subprocess.run([binary, "--quiet", "simulate", path, "--json", "--timings"],
                       capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        return {"status": "error", "message": p.stderr.strip()[:300]}
    d = json.loads(p.stdout)
    last = d["frames"][-1]
    tip = next(nd for nd in last["nodes"] if nd["node"] == "p1")["position"]
    # the library call (set-up, initial state, integration) as --timings reports it: what
    # Exudyn's t_solve_s measures
    m = re.search(r"simulate ([0-9.]+) ms", p.stderr)
    solve = float(m.group(1)) / 1e3 if m else None
    return {"status": "ok", "wall_s": wall, "solve_s": solve, "steps": d["stats"]["steps"],
            "newton_iterations": d["stats"]["newton_iterations"],
            "energy_error_J": d["stats"]["max_energy_error"], "tip": tip}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--flexmbd", required=True)
    ap.add_argument("--peers")
    ap.add_argument("--python", default=os.path.expanduser("~/.cache/flexmbd-peers/venv/bin/python"))
    ap.add_argument("--n", type=int, nargs="+", default=[10, 100, 1000])
    ap.add_argument("--h", type=float, default=1e-3)
    ap.add_argument("--out")
    a = ap.parse_args()
    records = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in a.n:
            t_end = 1.0 if n < 1000 else 0.2
            rec = {"problem": "pendulum_sim", "model": "3d", "n": n, "h": a.h, "t_end": t_end}
            f = run_flexmbd(a.flexmbd, n, t_end, a.h, tmp)
            rec["flexmbd"] = f
            if f["status"] == "ok" and n <= 100:
                ref = run_flexmbd(a.flexmbd, n, t_end, a.h / 8, tmp)
                if ref["status"] == "ok":
                    f["tip_error_m"] = max(abs(u - v) for u, v in zip(f["tip"], ref["tip"]))
            if a.peers:
                p = subprocess.run([a.python, os.path.join(a.peers, "pendulum_sim_exudyn.py"),
                                    "--n", str(n), "--model", "3d", "--h", str(a.h)],
                                   capture_output=True, text=True)
                lines = [ln for ln in p.stdout.splitlines() if ln.startswith("{")]
                rec["exudyn"] = json.loads(lines[-1]) if lines else {"status": "error",
                                                                     "message": p.stderr[-300:]}
            records.append(rec)
            print(json.dumps(rec), file=sys.stderr)
    print(f"{'N':>6} {'flexmbd s':>10} {'in proc. s':>10} {'steps/s':>9} {'Exudyn s':>10} "
          f"{'steps/s':>9} {'ratio':>7} {'in proc.':>9}"
          f" {'tip error flexmbd (m)':>22} {'energy err (J)':>15}  tip flexmbd | tip Exudyn")
    for r in records:
        f, x = r["flexmbd"], r.get("exudyn", {})
        fw, fs = f.get("wall_s"), f.get("solve_s")
        xw = x.get("t_solve_s") if x.get("status") == "ok" else None
        ratio = f"{xw / fw:7.1f}" if fw and xw else "      -"
        ratio_s = f"{xw / fs:9.1f}" if fs and xw else "        -"
        steps = f.get("steps", 0)
        print(f"{r['n']:>6} {fw or float('nan'):>10.3f} {fs or float('nan'):>10.3f} "
              f"{steps / fs if fs else 0:>9.0f} "
              f"{xw or float('nan'):>10.3f} {x.get('steps_per_s', 0):>9.0f} {ratio} {ratio_s} "
              f"{f.get('tip_error_m', float('nan')):>22.2e} {f.get('energy_error_J', float('nan')):>15.2e}  "
              f"{[round(v, 5) for v in f.get('tip', [])]} | "
              f"{[round(v, 5) for v in x.get('tip_position_m', [])]}")
    if a.out:
        with open(a.out, "w") as fo:
            for r in records:
                fo.write(json.dumps(r) + "\n")


if __name__ == "__main__":
    main()
