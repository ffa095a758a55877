"""Shared fixtures: where the project and the command line are, and a runner
for the command line (the tests compare the module with it bit for bit)."""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(os.environ.get("SODAEVO_ROOT", Path(__file__).resolve().parents[2]))
MODELS = ROOT / "models"
DAINTY = MODELS / "dainty_walker.xml"

# Importable from the build tree when run by hand (PYTHONPATH=build/python), unless
# the suite is to test an installed package (SODAEVO_TEST_INSTALLED=1: a pip install).
INSTALLED = os.environ.get("SODAEVO_TEST_INSTALLED") == "1"
if "PYTHONPATH" not in os.environ and not INSTALLED:
    sys.path.insert(0, str(ROOT / "build" / "python"))

if "SODAEVO_BINARY" in os.environ:
    BINARY = Path(os.environ["SODAEVO_BINARY"])
elif INSTALLED:
    from sodaevo._command import program
    BINARY = program()  # the command pip installed with the package
else:
    BINARY = ROOT / "build" / "sodaevo"


def run_cli(*args: str, check: bool = True) -> subprocess.CompletedProcess:
    return subprocess.run([str(BINARY), *map(str, args)], capture_output=True, text=True, check=check)


def cli_json(*args: str):
    return json.loads(run_cli(*args).stdout)


@pytest.fixture(scope="session")
def tiny_run(tmp_path_factory):
    """A tiny GA run made by the command line: its folder and its config."""
    folder = tmp_path_factory.mktemp("runs")
    config = {
        "name": "tiny", "seed": 7, "generations": 3,
        "population": {"size": 12, "seed_models": [str(DAINTY)], "random_fraction": 0.5},
        "selection": {"tournament_size": 3, "elites": 2},
        "fitness": {"frames": 400, "settle_frames": 50, "replicas": 3, "replicas_max": 6, "confirm": 2},
        "save": {"generation_every": 1, "checkpoint_every": 1},
    }
    path = folder / "tiny.json"
    path.write_text(json.dumps(config))
    run_cli("evolve", path, "--out", folder / "cli", "--quiet", "--threads", "2")
    return folder / "cli", config
