"""The examples in examples/python run (with small budgets)."""
import os
import subprocess
import sys

import pytest

import sodaevo

from conftest import ROOT

EXAMPLES = ROOT / "examples" / "python"


def run_example(name, *args, cwd):
    env = dict(os.environ)
    # The package this suite imports, wherever it came from (the build tree or an install).
    env["PYTHONPATH"] = os.path.dirname(os.path.dirname(os.path.abspath(sodaevo.__file__)))
    return subprocess.run([sys.executable, str(EXAMPLES / name), *args], cwd=cwd, env=env, capture_output=True,
                          text=True, check=True).stdout


def test_deap_loop(tmp_path):
    pytest.importorskip("deap")
    out = run_example("deap_walkers.py", "--generations", "3", "--population", "24", cwd=tmp_path)
    assert "Dainty Walker" in out and (tmp_path / "results" / "deap_champion.xml").is_file()


def test_random_search(tmp_path):
    out = run_example("random_search.py", "--batches", "2", "--batch", "40", cwd=tmp_path)
    assert "best so far" in out and (tmp_path / "results" / "random_search_best.xml").is_file()


def test_trajectory_plot(tmp_path):
    pytest.importorskip("matplotlib")
    run_example("plot_trajectory.py", "--frames", "300", "--out", "t.png", cwd=tmp_path)
    assert (tmp_path / "t.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_cmaes_improves_the_walker_and_replays_in_simulate(tmp_path):
    from conftest import cli_json
    out = run_example("cmaes_walker.py", "--generations", "4", "--frames", "800", cwd=tmp_path)
    last = out.strip().splitlines()[-2]  # "Dainty Walker: START px in 800 frames; CMA-ES best: BEST px"
    start = float(last.split("Dainty Walker: ")[1].split(" px")[0])
    best = float(last.split("CMA-ES best: ")[1].split(" px")[0])
    assert best > start
    assert not (tmp_path / "cmaes_best.xml").exists()  # not into the working folder
    replay = cli_json("simulate", tmp_path / "results" / "cmaes_best.xml", "--frames", "800", "--json")
    assert replay["centroid_dx"] == best  # bit for bit: repr round-trips a double


def test_ask_tell_ga(tmp_path, tiny_run):
    import json
    _, config = tiny_run
    path = tmp_path / "tiny.json"
    path.write_text(json.dumps(config))
    out = run_example("ask_tell_ga.py", "--config", str(path), "--out", "run", "--threads", "2", cwd=tmp_path)
    assert "generation 2/3" in out and "completed" in out and (tmp_path / "run" / "champions.json").is_file()
