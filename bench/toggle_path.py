#!/usr/bin/env python3
"""Statics path benchmark of issue 17: the Williams toggle frame (validation S05) followed to an
apex deflection of 0.7 in (17.78 mm), by flexmbd and by Exudyn.

The model is examples/williams_toggle.toml (the half model, 20 Euler-Bernoulli beams); the
script writes its variants into a temporary folder, changing only the apex load or replacing it
by a prescribed apex stroke, and [static]:

  flexmbd  arc length, load to P(0.7 in)   the half load P_07/2, P_07 = 88.184 lbf = 392.26 N (the
                                           reference load at 0.7 in), steps = 20, path = arc length:
                                           the path ends exactly at t = 1, i.e. at that load
  flexmbd  stroke, load steps              the apex y prescribed to -0.7 in, 14 steps of 0.05 in
                                           (the reference grid), the default path
  flexmbd  stroke, arc length              the same stroke with path = arc length
  flexmbd  load steps, load to P(0.7 in)   the load of the first case, 20 equal load steps
  flexmbd  arc length / load steps, 180 N  the example as it is (P = 180 N, steps = 20)
  Exudyn   load stepping, P(0.7 in) / 180 N  bench/peers/toggle_exudyn.py --mode load, 20 steps
  Exudyn   stroke                          bench/peers/toggle_exudyn.py --mode disp, 14 steps

flexmbd's time is the whole process as a user runs it (`flexmbd --quiet static FILE --json`:
start, reading, solving, the JSON of every step on a pipe); Exudyn's is its in-process
SolveStatic of the successful attempt (t_solve_s; model building, Python start and imports
excluded; t_total_s of the record adds the failed attempts of the kit's tolerance retries).

From every path (apex deflection delta, total load P at every converged step) the script takes:
whether the descending branch between the two limit points was followed; the first maximum of P
(the limit load as sampled by the steps) and the following minimum; a jump (two consecutive
points on either side of the unstable stretch 5.906 mm < delta < 9.97 mm); P at 5.906 mm and at
the reference deflections of validation.md S05 (quadratic interpolation along the path through
the three nearest points of a stretch where delta increases; exact where a step lands on the
reference deflection); and the end point against 0.7 in / 88.184 lbf.

Usage: toggle_path.py --flexmbd BIN [--peers DIR] [--python PY] [--repeat K] [--out DIR]
Prints the table (markdown); --out DIR writes records.jsonl (one line per case, first line the
run's description) and run.log, with machine paths written as $PEERS, $PEERS_VENV, $TMP.
"""
import argparse
import json
import os
import platform
import re
import statistics
import subprocess
import sys
import tempfile
import time

sys.dont_write_bytecode = True

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
EXAMPLE = os.path.join(ROOT, "examples", "williams_toggle.toml")

LBF, INCH = 4.4482216152605, 0.0254
# validation.md S05: (apex delta [in], P [lbf]) of the derived exact path
REF_PATH = [(0.05, 15.183), (0.10, 25.203), (0.15, 30.981), (0.20, 33.499), (0.25, 33.778),
            (0.30, 32.847), (0.35, 31.708), (0.40, 31.303), (0.45, 32.502), (0.50, 36.097),
            (0.60, 53.313), (0.70, 88.184)]
REF_MAX = (0.2325 * INCH, 33.870 * LBF)     # limit load 150.66 N at 5.906 mm
REF_MIN = (0.3925 * INCH, 31.282 * LBF)     # following minimum 139.15 N at 9.97 mm
P_07 = 88.184 * LBF                          # 392.26 N: the load at delta = 0.7 in
D_07 = 0.7 * INCH                            # 17.78 mm
P_FULL = 180.0                               # the example's load


