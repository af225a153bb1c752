"""Bad input raises a clear Python exception (never a crash); from_statespace; expm; the SDP solver;
Ctrl-C."""

import _thread
import threading
import time

import numpy as np
import pytest

import sporadic
from conftest import ROOT, without_timing

W = (0.1, 0.5)


class SS:  # duck-typed state space (what python-control's StateSpace offers)
    def __init__(self, A, B, C, dt=0):
        self.A, self.B, self.C, self.D, self.dt = A, B, C, np.zeros((np.shape(C)[0], np.shape(B)[1])), dt


def test_from_statespace_duck_typed():
    sys = SS(np.array([[0.0, 1.0], [-1.0, -0.2]]), np.array([[0.0], [1.0]]), np.array([[1.0, 0.0]]))
    p = sporadic.Plant.from_statespace(sys, window=W, name="osc")
    q = sporadic.Plant(sys.A, sys.B, sys.C, window=W, name="osc")
    assert without_timing(sporadic.design(p).to_dict()) == without_timing(sporadic.design(q).to_dict())
    assert sporadic.design(p).certified
    with pytest.raises(sporadic.PlantError, match="continuous-time"):
        sporadic.Plant.from_statespace(SS(sys.A, sys.B, sys.C, dt=0.1), window=W)
    with pytest.raises(sporadic.PlantError, match="no attribute 'A'"):
        sporadic.Plant.from_statespace(object(), window=W)


def test_from_statespace_python_control():
    control = pytest.importorskip("control")
    sys = control.ss([[0.0, 1.0], [-1.0, -0.2]], [[0.0], [1.0]], [[1.0, 0.0]], [[0.0]])
    p = sporadic.Plant.from_statespace(sys, window=W)
    np.testing.assert_array_equal(p.A, np.asarray(sys.A))
    assert sporadic.design(p).certified


@pytest.mark.parametrize(
    "kwargs, field",
    [
        (dict(A=[[0, 1], [2, 3]], C=[[1, 0, 0]], window=W), "plant.C"),
        (dict(A=[[0, 1, 2], [2, 3, 4]], C=[[1, 0]], window=W), "plant.A"),
        (dict(A=[[0, 1], [2, np.nan]], C=[[1, 0]], window=W), "plant.A"),
        (dict(A=[[0, 1], [2, 3]], C=[[1, 0]], window=(0.5, 0.1)), "sampling.window"),
        (dict(A=[[0, 1], [2, 3]], C=[[1, 0]], window=(0.1, 0.2, 0.3)), "sampling.window"),
        (dict(A=[["a", 1], [2, 3]], C=[[1, 0]], window=W), "plant.A"),
        (dict(A=np.zeros((2, 2, 2)), C=[[1, 0]], window=W), "plant.A"),
        (dict(A=[[0, 1], [2, 3]], B=[[1], [0], [0]], C=[[1, 0]], window=W), "plant.B"),
        (dict(A=[[0, 1], [2, 3]], sensors=[([[1, 0]], (0.1,))]), "sensors[0].window"),
    ],
)
def test_bad_plants_raise_plant_error_with_the_field(kwargs, field):
    A = kwargs.pop("A")
    B = kwargs.pop("B", None)
    C = kwargs.pop("C", None)
    with pytest.raises(sporadic.PlantError) as e:
        sporadic.Plant(A, B, C, **kwargs)
    assert e.value.field.startswith(field), (e.value.field, str(e.value))
    assert e.value.kind == "plant_file" and str(e.value)
    # The plant file behind arrays is generated: no line of it is quoted to the caller.
    assert e.value.line == 0 and "<Plant>" not in str(e.value), str(e.value)
    assert str(e.value).startswith(e.value.field + ": "), str(e.value)
    assert isinstance(e.value, ValueError)


def test_bad_plant_files():
    with pytest.raises(sporadic.PlantError) as e:
        sporadic.Plant.from_toml(ROOT / "no-such-file.toml")
    assert e.value.field == "file"
    with pytest.raises(sporadic.PlantError) as e:
        sporadic.Plant.from_toml_string('[plant]\nA = [[1, 2], [3]]\n', path="bad.toml")
    assert e.value.line == 2 and "bad.toml:2" in str(e.value)
    with pytest.raises(sporadic.PlantError):
        sporadic.Plant.from_toml_string("this is not toml = = =")


