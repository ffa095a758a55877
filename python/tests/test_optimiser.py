"""The ask/tell Optimiser drives the project's own GA and MAP-Elites loops: a loop
of ask(), evaluate(request), tell() makes the run folder `sodaevo evolve` makes,
byte for byte."""
import json

import pytest

import sodaevo
from conftest import DAINTY, run_cli

GA_FILES = ("generations.csv", "champions.json", "best/gen_00000.xml", "best/gen_00002.xml",
            "generations/gen_00000.xml", "generations/gen_00002.xml")


def drive(optimiser, threads=2):
    requests = 0
    while (request := optimiser.ask()) is not None:
        requests += 1
        optimiser.tell(sodaevo.evaluate(request, threads=threads))
    return requests


def test_ask_tell_ga_is_the_command_lines_run(tiny_run, tmp_path):
    run_dir, config = tiny_run
    progress = []
    opt = sodaevo.Optimiser(sodaevo.Config(config), tmp_path / "asktell", threads=2, callback=progress.append)
    assert drive(opt) >= 3
    for name in GA_FILES:
        assert (opt.dir / name).read_bytes() == (run_dir / name).read_bytes(), name
    assert [p["generation"] for p in progress] == [0, 1, 2]
    assert opt.done and opt.result["stopped_because"] == "completed"
    assert opt.result["best_fitness"] == sodaevo.open_run(opt.dir).generations["best"][-1]


def test_ask_tell_map_elites_is_the_command_lines_run(tmp_path):
    config = {
        "name": "tiny-me", "seed": 3, "algorithm": "map-elites",
        "population": {"size": 12, "seed_models": [str(DAINTY)], "random_fraction": 0.8},
        "fitness": {"frames": 300, "settle_frames": 30, "replicas": 2, "replicas_max": 4},
        "map_elites": {"descriptors": ["width", "mass_count"], "bins": [4, 4], "ranges": [[40, 300], [2.5, 14.5]],
                       "iterations": 3, "batch_size": 8, "snapshot_every": 1, "check_replicas": 4},
        "save": {"checkpoint_every": 1},
    }
    path = tmp_path / "me.json"
    path.write_text(json.dumps(config))
    run_cli("evolve", path, "--out", tmp_path / "cli", "--quiet", "--threads", "2")
    opt = sodaevo.Optimiser(path, tmp_path / "asktell")
    drive(opt)
    cli = tmp_path / "cli"
    # Every file but the wall times (timing.csv, a checkpoint's wall_seconds) and
    # the command line each records.
    names = sorted(p.relative_to(cli) for p in cli.rglob("*") if p.is_file() and p.suffix in (".json", ".csv", ".xml")
                   and p.name not in ("manifest.json", "config.json", "timing.csv"))
    assert len(names) > 3
    for name in names:
        mine, theirs = (opt.dir / name).read_bytes(), (cli / name).read_bytes()
        if name.name == "archive_checkpoint.json":
            mine, theirs = json.loads(mine), json.loads(theirs)
            assert mine.pop("wall_seconds") > 0 and theirs.pop("wall_seconds") > 0
        assert mine == theirs, name


def test_tell_refuses_what_does_not_answer_the_request(tiny_run, tmp_path):
    _, config = tiny_run
    opt = sodaevo.Optimiser(config, tmp_path / "asktell")
    first = sodaevo.evaluate(opt.ask(), threads=1)
    opt.tell(first)
    with pytest.raises(sodaevo.InputError, match="nothing was asked"):
        opt.tell(first)
    request = opt.ask()
    with pytest.raises(sodaevo.InputError, match="evaluate\\(request\\)'s result"):
        opt.tell(sodaevo.evaluate(request.models, config["fitness"]))
    with pytest.raises(sodaevo.InputError, match="an optimiser's request is evaluated as its run asks"):
        sodaevo.evaluate(request, replicas=2)
    assert opt.ask().id == request.id  # asked again before a tell: the same request
    with pytest.raises(sodaevo.InputError, match="answer request 1, the pending request is 2"):
        opt.tell(first)
