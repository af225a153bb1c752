"""Shared fixtures: the example plant files and the `sporadic` command-line program.

The CLI binary is `target/release/sporadic` of the repository (or $SPORADIC_CLI). Without it the
tests that compare with the CLI are skipped, unless SPORADIC_REQUIRE_CLI=1 (CI), then they fail.
"""

import json
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = sorted((ROOT / "examples").glob("*.toml"))
METHODS = ["ferrante2016", "sferlazza2021", "andrieu2014", "etienne2017", "rabehi2021"]


def _cli_path():
    p = os.environ.get("SPORADIC_CLI") or str(ROOT / "target" / "release" / "sporadic")
    return p if os.path.isfile(p) and os.access(p, os.X_OK) else None


@pytest.fixture(scope="session")
def cli():
    """Runs the CLI with arguments and returns its stdout parsed as JSON."""
    path = _cli_path()
    if path is None:
        msg = "the sporadic CLI is not built (cargo build --release --bin sporadic)"
        if os.environ.get("SPORADIC_REQUIRE_CLI") == "1":
            pytest.fail(msg)
        pytest.skip(msg)

    def run(*args, raw=False):
        out = subprocess.run([path, *map(str, args)], capture_output=True, text=True, check=False)
        if out.returncode not in (0, 1):
            raise AssertionError(f"sporadic {' '.join(map(str, args))}: exit {out.returncode}: {out.stderr}")
        return out.stdout if raw else json.loads(out.stdout)

    return run


def without_timing(x):
    """A report with every wall-time field (`seconds`) removed, recursively."""
    if isinstance(x, dict):
        return {k: without_timing(v) for k, v in x.items() if k != "seconds"}
    if isinstance(x, list):
        return [without_timing(v) for v in x]
    return x
