"""The primal–dual interior-point SDP solver of sporadic (``sporadic-sdp``).

Problem (block-diagonal cone of PSD and nonnegative "LP" blocks)::

    minimise ⟨C, X⟩  subject to  ⟨A_i, X⟩ = b_i (i = 1..m),  X ⪰ 0,

with dual ``maximise bᵀy  s.t.  Σ y_i A_i + Z = C, Z ⪰ 0``.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Any, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _native
from ._errors import InvalidInputError
from ._plant import _call

__all__ = ["solve", "solve_sdpa", "SdpResult"]


@dataclass
class SdpResult:
    """``status`` (``optimal``, ``almost_optimal``, ``primal_infeasible``, ``dual_infeasible``,
    ``max_iterations``, ``interrupted``, ``numerical_trouble``), objectives ``⟨C, X⟩`` and
    ``bᵀy``, ``y``, ``X`` and ``Z`` (one array per block; an LP block is an ``(n, 1)`` column),
    the six DIMACS errors, iterations and seconds. For an SDPA file also ``sdpa_status`` and the
    objectives in the SDPA sign convention (comparable with SDPLIB's table)."""

    status: str
    primal_objective: float
    dual_objective: float
    y: np.ndarray
    X: List[np.ndarray]
    Z: List[np.ndarray]
    dimacs: np.ndarray
    iterations: int
    seconds: float
    sdpa_status: Optional[str] = None
    sdpa_primal_objective: Optional[float] = None
    sdpa_dual_objective: Optional[float] = None

    @property
    def solved(self) -> bool:
        return self.status in ("optimal", "almost_optimal")

    def __repr__(self) -> str:
        # The dataclass default would print y, X and Z in full.
        blocks = ", ".join("x".join(map(str, x.shape)) for x in self.X)
        return (f"SdpResult(status={self.status!r}, primal_objective={self.primal_objective!r}, "
                f"dual_objective={self.dual_objective!r}, m={len(self.y)}, blocks=[{blocks}], "
                f"dimacs_max={float(np.max(np.abs(self.dimacs))) if len(self.dimacs) else None!r}, "
                f"iterations={self.iterations})")


def _result(d) -> SdpResult:
    return SdpResult(
        status=d["status"],
        primal_objective=d["primal_objective"],
        dual_objective=d["dual_objective"],
        y=np.asarray(d["y"], dtype=float),
        X=[np.asarray(x, dtype=float).reshape(len(x), -1) for x in d["X"]],
        Z=[np.asarray(z, dtype=float).reshape(len(z), -1) for z in d["Z"]],
        dimacs=np.asarray(d["dimacs"], dtype=float),
        iterations=d["iterations"],
        seconds=d["seconds"],
        sdpa_status=d.get("sdpa_status"),
        sdpa_primal_objective=d.get("sdpa_primal_objective"),
        sdpa_dual_objective=d.get("sdpa_dual_objective"),
    )


def solve_sdpa(path: "str | os.PathLike[str]", *, time_limit: Optional[float] = None) -> SdpResult:
    """Reads an SDPA sparse file (``.dat-s``) and solves it (as ``sporadic sdp solve FILE``)."""
    return _result(_call(_native.solve_sdpa, os.fspath(path), time_limit))


BlockSpec = Union[int, Tuple[str, int]]


def _blocks(blocks: Sequence[BlockSpec]) -> List[Tuple[str, int]]:
    out = []
    for k, b in enumerate(blocks):
        if isinstance(b, (int, np.integer)) and not isinstance(b, bool):
            # SDPA convention: a positive size is a PSD block, a negative one an LP block
            out.append(("psd", int(b)) if b > 0 else ("lp", -int(b)))
        elif isinstance(b, (tuple, list)) and len(b) == 2 and b[0] in ("psd", "lp"):
            out.append((b[0], int(b[1])))
        else:
            raise InvalidInputError(
                f"blocks[{k}]: expected a size (negative: LP block) or ('psd'|'lp', size), got {b!r}", "invalid_input")
        if out[-1][1] <= 0:
            raise InvalidInputError(f"blocks[{k}]: the size must be positive", "invalid_input")
    return out


def _triplets(name: str, mats: Sequence[Any], blocks: List[Tuple[str, int]]):
    """Upper-triangle entries (block, i, j, v) of a block-diagonal matrix given per block."""
    if len(mats) != len(blocks):
        raise InvalidInputError(f"{name}: expected {len(blocks)} blocks, got {len(mats)}", "invalid_input")
    out = []
    for k, ((kind, size), m) in enumerate(zip(blocks, mats)):
        try:
            a = np.asarray(m, dtype=float)
        except (TypeError, ValueError) as e:
            raise InvalidInputError(f"{name}[{k}]: not numeric ({e})", "invalid_input") from None
        if kind == "lp":
            a = a.reshape(-1) if a.ndim <= 1 or 1 in a.shape else np.diag(a)
            if a.shape != (size,):
                raise InvalidInputError(f"{name}[{k}]: LP block of length {size}, got shape {np.shape(m)}", "invalid_input")
            out += [(k, i, i, float(v)) for i, v in enumerate(a) if v != 0.0]
        else:
            if a.shape != (size, size):
                raise InvalidInputError(f"{name}[{k}]: PSD block of order {size}, got shape {a.shape}", "invalid_input")
            if not np.array_equal(a, a.T, equal_nan=True):
                raise InvalidInputError(f"{name}[{k}]: not symmetric", "invalid_input")
            ii, jj = np.triu_indices(size)
            out += [(k, int(i), int(j), float(a[i, j])) for i, j in zip(ii, jj) if a[i, j] != 0.0]
    return out


def solve(C: Sequence[Any], A: Sequence[Sequence[Any]], b: Sequence[float], blocks: Sequence[BlockSpec], *,
          time_limit: Optional[float] = None) -> SdpResult:
    """Solves ``min ⟨C, X⟩ s.t. ⟨A_i, X⟩ = b_i, X ⪰ 0``.

    ``blocks``: one entry per cone block, a size (SDPA convention: negative for an LP block) or
    ``("psd", n)`` / ``("lp", n)``. ``C``: one symmetric matrix per block (an LP block: a vector).
    ``A``: one list of per-block matrices per constraint. ``b``: one value per constraint.
    The GIL is released during the solve; Ctrl-C stops it (``KeyboardInterrupt``).
    """
    bl = _blocks(blocks)
    try:
        bv = [float(v) for v in np.asarray(b, dtype=float).reshape(-1)]
    except (TypeError, ValueError) as e:
        raise InvalidInputError(f"b: not numeric ({e})", "invalid_input") from None
    if len(A) != len(bv):
        raise InvalidInputError(f"A: expected {len(bv)} constraints (one per entry of b), got {len(A)}", "invalid_input")
    c = _triplets("C", C, bl)
    a = []
    for i, Ai in enumerate(A):
        a += [(i, k, r, s, v) for (k, r, s, v) in _triplets(f"A[{i}]", Ai, bl)]
    return _result(_call(_native.solve, bl, bv, c, a, time_limit))
