"""The ask/tell Optimiser drives the project's own GA and MAP-Elites loops: a loop
of ask(), evaluate(request), tell() makes the run folder `sodaevo evolve` makes,
byte for byte."""
import json

import pytest

import sodaevo
from conftest import DAINTY, run_cli

# What differs between two runs of the same config by design: wall times
# (timing.csv, a checkpoint's wall_seconds), the command line each records
# (manifest.json), and the report pages only the command writes.
UNCOMPARED = ("manifest.json", "timing.csv")


def assert_same_folder(mine, theirs):
    names = sorted(p.relative_to(theirs) for p in theirs.rglob("*")
                   if p.is_file() and p.name not in UNCOMPARED and p.suffix != ".html")
    assert names == sorted(p.relative_to(mine) for p in mine.rglob("*")
                           if p.is_file() and p.name not in UNCOMPARED and p.suffix != ".html")
    assert len(names) > 5
    for name in names:
        a, b = (mine / name).read_bytes(), (theirs / name).read_bytes()
        if name.name in ("checkpoint.json", "archive_checkpoint.json"):
            a, b = json.loads(a), json.loads(b)
            assert a.pop("wall_seconds") > 0 and b.pop("wall_seconds") > 0
        assert a == b, name


def drive(optimiser, threads=2):
    requests = 0
    while (request := optimiser.ask()) is not None:
        requests += 1
        optimiser.tell(sodaevo.evaluate(request, threads=threads))
    return requests


def test_ask_tell_ga_is_the_command_lines_run(tiny_run, tmp_path):
    _, tiny = tiny_run
    # Generations saved and checkpointed now and then, not every one: what a
    # pause per generation must not add to.
    config = dict(tiny, generations=4, save={"generation_every": 3, "checkpoint_every": 2})
    path = tmp_path / "ga.json"
    path.write_text(json.dumps(config))
    run_cli("evolve", path, "--out", tmp_path / "cli", "--quiet", "--threads", "2")
    progress = []
    opt = sodaevo.Optimiser(sodaevo.Config(path), tmp_path / "asktell", threads=2, callback=progress.append)
    assert drive(opt) >= 4
    assert_same_folder(opt.dir, tmp_path / "cli")
    assert [p["generation"] for p in progress] == [0, 1, 2, 3]
    assert opt.done and opt.result["stopped_because"] == "completed"
    assert opt.result["best_fitness"] == sodaevo.open_run(opt.dir).generations["best"][-1]


def test_ask_tell_map_elites_is_the_command_lines_run(tmp_path):
    config = {
        "name": "tiny-me", "seed": 3, "algorithm": "map-elites",
        "population": {"size": 12, "seed_models": [str(DAINTY)], "random_fraction": 0.8},
        "fitness": {"frames": 300, "settle_frames": 30, "replicas": 2, "replicas_max": 4},
        "map_elites": {"descriptors": ["width", "mass_count"], "bins": [4, 4], "ranges": [[40, 300], [2.5, 14.5]],
                       "iterations": 5, "batch_size": 8, "snapshot_every": 2, "check_replicas": 4},
        "save": {"checkpoint_every": 2},
    }
    path = tmp_path / "me.json"
    path.write_text(json.dumps(config))
    run_cli("evolve", path, "--out", tmp_path / "cli", "--quiet", "--threads", "2")
    opt = sodaevo.Optimiser(path, tmp_path / "asktell")
    drive(opt)
    assert_same_folder(opt.dir, tmp_path / "cli")


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


def test_an_abandoned_optimiser_stops_its_loop_and_the_command_resumes_it(tiny_run, tmp_path):
    # The loop runs on a thread of its own and waits for answers: dropping the
    # Optimiser mid-run must end that thread (no hang at exit), leaving the folder
    # as after its last checkpoint, which `sodaevo evolve --resume` finishes to the
    # uninterrupted command's run.
    import gc
    import time
    _, tiny = tiny_run
    config = dict(tiny, generations=4)
    path = tmp_path / "ga.json"
    path.write_text(json.dumps(config))
    run_cli("evolve", path, "--out", tmp_path / "cli", "--quiet", "--threads", "2")
    opt = sodaevo.Optimiser(path, tmp_path / "asktell", threads=2)
    for _ in range(3):  # generation 0, then generation 1's children, then its confirmation
        opt.tell(sodaevo.evaluate(opt.ask(), threads=2))
    assert opt.ask() is not None  # a request left unanswered
    folder = opt.dir
    start = time.perf_counter()
    del opt
    gc.collect()
    assert time.perf_counter() - start < 5
    run_cli("evolve", "--resume", folder, "--quiet", "--threads", "2")
    assert_same_folder(folder, tmp_path / "cli")
