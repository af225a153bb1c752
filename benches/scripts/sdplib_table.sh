#!/usr/bin/env bash
# The full SDPLIB table of issue 23: every problem with n <= 2000 solved by `sporadic sdp solve`
# and by the Debian `csdp` binary (coinor-csdp), each in its own process (whole-process wall time,
# peak memory from GNU time), with status, iterations, relative error against SDPLIB's optimum and
# the largest DIMACS error of both; problems that take under a second are repeated (see
# `sporadic sdp bench --help`).
#
#   benches/scripts/sdplib_table.sh [SDPLIB_DIR]   (default: $SPORADIC_SDPLIB or ../shared/sdplib)
#
# Environment: OUT (default benches/results). Writes $OUT/sdplib.md and $OUT/sdplib.csv and
# appends the commit, date, machine and load average to the markdown file.
set -euo pipefail

cd "$(dirname "$0")/../.."
ROOT=$(pwd)
SDPLIB=${1:-${SPORADIC_SDPLIB:-$ROOT/../shared/sdplib}}
OUT=${OUT:-$ROOT/benches/results}
[ -d "$SDPLIB" ] || { echo "SDPLIB directory $SDPLIB not found (set SPORADIC_SDPLIB)" >&2; exit 1; }
command -v csdp >/dev/null || { echo "csdp not found (apt-get install -y coinor-csdp)" >&2; exit 1; }
cargo build --release --bin sporadic
BIN=$(mktemp -d)/sporadic
cp target/release/sporadic "$BIN"   # later rebuilds cannot change the binary under test
COMMIT=$(git rev-parse --short HEAD)$(git diff --quiet HEAD -- . ':!benches/results' || echo "+changes")
load_before=$(cut -d' ' -f1-3 /proc/loadavg)
"$BIN" sdp bench "$SDPLIB" --vs-csdp --table "$OUT"
{
  echo "Measured by \`benches/scripts/sdplib_table.sh\` at commit $COMMIT" \
       "on $(date -u +%Y-%m-%d), $(nproc) cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)), " \
       "csdp $(dpkg-query -W -f '${Version}' coinor-csdp 2>/dev/null || echo '(version unknown)');" \
       "load average before $load_before, after $(cut -d' ' -f1-3 /proc/loadavg)."
} >> "$OUT/sdplib.md"
