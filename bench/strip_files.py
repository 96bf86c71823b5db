#!/usr/bin/env python3
"""Whole-process runs of the release binary on a clamped strip of N beams read from model files
(issue 14): the SPACAR `.dat` reader (`flexmbd convert`), and `check`, `static` and
`modes --count 10` from the `.dat` file and from a TOML file, each with its wall time and peak
memory (`/usr/bin/time`). The files list every node and beam (no `segments`), as a user's
generated model would, so that the readers see N items. With `--read-bench`, also the reading
alone in process (`read dat`, `read toml`: the text, the parse and the build of the model as
`static` and `modes` do; `cargo bench -p flexmbd-io --bench read_model`, best of three).

    python3 bench/strip_files.py --flexmbd target/release/flexmbd \\
        --n 1000 3000 10000 30000 100000 --out results/strip_files.jsonl --plot results/strip_files.png

The strip is the peer kit's (peercommon.py): L = 50 mm along x, b = 20 mm (y), t = 0.2 mm (z),
steel E = 210 GPa, nu = 0.3, rho = 7800 kg/m^3, clamped at x = 0. `convert`, `check` and
`modes` read the unloaded strip; `static` a copy with a tip force of 1 N along the strip (10
load steps). A transverse tip load is not a fair test at these sizes: the bending stiffness of
a 50 mm cantilever (3 EI/L^3 = 67 N/m) against that of one beam of L/N (12 EI/(L/N)^3) makes
the tangent's condition number about 4 N^3, beyond double precision from N = 30,000 on
(Newton's increments are then round-off noise in any program with nodal coordinates). All six
deformation modes of every beam are flexible; `check` takes the strip as a flexure (its Dcc:
6N x 6N, the deformations as generalised coordinates; no motion, no self-stress).
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

sys.dont_write_bytecode = True

L, B, T, E, NU, RHO = 0.05, 0.02, 0.0002, 210e9, 0.3, 7800.0
G = E / (2 * (1 + NU))
A, IY, IZ = B * T, B * T**3 / 12, T * B**3 / 12
J = B * T**3 / 3 * (1 - 0.63 * T / B)
FX = 1.0


def strip_toml(n, loaded=False):
    out = [f'[model]\nname = "clamped strip of {n} beams"\n', "[nodes]"]
    out += [f"n{i} = [{L * i / n!r}, 0.0, 0.0]" for i in range(n + 1)]
    out += ['\n[fix]\nn0 = "all"\n']
    out += [f"[[material]]\nid = \"steel\"\nE = {E}\nnu = {NU}\nrho = {RHO}\n"]
    out += [f'[[section]]\nid = "strip"\nshape = "rectangle"\nw = {B}\nt = {T}\nshear = false\n']
    for k in range(n):
        out.append(f'[[beam]]\nid = "b{k}"\nnodes = ["n{k}", "n{k + 1}"]\norient = [0.0, 1.0, 0.0]\n'
                   'section = "strip"\nmaterial = "steel"\n')
    if loaded:
        out.append(f'[[load]]\nnode = "n{n}"\nforce = [{FX}, 0.0, 0.0]\n')
        out.append("[static]\nsteps = 10\n")
    return "\n".join(out)


def strip_dat(n, loaded=False):
    out = [f"# a clamped steel strip of {n} beams (flexmbd bench/strip_files.py)"]
    out += [f"X {2 * i + 1} {L * i / n!r} 0.0 0.0" for i in range(n + 1)]
    for k in range(1, n + 1):
        out.append(f"BEAM {k} {2 * k - 1} {2 * k} {2 * k + 1} {2 * k + 2} 0.0 1.0 0.0")
    out += [f"DYNE {k} 1 2 3 4 5 6" for k in range(1, n + 1)]
    out += ["FIX 1", "FIX 2", "END", "HALT"]
    out += [f"ESTIFF {k} {E * A!r} {G * J!r} {E * IY!r} {E * IZ!r}" for k in range(1, n + 1)]
    out += [f"EM {k} {RHO * A!r} {RHO * (IY + IZ)!r} {RHO * IY!r} {RHO * IZ!r} 0.0"
            for k in range(1, n + 1)]
    if loaded:
        out += [f"DELXF {2 * n + 1} {FX} 0.0 0.0", "ITERSTEP 10 10 1e-6"]
    out += ["END", "END"]
    return "\n".join(out) + "\n"


def timed(cmd):
    """Wall time [s], peak resident memory [MiB], exit code and the last stderr line."""
    t0 = time.perf_counter()
    p = subprocess.run(["/usr/bin/time", "-f", "%M"] + cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    lines = p.stderr.strip().splitlines()
    try:
        rss = int(lines[-1]) / 1024
    except (ValueError, IndexError):
        rss = float("nan")
    errors = [ln for ln in lines if ln.startswith("error")]
    msg = errors[0] if errors else ""
    return {"wall_s": wall, "peak_mib": rss, "rc": p.returncode, "message": msg[:300]}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--flexmbd", required=True)
    ap.add_argument("--n", type=int, nargs="+", default=[1000, 3000, 10000, 30000, 100000])
    ap.add_argument("--out")
    ap.add_argument("--plot", help="PNG of time and memory against N (matplotlib)")
    ap.add_argument("--from", dest="from_file", help="tabulate and plot an earlier --out")
    ap.add_argument("--read-bench", action="store_true",
                    help="also time the reading in process (cargo bench -p flexmbd-io --bench "
                    "read_model: text, parse, build; best of three): runs `read dat`, `read toml`")
    a = ap.parse_args()
    records = []
    if a.from_file:
        records = [json.loads(ln) for ln in open(a.from_file) if ln.strip()]
    else:
        exe = os.path.abspath(a.flexmbd)
        with tempfile.TemporaryDirectory() as tmp:
            for n in a.n:
                files = {}
                for fmt, write in (("dat", strip_dat), ("toml", strip_toml)):
                    for loaded in (False, True):
                        path = os.path.join(tmp, f"strip{n}{'_loaded' if loaded else ''}.{fmt}")
                        open(path, "w").write(write(n, loaded))
                        files[fmt, loaded] = path
                dat = files["dat", False]
                runs = {
                    "convert dat": [exe, "--quiet", "convert", "--force", dat,
                                    os.path.join(tmp, "converted.toml")],
                }
                for fmt in ("dat", "toml"):
                    path = files[fmt, False]
                    runs[f"check {fmt}"] = [exe, "--quiet", "check", path, "--max-suggestions", "0"]
                    runs[f"static {fmt}"] = [exe, "--quiet", "static", files[fmt, True]]
                    runs[f"modes {fmt}"] = [exe, "--quiet", "modes", path, "--count", "10"]
                for name, cmd in runs.items():
                    r = timed(cmd)
                    rec = {"n": n, "run": name, **r}
                    records.append(rec)
                    print(json.dumps(rec), file=sys.stderr, flush=True)
                if a.read_bench:
                    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
                    p = subprocess.run(["cargo", "bench", "-q", "-p", "flexmbd-io", "--bench",
                                        "read_model", "--", dat, files["toml", False]],
                                       cwd=root, capture_output=True, text=True)
                    for fmt, line in zip(("dat", "toml"), p.stdout.splitlines()):
                        b = json.loads(line)
                        rec = {"n": n, "run": f"read {fmt}", "wall_s": b["read_s"],
                               "peak_mib": float("nan"), "rc": p.returncode, "message": "",
                               "stages_s": {k: b[k] for k in ("text_s", "parse_s", "build_s")}}
                        records.append(rec)
                        print(json.dumps(rec), file=sys.stderr, flush=True)
        if a.out:
            with open(a.out, "w") as f:
                for r in records:
                    f.write(json.dumps(r) + "\n")
    names = list(dict.fromkeys(r["run"] for r in records))
    ns = sorted(set(r["n"] for r in records))
    by = {(r["n"], r["run"]): r for r in records}

    def cell(n, name, key):
        r = by.get((n, name))
        if r is None:
            return "–"
        if r["rc"] != 0:
            return f"rc {r['rc']}"
        return f"{r[key]:.3g}"

    print("whole-process wall time [s] / peak memory [MiB]")
    print(f"{'run':>12} " + " ".join(f"{n:>16}" for n in ns))
    for name in names:
        print(f"{name:>12} " + " ".join(
            f"{cell(n, name, 'wall_s') + ' / ' + cell(n, name, 'peak_mib'):>16}" for n in ns))
    if a.plot:
        try:
            import matplotlib
        except ImportError:
            print("no plot: matplotlib is not installed (pip install matplotlib)", file=sys.stderr)
            return
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
        for name in names:
            pts = [(n, by[(n, name)]) for n in ns if (n, name) in by and by[(n, name)]["rc"] == 0]
            if not pts:
                continue
            x = [p[0] for p in pts]
            ls = "--" if name.endswith("toml") else "-"
            ax1.loglog(x, [p[1]["wall_s"] for p in pts], ls, marker="o", label=name)
            if not name.startswith("read"):  # in process: no memory of its own
                ax2.loglog(x, [p[1]["peak_mib"] for p in pts], ls, marker="o", label=name)
        ax1.set_xlabel("beams N")
        ax1.set_ylabel("wall time [s] (read: in process)")
        ax2.set_xlabel("beams N")
        ax2.set_ylabel("peak resident memory [MiB]")
        for ax in (ax1, ax2):
            ax.grid(True, which="both", alpha=0.3)
        ax1.legend(fontsize=7)
        fig.suptitle("flexmbd from model files: a clamped strip of N beams")
        fig.tight_layout()
        fig.savefig(a.plot, dpi=110)


if __name__ == "__main__":
    main()
