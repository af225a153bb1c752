"""Notebook-style example: design an observer for a plant with jittery sampling, prove the design
for every sampling interval of the window, simulate it and plot the state, its estimate and the
estimation error.

Run:  python python/examples/design_observer.py   (after `pip install ./python`)

Uses python-control for the plant when it is installed, plain numpy matrices otherwise, and
matplotlib for the figure when installed (written to observer_error.png). Runs in a few seconds.
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

# %% Design with every method and keep the certified ones.
for method in sporadic.methods():
    r = sporadic.design(plant, method=method)
    why = "" if r.certified else f" ({r.reason['kind']}: {r.reason['message'][:70]}...)"
    print(f"{method:14s} {r.status}{why}")

# %% Design with Ferrante et al. (2016) and prove it: the design's LMI condition is checked for
# *every* sampling interval of [T1, T2] in outward-rounded interval arithmetic, not only on the
# floating-point grid of the design's own re-verification.
report = sporadic.design(plant, method="ferrante2016", prove=True)
print(report)
for name, gain in report.gains.items():
    print(f"gain {name} =\n{gain}")
proof = report.proof
print(f"proof: {proof.status} on {proof.subintervals} pieces of the window; "
      f"margin ≥ {proof.margin_lower_bound!r} (floating-point margin {report.margin:.4g}; "
      f"{proof.margin_definition})")
print(f"proof: {proof.message}")
assert report.proved, "the design should be proved"

# %% The same gain checked (and proved) as if it came from elsewhere, e.g. a hand-tuned L.
checked = sporadic.verify(plant, "ferrante2016", {"L": report.gains["L"]}, prove=True)
print(f"verify L: {checked.status}, proof {checked.proof.status}")

# %% How far can the window stretch?
mi = sporadic.max_interval(plant, method="ferrante2016", limit=0.5)
print(f"largest certified T2 with T1 = {mi.t1}: {mi.largest_certified_t2}")

# %% Simulate the certified observer with random intervals in the window, from x(0) = x0 (the
# plant runs without input; x̂(0) = x0 − the default initial error).
sim = sporadic.simulate(plant, method="ferrante2016", horizon=1.0, seed=1, x0=[0.0, 1.0, 0.0])
print(f"{len(sim.jumps)} samples; |x − x̂| from {sim.norm[0]:.3g} to {sim.norm[-1]:.3g}")

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7, 5.5), sharex=True)
    for k in range(sim.x.shape[0]):
        (line,) = ax1.plot(sim.t, sim.x[k], label=f"x_{k + 1}")
        ax1.plot(sim.t, sim.x_hat[k], "--", color=line.get_color(), label=f"x̂_{k + 1}")
    ax1.set_ylabel("state and estimate")
    ax1.legend(fontsize=7, ncol=3)
    for name, e in zip(sim.signal_names, sim.error):
        ax2.plot(sim.t, e, label=name)
    ax2.plot(sim.t[sim.jumps], sim.norm[sim.jumps], "k.", ms=3, label="|x − x̂| at samples")
    ax2.set_xlabel("t [s]")
    ax2.set_ylabel("estimation error")
    ax2.legend(fontsize=8)
    ax1.set_title(f"{report.method}: {proof.status} on {report.window}; {sim.quantity}", fontsize=9)
    fig.tight_layout()
    fig.savefig("observer_error.png", dpi=120)
    print("figure: observer_error.png")
except ImportError:
    print("matplotlib is not installed: no figure")