def test_bad_arguments():
    path = ROOT / "examples" / "dc-motor-jitter.toml"
    with pytest.raises(sporadic.InvalidInputError, match="unknown method 'nobody1999'"):
        sporadic.design(path, method="nobody1999")
    with pytest.raises(sporadic.InvalidInputError, match="unknown option"):
        sporadic.design(path, speed="fast")
    with pytest.raises(sporadic.InvalidInputError, match="time_limit"):
        sporadic.design(path, time_limit=-1)
    with pytest.raises(sporadic.InvalidInputError, match="limit"):
        sporadic.max_interval(path, limit=float("inf"))
    with pytest.raises(sporadic.InvalidInputError, match="plant must be"):
        sporadic.design(42)
    with pytest.raises(sporadic.InvalidInputError, match="horizon"):
        sporadic.simulate(path, horizon=-1.0)


def test_missing_sampling_is_a_verdict_not_an_error():
    p = sporadic.Plant([[0, 1], [-1, 0]], None, [[1, 0]])
    r = sporadic.design(p)
    assert r.status == "not_applicable" and r.reason["kind"] == "missing_data"


def test_expm():
    np.testing.assert_allclose(sporadic.expm(np.diag([1.0, -2.0])), np.diag(np.exp([1.0, -2.0])), rtol=1e-14)
    t = 0.7
    R = sporadic.expm([[0.0, t], [-t, 0.0]])
    np.testing.assert_allclose(R, [[np.cos(t), np.sin(t)], [-np.sin(t), np.cos(t)]], rtol=1e-14, atol=1e-15)
    with pytest.raises(sporadic.InvalidInputError, match="square"):
        sporadic.expm(np.zeros((2, 3)))
    with pytest.raises(sporadic.SporadicError):
        sporadic.expm([[np.nan, 0.0], [0.0, 1.0]])


def test_sdp_solve_smallest_eigenvalue():
    # min <C, X> s.t. tr X = 1, X ⪰ 0  is  λ_min(C)
    C = np.array([[2.0, 1.0, 0.0], [1.0, 3.0, 0.5], [0.0, 0.5, 1.0]])
    r = sporadic.sdp.solve([C], [[np.eye(3)]], [1.0], [3])
    assert r.status == "optimal" and r.solved
    lam = np.linalg.eigvalsh(C)[0]
    assert abs(r.primal_objective - lam) < 1e-7 and abs(r.dual_objective - lam) < 1e-7
    assert r.X[0].shape == (3, 3) and r.Z[0].shape == (3, 3) and r.y.shape == (1,)
    assert r.dimacs.shape == (6,) and np.max(np.abs(r.dimacs)) < 1e-6
    # with an LP block: min x1 + 2 x2 s.t. x1 + x2 = 1, x >= 0
    r = sporadic.sdp.solve([[1.0, 2.0]], [[[1.0, 1.0]]], [1.0], [-2])
    assert r.status == "optimal" and abs(r.primal_objective - 1.0) < 1e-7
    assert r.X[0].shape == (2, 1)
    # One line with status, objectives and shapes, not y, X and Z in full.
    text = repr(r)
    assert "\n" not in text and "status='optimal'" in text and "blocks=[2x1]" in text, text


def test_sdp_bad_input():
    with pytest.raises(sporadic.InvalidInputError, match="symmetric"):
        sporadic.sdp.solve([np.array([[0.0, 1.0], [0.0, 0.0]])], [[np.eye(2)]], [1.0], [2])
    with pytest.raises(sporadic.InvalidInputError, match="constraints"):
        sporadic.sdp.solve([np.eye(2)], [[np.eye(2)], [np.eye(2)]], [1.0], [2])
    with pytest.raises(sporadic.InvalidInputError, match="blocks"):
        sporadic.sdp.solve([np.eye(2)], [[np.eye(2)]], [1.0], ["big"])
    with pytest.raises(sporadic.SdpError):
        sporadic.sdp.solve([np.eye(2)], [[np.eye(2)]], [np.inf], [2])


