#!/usr/bin/python3
"""The ask/tell Optimiser against `sodaevo evolve` on the same config (issue 48's
target: an ask/tell loop, evaluate() on every ask() batch, keeps at least 0.9x the
command's evaluations per second).

How it is fair: both make the same run folder (checked byte for byte in
generations.csv, champions.json and best/), so both do the same evaluations; the
rate is the run's evaluations (generations.csv's last `evaluations`) over the wall
time of the whole run, each in a fresh process. The command line's is its
process's wall time (start-up, checkpoints, its report.html, the champions'
check). Python's is timed inside its process from creating the Optimiser to the
end of the loop (the run folder made, every replay of a generation's variation
from the checkpoint, evaluate() per request, the champions' check): what a
researcher's loop costs, without starting the interpreter and importing numpy,
which a session pays once (reported apart). Same thread count. Rounds alternate
CLI, Python, so a change in machine load hits both; the report gives the median
of each and their ratio.

  PYTHONPATH=build/python /usr/bin/python3 bench/python_ask_tell.py [--config configs/quick.json] [--rounds 5]
"""
from __future__ import annotations

import argparse
import csv
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

LOOP = """
import sys, time
start = time.perf_counter()
import sodaevo
loop = time.perf_counter()
cpu = time.process_time()
opt = sodaevo.Optimiser(sys.argv[1], sys.argv[2], threads=int(sys.argv[3]))
while (request := opt.ask()) is not None:
    opt.tell(sodaevo.evaluate(request, threads=int(sys.argv[3])))
print(time.perf_counter() - loop, loop - start, time.process_time() - cpu)
"""


def evaluations(run: Path) -> int:
    with open(run / "generations.csv", newline="") as f:
        return int(list(csv.DictReader(f))[-1]["evaluations"])


def children_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def timed(command: list[str]) -> tuple[float, float]:
    """Wall seconds and CPU seconds (all threads) of the command's process."""
    start, cpu = time.perf_counter(), children_cpu()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - start, children_cpu() - cpu


def timed_inside(command: list[str]) -> tuple[float, float, float]:
    """The loop's wall seconds, the import's, and the loop's CPU seconds (all
    threads), as the Python process measured them."""
    out = subprocess.run(command, check=True, capture_output=True, text=True).stdout.split()
    return float(out[0]), float(out[1]), float(out[2])


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--config", default=str(ROOT / "configs" / "quick.json"))
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--binary", default=str(ROOT / "build" / "sodaevo"))
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(args.rounds):
            cli, py = Path(tmp) / f"cli{r}", Path(tmp) / f"py{r}"
            t_cli, cpu_cli = timed([args.binary, "evolve", args.config, "--out", str(cli), "--threads", str(args.threads),
                           "--quiet"])
            t_py, t_import, cpu_py = timed_inside([sys.executable, "-c", LOOP, args.config, str(py), str(args.threads)])
            for name in ("generations.csv", "champions.json"):
                if (cli / name).read_bytes() != (py / name).read_bytes():
                    sys.exit(f"round {r}: {name} differs between the command line and ask/tell")
            for f in sorted((cli / "best").iterdir()):
                if f.read_bytes() != (py / "best" / f.name).read_bytes():
                    sys.exit(f"round {r}: best/{f.name} differs")
            n = evaluations(cli)
            rows.append((r, n, t_cli, t_py, n / t_cli, n / t_py, t_import, n / cpu_cli, n / cpu_py))
            print(f"round {r}: {n} evaluations, CLI {t_cli:.2f} s ({n / t_cli:.1f}/s), "
                  f"ask/tell {t_py:.2f} s ({n / t_py:.1f}/s), import {t_import:.2f} s", file=sys.stderr)
    cli_rate = statistics.median(row[4] for row in rows)
    py_rate = statistics.median(row[5] for row in rows)
    cli_cpu_rate = statistics.median(row[7] for row in rows)
    py_cpu_rate = statistics.median(row[8] for row in rows)
    load = os.getloadavg()[0]
    print(f"Config `{os.path.relpath(args.config, ROOT)}`, {args.threads} threads, {args.rounds} rounds "
          f"(alternating), load average {load:.1f} at the end. Identical folders every round "
          f"(generations.csv, champions.json, best/).\n")
    print("| round | evaluations | CLI s | ask/tell s | CLI evaluations/s | ask/tell evaluations/s | import s "
          "| CLI evaluations/CPU s | ask/tell evaluations/CPU s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r, n, t_cli, t_py, a, b, t_import, c, d in rows:
        print(f"| {r} | {n} | {t_cli:.2f} | {t_py:.2f} | {a:.1f} | {b:.1f} | {t_import:.2f} | {c:.1f} | {d:.1f} |")
    print(f"\nMedian: CLI {cli_rate:.1f}, ask/tell {py_rate:.1f} evaluations/s: "
          f"**ratio ask/tell / CLI {py_rate / cli_rate:.3f}** (target >= 0.9). By CPU time (all threads; "
          f"what a loaded machine does not distort as much): CLI {cli_cpu_rate:.1f}, ask/tell {py_cpu_rate:.1f} "
          f"evaluations per CPU second, ratio {py_cpu_rate / cli_cpu_rate:.3f}.")


if __name__ == "__main__":
    main()
