"""A CVXPY solver interface to sporadic's SDP solver (``sporadic-sdp``).

>>> import cvxpy as cp, sporadic.cvxpy                            # doctest: +SKIP
>>> problem.solve(solver="SPORADIC")                               # doctest: +SKIP
>>> problem.solve(solver=sporadic.cvxpy.SPORADIC())                # the same, as a solver instance

Importing this module registers the solver under the name ``SPORADIC`` (cvxpy must be installed:
``pip install cvxpy``; it is not a dependency of sporadic). Cones: zero (equalities), nonnegative
and PSD, i.e. LPs and SDPs; ``solver_opts``: ``time_limit`` (seconds). The GIL is released during
the solve and Ctrl-C stops it (``KeyboardInterrupt``).

How: CVXPY's cone program ``min cᵀx + d s.t. Ax + b ∈ K`` is the *dual* form of the solver,
``max b_sᵀy s.t. Z = C_s − Σ y_i A_i ⪰ 0`` with ``y = x``, ``b_s = −c``, ``C_s`` the offset ``b``
and ``A_i = −A[:, i]``, each arranged in one LP block (the nonnegative rows, and each equality row
split into two opposite inequalities) and one PSD block per PSD cone (the symmetric part of the
column-major ``n×n`` slack). The primal ``X`` of the solver is the vector of multipliers CVXPY
reports as the constraints' dual values (an equality's is the difference of its two halves).
"""

from __future__ import annotations

from typing import Any, Dict, List, Tuple

import numpy as np

import cvxpy.settings as s
import scipy.sparse as sp
from cvxpy.constraints import PSD, NonNeg, Zero
from cvxpy.reductions.solution import Solution, failure_solution
from cvxpy.reductions.solvers import defines as _defines
from cvxpy.reductions.solvers import utilities
from cvxpy.reductions.solvers.conic_solvers.conic_solver import ConicSolver

from . import _native
from ._plant import _call

__all__ = ["SPORADIC", "register"]

NAME = "SPORADIC"

_STATUS = {
    "optimal": s.OPTIMAL,
    "almost_optimal": s.OPTIMAL_INACCURATE,
    # the solver's primal is CVXPY's dual and vice versa
    "primal_infeasible": s.UNBOUNDED,
    "dual_infeasible": s.INFEASIBLE,
    "max_iterations": s.SOLVER_ERROR,
    "numerical_trouble": s.SOLVER_ERROR,
    "interrupted": s.SOLVER_ERROR,
}


class SPORADIC(ConicSolver):
    """CVXPY conic solver class calling :func:`sporadic.sdp.solve`'s interior-point method."""

    MIP_CAPABLE = False
    SUPPORTED_CONSTRAINTS = ConicSolver.SUPPORTED_CONSTRAINTS + [PSD]

    def name(self) -> str:
        return NAME

    def import_solver(self) -> None:
        from . import _native  # noqa: F401

    def accepts(self, problem) -> bool:
        if not problem.objective.args[0].is_affine():
            return False
        for constr in problem.constraints:
            if type(constr) not in self.SUPPORTED_CONSTRAINTS:
                return False
            if not all(arg.is_affine() for arg in constr.args):
                return False
        return True

    def apply(self, problem):
        data: Dict[str, Any] = {}
        inv: Dict[str, Any] = {self.VAR_ID: problem.x.id}
        if not problem.formatted:
            problem = self.format_constraints(problem, None)
        data[s.PARAM_PROB] = problem
        data[self.DIMS] = problem.cone_dims
        inv[self.DIMS] = problem.cone_dims
        constr_map = problem.constr_map
        inv[self.EQ_CONSTR] = constr_map[Zero]
        inv[self.NEQ_CONSTR] = constr_map[NonNeg] + constr_map[PSD]
        c, d, A, b = problem.apply_parameters()
        data[s.C] = np.asarray(c, dtype=float).reshape(-1)
        inv[s.OFFSET] = d
        data[s.A] = sp.csc_matrix(A)
        data[s.B] = np.asarray(b, dtype=float).reshape(-1, order="F")
        return data, inv

    def invert(self, solution, inverse_data):
        status = solution["status"]
        if status in s.SOLUTION_PRESENT:
            opt_val = solution["value"] + inverse_data[s.OFFSET]
            primal_vars = {inverse_data[self.VAR_ID]: solution["primal"]}
            eq_dual = utilities.get_dual_values(
                solution["eq_dual"], utilities.extract_dual_value, inverse_data[self.EQ_CONSTR])
            leq_dual = utilities.get_dual_values(
                solution["ineq_dual"], utilities.extract_dual_value, inverse_data[self.NEQ_CONSTR])
            eq_dual.update(leq_dual)
            return Solution(status, opt_val, primal_vars, eq_dual, solution.get("attr", {}))
        return failure_solution(status, solution.get("attr", {}))

    def solve_via_data(self, data, warm_start: bool, verbose: bool, solver_opts, solver_cache=None):
        c, A, b, dims = data[s.C], data[s.A], data[s.B], data[self.DIMS]
        blocks, bvec, ctrip, atrip, psd = _sdp_data(c, A, b, dims.zero, dims.nonneg, list(dims.psd))
        opts = dict(solver_opts or {})
        time_limit = opts.pop("time_limit", None)
        if opts:
            raise ValueError(f"SPORADIC: unknown solver option(s) {', '.join(sorted(opts))} (supported: time_limit)")
        r = _call(_native.solve, blocks, bvec, ctrip, atrip, time_limit)
        status = _STATUS.get(r["status"], s.SOLVER_ERROR)
        out: Dict[str, Any] = {
            s.STATUS: status,
            "attr": {s.SOLVE_TIME: r["seconds"], s.NUM_ITERS: r["iterations"],
                     s.EXTRA_STATS: {"status": r["status"], "dimacs": r["dimacs"]}},
        }
        if status in s.SOLUTION_PRESENT:
            x = np.asarray(r["y"], dtype=float)
            f, l = dims.zero, dims.nonneg
            lp = np.asarray(r["X"][0], dtype=float).reshape(-1) if f + l else np.zeros(0)
            eq = lp[:f] - lp[f:2 * f]
            ineq = [lp[2 * f:2 * f + l]]
            for k, n in enumerate(psd):
                X = np.asarray(r["X"][k + (1 if f + l else 0)], dtype=float).reshape(n, n)
                ineq.append(X.reshape(-1, order="F"))
            out[s.VALUE] = float(c @ x)
            out[s.PRIMAL] = x
            out[s.EQ_DUAL] = eq
            out[s.INEQ_DUAL] = np.concatenate(ineq) if ineq else np.zeros(0)
        return out

    def cite(self, data):
        return "sporadic-sdp: the primal-dual interior-point SDP solver of the sporadic workbench"