# ------------------------------------------------------------------------------------------
# flexmbd
# ------------------------------------------------------------------------------------------
def toml_variant(load_half=None, stroke=None, steps=20, path=None):
    """examples/williams_toggle.toml with the apex load P/2 = load_half, or with the load
    replaced by a prescribed apex stroke (y = -stroke), and the [static] block replaced."""
    text = open(EXAMPLE).read()
    head, sep, tail = text.partition("[[load]]")
    assert sep and 'force = [0.0, -90.0, 0.0]' in tail, "examples/williams_toggle.toml changed"
    if stroke is not None:
        body = f'[[prescribe]]\nnode = "apex"\ndof = "y"\nvalue = {-stroke!r}\n'
    else:
        body = f'[[load]]\nnode = "apex"\nforce = [0.0, {-load_half!r}, 0.0]\n'
    static = f"\n[static]\nsteps = {steps}\n" + (f'path = "{path}"\n' if path else "")
    return head + body + static


def run_flexmbd(binary, toml_path, load_half):
    t0 = time.perf_counter()
    p = subprocess.run([binary, "--quiet", "static", toml_path, "--json"],
                       capture_output=True, text=True)
    wall = time.perf_counter() - t0
    rec = {"rc": p.returncode, "wall_s": wall, "stderr": p.stderr.strip()[-600:]}
    try:
        d = json.loads(p.stdout)
    except json.JSONDecodeError:
        rec["status"] = "error"
        return rec
    pts = []
    for s in d["steps"]:
        apex = next(n for n in s["nodes"] if n["node"] == "apex")
        delta = -apex["displacement"][1]
        if load_half is None:       # the stroke's actuation force on the half model
            P = -2.0 * apex["reaction_force"][1]
        else:
            P = 2.0 * s["load_factor"] * load_half
        pts.append([delta, P])
    later = d["steps"][1:]
    rec.update(status="ok" if p.returncode == 0 and not d.get("stopped") else "stopped",
               steps=len(later), substeps=sum(s["substeps"] for s in later),
               newton_iterations=sum(s["iterations"] for s in later),
               events=d.get("events", []), stopped=d.get("stopped"), path=pts)
    return rec


# ------------------------------------------------------------------------------------------
# Exudyn (bench/peers/toggle_exudyn.py, one process per run)
# ------------------------------------------------------------------------------------------
def run_exudyn(python, peers, args):
    cmd = [python, os.path.join(HERE, "peers", "toggle_exudyn.py"), "--peers", peers, "--n", "20"]
    p = subprocess.run(cmd + args, capture_output=True, text=True)
    lines = [ln for ln in p.stdout.splitlines() if ln.startswith("{")]
    if not lines:
        return {"status": "error", "rc": p.returncode, "stderr": p.stderr.strip()[-600:]}
    d = json.loads(lines[-1])
    d["wall_s"] = d.get("t_solve_s")
    d["path"] = [[dl, P] for _, dl, P in d.get("path", [])]
    d["stderr"] = p.stderr.strip()[-600:]
    return d


# ------------------------------------------------------------------------------------------
# Path analysis
# ------------------------------------------------------------------------------------------
def is_jump(a, b):
    """Two consecutive path points on either side of the unstable stretch of the reference path
    (a load step that snapped through): nothing between them is on the path."""
    return a[0] < REF_MAX[0] and b[0] > REF_MIN[0]


def interp(pts, x):
    """P at delta = x on the first stretch of the path where delta increases through x:
    quadratic through the three nearest points of that stretch (linear with two); None where
    the path has no point near x (before its start, past its end, inside a jump)."""
    eps = 1e-9                      # [m]: a step that lands on x (up to round-off) hits it
    for i in range(len(pts) - 1):
        (d0, _), (d1, _) = pts[i], pts[i + 1]
        if d0 - eps <= x <= d1 + eps and d1 > d0:
            if abs(x - d0) <= eps:
                return pts[i][1]
            if abs(x - d1) <= eps:
                return pts[i + 1][1]
            if is_jump(pts[i], pts[i + 1]):
                return None
            cand = [j for j in (i - 1, i + 2) if 0 <= j < len(pts)]
            cand = [j for j in cand if (j < i and pts[j][0] < d0 and not is_jump(pts[j], pts[i]))
                    or (j > i + 1 and pts[j][0] > d1 and not is_jump(pts[i + 1], pts[j]))]
            idx = [i, i + 1] + sorted(cand, key=lambda j: abs(pts[j][0] - x))[:1]
            xs = [pts[j][0] for j in idx]
            ys = [pts[j][1] for j in idx]
            if len(idx) == 2 or min(abs(a - b) for a in xs for b in xs if a is not b) < 1e-9:
                xs, ys = xs[:2], ys[:2]
            return sum(ys[k] * _lagrange(xs, k, x) for k in range(len(xs)))
    return None


