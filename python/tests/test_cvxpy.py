"""The CVXPY solver interface (sporadic.cvxpy), against CVXPY's bundled Clarabel; skipped
without cvxpy."""

import numpy as np
import pytest

cp = pytest.importorskip("cvxpy")
import sporadic.cvxpy  # noqa: E402  (registers SPORADIC)

REF = "CLARABEL" if "CLARABEL" in cp.installed_solvers() else None


def _both(problem, variables):
    v1 = problem.solve(solver="SPORADIC")
    s1 = problem.status
    vals1 = [np.asarray(v.value) for v in variables]
    duals1 = [np.asarray(c.dual_value) for c in problem.constraints]
    if REF is None:
        return v1, s1, None
    v2 = problem.solve(solver=REF)
    return (v1, s1, vals1, duals1), (v2, problem.status,
                                    [np.asarray(v.value) for v in variables],
                                    [np.asarray(c.dual_value) for c in problem.constraints])


def test_registered_by_name_and_as_an_instance():
    assert "SPORADIC" in cp.installed_solvers()
    x = cp.Variable(3)
    p = cp.Problem(cp.Minimize(np.array([1.0, 2.0, 3.0]) @ x), [x >= 0, cp.sum(x) == 1])
    assert p.solve(solver=sporadic.cvxpy.SPORADIC()) == pytest.approx(1.0, abs=1e-7)
    assert p.status == "optimal" and p.solver_stats.solver_name == "SPORADIC"
    np.testing.assert_allclose(x.value, [1.0, 0.0, 0.0], atol=1e-7)
    # the equality's multiplier: d(optimal value)/d(rhs) = 1, CVXPY's sign convention: −1
    assert p.constraints[1].dual_value == pytest.approx(-1.0, abs=1e-7)


def test_largest_eigenvalue_sdp():
    rng = np.random.default_rng(0)
    M = rng.standard_normal((5, 5))
    M = M + M.T
    lam = cp.Variable()
    p = cp.Problem(cp.Minimize(lam), [lam * np.eye(5) - M >> 0])
    assert p.solve(solver="SPORADIC") == pytest.approx(np.linalg.eigvalsh(M).max(), abs=1e-7)
    Z = p.constraints[0].dual_value
    assert np.trace(Z) == pytest.approx(1.0, abs=1e-7)  # the dual: a density matrix


@pytest.mark.skipif(REF is None, reason="no reference solver (Clarabel) in this cvxpy")
def test_sdp_with_equalities_and_inequalities_matches_clarabel():
    rng = np.random.default_rng(1)
    n = 4
    C = rng.standard_normal((n, n))
    C = C @ C.T
    A = rng.standard_normal((n, n))
    A = A + A.T
    X = cp.Variable((n, n), symmetric=True)
    p = cp.Problem(cp.Minimize(cp.trace(C @ X)), [X >> 0, cp.trace(A @ X) == 1, X[0, 0] >= 0.1, cp.trace(X) <= 10])
    (v1, s1, x1, d1), (v2, s2, x2, d2) = _both(p, [X])
    assert s1 == s2 == "optimal"
    assert v1 == pytest.approx(v2, rel=1e-6, abs=1e-7)
    for a, b in zip(d1, d2):
        np.testing.assert_allclose(a, b, rtol=1e-3, atol=1e-4)  # multipliers: to the solvers' accuracy
    np.testing.assert_allclose(x1[0], x2[0], rtol=1e-3, atol=1e-4)


def test_infeasible_and_unbounded():
    x = cp.Variable(2)
    p = cp.Problem(cp.Minimize(cp.sum(x)), [x >= 1, cp.sum(x) <= 1])
    p.solve(solver="SPORADIC")
    assert p.status == "infeasible"
    q = cp.Problem(cp.Minimize(cp.sum(x)), [x <= 1])
    q.solve(solver="SPORADIC")
    assert q.status == "unbounded"


def test_options_and_unsupported_cones():
    x = cp.Variable(2)
    p = cp.Problem(cp.Minimize(cp.sum(x)), [x >= 1])
    assert p.solve(solver="SPORADIC", time_limit=10.0) == pytest.approx(2.0, abs=1e-7)
    with pytest.raises(ValueError, match="unknown solver option"):
        p.solve(solver="SPORADIC", tolerance=3)
    # CVXPY turns a second-order cone into a PSD one for this solver
    q = cp.Problem(cp.Minimize(cp.norm(x, 2)), [x >= 1])
    assert q.solve(solver="SPORADIC") == pytest.approx(np.sqrt(2.0), abs=1e-6)
    # an exponential cone is not supported
    e = cp.Problem(cp.Maximize(cp.sum(cp.log(x))), [cp.sum(x) <= 1])
    with pytest.raises(cp.error.SolverError):
        e.solve(solver="SPORADIC")
