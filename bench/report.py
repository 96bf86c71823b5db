#!/usr/bin/env python3
"""flexmbd benchmark harness: turn flexmbd bench output into JSON records, and summarise a run.

  report.py flexmbd-record --n N --rc RC --runner-wall S --timeout S --stdout F --stderr F
      Parse the output of `cargo bench -p flexmbd-core --bench cantilever -- N` (one line per N,
      e.g. "N =   1000: build 0.001 s, solve 0.200 s, 59 Newton iterations, 10 substeps,
      u/L 0.2544202253560758, w/L 0.6032537459140974, phi 0.986017222259926 (errors ...)") and
      print one JSON line per N in the peers' record format (peer "flexmbd", problem
      "cantilever_k3"), with the values and their errors against the exact elastica.
  report.py summarize RESULTS.jsonl [--json OUT.json]
      Print the tables (times, ratios flexmbd/peer, errors against the closed forms) and write the
      summary JSON. The strip-modes records of flexmbd come from
      `cargo bench -p flexmbd-core --bench strip_modes -- N` directly (JSON in the peers' format).

Stdlib only (runs with any python3). Used by bench/run.sh.
"""
import argparse
import json
import math
import re
import statistics
import sys

sys.dont_write_bytecode = True

# Exact inextensible elastica at k = PL^2/EI = 3 (shooting on theta'' = -k cos theta, rtol 1e-12;
# the peer kit's peercommon.py elastica(3); validation.md S01 row k = 3.0 rounds these to
# 0.25442, 0.60325, 0.98602).
ELASTICA_K3 = {"u": 0.254420185, "w": 0.603253441, "phi": 0.986016947}
# Euler-Bernoulli clamped-free bending frequencies of the peers' steel strip (validation.md F01
# roots beta_n L = 1.875104, 4.694091, 7.854757 with L = 50 mm, b = 20 mm, t = 0.2 mm,
# E = 210 GPa, rho = 7800 kg/m^3; peercommon.analytic_bending()).
EB_STRIP_HZ = [67.05522035039634, 420.2278927554142, 1176.6502678672903]

NUM = r"([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)"


def _f(pattern, line, cast=float):
    m = re.search(pattern, line)
    return cast(m.group(1)) if m else None


def parse_flexmbd_line(line):
    """Fields of one bench line; tolerant to reordering and to extra fields."""
    if not re.match(r"\s*N\s*=\s*\d+", line):
        return None
    r = {"n_elements": _f(r"N\s*=\s*(\d+)", line, int),
         "t_build_s": _f(r"build\s+" + NUM + r"\s*s", line),
         "t_solve_s": _f(r"solve\s+" + NUM + r"\s*s", line),
         "newton_iterations": _f(r"(\d+)\s+Newton", line, int),
         "substeps": _f(r"(\d+)\s+sub-?steps", line, int),
         "halvings": _f(r"(\d+)\s+(?:step\s+)?halvings", line, int),
         # the computed tip values ("u/L 0.2544201" or "u/L = 0.2544201"; the first match)
         "u_over_L": _f(r"u/L\s*[=:]?\s*" + NUM, line),
         "w_over_L": _f(r"w/L\s*[=:]?\s*" + NUM, line),
         "phi_rad": _f(r"(?:phi|φ|rot\w*|theta|θ)\s*[=:]?\s*" + NUM, line)}
    return r


