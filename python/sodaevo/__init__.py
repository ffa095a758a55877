"""sodaevo from Python: the exact SodaConstructor engine, its batches and replicas,
and the run store, speaking numpy.

The numbers are the command line's, bit for bit: every function here calls the
library code the ``sodaevo`` command calls (see docs/python.md).

- ``Model.load(path)``, ``Model.from_xml(text)``, ``model.to_xml()``; ``model.nodes``,
  ``model.masses``, ``model.links`` (numpy) and ``model.world`` (a dict).
- ``simulate(model, frames, trace=..., replicas=...)``: one run, as ``sodaevo simulate``.
- ``evaluate(models, problem, replicas=K, threads=N)``: creatures scored as ``evolve``
  scores a generation (batches on N threads, the GIL released).
- ``race(race_file, contenders)``: as ``sodaevo race --json``.
- ``evolve(config, out)``, ``open_run(path)``: a whole run, and reading one back.
- ``mutate``, ``crossover``, ``random_creature``, ``creature``: the GA's own operators.
- ``Config(path_or_dict)``: a config parsed once, for evaluate, the operators and Optimiser.
- ``Optimiser(config, out)``: the GA or MAP-Elites as ask/tell (``ask()``, ``evaluate``, ``tell``).
- ``Model.from_arrays``, ``to_arrays``; ``to_vector``, ``from_vector``, ``vector_bounds``:
  creatures as numpy data and one body plan as a vector for CMA-ES and friends.
- ``InputError``: bad input, with file, line, column or JSON pointer.

Long calls (simulate, evaluate, race, evolve) stop on Ctrl-C with KeyboardInterrupt.
"""
from __future__ import annotations

import csv
import json
import os
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Union

import numpy as np

from ._errors import InputError
from . import _sodaevo
from ._sodaevo import Config, Model, Request, from_vector, to_vector, vector_bounds, vector_names

__version__: str = _sodaevo.__version__

__all__ = [
    "InputError", "Model", "Config", "Request", "Evaluations", "Run", "Optimiser", "simulate", "evaluate", "race",
    "evolve", "open_run", "mutate", "crossover", "random_creature", "creature", "to_arrays", "to_vector",
    "from_vector", "vector_bounds", "vector_names", "__version__",
]

PathLike = Union[str, "os.PathLike[str]"]
#: A run config: a Config, a dict (the JSON object), a path to a config file, or None (defaults).
ConfigLike = Union[None, Config, Mapping[str, Any], PathLike]


def simulate(model: Model, frames: int = 1000, *, trace: bool = False, replicas: int = 0, mode: str = "soda",
             integrator: str = "euler", substeps: int = 1, bar_engine: str = "2003", energy_check: bool = False,
             reference: bool = False, jitter: float = 0.002, settle: int = 0) -> Dict[str, Any]:
    """Runs `model` for `frames` frames as ``sodaevo simulate`` does; the same bits.

    Returns the summary as a dict with the keys of ``simulate --json``: frames,
    masses, links, centroid_dx, centroid_dy, px_per_frame, wall_seconds,
    frames_per_second, stepping, fixed_bars, bar_engine, diverged (and
    diverged_frame, diverged_reason). A run that blows up stops at its last healthy
    frame, as the command's does.

    trace=True adds ``trace``, a ``(frames + 1, masses, 4)`` float64 array of x, y,
    vx, vy of every free mass from frame 0 (as loaded) on (the numbers of
    ``simulate --trace``), and ``wave_phase``, ``wave_mode`` per frame.

    replicas=K runs K replicas instead (``simulate --replicas K``): replica 0 exact,
    replica r with sine jitter `jitter` of seed r, measured over `frames` after
    `settle` frames; returns n, mean, median, sd, min, max, interval95,
    non_finite, distances (array) and horizon.

    mode "continuous" steps the same model as an ODE with `integrator` (euler,
    verlet, rk4, backward-euler, implicit-midpoint) and `substeps` per frame.
    The GIL is released while the engine runs.
    """
    return _sodaevo.simulate(model, frames, trace=trace, replicas=replicas, mode=mode, integrator=integrator,
                             substeps=substeps, bar_engine=bar_engine, energy_check=energy_check,
                             reference=reference, jitter=jitter, settle=settle)


