#!/usr/bin/env bash
# flexmbd vs peers, same problems, same run, same machine. Run by hand (not part of cargo test).
#
#   bash bench/run.sh [options]
#
#   --sizes "N ..."        cantilever sizes (default: 10 100 1000 10000)
#   --modes-sizes "N ..."  strip-modes sizes (default: 10 100 1000 10000)
#   --modes M              modes computed by flexmbd in the strip-modes case (default 10; the
#                          peers compute their own default: Exudyn 8, OpenSeesPy 6)
#   --quick                both size lists = "10 100 1000"
#   --timeout S            wall-clock limit per case and program (default 240); a case that hits
#                          it is recorded with status "timeout"
#   --repeat R             run every case R times; the table shows medians (default 1)
#   --threads T            RAYON_NUM_THREADS for flexmbd and OMP/OPENBLAS threads for the peers
#                          (default: unset = flexmbd uses all cores, Exudyn is single-threaded)
#   --skip-static | --skip-modes | --skip-lattice
#   --only-lattice         only `flexmbd check` on the truss lattices (bench/lattice_check.sh;
#                          no peer program, so no peer kit needed)
#   --skip-files           leave out the whole-process runs from model files (below)
#   --only-files           only the whole-process runs of `convert`, `check`, `static` and
#                          `modes` on a clamped strip of N beams read from .dat and TOML files
#                          (bench/strip_files.py; no peer kit needed): strip_files.jsonl/.png
#   --files-sizes "N ..."  their sizes (default: 1000 3000 10000 30000 100000)
#   --with-calculix        also run the peer kit's CalculiX strip-modes script (needs ccx:
#                          bash PEERS/install.sh --with-calculix, as root)
#   --out DIR              result directory (default bench/results); writes latest.jsonl (raw
#                          records), latest.log (peer messages, stderr) and latest.json (summary)
#   --peers DIR            the peer kit (default: $FLEXMBD_PEERS_DIR; one of the two is needed)
#
# The peer kit is a folder of Python scripts kept outside this repository (install.sh,
# peercommon.py, strip_modes_exudyn.py, strip_modes_opensees.py, strip_modes_calculix.py).
# Its install.sh puts Exudyn, OpenSeesPy, numpy and scipy from PyPI (idempotently) into
# ${FLEXMBD_PEERS_VENV:-$HOME/.cache/flexmbd-peers/venv}; nothing is written into the kit.
# The logs and records name paths relative to the repository, the kit ($PEERS) and the venv
# ($PEERS_VENV), never the machine's absolute paths.
set -uo pipefail

BENCH="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$BENCH/.." && pwd)"
PEERS="${FLEXMBD_PEERS_DIR:-}"
SIZES="10 100 1000 10000"
MSIZES="10 100 1000 10000"
NMODES=10
TIMEOUT=240
REPEAT=1
THREADS=""
DO_STATIC=1
DO_MODES=1
DO_LATTICE=1
ONLY_LATTICE=0
DO_FILES=1
ONLY_FILES=0
FSIZES="1000 3000 10000 30000 100000"
WITH_CCX=0
OUTDIR="$BENCH/results"

usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; }
die() { echo "run.sh: $*" >&2; exit 2; }
while [ $# -gt 0 ]; do
  case "$1" in
    --sizes) SIZES="${2:?}"; shift 2 ;;
    --modes-sizes) MSIZES="${2:?}"; shift 2 ;;
    --modes) NMODES="${2:?}"; shift 2 ;;
    --quick) SIZES="10 100 1000"; MSIZES="10 100 1000"; shift ;;
    --timeout) TIMEOUT="${2:?}"; shift 2 ;;
    --repeat) REPEAT="${2:?}"; shift 2 ;;
    --threads) THREADS="${2:?}"; shift 2 ;;
    --skip-static) DO_STATIC=0; shift ;;
    --skip-modes) DO_MODES=0; shift ;;
    --skip-lattice) DO_LATTICE=0; shift ;;
    --only-lattice) ONLY_LATTICE=1; shift ;;
    --skip-files) DO_FILES=0; shift ;;
    --only-files) ONLY_FILES=1; shift ;;
    --files-sizes) FSIZES="${2:?}"; shift 2 ;;
    --with-calculix) WITH_CCX=1; shift ;;
    --out) OUTDIR="${2:?}"; shift 2 ;;
    --peers) PEERS="${2:?}"; shift 2 ;;
    -h|--help) usage; exit 0 ;;
    *) die "unknown argument $1 (see --help)" ;;
  esac
