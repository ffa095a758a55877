#!/usr/bin/python3
"""Evolve walkers with DEAP, scoring each generation with sodaevo.evaluate.

DEAP does the selection and the bookkeeping; sodaevo does what DEAP cannot: the
exact engine, the creatures' variation (the GA's own operators, so that every
child is a valid creature) and the scoring, a whole generation per call, on all
cores, with the GIL released. The fitness is configs/default.json's: distance
walked right over 4000 frames after 400, Sodarace scaling, mean of 8 replicas.

  PYTHONPATH=build/python /usr/bin/python3 examples/python/deap_walkers.py [--generations 30]

The champion is written to results/deap_champion.xml (--out), an output folder
beside the run folders, never into the sources.
"""
import argparse
import random
from pathlib import Path

from deap import base, creator, tools

import sodaevo

ROOT = Path(__file__).resolve().parents[2]
CONFIG = ROOT / "configs" / "default.json"  # world, limits, mutation rates and fitness

ap = argparse.ArgumentParser()
ap.add_argument("--generations", type=int, default=30)
ap.add_argument("--population", type=int, default=100)
ap.add_argument("--seed", type=int, default=1)
ap.add_argument("--out", type=Path, default=Path("results") / "deap_champion.xml", help="where the champion is written")
args = ap.parse_args()
random.seed(args.seed)  # DEAP's selection draws from the random module: the run is reproducible
rng = random

# A DEAP individual is a one-element list holding a sodaevo.Model (DEAP needs a
# container it can give a .fitness).
creator.create("FitnessMax", base.Fitness, weights=(1.0,))
creator.create("Walker", list, fitness=creator.FitnessMax)

toolbox = base.Toolbox()
toolbox.register("select", tools.selTournament, tournsize=3)


def mutate(ind):  # the GA's mutation, drawn from a seed of DEAP's random stream
    ind[0] = sodaevo.mutate(ind[0], rng.getrandbits(63), CONFIG)
    return ind,


def mate(a, b):  # the GA's one-point crossover on mass order
    a[0], b[0] = sodaevo.crossover(a[0], b[0], rng.getrandbits(63), CONFIG), \
                 sodaevo.crossover(b[0], a[0], rng.getrandbits(63), CONFIG)
    return a, b


def score(walkers):  # one batch for the whole generation: sodaevo spreads it over the cores
    result = sodaevo.evaluate([w[0] for w in walkers], CONFIG)
    for w, f in zip(walkers, result.fitness):
        w.fitness.values = (f,)


# The start: the Dainty Walker (made a creature as `evolve` makes its seeds),
# mutated copies of it, and random creatures.
dainty = sodaevo.creature(sodaevo.Model.load(ROOT / "models" / "dainty_walker.xml"), CONFIG)
population = [creator.Walker([dainty])]
population += [creator.Walker([sodaevo.mutate(dainty, rng.getrandbits(63), CONFIG)]) for _ in range(args.population // 2)]
while len(population) < args.population:
    population.append(creator.Walker([sodaevo.random_creature(rng.getrandbits(63), CONFIG)]))
score(population)

for generation in range(1, args.generations + 1):
    elites = [toolbox.clone(w) for w in tools.selBest(population, 2)]
    children = [toolbox.clone(w) for w in toolbox.select(population, len(population) - len(elites))]
    for a, b in zip(children[::2], children[1::2]):
        if rng.random() < 0.2:
            mate(a, b)
            del a.fitness.values, b.fitness.values
    for c in children:
        mutate(c)
        del c.fitness.values
    score([c for c in children if not c.fitness.valid])
    population = elites + children
    best = tools.selBest(population, 1)[0]
    print(f"generation {generation}: best {best.fitness.values[0]:.1f} px")

# The best's score was selected from many noisy ones (the winner's curse), so
# judge it, and the Dainty Walker, on 32 fresh replicas of another seed.
champion = tools.selBest(population, 1)[0][0]
check = sodaevo.evaluate([champion, dainty], CONFIG, replicas=32, seed=12345)
print(f"champion      {check.fitness[0]:.1f} px (95 % of runs in [{check.interval95[0, 0]:.1f}, "
      f"{check.interval95[0, 1]:.1f}])")
print(f"Dainty Walker {check.fitness[1]:.1f} px")
print("better than the Dainty Walker" if check.fitness[0] > check.fitness[1] else "not better than the Dainty Walker")
args.out.parent.mkdir(parents=True, exist_ok=True)
champion.save(str(args.out))
print(f"champion written to {args.out}")
