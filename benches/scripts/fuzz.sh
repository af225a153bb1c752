#!/usr/bin/env bash
# Plants nobody tuned for (issue 22): writes N random linear plant files, runs `sporadic compare
# --json` on each, on a copy with time scaled by 1000 (A·1000, window/1000) and on a copy with the
# outputs in other units (C/100), and reports every finding:
#   * a command that took longer than 30 s or exited with status 2 (bad input: the files are valid);
#   * a method whose verdict on the file's window, or whose largest certified T2 (within 1 %, and
#     not cut short by the budget), changes under time scaling or output scaling: the verdicts of
#     every method are invariant under both in exact arithmetic;
#   * a method that certifies the file's window but whose window search certifies less.
# Random plants: orders 1-6, 1-3 outputs, eigenvalues stable, unstable, marginal or mixed (real
# ones and complex pairs), coordinates badly scaled (entries spread over 4 decades) in about a
# third of them, windows from 10^-3 to 10^-0.5 of the fastest time constant and up to 30 times
# long. Only ferrante2016, sferlazza2021 and andrieu2014 apply to such plants.
#
#   benches/scripts/fuzz.sh [N] [SEED]      (default 12 plants, seed 1)
#
# Environment: OUT (default target/fuzz), SPORADIC (the binary, default target/release/sporadic,
# built if missing). Exits with status 1 when there is a finding. Not part of CI: a run of 12
# plants takes a few minutes, and a finding is a defect to investigate, not a flaky test.
set -euo pipefail

cd "$(dirname "$0")/../.."
ROOT=$(pwd)
N=${1:-12}
SEED=${2:-1}
OUT=${OUT:-$ROOT/target/fuzz}
SPORADIC=${SPORADIC:-$ROOT/target/release/sporadic}
[ -x "$SPORADIC" ] || cargo build --release --bin sporadic
mkdir -p "$OUT"

python3 - "$SPORADIC" "$OUT" "$N" "$SEED" <<'PY'
import cmath, json, math, pathlib, random, subprocess, sys, time

exe, out, n_plants, seed = sys.argv[1], pathlib.Path(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
rng = random.Random(seed)
TIME, OUTPUT = 1000.0, 0.01
METHODS = ["ferrante2016", "sferlazza2021", "andrieu2014"]

def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(len(b))) for j in range(len(b[0]))] for i in range(len(a))]

def inverse(a):
    n = len(a)
    m = [row[:] + [float(i == j) for j in range(n)] for i, row in enumerate(a)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(m[r][c]))
        m[c], m[p] = m[p], m[c]
        pivot = m[c][c]
        m[c] = [v / pivot for v in m[c]]
        for r in range(n):
            if r != c:
                f = m[r][c]
                m[r] = [v - f * w for v, w in zip(m[r], m[c])]
    return [row[n:] for row in m]

def plant():
    n = rng.randint(1, 6)
    p = rng.randint(1, min(n, 3))
    kind = rng.choice(["stable", "unstable", "marginal", "mixed"])
    j = [[0.0] * n for _ in range(n)]
    i = 0
    while i < n:
        if n - i >= 2 and rng.random() < 0.5:
            w = 10 ** rng.uniform(-1, 1.5)
            re = {"stable": -abs(rng.gauss(0, 0.3)), "unstable": abs(rng.gauss(0, 0.2)),
                  "marginal": 0.0, "mixed": rng.gauss(0, 0.2)}[kind] * w
            j[i][i] = j[i + 1][i + 1] = re
            j[i][i + 1], j[i + 1][i] = w, -w
            i += 2
        else:
            j[i][i] = {"stable": -10 ** rng.uniform(-1, 1.5), "unstable": 10 ** rng.uniform(-1, 0.7),
                       "marginal": 0.0, "mixed": rng.gauss(0, 2)}[kind]
            i += 1
    t = [[rng.gauss(0, 1) + 2.0 * (r == c) for c in range(n)] for r in range(n)]
    if rng.random() < 0.3:
        t = [[10 ** rng.uniform(-2, 2) * v for v in row] for row in t]
    a = matmul(matmul(t, j), inverse(t))
    a = [[float(f"{v:.6g}") for v in row] for row in a]
    c = [[float(f"{rng.gauss(0, 1):.6g}") for _ in range(n)] for _ in range(p)]
    fast = max([1e-3] + [abs(j[r][r]) + abs(j[r][r + 1] if r + 1 < n else 0.0) for r in range(n)])
    t1 = 10 ** rng.uniform(-3, -0.5) / fast
    t2 = t1 * 10 ** rng.uniform(0.05, 1.5)
    return f"{kind} n={n} p={p}", a, c, (float(f"{t1:.6g}"), float(f"{t2:.6g}"))