done
[[ "$TIMEOUT" =~ ^[0-9]+$ ]] || die "bad --timeout"
[[ "$REPEAT" =~ ^[0-9]+$ ]] && [ "$REPEAT" -ge 1 ] || die "bad --repeat"
[[ "$NMODES" =~ ^[0-9]+$ ]] && [ "$NMODES" -ge 1 ] || die "bad --modes"
for n in $SIZES $MSIZES $FSIZES; do [[ "$n" =~ ^[0-9]+$ ]] && [ "$n" -gt 0 ] || die "bad size '$n'"; done
# the lattice case has no peer: it runs without the peer kit
lattice_args=(--out "$OUTDIR")
[ -n "$THREADS" ] && lattice_args+=(--threads "$THREADS")
[ "$REPEAT" -gt 1 ] && lattice_args+=(--repeat "$REPEAT")
if [ "$ONLY_LATTICE" -eq 1 ]; then
  exec bash "$BENCH/lattice_check.sh" "${lattice_args[@]}"
fi
# whole-process runs from model files (no peer): the release binary on a strip of N beams
run_files() {
  echo "strip_files: cargo build --release -p flexmbd-cli"
  (cd "$ROOT" && cargo build --release -p flexmbd-cli 2>/dev/null) || { echo "run.sh: cargo build failed" >&2; return 1; }
  mkdir -p "$OUTDIR"
  # shellcheck disable=SC2086
  python3 -B "$BENCH/strip_files.py" --flexmbd "$ROOT/target/release/flexmbd" --n $FSIZES \
    --read-bench --out "$OUTDIR/strip_files.jsonl" --plot "$OUTDIR/strip_files.png" 2>"$OUTDIR/strip_files.log"
}
if [ "$ONLY_FILES" -eq 1 ]; then
  run_files
  exit $?
fi
# the peer kit: given, present and complete, or a message that says what to get
need_peers="install.sh peercommon.py"
[ "$DO_MODES" -eq 1 ] && need_peers="$need_peers strip_modes_exudyn.py strip_modes_opensees.py"
[ "$WITH_CCX" -eq 1 ] && need_peers="$need_peers strip_modes_calculix.py"
if [ -z "$PEERS" ]; then
  die "no peer kit given: pass --peers DIR or set FLEXMBD_PEERS_DIR to the folder of the peer
scripts (it must hold: $need_peers). The kit is the team's benchmark folder of
Exudyn/OpenSeesPy scripts, kept outside this repository; its install.sh installs Exudyn 1.13.6,
OpenSeesPy 3.7.1.2, numpy and scipy from PyPI into \$HOME/.cache/flexmbd-peers/venv
(or \$FLEXMBD_PEERS_VENV). See bench/README.md, 'Install the peers'."
fi
[ -d "$PEERS" ] || die "peer kit $PEERS: no such folder (--peers / FLEXMBD_PEERS_DIR)"
PEERS="$(cd "$PEERS" && pwd)"
for f in $need_peers; do
  [ -f "$PEERS/$f" ] || die "peer kit $PEERS has no $f: is it the benchmark peer kit? (it must hold: $need_peers)"
