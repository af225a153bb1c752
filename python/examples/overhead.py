"""The overhead of a Python call over the Rust call: `sporadic.design` (also with `prove=True`) and
`sporadic.verify` on a small plant, wall time in Python minus the time the Rust core reports for the
same call (`report.seconds`, plus `report.proof.seconds` for a proof)."""

import statistics
import time

import sporadic

plant = sporadic.Plant([[0.0, 1.0], [-1.0, -0.2]], None, [[1.0, 0.0]], window=(0.1, 0.5))
for method in ("ferrante2016", "andrieu2014"):
    over, total = [], []
    for _ in range(200):
        t0 = time.perf_counter()
        r = sporadic.design(plant, method=method)
        dt = time.perf_counter() - t0
        total.append(dt)
        over.append(dt - r.seconds)
    print(f"{method}: call {statistics.median(total) * 1e3:.3f} ms, "
          f"Rust design {statistics.median(total) * 1e3 - statistics.median(over) * 1e3:.3f} ms, "
          f"overhead median {statistics.median(over) * 1e3:.3f} ms (min {min(over) * 1e3:.3f} ms)")

# design + proof, and verify (with proof) of the designed gain: the Rust time is the report's
# seconds plus the proof's seconds
base = sporadic.design(plant, method="ferrante2016")
for label, call in (
    ("ferrante2016 design(prove=True)", lambda: sporadic.design(plant, method="ferrante2016", prove=True)),
    ("ferrante2016 verify(prove=True)",
     lambda: sporadic.verify(plant, "ferrante2016", {"L": base.gains["L"]}, prove=True)),
):
    over, total = [], []
    for _ in range(100):
        t0 = time.perf_counter()
        r = call()
        dt = time.perf_counter() - t0
        total.append(dt)
        over.append(dt - r.seconds - r.proof.seconds)
    print(f"{label}: call {statistics.median(total) * 1e3:.3f} ms, "
          f"overhead median {statistics.median(over) * 1e3:.3f} ms (min {min(over) * 1e3:.3f} ms)")

t0 = time.perf_counter()
for _ in range(1000):
    sporadic.expm([[0.0, 1.0], [-1.0, 0.0]])
print(f"expm 2x2 round trip: {(time.perf_counter() - t0) * 1e3:.3f} us")
