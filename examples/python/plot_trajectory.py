#!/usr/bin/python3
"""Plot the Dainty Walker's trajectory with matplotlib: simulate with
trace=True gives every frame's masses as a numpy array, (frames + 1, masses, 4)
of x, y, vx, vy, the numbers `sodaevo simulate --trace` writes.

  PYTHONPATH=build/python /usr/bin/python3 examples/python/plot_trajectory.py [--out results/trajectory.png]
"""
import argparse
from pathlib import Path

import matplotlib
matplotlib.use("Agg")  # files only, no window
import matplotlib.pyplot as plt

import sodaevo

ROOT = Path(__file__).resolve().parents[2]
ap = argparse.ArgumentParser()
ap.add_argument("--model", default=str(ROOT / "models" / "dainty_walker.xml"))
ap.add_argument("--frames", type=int, default=2000)
ap.add_argument("--out", default="results/trajectory.png")
args = ap.parse_args()

model = sodaevo.Model.load(args.model)
run = sodaevo.simulate(model, args.frames, trace=True)
x, y = run["trace"][:, :, 0], run["trace"][:, :, 1]  # (frames + 1, masses)

fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6))
top.plot(x, y, linewidth=0.4)  # one line per mass
top.plot(x.mean(axis=1), y.mean(axis=1), "k", linewidth=1.5, label="centroid")
top.set(xlabel="x (px)", ylabel="y (px)", title=f"{model.name}: {args.frames} frames")
top.legend()
bottom.plot(x.mean(axis=1) - x[0].mean())
bottom.set(xlabel="frame", ylabel="centroid dx (px)")
fig.tight_layout()
Path(args.out).parent.mkdir(parents=True, exist_ok=True)
fig.savefig(args.out, dpi=100)
print(f"{args.out}: centroid moved {run['centroid_dx']:+.2f} px in {run['frames']} frames")