SDPA = """\
"a small SDP: min tr(F0 Y)-style test
2 =mdim
2 =nblocks
2 -1
1.0 2.0
0 1 1 1 -1.0
0 1 2 2 -1.0
1 1 1 1 1.0
1 2 1 1 1.0
2 1 1 2 1.0
2 2 1 1 1.0
"""


def test_solve_sdpa_equals_cli(cli, tmp_path):
    f = tmp_path / "small.dat-s"
    f.write_text(SDPA)
    r = sporadic.sdp.solve_sdpa(f)
    expected = cli("sdp", "solve", f, "--json")
    assert r.sdpa_status == expected["status"]
    assert r.sdpa_primal_objective == expected["primal_objective_sdpa"]
    assert r.sdpa_dual_objective == expected["dual_objective_sdpa"]
    assert r.iterations == expected["iterations"]
    assert list(r.dimacs) == expected["dimacs"]


def test_solve_sdpa_errors(tmp_path):
    with pytest.raises(sporadic.SdpError) as e:
        sporadic.sdp.solve_sdpa(tmp_path / "missing.dat-s")
    assert e.value.kind == "io"
    bad = tmp_path / "bad.dat-s"
    bad.write_text("2\n1\nnot a number\n")
    with pytest.raises(sporadic.SdpError) as e:
        sporadic.sdp.solve_sdpa(bad)
    assert e.value.kind == "sdpa_format"


def test_the_gil_is_released_during_a_design():
    path = ROOT / "examples" / "dc-motor-jitter.toml"
    ticks = []
    stop = threading.Event()

    def ticker():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.005)

    t = threading.Thread(target=ticker)
    t.start()
    start = time.perf_counter()
    sporadic.max_interval(path, method="ferrante2016")
    elapsed = time.perf_counter() - start
    stop.set()
    t.join()
    if elapsed > 0.2:  # a Python thread kept running during the Rust call
        assert len(ticks) > 0.3 * elapsed / 0.005


def test_ctrl_c_interrupts_a_long_call():
    path = ROOT / "examples" / "etienne2017-flexible-joint.toml"
    timer = threading.Timer(0.3, _thread.interrupt_main)
    start = time.perf_counter()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            sporadic.compare(path, limit=100.0, time_limit=None)
            sporadic.compare(path, limit=100.0, time_limit=None)  # if the first was quick
            pytest.skip("the comparison finished before the interrupt")
    finally:
        timer.cancel()
    assert time.perf_counter() - start < 5.0
    # the interrupted solves left nothing behind: the next call works
    assert sporadic.design(ROOT / "examples" / "dc-motor-jitter.toml").certified


def test_any_name_round_trips():
    name = 'a "quoted" \\ name\nwith a tab\t, DEL \x7f and 😀'
    p = sporadic.Plant([[0.0, 1.0], [-1.0, 0.0]], None, [[1.0, 0.0]], window=W, name=name)
    assert p.name == name
    assert sporadic.design(p).plant == name


def test_non_finite_and_huge_values_are_plant_errors_not_crashes():
    for bad in (np.inf, -np.inf, np.nan):
        with pytest.raises(sporadic.PlantError):
            sporadic.Plant([[0.0, 1.0], [-1.0, bad]], None, [[1.0, 0.0]], window=W)
    with pytest.raises(sporadic.PlantError):
        sporadic.Plant([[0.0, 1.0], [-1.0, 0.0]], None, [[1.0, 0.0]], window=(0.0, np.inf))
    # a huge oscillation: the method rejects the window as invalid input (CLI exit 2), typed
    with pytest.raises(sporadic.InvalidInputError, match="invalid input") as e:
        sporadic.design(sporadic.Plant([[0.0, 1e300], [-1e300, 0.0]], None, [[1.0, 0.0]], window=W))
    assert e.value.kind == "invalid_input"
