#!/usr/bin/env bash
# Wall time of `sporadic compare` (designs at the file's window plus the largest-T2 search of every
# method that applies) and of `sporadic max-interval` for each applicable method, on every plant of
# the corpus `tests/corpus/*.toml`, with the default time budget (25 s per command).
#
#   benches/scripts/corpus.sh [MAX_ORDER]     (default 6: plants of order <= 6, the goal of issue 22)
#
# Environment: OUT (result directory, default target/corpus-bench), SPORADIC (the binary, default
# target/release/sporadic, built if missing).
#
# Writes $OUT/corpus.md (one row per plant: order, compare seconds, exit code, each method's
# largest certified T2 from the compare report and its max-interval seconds) and $OUT/corpus.csv,
# then prints the median and the slowest compare and max-interval times. Goals (issue 22):
# compare <= 10 s per plant and <= 2 s median; max-interval <= 30 s.
set -euo pipefail

cd "$(dirname "$0")/../.."
ROOT=$(pwd)
MAX_ORDER=${1:-6}
OUT=${OUT:-$ROOT/target/corpus-bench}
SPORADIC=${SPORADIC:-$ROOT/target/release/sporadic}
[ -x "$SPORADIC" ] || cargo build --release --bin sporadic
mkdir -p "$OUT"

python3 - "$SPORADIC" "$OUT" "$MAX_ORDER" "$ROOT/tests/corpus" <<'PY'
import json, pathlib, statistics, subprocess, sys, time, tomllib

exe, out, max_order, corpus = sys.argv[1], pathlib.Path(sys.argv[2]), int(sys.argv[3]), pathlib.Path(sys.argv[4])
METHODS = ["ferrante2016", "sferlazza2021", "andrieu2014", "etienne2017", "rabehi2021"]

def timed(args):
    t = time.perf_counter()
    p = subprocess.run([exe, *args], capture_output=True, text=True)
    return time.perf_counter() - t, p.returncode, p.stdout

rows = []
for f in sorted(corpus.glob("*.toml")):
    if f.stem == "expected":
        continue
    order = len(tomllib.loads(f.read_text())["plant"]["A"])
    if order > max_order:
        continue
    secs, code, text = timed(["compare", str(f), "--json", "--out", str(out / "figures" / f.stem)])
    report = json.loads(text) if text.strip() else {"results": []}
    row = {"plant": f.stem, "order": order, "compare_s": secs, "exit": code}
    for e in report["results"]:
        m = e["method"]
        lw = e.get("largest_window")
        row[m + "_t2"] = lw and lw.get("largest_certified_t2")
        if lw is not None:
            s, _, _ = timed(["max-interval", str(f), "--method", m, "--json"])
            row[m + "_max_interval_s"] = s
    rows.append(row)
    print(f"{f.stem:32s} n={order} compare {secs:6.2f} s (exit {code})", flush=True)

cols = ["plant", "order", "compare_s", "exit"] + [m + k for m in METHODS for k in ("_t2", "_max_interval_s")]
fmt = lambda v: "-" if v is None else (f"{v:.4g}" if isinstance(v, float) else str(v))
(out / "corpus.csv").write_text("\n".join([",".join(cols)] + [",".join(fmt(r.get(c)) for c in cols) for r in rows]) + "\n")
md = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
md += ["| " + " | ".join(fmt(r.get(c)) for c in cols) + " |" for r in rows]
(out / "corpus.md").write_text("\n".join(md) + "\n")

cmp = [r["compare_s"] for r in rows]
mi = [(r[c], r["plant"], c[: -len("_max_interval_s")]) for r in rows for c in r if c.endswith("_max_interval_s")]
slow = max(rows, key=lambda r: r["compare_s"])
print(f"\n{len(rows)} plants of order <= {max_order}")
print(f"compare: median {statistics.median(cmp):.2f} s, slowest {slow['compare_s']:.2f} s ({slow['plant']}); goal <= 10 s, median <= 2 s")
if mi:
    s, p, m = max(mi)
    print(f"max-interval: median {statistics.median(x[0] for x in mi):.2f} s, slowest {s:.2f} s ({p}, {m}); goal <= 30 s")
print(f"tables: {out / 'corpus.md'}, {out / 'corpus.csv'}")
PY
