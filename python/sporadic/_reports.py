"""Report objects over the JSON of the Rust serialiser (the same text as the CLI's ``--json``)."""

from __future__ import annotations

import json
from typing import Any, Dict, Iterator, List, Optional, Tuple

import numpy as np


def _window(w) -> Optional[Tuple[float, float]]:
    return None if w is None else (float(w[0]), float(w[1]))


class _Report:
    """A report: attribute access over the CLI's JSON; ``to_dict()``/``to_json()`` give it back."""

    def __init__(self, raw: str):
        self._raw = raw
        self._d: Dict[str, Any] = json.loads(raw)

    def to_json(self) -> str:
        """The report as JSON, byte for byte what ``sporadic ... --json`` prints (no newline)."""
        return self._raw

    def to_dict(self) -> Dict[str, Any]:
        """The report as a dict (a fresh copy of ``json.loads(to_json())``)."""
        return json.loads(self._raw)

    @property
    def status(self) -> str:
        """``certified``, ``not_certified`` or ``not_applicable``."""
        return self._d["status"]

    @property
    def reason(self) -> Optional[Dict[str, Any]]:
        """Why not certified / not applicable: a dict with ``kind`` and ``message``, or None."""
        return self._d.get("reason")

    @property
    def certified(self) -> bool:
        return self.status == "certified"

    @property
    def plant(self) -> str:
        return self._d["plant"]

    @property
    def seconds(self) -> float:
        return self._d["seconds"]

    def __getitem__(self, key: str) -> Any:
        return self._d[key]

    def __iter__(self) -> Iterator[str]:
        """The report's top-level JSON keys, as a dict's (without it Python would iterate by
        calling ``report[0]``, ``report[1]``, … and fail with ``KeyError: 0``)."""
        return iter(self._d)

    def __contains__(self, key: object) -> bool:
        return key in self._d

    def __eq__(self, other: object) -> bool:
        return type(other) is type(self) and other._d == self._d  # type: ignore[attr-defined]

    __hash__ = None  # type: ignore[assignment]


class DesignReport(_Report):
    """The report of one design (schema ``sporadic.design/1``)."""

    @property
    def method(self) -> str:
        return self._d["method"]

    @property
    def citation(self) -> str:
        return self._d["citation"]

    @property
    def window(self) -> Optional[Tuple[float, float]]:
        """The certified sampling window ``(T1, T2)`` (None for round-robin or no design)."""
        return _window(self._d.get("window"))

    @property
    def windows(self) -> Optional[List[Tuple[float, float]]]:
        """Per-sensor windows of a round-robin design."""
        ws = self._d.get("windows")
        return None if ws is None else [_window(w) for w in ws]

    @property
    def observer(self) -> str:
        return self._d["observer"]

    @property
    def gains(self) -> Dict[str, np.ndarray]:
        """Gain name → matrix (float64 arrays)."""
        return {g["name"]: _matrix(g["rows"]) for g in self._d["gains"]}

    @property
    def gain_schedules(self) -> Dict[str, Dict[str, Any]]:
        """Gain name → schedule (``law``, ``tau`` array, ``samples`` 3-D array) for scheduled gains."""
        out = {}
        for g in self._d["gains"]:
            s = g.get("schedule")
            if s:
                out[g["name"]] = {
                    "law": s["law"],
                    "tau": np.asarray(s["tau"], dtype=float),
                    "samples": np.asarray(s["samples"], dtype=float),
                }
        return out

    @property
    def certificate(self) -> Dict[str, np.ndarray]:
        """Certificate name → matrix (e.g. the Lyapunov matrix)."""
        return {c["name"]: _matrix(c["rows"]) for c in self._d["certificate"]}

    @property
    def margin(self) -> Optional[float]:
        m = self._d.get("margin")
        return None if m is None else m["value"]

    @property
    def margin_definition(self) -> Optional[str]:
        m = self._d.get("margin")
        return None if m is None else m["definition"]

    @property
    def checks(self) -> List[Dict[str, Any]]:
        return self._d["checks"]

    @property
    def notes(self) -> List[str]:
        return self._d["notes"]

    @property
    def simulation(self) -> Optional[Dict[str, Any]]:
        return self._d.get("simulation")

    @property
    def proof(self) -> Optional["Proof"]:
        """The rigorous proof section (``design(..., prove=True)``, ``verify``), or None."""
        p = self._d.get("proof")
        return None if p is None else Proof(p)

    @property
    def proved(self) -> bool:
        """Certified and proved (the CLI's exit status 0 with ``--prove``)."""
        p = self.proof
        return self.certified and p is not None and p.status == "proved"

    def __repr__(self) -> str:
        return f"DesignReport(method={self.method!r}, status={self.status!r}, window={self.window!r}, margin={self.margin!r})"