def _lagrange(xs, k, x):
    w = 1.0
    for j, xj in enumerate(xs):
        if j != k:
            w *= (x - xj) / (xs[k] - xj)
    return w


def analyse(pts):
    """Summary of a path [(delta, P)] against validation.md S05."""
    out = {"points": len(pts)}
    if not pts:
        return out
    i_max = next((i for i in range(1, len(pts) - 1)
                  if pts[i][1] >= pts[i - 1][1] and pts[i][1] > pts[i + 1][1]), None)
    if i_max is not None:
        d, P = pts[i_max]
        out.update(limit_load_n=P, limit_delta_m=d, limit_load_err=P / REF_MAX[1] - 1,
                   limit_delta_err=d / REF_MAX[0] - 1)
        i_min = next((i for i in range(i_max + 1, len(pts) - 1)
                      if pts[i][1] <= pts[i - 1][1] and pts[i][1] < pts[i + 1][1]), None)
        if i_min is not None:
            d, P = pts[i_min]
            out.update(min_load_n=P, min_delta_m=d, min_load_err=P / REF_MIN[1] - 1,
                       min_delta_err=d / REF_MIN[0] - 1)
    out["descending_branch"] = any(b[0] > a[0] and b[1] < a[1] and REF_MAX[0] * 0.9 < b[0] < REF_MIN[0] * 1.1
                                   for a, b in zip(pts, pts[1:]))
    jumps = [(a, b) for a, b in zip(pts, pts[1:]) if is_jump(a, b)]
    if jumps:
        a, b = jumps[0]
        out["jump"] = {"from_delta_m": a[0], "from_load_n": a[1], "to_delta_m": b[0], "to_load_n": b[1]}
    P = interp(pts, REF_MAX[0])
    if P is not None:
        out["load_at_5906_n"] = P
        out["load_at_5906_err"] = P / REF_MAX[1] - 1
    errs = []
    for din, plbf in REF_PATH:
        P = interp(pts, din * INCH)
        errs.append(None if P is None else P / (plbf * LBF) - 1)
    out["ref_path_err"] = errs
    covered = [e for e in errs if e is not None]
    out["ref_points_covered"] = len(covered)
    if covered:
        out["ref_path_max_abs_err"] = max(abs(e) for e in covered)
    out["end_delta_m"], out["end_load_n"] = pts[-1]
    out["steps_to_07"] = next((i for i, (d, _) in enumerate(pts) if d >= D_07 - 1e-9), None)
    return out


# ------------------------------------------------------------------------------------------
def cases(a):
    arc, ls = "arc-length", None
    c = [("flexmbd", "arc length, load to P(0.7 in)", dict(load_half=P_07 / 2, steps=20, path=arc)),
         ("flexmbd", "stroke 0.7 in, load steps", dict(stroke=D_07, steps=14, path=ls)),
         ("flexmbd", "stroke 0.7 in, arc length", dict(stroke=D_07, steps=14, path=arc)),
         ("flexmbd", "load steps, load to P(0.7 in)", dict(load_half=P_07 / 2, steps=20, path=ls)),
         ("flexmbd", "arc length, load 500 N (to the first point past 0.7 in)",
          dict(load_half=500.0 / 2, steps=20, path=arc)),
         ("flexmbd", "arc length, 180 N (the example)", dict(load_half=P_FULL / 2, steps=20, path=arc)),
         ("flexmbd", "load steps, 180 N (the example)", dict(load_half=P_FULL / 2, steps=20, path=ls))]
    if a.peers:
        c += [("exudyn", "load stepping, load to P(0.7 in)",
               ["--mode", "load", "--load", repr(P_07), "--steps", "20"]),
              ("exudyn", "load stepping, 180 N", ["--mode", "load", "--load", "180", "--steps", "20"]),
              ("exudyn", "stroke 0.7 in", ["--mode", "disp", "--stroke", repr(D_07), "--steps", "14"])]
    return c


