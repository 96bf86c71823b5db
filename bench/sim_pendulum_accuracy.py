#!/usr/bin/env python3
"""flexmbd simulate vs Exudyn at equal accuracy (issue 13's benchmark): the flexible pendulum of
sim_pendulum.py (the peer kit's pendulum_sim, model 3d), each program at a sequence of fixed
steps h, the tip error of each run against the same program's run at a much smaller step (its
own converged tip: the two beam models differ, so each program is measured against itself), and
the wall time each program needs for a given tip error, interpolated log-log between its runs.

Exudyn's time is its in-process solve (`t_solve_s` of the peer script, without Python start-up
and model building). flexmbd's is given both ways: in process (the library call of set-up,
initial state and integration, as `simulate --timings` reports it: like for like with Exudyn's)
and as a user runs it (the whole process from a TOML file, with start-up, reading and JSON
output: this favours Exudyn). Two ratios follow. With --repeat R every run is made R times and
the fastest kept, for both programs (a short run's time on a shared virtual machine scatters).

Usage: sim_pendulum_accuracy.py --flexmbd BIN --peers DIR [--python PY] [--n N ...]
       [--h H ...] [--t-end T] [--targets E ...] [--repeat R] [--out FILE] [--refs FILE]
       sim_pendulum_accuracy.py --from FILE   (the tables of an earlier --out)
Prints two tables (runs; time at equal error and the ratio); --out writes JSON lines. --refs
keeps the reference runs (their tips; only their accuracy matters, not their time) in a JSON
file, reused when the program, N, t_end and step match: at N = 1000 they take minutes.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sim_pendulum import run_flexmbd  # noqa: E402


def run_exudyn(python, peers, n, h, t_end):
    p = subprocess.run([python, os.path.join(peers, "pendulum_sim_exudyn.py"), "--n", str(n),
                        "--model", "3d", "--h", str(h), "--t-end", str(t_end)],
                       capture_output=True, text=True)
    lines = [ln for ln in p.stdout.splitlines() if ln.startswith("{")]
    if not lines:
        return {"status": "error", "message": p.stderr[-300:]}
    d = json.loads(lines[-1])
    if d.get("status") != "ok":
        return d
    return {"status": "ok", "wall_s": d["t_solve_s"], "tip": d["tip_position_m"]}


def dist(a, b):
    return max(abs(u - v) for u, v in zip(a, b))


def time_at(runs, target, key="wall_s"):
    """Wall time for a tip error `target`: the cheapest of the runs whose error is at or below
    it and of the log-log interpolations between neighbouring steps whose errors bracket it
    (error and time each a power of h between two runs; None if no run is as accurate). Time
    need not fall with h: at large steps Newton needs more iterations per step; and the error
    need not fall with h either (Exudyn's stops near its Newton tolerance), so only bracketing
    neighbours are interpolated, never extrapolated."""
    ok = [r for r in runs if r.get("error_m") is not None and r.get(key)]
    best = [r[key] for r in ok if r["error_m"] <= target]
    by_h = sorted(ok, key=lambda r: -r["h"])
    for a, b in zip(by_h, by_h[1:]):
        if a["error_m"] > target >= b["error_m"] > 0:
            s = math.log(target / a["error_m"]) / math.log(b["error_m"] / a["error_m"])
            best.append(math.exp(math.log(a[key]) + s * math.log(b[key] / a[key])))
    return min(best) if best else None


def table(records, targets):
    nan = float("nan")
    print(f"{'N':>6} {'h':>8} {'flexmbd s':>10} {'in proc. s':>10} {'tip err (m)':>12} "
          f"{'Exudyn s':>10} {'tip err (m)':>12}")
    for r in records:
        for f, x in zip(r["flexmbd"]["runs"], r["exudyn"]["runs"]):
            print(f"{r['n']:>6} {f['h']:>8.1e} {f.get('wall_s', nan):>10.3f} "
                  f"{f.get('solve_s') or nan:>10.4f} {f.get('error_m', nan):>12.2e} "
                  f"{x.get('wall_s', nan):>10.3f} {x.get('error_m', nan):>12.2e}")
    print(f"\n{'N':>6} {'tip error':>10} {'flexmbd s':>10} {'in proc. s':>10} {'Exudyn s':>10} "
          f"{'ratio':>7} {'in proc.':>9}")
    for r in records:
        for e in targets:
            tf = time_at(r["flexmbd"]["runs"], e)
            ts = time_at(r["flexmbd"]["runs"], e, "solve_s")
            tx = time_at(r["exudyn"]["runs"], e)
            ratio = f"{tx / tf:7.1f}" if tf and tx else "      -"
            ratio_s = f"{tx / ts:9.1f}" if ts and tx else "        -"
            print(f"{r['n']:>6} {e:>10.0e} {tf or nan:>10.3f} {ts or nan:>10.4f} "
                  f"{tx or nan:>10.3f} {ratio} {ratio_s}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--flexmbd")
    ap.add_argument("--peers")
    ap.add_argument("--python", default=os.path.expanduser("~/.cache/flexmbd-peers/venv/bin/python"))
    ap.add_argument("--n", type=int, nargs="+", default=[10, 100, 1000])
    ap.add_argument("--h", type=float, nargs="+", default=[4e-3, 2e-3, 1e-3, 5e-4])
    ap.add_argument("--targets", type=float, nargs="+", default=[1e-3, 1e-4, 1e-5])
    ap.add_argument("--from", dest="from_file", help="tabulate the records of an earlier --out")
    ap.add_argument("--t-end", type=float, default=0.25,
                    help="simulated time [s]; over 1 s the swinging chain is so sensitive that "
                         "the tip does not converge monotonically in h (default 0.25)")
    ap.add_argument("--repeat", type=int, default=1,
                    help="runs per program and step, the fastest kept (default 1)")
    ap.add_argument("--out")
    ap.add_argument("--refs", help="JSON file of reference runs, read and extended")
    a = ap.parse_args()
    if a.from_file:
        with open(a.from_file) as f:
            table([json.loads(ln) for ln in f if ln.strip()], a.targets)
        return
    if not (a.flexmbd and a.peers):
        ap.error("--flexmbd and --peers are needed for a run")
    records = []
    refs = {}
    if a.refs and os.path.exists(a.refs):
        with open(a.refs) as f:
            refs = json.load(f)
    with tempfile.TemporaryDirectory() as tmp:
        for n in a.n:
            t_end = a.t_end
            h_ref = min(a.h) / 16
            rec = {"problem": "pendulum_sim", "model": "3d", "n": n, "t_end": t_end,
                   "h_ref": h_ref}
            for name, run in (("flexmbd", lambda h: run_flexmbd(a.flexmbd, n, t_end, h, tmp)),
                              ("exudyn", lambda h: run_exudyn(a.python, a.peers, n, h, t_end))):
                key = f"{name} n={n} t_end={t_end} h={h_ref}"
                ref = refs.get(key) or run(h_ref)
                if a.refs and ref["status"] == "ok" and key not in refs:
                    refs[key] = ref
                    with open(a.refs, "w") as f:
                        json.dump(refs, f, indent=1)
                runs = []
                for h in a.h:
                    tries = [run(h) for _ in range(max(1, a.repeat))]
                    r = min(tries, key=lambda t: t.get("wall_s") or math.inf)
                    if r["status"] == "ok" and r.get("solve_s") is not None:
                        r["solve_s"] = min(t.get("solve_s") or math.inf for t in tries)
                    if a.repeat > 1:
                        r["repeat"] = a.repeat
                    r["h"] = h
                    if r["status"] == "ok" and ref["status"] == "ok":
                        r["error_m"] = dist(r["tip"], ref["tip"])
                    runs.append(r)
                rec[name] = {"ref": ref, "runs": runs}
                print(json.dumps({"n": n, name: rec[name]}), file=sys.stderr)
            records.append(rec)
    table(records, a.targets)
    if a.out:
        with open(a.out, "w") as fo:
            for r in records:
                fo.write(json.dumps(r) + "\n")


if __name__ == "__main__":
    main()
