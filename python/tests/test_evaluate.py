"""evaluate() against an `evolve` run's logged fitness, on any thread count, and
evolve() against `sodaevo evolve`."""
import numpy as np

import sodaevo
from conftest import run_cli


def generation_zero(run_dir):
    return sodaevo.open_run(run_dir).generation(0)


def test_evaluate_gives_the_logged_fitness(tiny_run):
    run_dir, _ = tiny_run
    individuals = generation_zero(run_dir)
    assert len(individuals) == 12
    e = sodaevo.evaluate([i["model"] for i in individuals], run_dir / "config.json", threads=2)
    logged = np.array([i["fitness"] for i in individuals])
    assert np.array_equal(e.fitness, logged)  # bit for bit, -inf for the invalid alike
    ok = [k for k, i in enumerate(individuals) if i["status"] == "ok"]
    assert len(ok) >= 6
    for k in ok:
        assert e.status[k] == "ok" and e.n[k] == individuals[k]["n"] == 3
        assert (e.mean[k], e.sd[k], e.median[k], e.distance[k]) == (
            individuals[k]["mean"], individuals[k]["sd"], individuals[k]["median"], individuals[k]["distance"])
        assert e.interval95[k, 0] <= e.mean[k] <= e.interval95[k, 1]


def test_resampled_and_confirmed_creatures_too(tiny_run):
    # The last generation holds elites that gathered more replicas and the best,
    # confirmed on replicas_max: each is its first n replicas, which evaluate()
    # gives with replicas=n.
    run_dir, _ = tiny_run
    last = sodaevo.open_run(run_dir).generation(2)
    counts = sorted({i["n"] for i in last if i["status"] == "ok"})
    assert len(counts) > 1  # some did gather more than 3
    for n in counts:
        group = [i for i in last if i["status"] == "ok" and i["n"] == n]
        e = sodaevo.evaluate([i["model"] for i in group], run_dir / "config.json", replicas=n)
        assert list(e.fitness) == [i["fitness"] for i in group] and list(e.sd) == [i["sd"] for i in group]


def test_threads_and_batches_do_not_change_results(tiny_run):
    run_dir, _ = tiny_run
    models = [i["model"] for i in generation_zero(run_dir)]
    config = run_dir / "config.json"
    one = sodaevo.evaluate(models, config, threads=1)
    for threads, batch in ((2, 0), (2, 1), (3, 5)):
        other = sodaevo.evaluate(models, config, threads=threads, batch=batch)
        assert np.array_equal(one.fitness, other.fitness) and np.array_equal(one.sd, other.sd, equal_nan=True)


def test_python_evolve_is_the_command_lines(tiny_run, tmp_path):
    run_dir, config = tiny_run
    folder = sodaevo.evolve(config, tmp_path / "py", threads=1)
    for name in ("generations.csv", "champions.json", "best/gen_00002.xml", "generations/gen_00002.xml"):
        assert (folder / name).read_bytes() == (run_dir / name).read_bytes(), name
    run = sodaevo.open_run(folder)
    assert list(run.generations["generation"]) == [0, 1, 2] and run.saved == [0, 1, 2]
    assert run.best(1)[0]["fitness"] == run.generations["best"][-1] or run.config["fitness"]["confirm"] > 0


def test_variation_operators_are_the_gas():
    dainty = sodaevo.creature(sodaevo.Model.load(sodaevo_path("dainty_walker.xml")))
    child = sodaevo.mutate(dainty, 11)
    assert child != dainty and child == sodaevo.mutate(dainty, 11)  # drawn from the seed alone
    cross = sodaevo.crossover(dainty, sodaevo.random_creature(3), 5)
    assert cross.mass_count >= 3 and not cross.fixed.any()
    assert sodaevo.evaluate([child, cross], {"frames": 200, "settle_frames": 10}, replicas=1).status == ["ok", "ok"]


def sodaevo_path(name):
    from conftest import MODELS
    return MODELS / name