@dataclass
class Evaluations:
    """Per-creature results of `evaluate`, arrays in the order of the models.

    fitness: the estimator's statistic (-inf for an invalid or diverged creature);
    distance: replica 0's score (the exact run; px for a walk, frames for a race);
    n, mean, sd, median: the replicas' count and scores; interval95: (len, 2), the
    95 % prediction interval of one more run; status: "ok", "invalid" or
    "diverged"; reason: why not ok. NaN where a creature has no score.
    """

    fitness: np.ndarray
    distance: np.ndarray
    px_per_frame: np.ndarray
    n: np.ndarray
    mean: np.ndarray
    sd: np.ndarray
    median: np.ndarray
    interval95: np.ndarray
    status: List[str]
    reason: List[str]
    #: Every evaluation in the wire format, exactly (what Optimiser.tell reads).
    wire: bytes = field(default=b"", repr=False)
    #: The optimiser's request these answer, or None.
    request: Optional[int] = field(default=None, repr=False)

    def __len__(self) -> int:
        return len(self.fitness)


def evaluate(models: Union[Sequence[Model], Request], problem: ConfigLike = None, *, replicas: Optional[int] = None,
             seed: Optional[int] = None, threads: int = 0, batch: int = 0) -> Evaluations:
    """Evaluates `models` as ``sodaevo evolve`` evaluates a generation.

    `problem` is the config's ``/fitness`` object as a dict (``{"frames": 4000,
    "settle_frames": 400}``, ``{"kind": "race", "race": {...}}``), or a whole run
    config (a dict with a "fitness" key, or a config file's path) whose world and
    limits then apply too; None: the defaults. `replicas` overrides
    /fitness/replicas and `seed` the run seed the replicas' sine jitter is drawn
    from. Each creature is prepared by the run's Problem (scaling, placement,
    limits: a creature outside them is "invalid"), run on its replicas by a
    ReplicaEstimator, in batches of creatures stepped together on `threads`
    threads (0: all cores). Neither `threads` nor `batch` changes a result. The GIL
    is released throughout, so other Python threads run meanwhile; Ctrl-C stops
    it (KeyboardInterrupt). A sodaevo.Config is used as it is, read once.

    `models` may be an Optimiser's Request (``opt.ask()``): it is then evaluated
    with the problem and estimator its run asks for (give no problem, replicas
    or seed), and the result is what ``opt.tell`` takes.
    """
    if not isinstance(models, Request):
        models = list(models)
    r = _sodaevo.evaluate(models, problem, replicas=replicas, seed=seed, threads=threads, batch=batch)
    return Evaluations(**r)


def race(race_file: PathLike, contenders: Sequence[Union[PathLike, Model]] = (), *, replicas: int = 0,
         jitter: float = 0.002, timeout: Optional[int] = None, threads: int = 0) -> Dict[str, Any]:
    """Races `contenders` on a Sodarace race file's terrain, as ``sodaevo race --json``.

    Contenders are model files, race files (their contenders) or Models; none: the
    race file's own. Returns the command's JSON: {"race", "timeout", "bar_engine",
    "contenders": [{"file", "name", "frames", "finished", "place", ("replicas"),
    ("no_result")}]}. replicas=K (>= 2) also races K sine-jitter replicas of each.
    """
    return _sodaevo.race(race_file, list(contenders), replicas=replicas, jitter=jitter, timeout=timeout,
                         threads=threads)


def evolve(config: Union[Config, Mapping[str, Any], PathLike], out: Optional[PathLike] = None, *, threads: int = 0,
           force: bool = False, callback: Optional[Callable[[Dict[str, Any]], Any]] = None) -> Path:
    """Runs a whole GA run (``sodaevo evolve CONFIG --out OUT``) and returns its folder.

    `config` is a config file's path or the config as a dict (seed model paths
    relative to the working directory). `out` defaults to
    results/<name>-<timestamp>, as the command's. The folder is the command's
    (config.json, generations.csv, best/, generations/, checkpoints,
    champions.json) without report.html (``sodaevo report RUN`` writes it).
    Ctrl-C finishes the current generation, saves it and raises
    KeyboardInterrupt; ``sodaevo evolve --resume RUN`` continues it.
    `callback(progress)` is called after every generation with a dict
    (generation, generations, evaluations, best, mean, median, worst, invalid,
    diverged); an exception it raises stops the run the same way and is raised.
    """
    cfg = _config_arg(config)
    out = _default_out(cfg) if out is None else out
    shown = cfg.source if isinstance(cfg, Config) else "<dict>" if isinstance(cfg, dict) else cfg
    line = f"sodaevo.evolve({shown!r}, out={os.fspath(out)!r})"
    return Path(_sodaevo.evolve(cfg, os.fspath(out), threads=threads, force=force, command_line=line,
                                callback=callback))