def _sdp_data(c: np.ndarray, A: sp.spmatrix, b: np.ndarray, f: int, l: int, psd: List[int]):
    """The solver's data (blocks, b, C triplets, A triplets) of ``min cᵀx s.t. Ax + b ∈ K``."""
    m = len(c)
    blocks: List[Tuple[str, int]] = []
    if f + l:
        blocks.append(("lp", 2 * f + l))
    blocks += [("psd", int(n)) for n in psd]
    # row r of (A, b) -> list of (block, i, j, weight) places in the solver's block matrices
    rows, blk, ii, jj, w = [], [], [], [], []
    for r in range(f):
        rows += [r, r]
        blk += [0, 0]
        ii += [r, f + r]
        jj += [r, f + r]
        w += [1.0, -1.0]
    for r in range(f, f + l):
        rows.append(r)
        blk.append(0)
        ii.append(f + r)
        jj.append(f + r)
        w.append(1.0)
    off = f + l
    first_psd = 1 if f + l else 0
    for k, n in enumerate(psd):
        p = np.arange(n * n)
        i, j = p % n, p // n  # column-major
        rows += list(off + p)
        blk += [first_psd + k] * (n * n)
        ii += list(np.minimum(i, j))
        jj += list(np.maximum(i, j))
        w += list(np.where(i == j, 1.0, 0.5))  # the symmetric part
        off += n * n
    if off != A.shape[0]:
        raise ValueError(f"SPORADIC: cone dimensions ({off}) do not match the constraint rows ({A.shape[0]})")
    rows_a = np.asarray(rows, dtype=np.int64)
    blk_a, ii_a, jj_a, w_a = (np.asarray(v) for v in (blk, ii, jj, w))
    # place ids: one per (block, i, j)
    keys = np.stack([blk_a, ii_a, jj_a], axis=1) if len(rows) else np.zeros((0, 3), dtype=np.int64)
    uniq, place = np.unique(keys, axis=0, return_inverse=True)
    place = np.asarray(place).reshape(-1)
    # P: places x rows, the weights; C_s = P b, A_i = −P A[:, i]
    P = sp.csr_matrix((w_a, (place, rows_a)), shape=(len(uniq), A.shape[0]))
    cvals = P @ b
    ctrip = [(int(uniq[q, 0]), int(uniq[q, 1]), int(uniq[q, 2]), float(v)) for q, v in enumerate(cvals) if v != 0.0]
    PA = (-(P @ sp.csc_matrix(A))).tocoo()
    PA.sum_duplicates()
    atrip = [(int(col), int(uniq[q, 0]), int(uniq[q, 1]), int(uniq[q, 2]), float(v))
             for q, col, v in zip(PA.row, PA.col, PA.data) if v != 0.0]
    bvec = [float(v) for v in -np.asarray(c, dtype=float)]
    assert len(bvec) == m
    return blocks, bvec, ctrip, atrip, list(psd)


def register() -> None:
    """Registers ``SPORADIC`` with CVXPY so that ``problem.solve(solver="SPORADIC")`` finds it
    (done on import; idempotent)."""
    inst = SPORADIC()
    _defines.SOLVER_MAP_CONIC[NAME] = inst
    for lst in ("CONIC_SOLVERS", "INSTALLED_SOLVERS", "INSTALLED_CONIC_SOLVERS"):
        v = getattr(_defines, lst, None)
        if isinstance(v, list) and NAME not in v:
            v.append(NAME)


register()