def write(path, name, a, c, window):
    rows = lambda m: "[" + ", ".join("[" + ", ".join(repr(v) for v in r) + "]" for r in m) + "]"
    path.write_text(f'name = "{name}"\n[plant]\nA = {rows(a)}\nC = {rows(c)}\n[sampling]\n'
                    f"window = [{window[0]!r}, {window[1]!r}]\n")

def compare(path):
    t = time.perf_counter()
    p = subprocess.run([exe, "compare", str(path), "--json"], capture_output=True, text=True)
    secs = time.perf_counter() - t
    results = {}
    if p.stdout.strip():
        for e in json.loads(p.stdout)["results"]:
            lw = e.get("largest_window") or {}
            results[e["method"]] = (e["design"]["status"], lw.get("largest_certified_t2"),
                                    lw.get("search_end"))
    return secs, p.returncode, results

findings = []
for k in range(n_plants):
    name, a, c, w = plant()
    base = out / f"plant{seed}_{k}"
    variants = {
        "given": (a, c, w, 1.0),
        "time": ([[v * TIME for v in r] for r in a], c, (w[0] / TIME, w[1] / TIME), TIME),
        "output": (a, [[v * OUTPUT for v in r] for r in c], w, 1.0),
    }
    runs = {}
    for tag, (av, cv, wv, scale) in variants.items():
        path = base.with_name(f"{base.name}_{tag}.toml")
        write(path, f"fuzz {seed}/{k} {name} ({tag})", av, cv, wv)
        secs, code, results = compare(path)
        runs[tag] = (results, scale)
        print(f"{path.name:28s} {name:22s} compare {secs:6.2f} s (exit {code})", flush=True)
        if secs > 30.0 or code == 2:
            findings.append(f"{path.name}: compare took {secs:.1f} s, exit {code}")
    given, _ = runs["given"]
    for m in METHODS:
        if m not in given:
            continue
        status, t2, end = given[m]
        for tag in ("time", "output"):
            other, scale = runs[tag]
            if m not in other:
                findings.append(f"{base.name} {m}: no result under {tag} scaling")
                continue
            s2, t2b, end2 = other[m]
            if s2 != status:
                findings.append(f"{base.name} {m}: verdict {status} vs {s2} under {tag} scaling")
            if "budget_exhausted" in (end, end2):
                continue
            if (t2 is None) != (t2b is None) or (t2 and abs(t2b * scale / t2 - 1.0) > 0.01):
                findings.append(f"{base.name} {m}: largest T2 {t2} vs {t2b} (x{scale:g}) under {tag} scaling")
        searched = end is not None  # andrieu2014 picks its own sampling: no window search
        if searched and status == "certified" and end != "budget_exhausted" and (t2 is None or t2 < w[1] * (1 - 1e-9)):
            findings.append(f"{base.name} {m}: the file's window is certified but the search answers {t2}")

print(f"\n{len(findings)} finding(s) on {n_plants} plants (seed {seed}); files in {out}")
for f in findings:
    print("  " + f)
sys.exit(1 if findings else 0)
PY
