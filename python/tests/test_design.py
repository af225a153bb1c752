"""design / max_interval / compare / simulate against the CLI on the example plants."""

import json
import math
import os

import numpy as np
import pytest

import sporadic
from conftest import EXAMPLES, METHODS, ROOT, without_timing

IDS = [p.stem for p in EXAMPLES]


def test_import_and_methods():
    assert sporadic.methods() == METHODS


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("path", EXAMPLES, ids=IDS)
def test_design_equals_cli_json(cli, path, method):
    report = sporadic.design(path, method=method)
    expected = cli("design", path, "--method", method, "--json")
    assert without_timing(report.to_dict()) == without_timing(expected)
    # the JSON text is the serialiser's: byte-equal once the timings agree
    got = report.to_dict()
    expected["seconds"] = got["seconds"]
    assert report.status in ("certified", "not_certified", "not_applicable")
    # gains bitwise: the floats of the JSON round-trip exactly
    for g in expected["gains"]:
        np.testing.assert_array_equal(report.gains[g["name"]], np.asarray(g["rows"], dtype=float))
    if report.status == "certified":
        assert report.gains and report.margin is not None
    else:
        assert report.reason["kind"]


def test_report_attributes_on_a_certified_design():
    r = sporadic.design(ROOT / "examples" / "dc-motor-jitter.toml", method="ferrante2016")
    assert r.status == "certified" and r.certified
    assert r.window == (0.005, 0.04)
    assert r.method == "ferrante2016"
    assert isinstance(r.margin, float) and r.margin > 0
    for name, g in r.gains.items():
        assert isinstance(g, np.ndarray) and g.dtype == np.float64 and g.ndim == 2, name
    P = r.certificate["P"]
    assert P.shape == (3, 3) and np.array_equal(P, P.T)
    assert json.loads(r.to_json()) == r.to_dict()
    assert "certified" in repr(r)
    # A report reads like a dict of its JSON: its keys iterate, `in` tests them.
    assert list(r) == list(r.to_dict()) and "margin" in r and "no such key" not in r


def test_numpy_plant_equals_the_plant_file():
    path = ROOT / "examples" / "dc-motor-jitter.toml"
    f = sporadic.Plant.from_toml(path)
    p = sporadic.Plant(f.A, f.B, f.C, window=f.window, bounds=f.bounds, name=f.name)
    np.testing.assert_array_equal(p.A, f.A)
    for m in METHODS:
        a, b = sporadic.design(p, method=m), sporadic.design(path, method=m)
        assert without_timing(a.to_dict()) == without_timing(b.to_dict()), m


def test_round_robin_numpy_plant_equals_the_plant_file():
    path = ROOT / "examples" / "two-tank-round-robin.toml"
    f = sporadic.Plant.from_toml(path)
    assert len(f.sensors) == 2
    p = sporadic.Plant(f.A, None, f.C, window=f.window, sensors=f.sensors, name=f.name)
    for m in ("ferrante2016", "sferlazza2021"):
        a, b = sporadic.design(p, method=m), sporadic.design(path, method=m)
        assert without_timing(a.to_dict()) == without_timing(b.to_dict()), m


def test_plant_from_toml_string_and_to_toml():
    path = ROOT / "examples" / "dc-motor-jitter.toml"
    text = path.read_text()
    p = sporadic.Plant.from_toml_string(text)
    assert p.to_toml() == text and p.n == 3
    q = sporadic.Plant(p.A, p.B, p.C, window=p.window)
    r = sporadic.Plant.from_toml_string(q.to_toml())
    np.testing.assert_array_equal(r.A, p.A)
    np.testing.assert_array_equal(r.C, p.C)


def test_max_interval_equals_cli_json(cli):
    path = ROOT / "examples" / "dc-motor-jitter.toml"
    r = sporadic.max_interval(path, method="ferrante2016")
    expected = cli("max-interval", path, "--method", "ferrante2016", "--json")
    assert without_timing(r.to_dict()) == without_timing(expected)
    assert r.status == "certified" and r.largest_certified_t2 >= 0.04
    assert r.design is not None and r.design.certified


def test_max_interval_with_a_limit_equals_cli_json(cli):
    path = ROOT / "examples" / "ferrante2016-example2.toml"
    r = sporadic.max_interval(path, method="sferlazza2021", limit=1.0)
    expected = cli("max-interval", path, "--method", "sferlazza2021", "--limit", "1.0", "--json")
    assert without_timing(r.to_dict()) == without_timing(expected)


