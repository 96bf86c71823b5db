#!/usr/bin/env bash
# `flexmbd check` on 3D truss lattices (issue 14): the whole process of the release binary, text
# report (the default output), with the default verified advice and with --max-suggestions 0,
# wall time and peak memory (/usr/bin/time -v). No peer program; run by hand, or by
# bench/run.sh (unless --skip-lattice; `bash bench/run.sh --only-lattice` runs this alone,
# without the peer kit).
#
#   bash bench/lattice_check.sh [options]
#
#   --sizes "K ..."    cells per side (default: 2 3 4 6 8 12 16 24 32; k = 32 has 104,544
#                      columns and 202,784 rows; above 2,500 rows or columns, or a dense SVD
#                      work m·n·min(m, n) above 2e9, `check` takes its sparse path)
#   --plot FILE        also write the log-log plot of time and memory against the number of
#                      columns (matplotlib; default bench/results/lattice_scaling.png; "" for none)
#   --strips "N ..."   also N rigid beams in a chain, a regular 6N x 6N Dcc (default: 333, i.e.
#                      1998 x 1998; "" for none)
#   --timeout S        wall-clock limit per run (default 120); a run that hits it is recorded
#                      with status "timeout" and the larger sizes of that variant are skipped
#   --repeat R         every run R times (default 1)
#   --threads T        RAYON_NUM_THREADS (default: unset, all cores)
#   --out DIR          result directory (default bench/results): lattice.jsonl (one JSON record
#                      per run, first line = run description) and lattice.log
#
# The models are generated (bench/lattice_model.py, TOML) into a temporary folder and removed.
set -uo pipefail

BENCH="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$BENCH/.." && pwd)"
SIZES="2 3 4 6 8 12 16 24 32"
PLOT="$BENCH/results/lattice_scaling.png"
STRIPS="333"
TIMEOUT=120
REPEAT=1
OUTDIR="$BENCH/results"
usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; }
die() { echo "lattice_check.sh: $*" >&2; exit 2; }
while [ $# -gt 0 ]; do
  case "$1" in
    --sizes) SIZES="${2:?}"; shift 2 ;;
    --strips) STRIPS="${2-}"; shift 2 ;;
    --timeout) TIMEOUT="${2:?}"; shift 2 ;;
    --repeat) REPEAT="${2:?}"; shift 2 ;;
    --threads) export RAYON_NUM_THREADS="${2:?}"; shift 2 ;;
    --out) OUTDIR="${2:?}"; shift 2 ;;
    --plot) PLOT="${2-}"; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) die "unknown argument $1 (see --help)" ;;
  esac
done
[[ "$TIMEOUT" =~ ^[0-9]+$ ]] || die "bad --timeout"
[[ "$REPEAT" =~ ^[0-9]+$ ]] && [ "$REPEAT" -ge 1 ] || die "bad --repeat"
for k in $SIZES $STRIPS; do [[ "$k" =~ ^[0-9]+$ ]] && [ "$k" -gt 0 ] || die "bad size '$k'"; done
command -v python3 >/dev/null || die "python3 is needed to write the lattice models"

mkdir -p "$OUTDIR"
OUTDIR="$(cd "$OUTDIR" && pwd)"
JSONL="$OUTDIR/lattice.jsonl"; LOG="$OUTDIR/lattice.log"
: >"$JSONL"; : >"$LOG"
TMPD="$(mktemp -d)"
trap 'sed -i -e "s#$TMPD#\$TMP#g" -e "s#$ROOT/##g" "$JSONL" "$LOG"; rm -rf "$TMPD"' EXIT
say() { echo "[lattice] $*" >&2; }

