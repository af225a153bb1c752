#!/usr/bin/env bash
# Whole-process time of `sporadic sdp solve FILE` against the Debian `csdp` binary
# (coinor-csdp) on the SDPLIB problems of issue 3 and on an LMI problem with many small blocks
# exported from the modelling layer, measured in the same run with hyperfine.
#
#   benches/scripts/vs_csdp.sh [SDPLIB_DIR]        (default: $SPORADIC_SDPLIB or ../shared/sdplib)
#
# Environment: RUNS (hyperfine runs per command, default 5), WARMUP (default 1),
# PROBLEMS (space-separated list overriding the default set), OUT (result directory,
# default target/vs_csdp).
#
# For each problem it prints both mean times, their ratio ours/csdp (< 1: we are faster), the
# time and ratio of ours stopped at the accuracy CSDP reached (`ours@acc`: CSDP stops early with
# "partial success" on several hinf problems, at relative gaps up to 1e-3), and the
# status of both solvers (our status from the JSON output; CSDP's exit code: 0 success,
# 3 partial success). It also writes the in-process table of `sporadic sdp bench DIR --vs-csdp`
# (solve time without process start-up and file reading, same solvers) to $OUT/bench.txt.
# The LMI problem (LMI (41) of Ferrante et al. 2016 on 64 vertices: 64 blocks of order 15 in 46
# shared variables) is written by the `lmi` criterion bench, which also times it in process
# (`lmi_vs_csdp/{ours,csdp}`).
set -euo pipefail

cd "$(dirname "$0")/../.."
ROOT=$(pwd)
SDPLIB=${1:-${SPORADIC_SDPLIB:-$ROOT/../shared/sdplib}}
RUNS=${RUNS:-5}
WARMUP=${WARMUP:-1}
OUT=${OUT:-$ROOT/target/vs_csdp}
CSDP=${CSDP:-/usr/bin/csdp}
DEFAULT_PROBLEMS="control1 control2 control3 control4 control5
truss1 truss2 truss3 truss4 truss5 truss6 truss7 truss8
theta1 theta2 theta3
hinf1 hinf2 hinf3 hinf4 hinf5 hinf6 hinf7 hinf8 hinf9 hinf10"
PROBLEMS=${PROBLEMS:-$DEFAULT_PROBLEMS}

command -v hyperfine >/dev/null || { echo "hyperfine not found (apt-get install -y hyperfine)" >&2; exit 1; }
[ -x "$CSDP" ] || { echo "csdp not found at $CSDP (apt-get install -y coinor-csdp)" >&2; exit 1; }
[ -d "$SDPLIB" ] || { echo "SDPLIB directory $SDPLIB not found" >&2; exit 1; }

mkdir -p "$OUT"
cargo build --release --bin sporadic
SPORADIC=$ROOT/target/release/sporadic

# The many-small-blocks LMI, exported from the modelling layer by the lmi bench.
LMI_FILE=${TMPDIR:-/tmp}/sporadic-lmi64x15.dat-s
cargo bench -p sporadic-benches --bench lmi -- lmi_vs_csdp --warm-up-time 1 --measurement-time 3 \
    | tee "$OUT/lmi_bench.txt"
[ -f "$LMI_FILE" ] || { echo "the lmi bench did not write $LMI_FILE" >&2; exit 1; }

files=()
for p in $PROBLEMS; do files+=("$SDPLIB/$p.dat-s"); done
files+=("$LMI_FILE")

printf '%-22s %10s %10s %7s %12s %7s  %-18s %-9s %s\n' problem 'ours[s]' 'csdp[s]' ratio \
    'ours@acc[s]' ratio 'our status' 'csdp exit' 'csdp accuracy (gap, infeas.)'
for f in "${files[@]}"; do
    name=$(basename "$f" .dat-s)
    json=$OUT/$name.json
    # CSDP's own result first: its exit code and the accuracy it reached (its printed relative
    # infeasibilities, real relative gap and XZ gap, which are defined as ours). Where CSDP stops
    # short of 1e-8 ("partial success", or success on the XZ gap with a larger real gap), the
    # `ours@acc` run stops at that same accuracy (--tol-gap/--tol-feas, never below 1e-8), which
    # compares the two solvers at equal accuracy as well as at their defaults.
    set +e; "$CSDP" "$f" "$OUT/$name.csdp.sol" > "$OUT/$name.csdp.txt"; code=$?; set -e
    read -r tol_gap tol_feas < <(python3 -c '
import re, sys
text = open(sys.argv[1]).read()
def last(label):
    v = re.findall(label + r":\s*([-+0-9.eE]+)", text)
    return abs(float(v[-1])) if v else 0.0
gap = max(1e-8, last("Real Relative Gap"), last("XZ Relative Gap"))
feas = max(1e-8, last("Relative primal infeasibility"), last("Relative dual infeasibility"))
print(f"{gap:.3g} {feas:.3g}")' "$OUT/$name.csdp.txt")
    # CSDP exits with 3 ("partial success") on several of these problems, so exit codes are
    # ignored (-i) rather than wrapping csdp in a shell, whose start-up would be charged to CSDP;
    # the exit code is reported below. -N: no intermediate shell for either command. Hyperfine's
    # warnings (outliers, ignored exit codes) go to $OUT/NAME.hyperfine.log.
    hyperfine -N -i --runs "$RUNS" --warmup "$WARMUP" --style none --export-json "$json" \
        -n ours "$SPORADIC sdp solve $f" \
        -n ours_acc "$SPORADIC sdp solve --tol-gap $tol_gap --tol-feas $tol_feas $f" \
        -n csdp "$CSDP $f $OUT/$name.csdp.sol" >/dev/null 2>"$OUT/$name.hyperfine.log"
    read -r ours ours_acc csdp < <(python3 -c '
import json, sys
r = {x["command"]: x["mean"] for x in json.load(open(sys.argv[1]))["results"]}
print(r["ours"], r["ours_acc"], r["csdp"])' "$json")
    # `sdp solve` exits with 1 when the status is not (almost) optimal; the status is read
    # from the JSON either way (pipefail would otherwise abort the script).
    status=$({ "$SPORADIC" sdp solve "$f" --json || [ $? -eq 1 ]; } | python3 -c 'import json,sys; print(json.load(sys.stdin)["status"])')
    printf '%-22s %10.4f %10.4f %7.2f %12.4f %7.2f  %-18s %-9s %s %s\n' "$name" "$ours" "$csdp" \
        "$(python3 -c "print($ours/$csdp)")" "$ours_acc" "$(python3 -c "print($ours_acc/$csdp)")" \
        "$status" "$code" "$tol_gap" "$tol_feas"
done | tee "$OUT/hyperfine.txt"

# In-process table on the same problems only (the whole SDPLIB directory takes hours).
SEL=$OUT/selected
rm -rf "$SEL"; mkdir -p "$SEL"
ln -s "$SDPLIB/README-SDPLIB.md" "$SEL/"
for f in "${files[@]}"; do ln -s "$f" "$SEL/"; done
"$SPORADIC" sdp bench "$SEL" --vs-csdp > "$OUT/bench.txt"
echo "in-process table: $OUT/bench.txt; hyperfine JSON: $OUT/*.json"
