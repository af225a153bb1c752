"""sporadic: observer design and certification for plants with sporadic sampled outputs.

Python bindings of the sporadic Rust workbench: the same core as the ``sporadic`` command-line
program, numpy arrays in and out, reports equal to the CLI's ``--json`` output.

>>> import numpy as np, sporadic
>>> plant = sporadic.Plant([[0, 1], [-1, -0.2]], None, [[1, 0]], window=(0.1, 0.5))
>>> report = sporadic.design(plant, method="ferrante2016")
>>> report.status, report.gains["L"].shape        # doctest: +SKIP
('certified', (2, 1))
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any, Dict, List, Optional, Sequence, Union

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
)
from ._plant import Plant, _call
from ._reports import CompareReport, DesignReport, MaxIntervalReport
from . import sdp

__all__ = [
    "Plant", "design", "max_interval", "compare", "simulate", "expm", "methods", "sdp",
    "DesignReport", "MaxIntervalReport", "CompareReport", "Simulation",
    "SporadicError", "PlantError", "InvalidInputError", "NumericalError", "NotCertifiedError",
    "SimulationUnavailableError", "SdpError", "DEFAULT_TIME_LIMIT",
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


def _prove(prove: bool) -> None:
    if prove:
        raise NotImplementedError(
            "prove=True: exact (interval-arithmetic) certificates are issue 24, not available yet; "
            "use prove=False (the floating-point certificate with its checks)"
        )


def design(plant: PlantLike, method: str = "ferrante2016", prove: bool = False, *,
           time_limit: Optional[float] = DEFAULT_TIME_LIMIT, **options: Any) -> DesignReport:
    """Designs an observer with ``method`` (see :func:`methods`) for ``plant`` (a
    :class:`Plant` or a plant-file path): ``sporadic design FILE --method M --json``.

    Returns a :class:`DesignReport` (``status``, ``gains``, ``certificate``, ``margin``,
    ``window``, ``to_dict()``/``to_json()``). A plant the method does not certify is a report
    with status ``not_certified``/``not_applicable`` and a ``reason``, not an exception.
    The GIL is released during the design; Ctrl-C interrupts it (``KeyboardInterrupt``).
    """
    _prove(prove)
    _no_options("design", options)
    p = _plant(plant)
    return DesignReport(_call(_native.design, p._text, p._path, method, time_limit))


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
    """A simulated observer: ``t`` (N,), ``j`` (N,) jump counters, ``jumps`` (indices where a
    sample is taken), ``error`` (k, N) the simulated signals: the method's estimation error
    (``quantity`` says which: ``x − x̂``, or that of its error coordinates; the interval width for
    rabehi2021), one row per name in ``signal_names``; the core does not return ``x`` and ``x̂``),
    ``norm`` (N,), the design ``report`` and the simulation ``summary`` dict."""

    quantity: str
    t: np.ndarray
    j: np.ndarray
    jumps: np.ndarray
    signal_names: List[str]
    error: np.ndarray
    norm: np.ndarray
    report: DesignReport
    summary: Dict[str, Any]


def simulate(plant: PlantLike, method: str = "ferrante2016", *, horizon: Optional[float] = None,
             initial_error: Optional[Sequence[float]] = None, scenario: str = "uniform", seed: int = 1,
             time_limit: Optional[float] = DEFAULT_TIME_LIMIT) -> Simulation:
    """Designs with ``method`` and simulates the certified observer (as ``sporadic design
    --simulate/--csv``): ``scenario`` is ``uniform`` (random intervals with ``seed``),
    ``periodic_t1`` or ``periodic_t2``. Raises :class:`NotCertifiedError` when the design is not
    certified, :class:`SimulationUnavailableError` when the method has no simulation."""
    import json

    p = _plant(plant)
    ie = None if initial_error is None else [float(v) for v in np.asarray(initial_error, dtype=float).reshape(-1)]
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InvalidInputError(f"seed must be a non-negative integer, got {seed!r}", "invalid_input")
    (design_json, quantity, t, j, names, signals, norm, summary) = _call(
        _native.simulate, p._text, p._path, method, horizon, ie, scenario, int(seed), time_limit
    )
    j = np.asarray(j, dtype=np.int64)
    jumps = np.nonzero(np.diff(j) > 0)[0] + 1
    return Simulation(
        quantity=quantity,
        t=np.asarray(t, dtype=float),
        j=j,
        jumps=jumps,
        signal_names=list(names),
        error=np.asarray(signals, dtype=float).reshape(len(signals), -1),
        norm=np.asarray(norm, dtype=float),
        report=DesignReport(design_json),
        summary=json.loads(summary),
    )


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
