#!/usr/bin/python3
"""The project's own GA as ask/tell: sodaevo.Optimiser runs the loop of `sodaevo
evolve` and hands out each generation's creatures; here they are scored with
sodaevo.evaluate on this machine's threads (anything that evaluates them as
evaluate(request) does may take its place: a cluster, a cache). The run folder
is the command line's, byte for byte: `sodaevo report RUN` and `sodaevo export
RUN` read it.

  PYTHONPATH=build/python /usr/bin/python3 examples/python/ask_tell_ga.py [--config configs/quick.json]
"""
import argparse
import os

import sodaevo

ap = argparse.ArgumentParser()
ap.add_argument("--config", default=os.path.join(os.path.dirname(__file__), "..", "..", "configs", "quick.json"))
ap.add_argument("--out", default="ask_tell_run")
ap.add_argument("--threads", type=int, default=0)
args = ap.parse_args()

config = sodaevo.Config(args.config)  # read once: seed paths against the config's folder


def show(progress):
    print(f"generation {progress['generation']}/{progress['generations']}: best {progress['best']:.1f}, "
          f"median {progress['median']:.1f}, {progress['evaluations']} evaluations")


optimiser = sodaevo.Optimiser(config, args.out, force=True, threads=args.threads, callback=show)
while (request := optimiser.ask()) is not None:  # the creatures the GA wants scored
    results = sodaevo.evaluate(request, threads=args.threads)  # with the run's own problem and estimator
    optimiser.tell(results)
result = optimiser.result
print(f"{result['stopped_because']}: best {result['best_id']} with {result['best_fitness']:.1f}; run folder {result['run']}")
