"""Notebook-style example: design an observer for a plant with jittery sampling, simulate it and
plot the estimation error.

Run:  python python/examples/design_observer.py   (after `pip install ./python`)

Uses python-control for the plant when it is installed, plain numpy matrices otherwise, and
matplotlib for the figure when installed (written to observer_error.png).
"""

# %% The plant: a DC motor (angle, speed, current); the angle is measured over a network whose
# sampling interval jitters between 5 ms and 40 ms.
import numpy as np

import sporadic

A = np.array([[0.0, 1.0, 0.0], [0.0, -0.5, 10.0], [0.0, -2.0, -20.0]])
B = np.array([[0.0], [0.0], [20.0]])
C = np.array([[1.0, 0.0, 0.0]])
window = (0.005, 0.04)

try:
    import control

    sys = control.ss(A, B, C, 0)
    plant = sporadic.Plant.from_statespace(sys, window=window, name="dc motor")
    print("plant from python-control:", plant)
except ImportError:
    plant = sporadic.Plant(A, B, C, window=window, name="dc motor")
    print("plant from numpy matrices:", plant)

# %% Design with every method and keep the certified ones. prove=True (exact certificates) is
# issue 24 and raises NotImplementedError for now.
for method in sporadic.methods():
    r = sporadic.design(plant, method=method, prove=False)
    why = "" if r.certified else f" ({r.reason['kind']}: {r.reason['message'][:70]}...)"
    print(f"{method:14s} {r.status}{why}")

report = sporadic.design(plant, method="ferrante2016")
print(report)
for name, gain in report.gains.items():
    print(f"gain {name} =\n{gain}")

# %% How far can the window stretch?
mi = sporadic.max_interval(plant, method="ferrante2016", limit=0.5)
print(f"largest certified T2 with T1 = {mi.t1}: {mi.largest_certified_t2}")

# %% Simulate the certified observer with random intervals in the window.
sim = sporadic.simulate(plant, method="ferrante2016", horizon=1.0, seed=1)
print(f"{len(sim.jumps)} samples; |e| from {sim.norm[0]:.3g} to {sim.norm[-1]:.3g}")

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 3.5))
    for name, e in zip(sim.signal_names, sim.error):
        ax.plot(sim.t, e, label=name)
    ax.plot(sim.t[sim.jumps], sim.norm[sim.jumps], "k.", ms=3, label="|e| at samples")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("estimation error")
    ax.set_title(sim.quantity, fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig("observer_error.png", dpi=120)
    print("figure: observer_error.png")
except ImportError:
    print("matplotlib is not installed: no figure")
