"""sporadic: observer design and certification for plants with sporadic sampled outputs.

Python bindings of the sporadic Rust workbench: the same core as the ``sporadic`` command-line
program, numpy arrays in and out, reports equal to the CLI's ``--json`` output.

>>> import numpy as np, sporadic
>>> plant = sporadic.Plant([[0, 1], [-1, -0.2]], None, [[1, 0]], window=(0.1, 0.5))
>>> report = sporadic.design(plant, method="ferrante2016")
>>> report.status, report.gains["L"].shape        # doctest: +SKIP
('certified', (2, 1))
>>> sporadic.design(plant, prove=True).proof.status             # doctest: +SKIP
'proved'
>>> sporadic.verify(plant, "ferrante2016", {"L": report.gains["L"]}).status   # doctest: +SKIP
'certified'

``sporadic.sdp`` is the SDP solver; ``import sporadic.cvxpy`` registers it with CVXPY
(``problem.solve(solver="SPORADIC")``) when cvxpy is installed.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from typing import Any, Dict, List, Mapping, Optional, Sequence, Union

import numpy as np

from . import _native
from ._errors import (
    InvalidInputError,
    NotCertifiedError,
    NumericalError,
    PlantError,
    SdpError,
    SimulationUnavailableError,
    SporadicError,
    VerificationUnavailableError,
)
from ._plant import Plant, _call
from ._reports import CompareReport, DesignReport, MaxIntervalReport, Proof
from . import sdp

__all__ = [
    "Plant", "design", "verify", "max_interval", "compare", "simulate", "expm", "methods", "sdp",
    "DesignReport", "Proof", "MaxIntervalReport", "CompareReport", "Simulation",
    "SporadicError", "PlantError", "InvalidInputError", "NumericalError", "NotCertifiedError",
    "SimulationUnavailableError", "VerificationUnavailableError", "SdpError", "DEFAULT_TIME_LIMIT",
]
__version__ = "0.1.0"

#: The CLI's default ``--time-limit`` (seconds); ``time_limit=None`` runs without a budget.
DEFAULT_TIME_LIMIT = 25.0

PlantLike = Union[Plant, str, "os.PathLike[str]"]


def methods() -> List[str]:
    """The method ids, in registry order."""
    return list(_native.method_ids())


def _plant(plant: PlantLike) -> Plant:
    if isinstance(plant, Plant):
        return plant
    if isinstance(plant, (str, os.PathLike)):
        return Plant.from_toml(plant)
    raise InvalidInputError(
        f"plant must be a sporadic.Plant or the path of a plant file, got {type(plant).__name__}",
        "invalid_input",
    )


def _no_options(fn: str, options: Dict[str, Any]) -> None:
    if options:
        raise InvalidInputError(
            f"{fn}: unknown option(s) {', '.join(sorted(options))} (supported: time_limit)", "invalid_input"
        )


def _proof_args(prove: Any, proof_pieces: Any) -> None:
    if not isinstance(prove, (bool, np.bool_)):
        raise InvalidInputError(f"prove must be True or False, got {prove!r}", "invalid_input")
    if proof_pieces is not None and (
        isinstance(proof_pieces, bool) or not isinstance(proof_pieces, (int, np.integer)) or proof_pieces < 1
    ):
        raise InvalidInputError(
            f"proof_pieces must be a positive integer or None, got {proof_pieces!r}", "invalid_input"
        )


def design(plant: PlantLike, method: str = "ferrante2016", prove: bool = False, *,
           time_limit: Optional[float] = DEFAULT_TIME_LIMIT, proof_pieces: Optional[int] = None,
           **options: Any) -> DesignReport:
    """Designs an observer with ``method`` (see :func:`methods`) for ``plant`` (a
    :class:`Plant` or a plant-file path): ``sporadic design FILE --method M --json``.

    Returns a :class:`DesignReport` (``status``, ``gains``, ``certificate``, ``margin``,
    ``window``, ``to_dict()``/``to_json()``). A plant the method does not certify is a report
    with status ``not_certified``/``not_applicable`` and a ``reason``, not an exception.

    ``prove=True`` (``--prove``) adds ``report.proof`` (a :class:`Proof`): the design's condition
    proven for every sampling interval of the window in interval arithmetic (``proved``), shown
    to fail (``not_proved``), or neither within ``proof_pieces`` (default 4096, as
    ``--proof-pieces``) and ``time_limit`` (``inconclusive``; also for a method without a
    prover). The proof has its own ``time_limit`` budget, as in the CLI.

    The GIL is released during the design; Ctrl-C interrupts it (``KeyboardInterrupt``).
    """
    _proof_args(prove, proof_pieces)
    _no_options("design", options)
    p = _plant(plant)
    return DesignReport(
        _call(_native.design, p._text, p._path, method, time_limit, bool(prove),
              None if proof_pieces is None else int(proof_pieces))
    )


def _named_matrices(what: str, m: Any) -> List[Dict[str, Any]]:
    """``{name: matrix}`` (or a list of ``{"name", "rows", ...}`` dicts) as the JSON entries of
    ``sporadic verify --gains``, with finite 2-D float matrices."""
    if isinstance(m, Mapping):
        items = [{"name": k, "rows": v} for k, v in m.items()]
    elif isinstance(m, (list, tuple)) and all(isinstance(e, Mapping) for e in m):
        items = [dict(e) for e in m]
    else:
        raise InvalidInputError(
            f"{what} must be a dict {{name: matrix}}, a list of {{'name', 'rows'}} dicts or a DesignReport, "
            f"got {type(m).__name__}", "invalid_input")
    out = []
    for e in items:
        name = e.get("name")
        if not isinstance(name, str) or not name:
            raise InvalidInputError(f"{what}: every matrix needs a non-empty string name, got {name!r}",
                                    "invalid_input")
        try:
            a = np.asarray(e.get("rows"), dtype=float)
        except (TypeError, ValueError) as err:
            raise InvalidInputError(f"{what} {name}: not a numeric matrix ({err})", "invalid_input") from None
        if a.ndim != 2 or a.size == 0:
            raise InvalidInputError(
                f"{what} {name}: expected a non-empty 2-D matrix, got shape {a.shape}", "invalid_input")
        if not np.all(np.isfinite(a)):
            raise InvalidInputError(f"{what} {name} has an entry that is not a finite number", "invalid_input")
        e = {k: v for k, v in e.items() if k not in ("name", "rows")}
        entry: Dict[str, Any] = {"name": name, "rows": a.tolist()}
        for k in ("meaning", "schedule"):
            if e.get(k) is not None:
                entry[k] = e[k]
        out.append(entry)
    return out


def verify(plant: PlantLike, method: str, gains: Any, certificate: Any = None,
           window: Optional[Sequence[float]] = None, prove: bool = False, *,
           time_limit: Optional[float] = DEFAULT_TIME_LIMIT, proof_pieces: Optional[int] = None) -> DesignReport:
    """Checks gains the user brings against ``method``'s condition on ``plant``'s sampling (or
    on ``window=(T1, T2)``, every sensor's for round-robin sampling): ``sporadic verify FILE
    --method M --gains G.json [--window T1 T2] [--prove] --json``.

    ``gains`` is a dict ``{name: matrix}`` (e.g. ``{"L": L}``), a list of ``{"name", "rows"}``
    dicts, or a :class:`DesignReport` (its gains and, unless ``certificate`` is given, its
    certificate are used, as when the CLI reads a design report). ``certificate`` is an optional
    dict ``{name: matrix}`` (e.g. the Lyapunov matrix ``P``) the check tries first.

    The report always has a ``proof``: with ``prove=True`` the rigorous proof; without it
    ``inconclusive`` ("no proof was asked for") when the gains pass the floating-point check,
    ``not_proved`` when they fail it. Raises :class:`VerificationUnavailableError` for a method
    without a check of given gains (andrieu2014), as the CLI exits with an error.
    """
    _proof_args(prove, proof_pieces)
    p = _plant(plant)
    if isinstance(gains, DesignReport) and certificate is None:
        payload = gains.to_json()
    else:
        if isinstance(gains, DesignReport):
            d = gains.to_dict()
            g = _named_matrices("gains", d["gains"])
        else:
            g = _named_matrices("gains", gains)
        if not g:
            raise InvalidInputError("gains: no gains given", "invalid_input")
        doc: Dict[str, Any] = {"gains": g}
        if certificate is not None:
            doc["certificate"] = _named_matrices("certificate", certificate)
        payload = json.dumps(doc)
    w = None
    if window is not None:
        try:
            t1, t2 = (float(v) for v in window)
        except (TypeError, ValueError):
            raise InvalidInputError(f"window must be a pair (T1, T2) of numbers, got {window!r}",
                                    "invalid_input") from None
        w = (t1, t2)
    return DesignReport(
        _call(_native.verify, p._text, p._path, method, payload, w, bool(prove),
              None if proof_pieces is None else int(proof_pieces), time_limit)
    )


def max_interval(plant: PlantLike, method: str = "ferrante2016", limit: Optional[float] = None, *,
                 time_limit: Optional[float] = DEFAULT_TIME_LIMIT, **options: Any) -> MaxIntervalReport:
    """The largest certified ``T2 ≤ limit`` (default 10 × the plant's largest ``T2``) with the
    plant's ``T1``: ``sporadic max-interval FILE --method M --json``."""
    _no_options("max_interval", options)
    p = _plant(plant)
    return MaxIntervalReport(_call(_native.max_interval, p._text, p._path, method, limit, time_limit))


def compare(plant: PlantLike, limit: Optional[float] = None, *, search: bool = True,
            time_limit: Optional[float] = DEFAULT_TIME_LIMIT, **options: Any) -> CompareReport:
    """Every method on ``plant``: the design at its own sampling and (``search=True``) the
    largest certified ``T2 ≤ limit``: ``sporadic compare FILE --json`` (no figure is written)."""
    _no_options("compare", options)
    p = _plant(plant)
    return CompareReport(_call(_native.compare, p._text, p._path, search, limit, time_limit))


@dataclass
class Simulation:
    """A simulated observer.

    - ``t`` (N,) times and ``j`` (N,) jump counters (a sample increments ``j`` at the same ``t``,
      so a jump is two consecutive points with equal ``t``); ``jumps`` the indices ``k`` where a
      sample is taken (``j[k] = j[k-1] + 1``: ``k-1`` is just before, ``k`` just after);
    - ``error`` (k, N) the simulated signals, one row per name in ``signal_names``: the method's
      estimation error (``quantity`` says which: ``x − x̂`` for ferrante2016, sferlazza2021 and
      andrieu2014; the interval width ``x̄ − x̲`` for rabehi2021); ``norm`` (N,) their norm;
    - ``x`` (n, N) the plant's state and ``x_hat`` (n, N) the observer's estimate, for the methods
      whose signals are ``x − x̂`` of a linear plant (ferrante2016, sferlazza2021, andrieu2014):
      ``x(t) = e^{At} x0`` (the plant runs without input, ``u = 0``, and does not jump; the error
      dynamics do not depend on ``u``) and ``x̂ = x − error`` (so ``x̂`` jumps at the samples).
      ``None`` for rabehi2021 (its signals are interval widths: ``x`` lies between bounds the core
      does not return) and for a plant with a Lipschitz nonlinearity (its ``φ`` is only bounded
      by the plant file; etienne2017 has no simulation for that reason);
    - ``report`` the design and ``summary`` the simulation summary dict (as the CLI's
      ``simulation`` section).
    """

    quantity: str
    t: np.ndarray
    j: np.ndarray
    jumps: np.ndarray
    signal_names: List[str]
    error: np.ndarray
    norm: np.ndarray
    report: DesignReport
    summary: Dict[str, Any]
    x: Optional[np.ndarray] = None
    x_hat: Optional[np.ndarray] = None

    def __repr__(self) -> str:
        # The dataclass default would print every array in full.
        span = (float(self.t[0]), float(self.t[-1])) if len(self.t) else None
        last = float(self.norm[-1]) if len(self.norm) else None
        return (f"Simulation(method={self.report.method!r}, quantity={self.quantity!r}, t={span!r}, "
                f"points={len(self.t)}, samples={len(self.jumps)}, final_norm={last!r})")


def simulate(plant: PlantLike, method: str = "ferrante2016", *, horizon: Optional[float] = None,
             initial_error: Optional[Sequence[float]] = None, scenario: str = "uniform", seed: int = 1,
             time_limit: Optional[float] = DEFAULT_TIME_LIMIT, x0: Optional[Sequence[float]] = None) -> Simulation:
    """Designs with ``method`` and simulates the certified observer (as ``sporadic design
    --simulate/--csv``): ``scenario`` is ``uniform`` (random intervals with ``seed``),
    ``periodic_t1`` or ``periodic_t2``; ``initial_error`` the initial estimation error (the
    CLI's default when None).

    ``x0`` is the plant's initial state (default: zeros, the plant at rest), used for
    ``Simulation.x`` and ``x_hat`` (``x̂(0) = x0 − initial error``); see :class:`Simulation`.
    Raises :class:`NotCertifiedError` when the design is not certified,
    :class:`SimulationUnavailableError` when the method has no simulation (etienne2017)."""
    p = _plant(plant)
    ie = None if initial_error is None else _vector("initial_error", initial_error)
    xs = None if x0 is None else _vector("x0", x0)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InvalidInputError(f"seed must be a non-negative integer, got {seed!r}", "invalid_input")
    (design_json, quantity, t, j, names, signals, norm, summary, x) = _call(
        _native.simulate, p._text, p._path, method, horizon, ie, scenario, int(seed), time_limit, xs
    )
    j = np.asarray(j, dtype=np.int64)
    jumps = np.nonzero(np.diff(j) > 0)[0] + 1
    error = np.asarray(signals, dtype=float).reshape(len(signals), -1)
    xa = None if x is None else np.asarray(x, dtype=float).reshape(len(x), -1)
    return Simulation(
        quantity=quantity,
        t=np.asarray(t, dtype=float),
        j=j,
        jumps=jumps,
        signal_names=list(names),
        error=error,
        norm=np.asarray(norm, dtype=float),
        report=DesignReport(design_json),
        summary=json.loads(summary),
        x=xa,
        x_hat=None if xa is None else xa - error,
    )


def _vector(name: str, v: Any) -> List[float]:
    try:
        a = np.asarray(v, dtype=float)
    except (TypeError, ValueError) as e:
        raise InvalidInputError(f"{name}: not a numeric vector ({e})", "invalid_input") from None
    if a.ndim > 1 and a.size != max(a.shape):
        raise InvalidInputError(f"{name}: expected a vector, got shape {a.shape}", "invalid_input")
    return [float(e) for e in a.reshape(-1)]


def expm(A: Any) -> np.ndarray:
    """The matrix exponential ``e^A`` (the Padé kernel the methods use)."""
    try:
        a = np.asarray(A, dtype=float)
    except (TypeError, ValueError) as e:
        raise InvalidInputError(f"expm: not a numeric matrix ({e})", "invalid_input") from None
    if a.ndim != 2:
        raise InvalidInputError(f"expm: expected a square 2-D matrix, got shape {a.shape}", "invalid_input")
    if a.shape[0] != a.shape[1]:
        raise InvalidInputError(f"expm: expected a square matrix, got shape {a.shape}", "invalid_input")
    return np.asarray(_call(_native.expm, a.tolist()), dtype=float).reshape(a.shape)