class MaxIntervalReport(_Report):
    """The largest certified ``T2`` of one method (schema ``sporadic.max-interval/1``)."""

    @property
    def method(self) -> str:
        return self._d["method"]

    @property
    def t1(self) -> Optional[float]:
        return self._d.get("t1")

    @property
    def limit(self) -> Optional[float]:
        return self._d.get("limit")

    @property
    def largest_certified_t2(self) -> Optional[float]:
        return self._d.get("largest_certified_t2")

    @property
    def first_failing_t2(self) -> Optional[float]:
        return self._d.get("first_failing_t2")

    @property
    def search_end(self):
        return self._d.get("search_end")

    @property
    def monotone(self) -> bool:
        return self._d["monotone"]

    @property
    def probes(self) -> List[Dict[str, Any]]:
        return self._d["probes"]

    @property
    def first_failure_reason(self) -> Optional[Dict[str, Any]]:
        """Why the first failing ``T2`` was refused: the ``reason`` (``kind``, ``message``) of the
        probe at :attr:`first_failing_t2`, or None when there is none. A method's boundary (e.g.
        ``undetectable`` at an aliasing interval) and a margin that double precision cannot verify
        call for different actions; the CLI prints it as its ``failure`` line."""
        f = self.first_failing_t2
        if f is None:
            return None
        for p in reversed(self.probes):
            if not p["certified"] and p["t2"] == f:
                return p.get("reason")
        return None

    @property
    def design(self) -> Optional[DesignReport]:
        """The design at the largest certified window."""
        d = self._d.get("design")
        return None if d is None else DesignReport(json.dumps(d))

    def __repr__(self) -> str:
        return f"MaxIntervalReport(method={self.method!r}, status={self.status!r}, largest_certified_t2={self.largest_certified_t2!r})"


class CompareReport(_Report):
    """Every method on one plant (schema ``sporadic.compare/1``)."""

    @property
    def status(self) -> str:  # a comparison has no single status
        raise AttributeError("a CompareReport has no status; see .results")

    @property
    def results(self) -> List[Dict[str, Any]]:
        return self._d["results"]

    @property
    def designs(self) -> Dict[str, DesignReport]:
        """Method id → its design report at the file's own sampling."""
        return {e["method"]: DesignReport(json.dumps(e["design"])) for e in self._d["results"]}

    @property
    def largest_windows(self) -> Dict[str, Optional[MaxIntervalReport]]:
        """Method id → its window search (None when not searched)."""
        return {
            e["method"]: None if e.get("largest_window") is None else MaxIntervalReport(json.dumps(e["largest_window"]))
            for e in self._d["results"]
        }

    def __repr__(self) -> str:
        st = ", ".join(f"{e['method']}: {e['design']['status']}" for e in self._d["results"])
        return f"CompareReport({st})"


class Proof:
    """The ``proof`` section of a design report: whether the design's condition holds for
    **every** sampling interval of the window, proven in outward-rounded interval arithmetic
    (schema in the Rust ``sporadic_model::Proof``).

    ``status`` is ``proved``, ``not_proved`` or ``inconclusive``; ``margin_lower_bound`` a
    rigorous lower bound of the margin (``proved`` only); ``failed_on`` the piece
    ``{condition, tau, enclosure}`` where it failed or stopped; ``message`` the result in words.
    """

    def __init__(self, d: Dict[str, Any]):
        self._d = d

    @property
    def status(self) -> str:
        """``proved``, ``not_proved`` or ``inconclusive``."""
        return self._d["status"]

    @property
    def proved(self) -> bool:
        return self.status == "proved"

    @property
    def condition(self) -> str:
        return self._d["condition"]

    @property
    def how(self) -> str:
        return self._d["how"]

    @property
    def subintervals(self) -> int:
        return self._d["subintervals"]

    @property
    def margin_lower_bound(self) -> Optional[float]:
        return self._d.get("margin_lower_bound")

    @property
    def margin_definition(self) -> str:
        return self._d["margin_definition"]

    @property
    def failed_on(self) -> Optional[Dict[str, Any]]:
        return self._d.get("failed_on")

    @property
    def enclosure_width(self) -> Optional[float]:
        return self._d.get("enclosure_width")

    @property
    def message(self) -> str:
        return self._d["message"]

    @property
    def seconds(self) -> float:
        return self._d["seconds"]

    def __getitem__(self, key: str) -> Any:
        return self._d[key]

    def to_dict(self) -> Dict[str, Any]:
        """The section as a dict (a copy)."""
        return json.loads(json.dumps(self._d))

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Proof) and other._d == self._d

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        return f"Proof(status={self.status!r}, margin_lower_bound={self.margin_lower_bound!r}, subintervals={self.subintervals!r})"


def _matrix(rows) -> np.ndarray:
    a = np.asarray(rows, dtype=float)
    if a.ndim != 2:
        a = a.reshape(len(rows), -1)
    return a
