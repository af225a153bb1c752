"""Exceptions of the sporadic package: every error of the Rust core arrives as one of these,
with the typed reason in ``kind`` (and ``details`` for plant-file errors)."""

from __future__ import annotations

from typing import Any, Dict


class SporadicError(Exception):
    """Base class. ``kind`` is the typed reason of the Rust core (e.g. ``plant_file``,
    ``invalid_input``, ``numerical``, ``sdpa_format``); ``details`` a dict of extra fields."""

    def __init__(self, message: str, kind: str = "error", details: Dict[str, Any] | None = None):
        super().__init__(message)
        self.message = message
        self.kind = kind
        self.details = dict(details or {})


class PlantError(SporadicError, ValueError):
    """An invalid plant: ``field`` (e.g. ``plant.A``, ``sensors[1].window``), ``line`` (in a
    plant file, 0 when not applicable), ``path`` and ``reason``."""

    @property
    def field(self) -> str:
        return self.details.get("field", "")

    @property
    def line(self) -> int:
        return self.details.get("line", 0)

    @property
    def path(self) -> str:
        return self.details.get("path", "")

    @property
    def reason(self) -> str:
        return self.details.get("reason", self.message)


class InvalidInputError(SporadicError, ValueError):
    """Invalid arguments (unknown method, bad option, data a method rejects)."""


class NumericalError(SporadicError, ArithmeticError):
    """A numerical failure of the core outside a verdict (e.g. ``expm`` overflow)."""


class NotCertifiedError(SporadicError):
    """``simulate`` on a plant the method does not certify; ``report`` is the design report."""

    @property
    def report(self):
        from ._reports import DesignReport

        raw = self.details.get("report")
        return DesignReport(raw) if raw else None


class SimulationUnavailableError(SporadicError):
    """The method has no simulation for this plant."""


class VerificationUnavailableError(SporadicError):
    """The method has no check of given gains (``verify``; andrieu2014)."""


class SdpError(SporadicError, ValueError):
    """An SDP problem or SDPA file the solver cannot use (``kind``: ``sdpa_format``, ``io``,
    ``dimension_mismatch``, ``non_finite``, ``structure``, ...)."""


_BY_KIND = {
    "plant_file": PlantError,
    "invalid_input": InvalidInputError,
    "unknown_method": InvalidInputError,
    "numerical": NumericalError,
    "not_certified": NotCertifiedError,
    "simulation_unavailable": SimulationUnavailableError,
    "verification_unavailable": VerificationUnavailableError,
    # sporadic-sdp's SdpError variants
    "non_finite": SdpError,
    "structure": SdpError,
    "sdpa_format": SdpError,
    "io": SdpError,
    "dimension_mismatch": SdpError,
    "invalid_settings": SdpError,
    # sporadic-linalg's LinalgError variants
    "input": InvalidInputError,
    "invalid_argument": InvalidInputError,
    "singular": NumericalError,
    "no_convergence": NumericalError,
    "overflow": NumericalError,
}


def translate(err: BaseException) -> SporadicError:
    """The package exception for a ``_native.NativeError(kind, message, details)``."""
    kind, message, details = err.args
    return _BY_KIND.get(kind, SporadicError)(message, kind, details)