def cmd_flexmbd_record(a):
    out = open(a.stdout, errors="replace").read() if a.stdout else ""
    err = open(a.stderr, errors="replace").read() if a.stderr else ""
    base = {"peer": "flexmbd", "peer_version": a.version, "problem": "cantilever_k3",
            "variant": "bench-cantilever", "k": 3.0, "load_steps": 10, "ea": 1e7,
            "rc": a.rc, "runner_wall_s": a.runner_wall, "threads": a.threads}
    recs = []
    for line in out.splitlines():
        p = parse_flexmbd_line(line)
        if p is None:
            continue
        rec = dict(base, **{k: v for k, v in p.items() if v is not None})
        rec["raw"] = line.strip()
        tb, ts = p["t_build_s"] or 0.0, p["t_solve_s"]
        rec["wall_s"] = (tb + ts) if ts is not None else None
        rec["n_dof"] = 7 * (p["n_elements"] + 1)   # 3 positions + 4 Euler parameters per node
        # errors against the exact elastica, from the values the bench prints (as the Exudyn
        # script computes its own)
        errs = {}
        for q, key in (("u", "u_over_L"), ("w", "w_over_L"), ("phi", "phi_rad")):
            rec["ref_" + key] = ELASTICA_K3[q]
            if p[key] is not None:
                errs[q] = abs(p[key] - ELASTICA_K3[q])
            rec["err_" + q] = errs.get(q)
        rec["err_basis"] = "exact elastica"
        rec["max_abs_err"] = max(errs.values()) if errs else None
        # the bench unwraps statics::solve with StaticOptions::default(): a printed line means
        # that Newton converged at the default settings
        rec["status"] = "ok"
        rec["converged_default"] = True
        recs.append(rec)
    if not recs:
        status = "timeout" if a.rc in (124, 137) else "failed" if "panicked" in err else "error"
        recs.append(dict(base, n_elements=a.n, status=status, wall_s=None, converged_default=None,
                         timeout_s=a.timeout,
                         error=" ".join((err.strip().splitlines() or [""])[-3:])[:400]))
    for rec in recs:
        print(json.dumps(rec, separators=(", ", ": ")))


# ---------------------------------------------------------------------------------------------
def load(path):
    recs = []
    with open(path) as fh:
        for line in fh:
            line = line.strip()
            if line.startswith("{"):
                try:
                    recs.append(json.loads(line))
                except ValueError:
                    pass
    return recs


def med(vals):
    vals = [v for v in vals if isinstance(v, (int, float))]
    return statistics.median(vals) if vals else None


def fmt(x, spec="%.3g", none="-"):
    return none if x is None else spec % x