def fmt(x, spec):
    return "–" if x is None else format(x, spec)


def row(r):
    s = r["summary"]
    jump = s.get("jump")
    if s.get("descending_branch"):
        passed = "yes"
    elif jump:
        passed = "jumps %.2f → %.2f mm at %.1f N" % (jump["from_delta_m"] * 1e3, jump["to_delta_m"] * 1e3,
                                                     jump["to_load_n"])
    elif s.get("limit_load_n") is None and s.get("end_delta_m", 0) < REF_MIN[0]:
        passed = "stops at %.3f mm" % (s.get("end_delta_m", 0) * 1e3)
    else:
        passed = "no"
    if jump:
        lim = "between %.2f and %.2f (jump)" % (jump["from_load_n"], jump["to_load_n"])
    else:
        lim = (fmt(s.get("limit_load_n"), ".2f") + " (" + fmt(100 * s["limit_load_err"], "+.2f") + " %) at "
               + fmt(1e3 * s["limit_delta_m"], ".2f") + " mm") if s.get("limit_load_n") else "–"
    mn = (fmt(s.get("min_load_n"), ".2f") + " (" + fmt(100 * s["min_load_err"], "+.2f") + " %)"
          ) if s.get("min_load_n") else "–"
    p59 = (fmt(s.get("load_at_5906_n"), ".2f") + " (" + fmt(100 * s["load_at_5906_err"], "+.2f") + " %)"
           ) if s.get("load_at_5906_n") else "–"
    path_err = (fmt(100 * s.get("ref_path_max_abs_err"), ".2f") + " %% (%d/12)" % s["ref_points_covered"]
                ) if s.get("ref_path_max_abs_err") is not None else "–"
    end = "%.3f mm, %.2f N" % (s["end_delta_m"] * 1e3, s["end_load_n"]) if "end_delta_m" in s else "–"
    newton = r.get("newton_iterations")
    steps = r.get("steps", "–")
    if s.get("steps_to_07") is not None and s["steps_to_07"] != steps:
        steps = f"{s['steps_to_07']} of {steps}"
    status = r["status"]
    if r["program"] == "exudyn" and r.get("rtol") is not None and not r.get("converged_default", True):
        status += ", rtol %g (%s failed)" % (r["rtol"], ", ".join(
            "%g" % x["rtol"] for x in r.get("attempts", []) if not x["ok"]))
    return (f"| {r['program']} | {r['case']} | {status} | {steps} | {fmt(newton, 'd')} | "
            f"{fmt(r.get('wall_s_median'), '.4f')} | {passed} | {lim} | {mn} | {p59} | {path_err} | {end} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--flexmbd", required=True, help="the flexmbd binary (a release build)")
    ap.add_argument("--peers", help="the peer kit (for peercommon.py); without it, no Exudyn")
    ap.add_argument("--python", default=os.path.expanduser("~/.cache/flexmbd-peers/venv/bin/python"),
                    help="the peers' Python (default: the kit's venv)")
    ap.add_argument("--repeat", type=int, default=1, help="runs of every case; times are medians")
    ap.add_argument("--out", help="folder for records.jsonl and run.log")
    a = ap.parse_args()
    binary = os.path.abspath(a.flexmbd)
    version = subprocess.run([binary, "--version"], capture_output=True, text=True).stdout.strip()
    meta = {"problem": "meta", "date": time.strftime("%Y-%m-%d %H:%M:%S %z"), "host_cpus": os.cpu_count(),
            "os": platform.platform(), "flexmbd_version": version, "bench_commit": git_commit(),
            "crates_commit": git_commit("crates", "Cargo.toml", "Cargo.lock"),
            "flexmbd_binary_note": "the binary given by --flexmbd; crates_commit is this "
                                   "checkout's code, which the binary should be built from",
            "flexmbd_process_start_s": process_start(binary),
            "repeat": a.repeat, "loadavg_before": os.getloadavg(), "example": "examples/williams_toggle.toml",
            "p07_n": P_07, "d07_m": D_07}
    records, log = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for k, (prog, name, spec) in enumerate(cases(a)):
            runs = []
            for _ in range(a.repeat):
                if prog == "flexmbd":
                    path = os.path.join(tmp, f"toggle_{k}.toml")
                    with open(path, "w") as f:
                        f.write(toml_variant(**spec))
                    runs.append(run_flexmbd(binary, path, spec.get("load_half")))
                else:
                    runs.append(run_exudyn(a.python, a.peers, spec))
            r = dict(runs[0], program=prog, case=name,
                     wall_s_runs=[x.get("wall_s") for x in runs])
            times = [t for t in r["wall_s_runs"] if t is not None]
            r["wall_s_median"] = statistics.median(times) if times else None
            if prog == "flexmbd":
                r["input"] = {k2: v for k2, v in spec.items()}
            else:
                r["args"] = spec
                r["wall_s_note"] = "SolveStatic of the successful attempt, in process"
            r["summary"] = analyse(r.get("path", []))
            if any(x.get("path") != r.get("path") for x in runs[1:]):
                r["note"] = "the repeats gave different paths"
            log.append(f"=== {prog} {name}: rc {r.get('rc')} status {r.get('status')}\n{r.get('stderr', '')}")
            r.pop("stderr", None)
            records.append(r)
            print(f"{prog} {name}: {r.get('status')}, {r.get('steps')} steps, "
                  f"{r['wall_s_median']} s", file=sys.stderr)
    meta["loadavg_after"] = os.getloadavg()
    head = ("| program | case | status | steps | Newton it. | time [s] | limit points passed | "
            "limit load found [N] | following min. [N] | P at 5.906 mm [N] | path error (max, points) "
            "| end |\n|" + "---|" * 12)
    print(head)
    for r in records:
        print(row(r))
    if a.out:
        os.makedirs(a.out, exist_ok=True)
        scrub = scrubber(a, tmp, binary)
        with open(os.path.join(a.out, "records.jsonl"), "w") as f:
            for r in [meta] + records:
                f.write(scrub(json.dumps(r)) + "\n")
        with open(os.path.join(a.out, "run.log"), "w") as f:
            f.write(scrub("\n".join(log)) + "\n")