def _default_out(config: Any) -> str:
    """results/<name>-<timestamp>, as the command's."""
    if isinstance(config, Config):
        name = config.name
    elif isinstance(config, dict):
        name = config.get("name", "run")
    else:
        with open(config, encoding="utf-8") as f:
            name = json.load(f).get("name", "run")
    return os.path.join("results", f"{name}-{time.strftime('%Y%m%d-%H%M%S')}")


class Optimiser:
    """The project's GA (or MAP-Elites, by the config's /algorithm) as ask/tell.

    ::

        opt = sodaevo.Optimiser("configs/quick.json", "results/quick-asktell")
        while (request := opt.ask()) is not None:
            opt.tell(sodaevo.evaluate(request, threads=2))
        opt.result        # {"run", "finished", "stopped_because", "best_id", "best_fitness"}

    Driven so, the run folder is ``sodaevo evolve``'s, byte for byte
    (generations.csv, best/, generations/, champions.json): the run's own loop
    runs, only its evaluations are handed out. ``ask()`` returns a Request (its
    ``models``, a list of Models) or None once the run is over; evaluate the
    Request itself, not its models, so that its run's problem and estimator
    are used. ``callback(progress)`` is called for each generation finished.
    ``open_run(opt.dir)`` reads the run back.
    """

    def __init__(self, config: Union[Config, Mapping[str, Any], PathLike], out: Optional[PathLike] = None, *,
                 threads: int = 0, force: bool = False,
                 callback: Optional[Callable[[Dict[str, Any]], Any]] = None) -> None:
        cfg = _config_arg(config)
        out = _default_out(cfg) if out is None else out
        self._callback = callback
        self._impl = _sodaevo.Optimiser(cfg, os.fspath(out), force=force, threads=threads,
                                        command_line=f"sodaevo.Optimiser(out={os.fspath(out)!r})")

    def ask(self) -> Optional[Request]:
        """The next creatures to evaluate, or None when the run is over."""
        request = self._impl.ask()
        for progress in self._impl.take_progress():
            if self._callback is not None:
                self._callback(progress)
        return request

    def tell(self, evaluations: "Evaluations") -> None:
        """Hands back ``evaluate(request)``'s result for the last request."""
        if not isinstance(evaluations, Evaluations) or evaluations.request is None:
            raise InputError("tell: expected evaluate(request)'s result for the Request ask() returned")
        self._impl.tell(evaluations.request, evaluations.wire)

    @property
    def done(self) -> bool:
        return self._impl.done

    @property
    def dir(self) -> Path:
        """The run folder."""
        return Path(self._impl.dir)

    @property
    def result(self) -> Dict[str, Any]:
        """The run folder, whether it is over and why, and its best (GA) or filled cells (MAP-Elites)."""
        return self._impl.result


@dataclass
class Run:
    """A run folder read back (`open_run`).

    config: the resolved config (dict; seed-model paths made absolute, so that
    evaluate() and Config take it as it is); manifest: manifest.json; generations: the
    rows of generations.csv as a numpy structured array (generation, evaluations,
    best, mean, median, worst, invalid, diverged, best_id, best_replicas, best_sd,
    best_interval95_lo, best_interval95_hi); champions: champions.json (the best
    creatures checked on fresh replicas) or None; saved: the generation numbers
    saved whole.
    """

    path: Path
    config: Dict[str, Any]
    manifest: Dict[str, Any]
    generations: np.ndarray
    champions: Optional[Any]
    saved: List[int] = field(default_factory=list)

    def generation(self, index: int) -> List[Dict[str, Any]]:
        """A saved generation's individuals: id, parents, model (a Model), status,
        reason, fitness, distance, n, mean, sd, median."""
        return _sodaevo.read_generation(os.fspath(self.path), index)

    def best(self, count: int = 1) -> List[Dict[str, Any]]:
        """The `count` best distinct creatures of the last saved generation, best first."""
        return _sodaevo.best_individuals(os.fspath(self.path), count)

    def best_model(self, generation: int) -> Model:
        """best/gen_NNNNN.xml: a generation's best creature as it was evaluated."""
        return Model.load(os.fspath(self.path / "best" / f"gen_{generation:05d}.xml"))