done
export FLEXMBD_PEERS_DIR="$PEERS"
if [ -n "$THREADS" ]; then
  export RAYON_NUM_THREADS="$THREADS" OMP_NUM_THREADS="$THREADS" OPENBLAS_NUM_THREADS="$THREADS"
fi

mkdir -p "$OUTDIR"
OUTDIR="$(cd "$OUTDIR" && pwd)"
case "$OUTDIR/" in "$PEERS"/*) die "--out must not point into the peer kit $PEERS";; esac
JSONL="$OUTDIR/latest.jsonl"; LOG="$OUTDIR/latest.log"; SUMMARY="$OUTDIR/latest.json"
: >"$JSONL"; : >"$LOG"
TMPD="$(mktemp -d)"
VENV=""
# Machine paths -> names in everything written under --out (the results are committed): the
# temporary folder, the venv, the peer kit, the repository (relative), the home folder.
scrub_results() {
  local f args=()
  [ -n "$TMPD" ] && args+=(-e "s#$TMPD#\$TMP#g")
  [ -n "$VENV" ] && args+=(-e "s#$VENV#\$PEERS_VENV#g")
  args+=(-e "s#$PEERS#\$PEERS#g" -e "s#$ROOT/##g" -e "s#$ROOT#.#g" -e "s#$HOME#\$HOME#g")
  for f in "$JSONL" "$LOG" "$SUMMARY"; do
    [ -f "$f" ] && sed -i "${args[@]}" "$f"
  done
}
trap 'scrub_results; rm -rf "$TMPD"' EXIT
T_START=$(date +%s)
say() { echo "[bench] $*" >&2; }

# ---- 1. peers (idempotent: ~2 s when already installed) -------------------------------------
say "peers: $PEERS/install.sh"
PY="$(bash "$PEERS/install.sh" 2>>"$LOG" | tail -n 1)"
[ -x "$PY" ] || die "the peer kit's install.sh did not give a Python with Exudyn and OpenSeesPy (it needs Python 3 with venv and pip, and PyPI; see $LOG)"
VENV="$(cd "$(dirname "$PY")/.." && pwd)"

# ---- 2. flexmbd, release (bench profile) ----------------------------------------------------
say "building flexmbd (cargo bench --no-run, release profile)"
FLEX_EXE=""
MODES_EXE=""
BENCHES=""
[ "$DO_STATIC" -eq 1 ] && BENCHES="$BENCHES --bench cantilever"
[ "$DO_MODES" -eq 1 ] && BENCHES="$BENCHES --bench strip_modes"
if [ -n "$BENCHES" ]; then
  # shellcheck disable=SC2086
  (cd "$ROOT" && cargo bench -p flexmbd-core $BENCHES --no-run --message-format=json \
      2>>"$LOG") >"$TMPD/cargo.json" || die "cargo bench --no-run failed (see $LOG)"
  exe_of() {  # the executable of one bench target
    "$PY" -B -c '
import json, sys
exe = [json.loads(l) for l in open(sys.argv[1]) if l.startswith("{")]
exe = [r.get("executable") for r in exe if r.get("target", {}).get("name") == sys.argv[2]]
exe = [e for e in exe if e]
print(exe[-1] if exe else "")' "$TMPD/cargo.json" "$1"
  }
  # private copies, so that a concurrent rebuild by someone else cannot swap them mid-run
  if [ "$DO_STATIC" -eq 1 ]; then
    FLEX_EXE="$(exe_of cantilever)"
    [ -x "$FLEX_EXE" ] || die "cantilever bench executable not found"
    cp "$FLEX_EXE" "$TMPD/cantilever-bench"; FLEX_EXE="$TMPD/cantilever-bench"
  fi
  if [ "$DO_MODES" -eq 1 ]; then
    MODES_EXE="$(exe_of strip_modes)"
    [ -x "$MODES_EXE" ] || die "strip_modes bench executable not found"
    cp "$MODES_EXE" "$TMPD/strip-modes-bench"; MODES_EXE="$TMPD/strip-modes-bench"
  fi
fi

# ---- 3. run description ---------------------------------------------------------------------
COMMIT="$(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo '?')"
git -C "$ROOT" diff --quiet HEAD -- crates 2>/dev/null || COMMIT="$COMMIT+dirty"
"$PY" -B - "$JSONL" <<EOF
import json, os, sys
rec = {"peer": "run.sh", "problem": "meta", "status": "meta",
       "date": "$(date '+%F %T %z')", "host_cpus": $(nproc),
       "cpu_model": "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')",
       "mem_gib": $(awk '/MemTotal/{printf "%.1f", $2/1048576}' /proc/meminfo),
       "os": "$(. /etc/os-release && echo "${PRETTY_NAME:-?}")",
       "rustc": "$(rustc --version 2>/dev/null)", "flexmbd_commit": "$COMMIT",
       "python": "$("$PY" -c 'import sys; print(sys.version.split()[0])')", "sizes": "$SIZES", "modes_sizes": "$MSIZES", "flexmbd_modes": $NMODES,
       "timeout_s": $TIMEOUT,
       "repeat": $REPEAT, "rayon_num_threads": os.environ.get("RAYON_NUM_THREADS", "unset (all cores)"),
       "omp_num_threads": os.environ.get("OMP_NUM_THREADS", "unset"),
       "loadavg_before": open("/proc/loadavg").read().split()[:3]}
open(sys.argv[1], "a").write(json.dumps(rec) + "\n")
EOF

# ---- helpers --------------------------------------------------------------------------------
# peer_case NAME PROBLEM N -- COMMAND ...: JSON lines to $JSONL, the rest to $LOG; a failure
# without a JSON line still leaves a record (as the peer kit's run_all.sh does).
peer_case() {
  local peer="$1" problem="$2" n="$3"; shift 4
  local t0 t1 rc nrec
  t0=$(date +%s.%N)
  # ("; exit $?": the subshell waits instead of exec'ing, so bash's "Segmentation fault" job
  # message goes to the log, not to the terminal)
  (cd "$TMPD" && timeout -k 10 "$TIMEOUT" "$@"; exit $?) >"$TMPD/o" 2>"$TMPD/e" </dev/null
  rc=$?
  t1=$(date +%s.%N)
  nrec=$(grep -c '^{' "$TMPD/o" || true)
  grep '^{' "$TMPD/o" >>"$JSONL" || true
  { echo "=== $(date '+%F %T') $peer $problem N=$n rc=$rc: $*"; grep -v '^{' "$TMPD/o"; cat "$TMPD/e"; } >>"$LOG"
  if [ "$nrec" -eq 0 ]; then
    local st=error; { [ "$rc" -eq 124 ] || [ "$rc" -eq 137 ]; } && st=timeout
    "$PY" -B - "$JSONL" "$peer" "$problem" "$n" "$st" "$rc" "$TIMEOUT" "$TMPD/e" <<'EOF'
import json, sys
out, peer, problem, n, st, rc, tmo, errf = sys.argv[1:]
lines = [l for l in open(errf, errors="replace").read().strip().splitlines() if "run.sh: line" not in l]
tail = " ".join(lines[-2:])[:300]
if rc == "139":
    tail = "segmentation fault (rc 139). " + tail
rec = {"peer": peer, "problem": problem, "n_elements": int(n), "status": st, "rc": int(rc),
       "wall_s": None, "timeout_s": int(tmo), "error": tail}
open(out, "a").write(json.dumps(rec) + "\n")
EOF
  fi
  say "$(printf '%-9s %-13s N=%-6s rc=%-3s %7.1f s' "$peer" "$problem" "$n" "$rc" "$(awk -v a="$t0" -v b="$t1" 'BEGIN{printf "%.3f", b-a}')")"
}

flexmbd_case() {  # flexmbd_case N
  local n="$1" t0 t1 rc
  t0=$(date +%s.%N)
  # the binary cargo bench runs, called as cargo bench calls it (extra argument --bench)
  (cd "$ROOT/crates/flexmbd-core" && timeout -k 10 "$TIMEOUT" "$FLEX_EXE" "$n" --bench; exit $?) \
    >"$TMPD/fo" 2>"$TMPD/fe" </dev/null
  rc=$?
  t1=$(date +%s.%N)
  { echo "=== $(date '+%F %T') flexmbd cantilever N=$n rc=$rc"; cat "$TMPD/fo" "$TMPD/fe"; } >>"$LOG"
  "$PY" -B "$BENCH/report.py" flexmbd-record --n "$n" --rc "$rc" --timeout "$TIMEOUT" \
    --runner-wall "$(awk -v a="$t0" -v b="$t1" 'BEGIN{printf "%.3f", b-a}')" --threads "${RAYON_NUM_THREADS:-all}" \
    --version "$COMMIT" --stdout "$TMPD/fo" --stderr "$TMPD/fe" >>"$JSONL"
  say "$(printf '%-9s %-13s N=%-6s rc=%-3s %7.1f s' flexmbd cantilever_k3 "$n" "$rc" "$(awk -v a="$t0" -v b="$t1" 'BEGIN{printf "%.3f", b-a}')")"
}

# ---- 4. large-deflection cantilever, k = 3 (flexmbd and Exudyn alternate per N) ------------
if [ "$DO_STATIC" -eq 1 ]; then
  for ((rep = 1; rep <= REPEAT; rep++)); do
    for n in $SIZES; do
      flexmbd_case "$n"
      peer_case exudyn cantilever_k3 "$n" -- "$PY" -B "$BENCH/peers/cantilever_k3_exudyn.py" --n "$n"
    done
  done
fi

# ---- 5. strip eigenfrequencies (flexmbd, Exudyn and OpenSeesPy alternate per N) -------------
if [ "$DO_MODES" -eq 1 ]; then
  for ((rep = 1; rep <= REPEAT; rep++)); do
    for n in $MSIZES; do
      # the binary cargo bench runs, called as cargo bench calls it; one JSON record per N
      peer_case flexmbd  strip_modes "$n" -- "$MODES_EXE" "$n" --modes "$NMODES" --bench
      peer_case exudyn   strip_modes "$n" -- "$PY" -B "$PEERS/strip_modes_exudyn.py" --n "$n"
      peer_case opensees strip_modes "$n" -- "$PY" -B "$PEERS/strip_modes_opensees.py" --n "$n"
      if [ "$WITH_CCX" -eq 1 ]; then
        peer_case calculix strip_modes "$n" -- "$PY" -B "$PEERS/strip_modes_calculix.py" --n "$n"
      fi
    done
  done
fi

# ---- 6. summary -----------------------------------------------------------------------------
"$PY" -B - "$JSONL" <<'EOF'
import json, sys
lines = open(sys.argv[1]).read().splitlines()
meta = json.loads(lines[0])
meta["loadavg_after"] = open("/proc/loadavg").read().split()[:3]
lines[0] = json.dumps(meta)
open(sys.argv[1], "w").write("\n".join(lines) + "\n")
EOF
say "total $(( $(date +%s) - T_START )) s; raw records $JSONL, log $LOG"
echo
"$PY" -B "$BENCH/report.py" summarize "$JSONL" --json "$SUMMARY"

# ---- 7. flexmbd check on truss lattices (no peer; its own records lattice.jsonl/.log) --------
if [ "$DO_LATTICE" -eq 1 ]; then
  echo
  bash "$BENCH/lattice_check.sh" "${lattice_args[@]}"
fi

# ---- 8. whole process from model files (no peer; strip_files.jsonl/.log/.png) ---------------
if [ "$DO_FILES" -eq 1 ]; then
  echo
  run_files
fi