def git_commit(*what):
    """The short commit of this checkout (HEAD), or the last one that changed the given paths;
    +dirty when crates/ has changes not committed."""
    try:
        c = subprocess.run(["git", "-C", ROOT, "log", "-1", "--format=%h", "--", *what],
                           capture_output=True, text=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", ROOT, "status", "--porcelain", "--", "crates"],
                               capture_output=True, text=True).stdout.strip()
        return c + ("+dirty" if dirty else "")
    except OSError:
        return None


def process_start(binary, n=5):
    """Median wall time of `flexmbd --version`: the start of a process, no model."""
    times = []
    for _ in range(n):
        t0 = time.perf_counter()
        subprocess.run([binary, "--version"], capture_output=True)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def scrubber(a, tmp, binary):
    """Machine paths out of the records: the kit, its venv, the temporary folder, the binary."""
    subs = []
    if a.peers:
        subs.append((os.path.abspath(a.peers), "$PEERS"))
    venv = os.path.dirname(os.path.dirname(os.path.abspath(a.python)))
    subs += [(venv, "$PEERS_VENV"), (tmp, "$TMP"), (binary, "$FLEXMBD"), (ROOT + "/", "")]
    subs.sort(key=lambda s: -len(s[0]))

    def f(text):
        for old, new in subs:
            text = text.replace(old, new)
        return re.sub(r"/(?:work|root|home|tmp|Users)/[^\s\"']*", "$PATH", text)
    return f


if __name__ == "__main__":
    main()
