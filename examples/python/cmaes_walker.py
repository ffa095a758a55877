#!/usr/bin/python3
"""CMA-ES on one body plan: the Dainty Walker's vector (sodaevo.to_vector: rest
lengths, muscle amplitudes and phases) searched in numpy, each candidate scored
by the distance `sodaevo simulate` reports. The best is saved as XML, so

  sodaevo simulate results/cmaes_best.xml --frames 2000 --json

(the file goes to results/cmaes_best.xml, --out, not the working folder) replays it to the last bit (the printed centroid_dx).

The optimiser below is a plain CMA-ES (Hansen's (mu/mu_w, lambda) with rank-one
and rank-mu updates) with the ask/tell interface of the `cma` package: with
`pip install cma`, replace `CMAES(x0, 0.1, seed=1)` by
`cma.CMAEvolutionStrategy(x0, 0.1, {"seed": 1})` and the loop stays as it is.

  PYTHONPATH=build/python /usr/bin/python3 examples/python/cmaes_walker.py [--generations 40] [--out FILE]
"""
import argparse
import os

import numpy as np

import sodaevo

ap = argparse.ArgumentParser()
ap.add_argument("--generations", type=int, default=40)
ap.add_argument("--frames", type=int, default=2000)
ap.add_argument("--model", default=os.path.join(os.path.dirname(__file__), "..", "..", "models", "dainty_walker.xml"))
ap.add_argument("--out", default="results/cmaes_best.xml")
args = ap.parse_args()


class CMAES:
    """Minimises: ask() -> candidates, tell(candidates, values)."""

    def __init__(self, x0, sigma, popsize=None, seed=0):
        n = self.n = len(x0)
        self.mean, self.sigma = np.array(x0, dtype=float), sigma
        self.popsize = popsize or 4 + int(3 * np.log(n))
        self.mu = self.popsize // 2
        w = np.log(self.mu + 0.5) - np.log(np.arange(1, self.mu + 1))
        self.w = w / w.sum()
        self.mueff = 1 / np.sum(self.w ** 2)
        self.cc = (4 + self.mueff / n) / (n + 4 + 2 * self.mueff / n)
        self.cs = (self.mueff + 2) / (n + self.mueff + 5)
        self.c1 = 2 / ((n + 1.3) ** 2 + self.mueff)
        self.cmu = min(1 - self.c1, 2 * (self.mueff - 2 + 1 / self.mueff) / ((n + 2) ** 2 + self.mueff))
        self.damps = 1 + 2 * max(0.0, np.sqrt((self.mueff - 1) / (n + 1)) - 1) + self.cs
        self.chi_n = np.sqrt(n) * (1 - 1 / (4 * n) + 1 / (21 * n * n))
        self.pc, self.ps = np.zeros(n), np.zeros(n)
        self.C, self.B, self.D = np.eye(n), np.eye(n), np.ones(n)
        self.rng = np.random.default_rng(seed)
        self.generation = 0

    def ask(self):
        z = self.rng.standard_normal((self.popsize, self.n))
        return list(self.mean + self.sigma * (z * self.D) @ self.B.T)

    def tell(self, candidates, values):
        order = np.argsort(values)[: self.mu]
        y = (np.asarray(candidates)[order] - self.mean) / self.sigma
        yw = self.w @ y
        self.mean = self.mean + self.sigma * yw
        self.generation += 1
        c_half_inv = self.B @ np.diag(1 / self.D) @ self.B.T
        self.ps = (1 - self.cs) * self.ps + np.sqrt(self.cs * (2 - self.cs) * self.mueff) * c_half_inv @ yw
        ps_norm = np.linalg.norm(self.ps) / np.sqrt(1 - (1 - self.cs) ** (2 * self.generation))
        hsig = float(ps_norm / self.chi_n < 1.4 + 2 / (self.n + 1))
        self.pc = (1 - self.cc) * self.pc + hsig * np.sqrt(self.cc * (2 - self.cc) * self.mueff) * yw
        self.C = ((1 - self.c1 - self.cmu) * self.C
                  + self.c1 * (np.outer(self.pc, self.pc) + (1 - hsig) * self.cc * (2 - self.cc) * self.C)
                  + self.cmu * (y.T * self.w) @ y)
        self.sigma *= np.exp((self.cs / self.damps) * (np.linalg.norm(self.ps) / self.chi_n - 1))
        eigenvalues, self.B = np.linalg.eigh(self.C)
        self.D = np.sqrt(np.maximum(eigenvalues, 1e-20))


walker = sodaevo.Model.load(args.model)
low, high = sodaevo.vector_bounds(walker, world=False)  # rest lengths, amplitudes, phases
span = high - low


def creature(u):
    """A point of the unit cube (CMA-ES's space) as a creature: bounds kept, phases wrap."""
    return sodaevo.from_vector(walker, np.clip(low + u * span, low, high), world=False)


def distance(model):
    return sodaevo.simulate(model, args.frames)["centroid_dx"]


start = distance(walker)
best, best_distance = walker, start
es = CMAES((sodaevo.to_vector(walker, world=False) - low) / span, 0.1, seed=1)
for g in range(args.generations):
    candidates = es.ask()
    creatures = [creature(u) for u in candidates]
    distances = [distance(c) for c in creatures]
    es.tell(candidates, [-d for d in distances])  # CMA-ES minimises
    k = int(np.argmax(distances))
    if distances[k] > best_distance:
        best, best_distance = creatures[k], distances[k]
    print(f"generation {g}: best {max(distances):.1f} px, best so far {best_distance:.1f} px, sigma {es.sigma:.3f}")
os.makedirs(os.path.dirname(args.out) or ".", exist_ok=True)
best.save(args.out)
print(f"Dainty Walker: {start!r} px in {args.frames} frames; CMA-ES best: {best_distance!r} px")
print(f"replay: sodaevo simulate {args.out} --frames {args.frames} --json  (centroid_dx {best_distance!r})")
