"""A parsed Config is reused by evaluate and the operators with the same results
as a path or dict, and seed paths resolve against the config's own folder."""
import json
import os

import numpy as np

import sodaevo
from conftest import DAINTY, ROOT


def test_config_gives_the_same_results_as_the_file(tiny_run):
    run_dir, _ = tiny_run
    path = run_dir / "config.json"
    config = sodaevo.Config(path)
    models = [i["model"] for i in sodaevo.open_run(run_dir).generation(0)]
    assert sodaevo.evaluate(models, config).fitness.tobytes() == sodaevo.evaluate(models, path).fitness.tobytes()
    m = models[0]
    assert sodaevo.mutate(m, 11, config) == sodaevo.mutate(m, 11, path)
    assert sodaevo.crossover(models[0], models[1], 12, config) == sodaevo.crossover(models[0], models[1], 12, path)
    assert sodaevo.random_creature(13, config) == sodaevo.random_creature(13, path)


def test_seed_paths_resolve_against_the_configs_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # not the project's folder
    config = sodaevo.Config(ROOT / "configs" / "quick.json")
    assert config.dict["population"]["seed_models"] == [str(DAINTY.resolve())]
    text = json.loads((ROOT / "configs" / "quick.json").read_text())
    by_base = sodaevo.Config(text, base=ROOT / "configs")
    assert by_base.dict == config.dict
    seeds = [sodaevo.creature(sodaevo.Model.load(DAINTY), config)]
    e = sodaevo.evaluate(seeds, config)
    assert np.isfinite(e.fitness[0])


def test_a_bad_config_is_an_input_error_once():
    try:
        sodaevo.Config({"fitness": {"frames": 0}})
    except sodaevo.InputError as e:
        assert e.pointer == "/fitness/frames"
    else:
        raise AssertionError("no error")
