#!/usr/bin/python3
"""evaluate() from Python against the command line: evaluations per second on the
same creatures with the same settings (issue 38's target: at least 0.9x).

How it is fair: the command line's figure is its own, the evaluation rate
`sodaevo evolve` logs for generation 0 in timing.csv (evaluations over the wall
time of evaluate_generation alone: no start-up, no file writing). Generation 0
is every creature of the run's first generation, all new, so all are evaluated.
Python then evaluates exactly those creatures (read back from the run's
generations/gen_00000.xml) with the run's config.json through sodaevo.evaluate,
timed around the call (which includes handing the models over and building the
numpy results), in a fresh Python process per round as the command's is fresh. Same Problem, same ReplicaEstimator, same ThreadEvaluator, same
thread count. Runs alternate CLI, Python, CLI, ... so a change in machine load
hits both; the report gives the median of each and their ratio.

  PYTHONPATH=build/python /usr/bin/python3 bench/python_throughput.py [--rounds 5] [--threads 2]
"""
from __future__ import annotations

import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "build" / "python"))
import sodaevo  # noqa: E402


def python_round(run: Path, threads: int) -> None:
    """One Python measurement: generation 0 of `run` through evaluate(), timed
    around the call; checks the fitnesses against the run's log."""
    individuals = sodaevo.open_run(run).generation(0)
    models = [i["model"] for i in individuals]
    t0 = time.perf_counter()
    result = sodaevo.evaluate(models, run / "config.json", threads=threads)
    seconds = time.perf_counter() - t0
    assert list(result.fitness) == [i["fitness"] for i in individuals], "not the same evaluations"
    print(len(models) / seconds)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--population", type=int, default=1000)
    ap.add_argument("--binary", default=str(ROOT / "build" / "sodaevo"))
    ap.add_argument("--out", help="write the Markdown report here")
    ap.add_argument("--python-round", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.python_round:
        python_round(Path(args.python_round), args.threads)
        return

    # configs/default.json's creatures and fitness (4000 frames after 400, 8 replicas),
    # one generation of `population`, no confirmation round (so that generation 0's
    # timing is its evaluation alone).
    with open(ROOT / "configs" / "default.json", encoding="utf-8") as f:
        config = json.load(f)
    config.update(name="bench", generations=1)
    config["population"].update(size=args.population, seed_models=[str(ROOT / "models" / "dainty_walker.xml")])
    config["fitness"]["confirm"] = 0
    config["save"] = {"generation_every": 1, "checkpoint_every": 1}

    load_before = os.getloadavg()[0]
    cli_rates, py_rates = [], []
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "bench.json"
        path.write_text(json.dumps(config))
        for r in range(args.rounds):
            run = Path(tmp) / f"run{r}"
            subprocess.run([args.binary, "evolve", str(path), "--out", str(run), "--quiet", "--threads",
                            str(args.threads)], check=True, stdout=subprocess.DEVNULL)
            with open(run / "timing.csv", newline="") as f:
                row = next(csv.DictReader(f))
            cli_rates.append(float(row["evaluations_per_second"]))
            # A fresh Python process per round, as the command line's is fresh: neither
            # side's allocator or threads are warm from an earlier round.
            child = subprocess.run([sys.executable, __file__, "--python-round", str(run), "--threads",
                                    str(args.threads)], check=True, capture_output=True, text=True)
            py_rates.append(float(child.stdout.split()[-1]))
            print(f"round {r}: CLI {cli_rates[-1]:.1f} evaluations/s, Python {py_rates[-1]:.1f} evaluations/s",
                  flush=True)
    cli, py = statistics.median(cli_rates), statistics.median(py_rates)
    lines = [
        "# Python module throughput (issue 38)",
        "",
        "`sodaevo.evaluate` against the command line on the same creatures with the same settings:",
        f"generation 0 of `configs/default.json` with population {args.population} (half mutated Dainty "
        "Walkers, half random creatures), 4000 scored frames after 400, 8 replicas each, "
        f"{args.threads} threads. The command line's rate is what `sodaevo evolve` logs for that generation "
        "(timing.csv: evaluations over the wall time of evaluating it); Python's is the same creatures, read "
        "back from the run folder, through `sodaevo.evaluate(models, RUN/config.json)`, timed around the call, in a "
        "fresh Python process per round as the command's is fresh. "
        "The fitnesses are checked equal bit for bit. Rounds alternate CLI and Python; medians.",
        "",
        "| round | CLI evaluations/s | Python evaluations/s |",
        "|---|---|---|",
    ]
    lines += [f"| {k} | {c:.1f} | {p:.1f} |" for k, (c, p) in enumerate(zip(cli_rates, py_rates))]
    lines += [
        "",
        f"Median: CLI {cli:.1f}, Python {py:.1f} evaluations/s: **ratio Python/CLI {py / cli:.3f}** (target >= 0.9).",
        "",
        f"Machine: {os.cpu_count()} cores, load average {load_before:.1f} before and {os.getloadavg()[0]:.1f} after "
        "(other builds were running: absolute rates are low and vary by round, the alternating rounds share it).",
        "",
        "Command: `PYTHONPATH=build/python /usr/bin/python3 bench/python_throughput.py "
        f"--rounds {args.rounds} --threads {args.threads} --population {args.population}"
        + (f" --out {args.out}`" if args.out else "`"),
    ]
    text = "\n".join(lines) + "\n"
    print(text)
    if args.out:
        Path(args.out).write_text(text)


if __name__ == "__main__":
    main()
