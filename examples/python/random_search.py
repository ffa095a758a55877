#!/usr/bin/python3
"""Random search with numpy: draw random creatures in batches, score each batch
with sodaevo.evaluate, keep the best. The baseline any algorithm should beat.

  PYTHONPATH=build/python /usr/bin/python3 examples/python/random_search.py [--batches 10] [--out FILE]

The best creature goes to results/random_search_best.xml (--out), not the working
folder.
"""
import argparse
from pathlib import Path

import numpy as np

import sodaevo

ap = argparse.ArgumentParser()
ap.add_argument("--batches", type=int, default=10)
ap.add_argument("--batch", type=int, default=200)
ap.add_argument("--out", default="results/random_search_best.xml")
args = ap.parse_args()

rng = np.random.default_rng(1)
problem = {"frames": 2000, "settle_frames": 200}  # the /fitness object of a run config
best, best_fitness = None, -np.inf
for b in range(args.batches):
    seeds = rng.integers(0, 2**62, size=args.batch)
    creatures = [sodaevo.random_creature(int(s)) for s in seeds]
    result = sodaevo.evaluate(creatures, problem, replicas=4)  # arrays, one entry per creature
    k = int(np.argmax(result.fitness))
    if result.fitness[k] > best_fitness:
        best, best_fitness = creatures[k], result.fitness[k]
    ok = np.isfinite(result.fitness)
    print(f"batch {b}: {ok.sum()} scored, median {np.median(result.fitness[ok]):.1f} px, "
          f"best so far {best_fitness:.1f} px ({best.mass_count} masses)")
Path(args.out).parent.mkdir(parents=True, exist_ok=True)
best.save(args.out)
print(f"{args.out}: the best creature")
