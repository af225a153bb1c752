"""The overhead of a Python call over the Rust call: `sporadic.design` on a small plant, wall time
in Python minus the time the Rust core reports for the same design (`report.seconds`)."""

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

t0 = time.perf_counter()
for _ in range(1000):
    sporadic.expm([[0.0, 1.0], [-1.0, 0.0]])
print(f"expm 2x2 round trip: {(time.perf_counter() - t0) * 1e3:.3f} us")