_GENERATION_COLUMNS = [("generation", "i8"), ("evaluations", "i8"), ("best", "f8"), ("mean", "f8"),
                       ("median", "f8"), ("worst", "f8"), ("invalid", "i8"), ("diverged", "i8"),
                       ("best_id", "U32"), ("best_replicas", "i8"), ("best_sd", "f8"),
                       ("best_interval95_lo", "f8"), ("best_interval95_hi", "f8")]


def _read_generations_csv(path: Path) -> np.ndarray:
    rows = []
    with open(path, newline="", encoding="utf-8") as f:
        for row in csv.DictReader(f):
            cells = []
            for name, kind in _GENERATION_COLUMNS:
                text = row.get(name, "")
                if kind == "U32":
                    cells.append(text)
                elif text == "":
                    cells.append(np.nan if kind == "f8" else 0)
                else:
                    cells.append(float(text) if kind == "f8" else int(text))
            rows.append(tuple(cells))
    return np.array(rows, dtype=_GENERATION_COLUMNS)


def open_run(path: PathLike) -> Run:
    """Reads a run folder written by `evolve` or ``sodaevo evolve``."""
    p = Path(path)
    if not (p / "config.json").is_file():
        raise InputError(f"{p}: not a run folder (no config.json)")
    with open(p / "config.json", encoding="utf-8") as f:
        config = json.load(f)
    # A run keeps copies of its seed models, named relative to its folder: made
    # absolute, so that the dict is a config wherever it is used.
    seeds = config.get("population", {}).get("seed_models")
    if isinstance(seeds, list):
        config["population"]["seed_models"] = [s if os.path.isabs(s) else str((p / s).resolve()) for s in seeds]
    manifest: Dict[str, Any] = {}
    if (p / "manifest.json").is_file():
        with open(p / "manifest.json", encoding="utf-8") as f:
            manifest = json.load(f)
    champions = None
    if (p / "champions.json").is_file():
        with open(p / "champions.json", encoding="utf-8") as f:
            champions = json.load(f)
    generations = _read_generations_csv(p / "generations.csv") if (p / "generations.csv").is_file() \
        else np.array([], dtype=_GENERATION_COLUMNS)
    return Run(p, config, manifest, generations, champions, list(_sodaevo.saved_generations(os.fspath(p))))


def to_arrays(model: Model) -> Dict[str, Any]:
    """The model as data: ``Model.from_arrays(**to_arrays(m)) == m``. Keys: nodes,
    links, world, fixed, node_ids, name, comment (arrays read-only; copy to edit)."""
    return {"nodes": model.nodes, "links": model.links, "world": dict(model.world), "fixed": model.fixed,
            "node_ids": list(model.node_ids), "name": model.name, "comment": model.comment}


def mutate(model: Model, rng_seed: int, config: ConfigLike = None) -> Model:
    """A mutated copy of `model` made by the GA's mutation (each operator at its
    /mutation rate, at least one change, limits kept), drawn from `rng_seed`."""
    return _sodaevo.mutate(model, rng_seed, _config_arg(config))


def crossover(a: Model, b: Model, rng_seed: int, config: ConfigLike = None) -> Model:
    """The GA's one-point crossover on mass order of `a` and `b` (a copy of `a`
    when the child breaks the limits), drawn from `rng_seed`."""
    return _sodaevo.crossover(a, b, rng_seed, _config_arg(config))


def random_creature(rng_seed: int, config: ConfigLike = None) -> Model:
    """A random connected creature as the GA's first generation makes them
    (/population/random), drawn from `rng_seed`."""
    return _sodaevo.random_creature(rng_seed, _config_arg(config))


def creature(model: Model, config: ConfigLike = None) -> Model:
    """A seed model made fit for evolution, as ``evolve`` takes its seed models:
    fixed nodes and bars removed, the largest connected piece, canonical form."""
    return _sodaevo.creature(model, _config_arg(config))


def _config_arg(config: ConfigLike) -> Any:
    if config is None or isinstance(config, (dict, Config)):
        return config
    if isinstance(config, Mapping):
        return dict(config)
    return os.fspath(config)
