"""Every argument out of range raises InputError naming it and its range (never
pybind11's "incompatible function arguments" or a cast error); numpy scalars are
accepted wherever a number is; simulate's frames are capped and a trace's size is
checked before anything is allocated."""
import numpy as np
import pytest

import sodaevo
from conftest import DAINTY


@pytest.fixture(scope="module")
def m():
    return sodaevo.Model.load(DAINTY)


@pytest.mark.parametrize("call, name", [
    (lambda m: sodaevo.evaluate([m], {"frames": 10}, seed=-1), "seed"),
    (lambda m: sodaevo.evaluate([m], {"frames": 10}, seed=2**60), "seed"),
    (lambda m: sodaevo.evaluate([m], {"frames": 10}, batch=-1), "batch"),
    (lambda m: sodaevo.evaluate([m], {"frames": 10}, threads=100000), "threads"),
    (lambda m: sodaevo.evaluate([m], {"frames": 10}, threads=-1), "threads"),
    (lambda m: sodaevo.evaluate([m], {"frames": 10}, replicas=0), "replicas"),
    (lambda m: sodaevo.mutate(m, -1), "rng_seed"),
    (lambda m: sodaevo.mutate(m, 2**64), "rng_seed"),
    (lambda m: sodaevo.mutate(m, 1.5), "rng_seed"),
    (lambda m: sodaevo.crossover(m, m, -3), "rng_seed"),
    (lambda m: sodaevo.random_creature(2**70), "rng_seed"),
    (lambda m: sodaevo.simulate(m, 2**40), "frames"),
    (lambda m: sodaevo.simulate(m, -1), "frames"),
    (lambda m: sodaevo.simulate(m, 10, replicas=-2), "replicas"),
    (lambda m: sodaevo.simulate(m, 10, replicas=4, jitter=2.0), "jitter"),
    (lambda m: sodaevo.race(DAINTY.parent / "terrains" / "TerrainFlat.xml", [m], threads=5000), "threads"),
    (lambda m: sodaevo.evolve({"generations": 1}, "never", threads=2000), "threads"),
])
def test_out_of_range_names_the_argument(m, call, name):
    with pytest.raises(sodaevo.InputError) as e:
        call(m)
    assert str(e.value).startswith(name + ": expected"), str(e.value)
    assert "[" in str(e.value) and "got" in str(e.value)


def test_numpy_scalars_are_numbers(m):
    assert sodaevo.mutate(m, np.uint64(5)) == sodaevo.mutate(m, 5)
    assert sodaevo.mutate(m, np.int32(5), {"mutation": {"rest_length": {"rate": np.float64(0.5), "sigma": np.float32(0.25)}}}) == \
        sodaevo.mutate(m, 5, {"mutation": {"rest_length": {"rate": 0.5, "sigma": 0.25}}})
    a = sodaevo.simulate(m, np.int64(50), replicas=np.int16(3), jitter=np.float32(0.25))
    b = sodaevo.simulate(m, 50, replicas=3, jitter=float(np.float32(0.25)))
    assert a["mean"] == b["mean"]
    e = sodaevo.evaluate([m], {"frames": np.int64(100), "settle_frames": np.int64(10)}, threads=np.int64(1),
                         seed=np.uint8(3), replicas=np.int64(2))
    f = sodaevo.evaluate([m], {"frames": 100, "settle_frames": 10}, threads=1, seed=3, replicas=2)
    assert e.fitness.tobytes() == f.fitness.tobytes()


def test_a_trace_too_large_is_refused_before_allocation(m):
    with pytest.raises(sodaevo.InputError) as e:
        sodaevo.simulate(m, 10**9, trace=True)
    assert str(e.value).startswith("trace:") and "MiB" in str(e.value)


def test_a_runs_own_config_evaluates(tiny_run):
    run_dir, _ = tiny_run
    run = sodaevo.open_run(run_dir)
    models = [i["model"] for i in run.generation(0)]
    by_dict = sodaevo.evaluate(models, run.config, threads=2)
    by_file = sodaevo.evaluate(models, run_dir / "config.json", threads=2)
    assert by_dict.fitness.tobytes() == by_file.fitness.tobytes()