say "building flexmbd (cargo build --release -p flexmbd-cli)"
(cd "$ROOT" && cargo build --release -p flexmbd-cli 2>>"$LOG") || die "cargo build failed (see $LOG)"
# a private copy, so that a concurrent rebuild cannot swap it mid-run
cp "$ROOT/target/release/flexmbd" "$TMPD/flexmbd"
COMMIT="$(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo '?')"
git -C "$ROOT" diff --quiet HEAD -- crates 2>/dev/null || COMMIT="$COMMIT+dirty"
printf '{"problem": "meta", "status": "meta", "date": "%s", "host_cpus": %s, "flexmbd_commit": "%s", "rayon_num_threads": "%s", "loadavg_before": "%s", "timeout_s": %s}\n' \
  "$(date '+%F %T %z')" "$(nproc)" "$COMMIT" "${RAYON_NUM_THREADS:-unset (all cores)}" \
  "$(cut -d' ' -f1-3 /proc/loadavg)" "$TIMEOUT" >>"$JSONL"

# one_run PROBLEM SIZE MODEL ADVICE: time the whole process, append a record; rc 124 = timeout
one_run() {
  local problem="$1" size="$2" model="$3" advice="$4" t0 t1 rc st wall dims
  local args=(check "$model")
  [ "$advice" = "none" ] && args+=(--max-suggestions 0)
  t0=$(date +%s.%N)
  /usr/bin/time -v -o "$TMPD/time" timeout -k 5 "$TIMEOUT" "$TMPD/flexmbd" "${args[@]}" >"$TMPD/o" 2>"$TMPD/e" </dev/null
  rc=$?
  t1=$(date +%s.%N)
  wall=$(awk -v a="$t0" -v b="$t1" 'BEGIN{printf "%.3f", b-a}')
  # /usr/bin/time reports the child's exit status itself when it is not zero
  grep -q "Command exited with non-zero status" "$TMPD/time" && rc=$(sed -n 's/.*non-zero status \([0-9]*\).*/\1/p' "$TMPD/time")
  rss=$(awk -F: '/Maximum resident set size/ {gsub(/ /, "", $2); printf "%.1f", $2 / 1024}' "$TMPD/time")
  st=ok; [ "$rc" -ne 0 ] && st=error; { [ "$rc" -eq 124 ] || [ "$rc" -eq 137 ]; } && st=timeout
  # the counts, from the text report (the default output, which is what is timed)
  dims=$(python3 -c 'import re, sys
t = open(sys.argv[1]).read()
def num(pat):
    m = re.search(pat, t, re.M)
    return m.group(1) if m else "null"
print(num(r"^Dcc: (\d+) rows"), num(r"^Dcc: \d+ rows .* x (\d+) columns"), num(r"^rank (\d+)"),
      num(r"motions \(n - r\): *(\d+)"), num(r"self-stress states \(m - r\): *(\d+)"),
      len(re.findall(r"^    - .*->", t, re.M)),
      "sparse" if "sparse rank-revealing LU" in t else "dense")' "$TMPD/o")
  set -- $dims
  printf '{"peer": "flexmbd", "problem": "%s", "size": %s, "advice": "%s", "status": "%s", "rc": %s, "wall_s": %s, "peak_mib": %s, "rows": %s, "cols": %s, "rank": %s, "n_mechanisms": %s, "n_self_stresses": %s, "suggestions": %s, "path": "%s"}\n' \
    "$problem" "$size" "$advice" "$st" "$rc" "$([ "$st" = ok ] && echo "$wall" || echo null)" "${rss:-null}" "$@" >>"$JSONL"
  { echo "=== $(date '+%F %T') $problem $size advice=$advice rc=$rc ${wall} s"; cat "$TMPD/e"; } >>"$LOG"
  say "$(printf '%-8s %-5s advice=%-8s rc=%-3s %8s s %8s MiB  Dcc %s x %s (%s)' "$problem" "$size" "$advice" "$rc" "$wall" "${rss:-?}" "$1" "$2" "$7")"
  [ "$st" = ok ]
}

for advice in default none; do
  for ((rep = 1; rep <= REPEAT; rep++)); do
    for k in $SIZES; do
      [ -f "$TMPD/lattice_$k.toml" ] || python3 "$BENCH/lattice_model.py" "$k" "$TMPD/lattice_$k.toml"
      one_run lattice "$k" "$TMPD/lattice_$k.toml" "$advice" || break
    done
    for n in $STRIPS; do
      [ -f "$TMPD/strip_$n.toml" ] || python3 "$BENCH/lattice_model.py" --strip "$n" "$TMPD/strip_$n.toml"
      one_run strip "$n" "$TMPD/strip_$n.toml" "$advice" || break
    done
  done
done

echo
python3 - "$JSONL" <<'EOF2'
import json, statistics, sys
recs = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
meta, runs = recs[0], recs[1:]
print(f"flexmbd check, whole process (commit {meta['flexmbd_commit']}, {meta['host_cpus']} cores, "
      f"load {meta['loadavg_before']}, RAYON_NUM_THREADS {meta['rayon_num_threads']})")
print("| model | size | Dcc | path | self-stresses / motions | default advice s | --max-suggestions 0 s | peak MiB (default) |")
print("|---|---|---|---|---|---|---|---|")
keys = []
for r in runs:
    if (r["problem"], r["size"]) not in keys:
        keys.append((r["problem"], r["size"]))
def cell(p, s, adv):
    rs = [r for r in runs if (r["problem"], r["size"], r["advice"]) == (p, s, adv)]
    ok = [r["wall_s"] for r in rs if r["status"] == "ok"]
    if ok:
        return f"{statistics.median(ok):.3f}"
    return rs[0]["status"] if rs else "–"
def mem(p, s, adv):
    ok = [r["peak_mib"] for r in runs
          if (r["problem"], r["size"], r["advice"]) == (p, s, adv) and r["status"] == "ok"
          and r.get("peak_mib") is not None]
    return f"{max(ok):.0f}" if ok else "–"
for p, s in keys:
    r = next(r for r in runs if (r["problem"], r["size"]) == (p, s))
    dcc = f"{r['rows']} x {r['cols']}" if r["rows"] is not None else "–"
    print(f"| {p} | {s} | {dcc} | {r.get('path', '?')} | {r['n_self_stresses']} / {r['n_mechanisms']} | "
          f"{cell(p, s, 'default')} | {cell(p, s, 'none')} | {mem(p, s, 'default')} |")
EOF2

if [ -n "$PLOT" ]; then
  python3 - "$JSONL" "$PLOT" <<'EOF3' || say "no plot (matplotlib missing?)"
import json, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
recs = [json.loads(l) for l in open(sys.argv[1]) if l.strip()][1:]
lat = [r for r in recs if r["problem"] == "lattice" and r["advice"] == "default"
       and r["status"] == "ok" and r["cols"] is not None]
best = {}
for r in lat:
    b = best.get(r["size"])
    if b is None or r["wall_s"] < b["wall_s"]:
        best[r["size"]] = r
pts = sorted(best.values(), key=lambda r: r["cols"])
fig, ax = plt.subplots(1, 2, figsize=(10, 4))
for path, mk in (("dense", "o"), ("sparse", "s")):
    q = [r for r in pts if r.get("path") == path]
    if q:
        ax[0].loglog([r["cols"] for r in q], [r["wall_s"] for r in q], mk + "-", label=path)
        ax[1].loglog([r["cols"] for r in q], [r["peak_mib"] for r in q], mk + "-", label=path)
for a, t in ((ax[0], "wall time [s]"), (ax[1], "peak memory [MiB]")):
    a.set_xlabel("columns of Dcc (dependent velocities)")
    a.set_ylabel(t)
    a.grid(True, which="both", alpha=0.3)
    a.legend()
ax[0].axhline(10, color="grey", ls=":")
ax[1].axhline(4096, color="grey", ls=":")
fig.suptitle("flexmbd check on truss lattices (whole process, default advice)")
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=100)
print(f"plot: {sys.argv[2]}")
EOF3
fi