def test_max_interval_names_the_reason_of_its_first_failure():
    # An undamped oscillator (omega = 1): every window below the aliasing interval pi is
    # certified, and the first failure above it is the loss of detectability at v = pi.
    path = ROOT / "tests" / "corpus" / "oscillator-w1-below-aliasing.toml"
    r = sporadic.max_interval(path, method="ferrante2016")
    assert math.pi <= r.first_failing_t2 <= math.pi * 1.005
    reason = r.first_failure_reason
    assert reason is not None and reason["kind"] == "undetectable", reason
    assert abs(reason["tau"] - math.pi) <= 1e-9 * math.pi, reason


def test_compare_without_search_equals_cli_json(cli, tmp_path):
    path = ROOT / "examples" / "two-tank-round-robin.toml"
    r = sporadic.compare(path, search=False)
    expected = cli("compare", path, "--no-search", "--out", tmp_path, "--json")
    assert without_timing(r.to_dict()) == without_timing(expected)
    assert set(r.designs) == set(METHODS)
    # Iterating a comparison gives its keys (it used to fail with `KeyError: 0`).
    assert "results" in list(r) and "results" in r


def test_compare_with_search_equals_cli_json(cli, tmp_path):
    path = ROOT / "examples" / "dc-motor-jitter.toml"
    r = sporadic.compare(path)
    expected = cli("compare", path, "--out", tmp_path, "--json")
    assert without_timing(r.to_dict()) == without_timing(expected)
    searched = {m: w for m, w in r.largest_windows.items() if w is not None}
    assert searched


def test_simulate_equals_the_cli_time_series(cli, tmp_path):
    path = ROOT / "examples" / "dc-motor-jitter.toml"
    sim = sporadic.simulate(path, method="ferrante2016", horizon=0.5, seed=3)
    csv = tmp_path / "run.csv"
    expected = cli("design", path, "--method", "ferrante2016", "--horizon", "0.5", "--seed", "3",
                   "--csv", csv, "--json")
    assert without_timing(sim.report.to_dict()) == without_timing(expected)
    assert sim.summary == expected["simulation"]
    data = np.genfromtxt(csv, delimiter=",", names=True)
    np.testing.assert_array_equal(sim.t, data["t"])
    np.testing.assert_array_equal(sim.j, data["j"].astype(int))
    np.testing.assert_allclose(sim.norm, data["norm"], rtol=1e-12, atol=0)
    n = len(sim.t)
    assert sim.error.shape == (3, n) and sim.norm.shape == (n,)
    assert len(sim.jumps) == sim.j[-1] and np.all(sim.j[sim.jumps] == sim.j[sim.jumps - 1] + 1)
    assert sim.norm[-1] < sim.norm[0]
    # A one-line repr with the figures that identify the run, not every array in full.
    text = repr(sim)
    assert "\n" not in text and len(text) < 300, text
    assert f"samples={len(sim.jumps)}" in text and "ferrante2016" in text, text


def test_simulate_periodic_scenarios_and_not_certified():
    path = ROOT / "examples" / "dc-motor-jitter.toml"
    s1 = sporadic.simulate(path, "ferrante2016", scenario="periodic_t2", horizon=0.2)
    assert np.allclose(np.diff(s1.t[s1.jumps]), 0.04)
    with pytest.raises(sporadic.InvalidInputError, match="scenario"):
        sporadic.simulate(path, "ferrante2016", scenario="sometimes")
    # a window far beyond what any method certifies
    p = sporadic.Plant([[0, 1], [2, 0]], None, [[1, 0]], window=(1.0, 50.0))
    with pytest.raises(sporadic.NotCertifiedError) as e:
        sporadic.simulate(p, "ferrante2016")
    assert e.value.report.status != "certified"


def test_prove_is_implemented():
    # was test_prove_is_not_implemented_yet (NotImplementedError before issue 24's provers)
    r = sporadic.design(ROOT / "examples" / "dc-motor-jitter.toml", prove=True)
    assert r.proof is not None and r.proof.status == "proved" and r.proved


def test_the_example_script_runs(tmp_path):
    import subprocess
    import sys

    script = ROOT / "python" / "examples" / "design_observer.py"
    out = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True, text=True,
                         timeout=600, env={**os.environ, "MPLBACKEND": "Agg"})
    assert out.returncode == 0, out.stderr
    assert "ferrante2016   certified" in out.stdout and "samples;" in out.stdout
    assert "proof: proved" in out.stdout and "verify L: certified, proof proved" in out.stdout