def pick(recs, peer, problem, n):
    """All records of one (peer, problem, N); repeated runs are combined with the median."""
    rs = [r for r in recs if r.get("peer") == peer and r.get("problem") == problem
          and r.get("n_elements") == n]
    ok = [r for r in rs if r.get("status") == "ok"]
    if not rs:
        return None
    if not ok:
        r = dict(rs[-1])
        r["runs"] = len(rs)
        return r
    r = dict(ok[len(ok) // 2])
    for key in ("wall_s", "t_solve_s", "t_total_s", "t_build_s"):
        if any(key in x for x in ok):
            r[key] = med([x.get(key) for x in ok])
    r["runs"], r["runs_ok"] = len(rs), len(ok)
    return r


def cmd_summarize(a):
    recs = load(a.results)
    meta = next((r for r in recs if r.get("problem") == "meta"), {})
    recs = [r for r in recs if r.get("problem") != "meta"]
    out = {"meta": meta, "cantilever_k3": [], "strip_modes": []}

    print("machine: %s CPUs (nproc), %s | %s GiB | %s | load avg before %s, after %s" % (
        meta.get("host_cpus"), meta.get("cpu_model"), meta.get("mem_gib"), meta.get("os"),
        meta.get("loadavg_before"), meta.get("loadavg_after", "?")))
    print("flexmbd %s (%s), threads: flexmbd RAYON_NUM_THREADS=%s, Exudyn 1 thread, BLAS/OMP=%s" % (
        meta.get("flexmbd_commit"), meta.get("rustc"), meta.get("rayon_num_threads"),
        meta.get("omp_num_threads")))

    # ---- 1. static cantilever, k = 3 -------------------------------------------------------
    ns = sorted({r["n_elements"] for r in recs if r.get("problem") == "cantilever_k3"})
    if ns:
        print()
        print("1. Large-deflection cantilever, k = PL^2/EI = 3, L = 1, EI = 1, EA = 1e7, 10 load steps")
        print("   reference: exact elastica u/L = %.7f, w/L = %.7f, phi = %.7f" % (
            ELASTICA_K3["u"], ELASTICA_K3["w"], ELASTICA_K3["phi"]))
        print("   times: build + solve inside the process (flexmbd: bench's build + solve; Exudyn: the")
        print("   successful attempt; 'exu total' also counts failed attempts at stricter tolerances)")
        hdr = ("%6s | %9s %5s %4s | %9s %9s %5s %6s %4s | %8s %8s | %-28s | %-28s" % (
            "N", "flex s", "iters", "conv", "exu s", "exu total", "iters", "rtol", "conv",
            "flex/exu", "flex/tot", "flexmbd err u, w, phi", "Exudyn err u, w, phi"))
        print(hdr)
        print("-" * len(hdr))
        for n in ns:
            fr = pick(recs, "flexmbd", "cantilever_k3", n)
            er = pick(recs, "exudyn", "cantilever_k3", n)
            row = {"n_elements": n, "flexmbd": fr, "exudyn": er}

            def errs(r):
                if not r or r.get("status") != "ok":
                    return (r or {}).get("status", "not run")
                if r.get("peer") == "flexmbd" and r.get("err_basis") != "exact elastica":
                    return "no values (older bench)"
                return ", ".join(fmt(r.get("err_" + q), "%.2e") for q in ("u", "w", "phi"))

            fw = fr.get("wall_s") if fr and fr.get("status") == "ok" else None
            ew = er.get("wall_s") if er and er.get("status") == "ok" else None
            et = er.get("t_total_s") if er and er.get("status") == "ok" else None
            ratio = fw / ew if fw and ew else None
            ratio_t = fw / et if fw and et else None
            row["ratio_flexmbd_over_exudyn"] = ratio
            row["ratio_flexmbd_over_exudyn_total"] = ratio_t

            def conv(r):
                if not r or r.get("status") not in ("ok", "failed"):
                    return "-"
                return "yes" if r.get("converged_default") else "no"
            fstat = fmt(fw, "%.4g") if fw else (fr or {}).get("status", "-")
            estat = fmt(ew, "%.4g") if ew else (er or {}).get("status", "-")
            print("%6d | %9s %5s %4s | %9s %9s %5s %6s %4s | %8s %8s | %-28s | %-28s" % (
                n, fstat, fmt((fr or {}).get("newton_iterations"), "%d"), conv(fr),
                estat, fmt(et, "%.4g"), fmt((er or {}).get("newton_iterations"), "%d"),
                fmt((er or {}).get("rtol"), "%.0e"), conv(er),
                fmt(ratio, "%.3g"), fmt(ratio_t, "%.3g"), errs(fr), errs(er)))
            out["cantilever_k3"].append(row)
        print("   flex/exu = flexmbd wall / Exudyn wall of its successful attempt, flex/tot = flexmbd wall /"
              " Exudyn total incl. failed attempts (< 1: flexmbd faster)")
        print("   conv = converged at default settings (flexmbd: StaticOptions::default(); Exudyn: "
              "Newton relativeTolerance 1e-8, retried with 1e-6, 1e-4)")

    # ---- 2. strip modes --------------------------------------------------------------------
    ns = sorted({r["n_elements"] for r in recs if r.get("problem") == "strip_modes"})
    if ns:
        print()
        print("2. Strip eigenfrequencies (L = 50 mm, 20 x 0.2 mm, steel, clamped-free), lowest modes")
        print("   reference: Euler-Bernoulli bending %.4f, %.4f, %.3f Hz (errors: the first three "
              "out-of-plane bending modes found)" % tuple(EB_STRIP_HZ))
        print("   times: wall_s = model build + solve inside the process (flexmbd: also the static "
              "state and the energy split of every mode)")
        peers = ("flexmbd", "exudyn", "opensees", "calculix")
        hdr = "%6s | %9s %9s %9s | %8s %8s %9s | %-28s | %-28s | %-28s" % (
            "N", "flex s", "exu s", "ops s", "flex/exu", "flex/ops", "best/flex",
            "flexmbd err f1, f2, f3", "Exudyn err f1, f2, f3", "OpenSeesPy err f1, f2, f3")
        print(hdr)
        print("-" * len(hdr))
        for n in ns:
            rows = {peer: pick(recs, peer, "strip_modes", n) for peer in peers}
            row = {"n_elements": n}

            def wall(r):
                return r.get("wall_s") if r and r.get("status") == "ok" else None

            def errs(r):
                if not r or r.get("status") != "ok":
                    return ((r or {}).get("status") or "not run")[:28]
                bz = r.get("bending_z_hz") or []
                rel = [(f - f0) / f0 for f, f0 in zip(bz, EB_STRIP_HZ)]
                return ", ".join("%+.1e" % e for e in rel) or "no bending mode"

            fw, ew, ow = (wall(rows[p]) for p in ("flexmbd", "exudyn", "opensees"))
            peer_walls = [w for w in (ew, ow) if w]
            best = min(peer_walls) if peer_walls else None
            row["ratio_flexmbd_over_exudyn"] = fw / ew if fw and ew else None
            row["ratio_flexmbd_over_opensees"] = fw / ow if fw and ow else None
            row["speedup_vs_faster_peer"] = best / fw if fw and best else None
            for peer in peers:
                r = rows[peer]
                if r is None:
                    continue
                bz = r.get("bending_z_hz") or []
                r["rel_err_bending"] = [(f - f0) / f0 for f, f0 in zip(bz, EB_STRIP_HZ)]
                row[peer] = r
            out["strip_modes"].append(row)

            def cell(w, r):
                return fmt(w, "%.4g") if w else ((r or {}).get("status") or "-")[:9]
            print("%6d | %9s %9s %9s | %8s %8s %9s | %-28s | %-28s | %-28s" % (
                n, cell(fw, rows["flexmbd"]), cell(ew, rows["exudyn"]), cell(ow, rows["opensees"]),
                fmt(row["ratio_flexmbd_over_exudyn"], "%.3g"),
                fmt(row["ratio_flexmbd_over_opensees"], "%.3g"),
                fmt(row["speedup_vs_faster_peer"], "%.3gx"),
                errs(rows["flexmbd"]), errs(rows["exudyn"]), errs(rows["opensees"])))
        print("   flex/exu, flex/ops = flexmbd wall / peer wall (< 1: flexmbd faster); best/flex = the "
              "faster peer's wall / flexmbd's (speed-up)")
        print("   models and solvers:")
        for n in ns:
            for peer in peers:
                r = pick(recs, peer, "strip_modes", n)
                if r is None:
                    continue
                more = ""
                if r.get("status") == "ok":
                    more = "%d modes, f1 = %s Hz" % (len(r.get("freqs_hz") or []),
                                                     fmt(r.get("f1_hz"), "%.7g"))
                else:
                    more = (r.get("error") or "")[:70]
                print("   %6d %-9s %-28s %-8s %s" % (n, peer, str(r.get("variant") or "")[:28],
                                                    r.get("status"), more))
    if a.json:
        with open(a.json, "w") as fh:
            json.dump({**out, "records": recs}, fh, indent=1)
        print()
        print("summary written to %s" % a.json)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    p = sub.add_parser("flexmbd-record")
    p.add_argument("--n", type=int, required=True)
    p.add_argument("--rc", type=int, required=True)
    p.add_argument("--runner-wall", type=float, default=None)
    p.add_argument("--timeout", type=float, default=None)
    p.add_argument("--threads", default=None)
    p.add_argument("--version", default=None)
    p.add_argument("--stdout")
    p.add_argument("--stderr")
    p.set_defaults(func=cmd_flexmbd_record)
    p = sub.add_parser("summarize")
    p.add_argument("results")
    p.add_argument("--json", default=None)
    p.set_defaults(func=cmd_summarize)
    a = ap.parse_args()
    a.func(a)


if __name__ == "__main__":
    main()
