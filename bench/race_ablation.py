#!/usr/bin/python3
"""An ablation of a racer-search feature: the same config with and without it, over
several seeds at the same budget (generations x population), each champion raced
exactly on the config's race files and on 16 jittered replicas
(`sodaevo race --json --replicas 16`). Writes a markdown table and a CSV.

  bench/race_ablation.py --config configs/records/race05.json \
      --variant 'racer score={"fitness": {"race": {"score": "racer"}}}' \
      --variant 'progress score={}' --seeds 3 --generations 40 --out results/bench/race_ablation_score

A variant is NAME=JSON: a patch merged into the config (objects merged key by key).
Runs go to OUT-runs/ (resumable: a finished run is not run again)."""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import time


def merge(base, patch):
    for key, value in patch.items():
        if isinstance(value, dict) and isinstance(base.get(key), dict):
            merge(base[key], value)
        else:
            base[key] = value
    return base


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--config", required=True)
    ap.add_argument("--variant", action="append", required=True, help="NAME=JSON patch")
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--generations", type=int, default=0, help="0: the config's")
    ap.add_argument("--population", type=int, default=0, help="0: the config's")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--bin", default="build/sodaevo")
    ap.add_argument("--out", required=True, help="OUT.md and OUT.csv are written, runs go to OUT-runs/")
    a = ap.parse_args()

    base_dir = os.path.dirname(os.path.abspath(a.config))
    runs = a.out + "-runs"
    os.makedirs(runs, exist_ok=True)
    rows = []
    for spec in a.variant:
        name, _, patch = spec.partition("=")
        for seed in range(1, a.seeds + 1):
            with open(a.config) as f:
                config = json.load(f)
            merge(config, json.loads(patch or "{}"))
            config["seed"] = seed
            if a.generations:
                config["generations"] = a.generations
            if a.population:
                config["population"]["size"] = a.population
            config.pop("budget", None)
            tag = "".join(c if c.isalnum() else "_" for c in name) + f"_s{seed}"
            # Written beside the config, so its relative paths (seeds, terrains) still resolve.
            cfg_path = os.path.join(base_dir, f".ablation_{tag}.json")
            with open(cfg_path, "w") as f:
                json.dump(config, f, indent=2)
            run = os.path.join(runs, tag)
            started = time.time()
            if not os.path.exists(os.path.join(run, ".done")):
                subprocess.run([a.bin, "evolve", cfg_path, "--out", run, "--threads", str(a.threads), "--quiet",
                                "--force"], check=True)
                open(os.path.join(run, ".done"), "w").close()
            seconds = time.time() - started
            os.remove(cfg_path)
            export = os.path.join(run, "export")
            subprocess.run([a.bin, "export", run, "--best", "1", "--out", export, "--threads", str(a.threads)],
                           check=True, stdout=subprocess.DEVNULL)
            champion = [os.path.join(export, f) for f in os.listdir(export) if f.startswith("rank01_")][0]
            with open(os.path.join(run, "config.json")) as f:
                terrains = json.load(f)["fitness"]["race"].get("terrains") or []
            finished, frames, shares, medians = 0, [], [], []
            for terrain in terrains:
                out = subprocess.run([a.bin, "race", terrain, champion, "--json", "--replicas", "16", "--threads",
                                      str(a.threads)], check=True, capture_output=True, text=True).stdout
                entry = json.loads(out)["contenders"][0]
                finished += 1 if entry["finished"] else 0
                frames.append(entry["frames"])
                reps = entry["replicas"]
                medians.append(reps["median"])
                shares.append(reps["finished"])
            # One file: the first generation whose best finished. The racer's result and the
            # progress score's cost are at most the timeout exactly when the racer finishes
            # (before the first finish the adaptive timeout stays the file's own).
            with open(os.path.join(run, "config.json")) as f:
                limit = json.load(f)["fitness"]["race"]["timeout"] or 10000
            first = None
            with open(os.path.join(run, "generations.csv")) as f:
                for row in csv.DictReader(f):
                    if len(terrains) == 1 and -float(row["best"]) <= limit:
                        first = int(row["generation"])
                        break
            rows.append({"variant": name, "seed": seed, "files": len(terrains), "finished": finished, "first": first,
                         "frames": frames, "replica_median": medians, "replica_share": shares,
                         "seconds": round(seconds, 1),
                         "champion": champion})
            print(f"{name} seed {seed}: finished {finished}/{len(terrains)}, frames {frames}", file=sys.stderr)

    with open(a.out + ".csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["variant", "seed", "files", "finished", "frames", "replica_median", "replicas_finished", "seconds",
                    "champion"])
        for r in rows:
            w.writerow([r["variant"], r["seed"], r["files"], r["finished"], " ".join(map(str, r["frames"])),
                        " ".join(map(str, r["replica_median"])), " ".join(map(str, r["replica_share"])),
                        r["seconds"], r["champion"]])
    with open(a.out + ".md", "w") as f:
        f.write(f"# Ablation: {', '.join(v.partition('=')[0] for v in a.variant)}\n\n")
        f.write(f"`bench/race_ablation.py {' '.join(sys.argv[1:])}`\n\n")
        f.write(f"Base config `{a.config}`; every variant at the same budget, seeds 1 to {a.seeds}; each champion "
                "(`export --best 1`) raced exactly and on 16 jittered replicas on the config's race files.\n\n")
        f.write("| variant | seeds finishing every file | median frames (exact) | replicas finishing (mean) | "
                "first generation whose best finishes, per seed | per seed: frames (replica median, share finishing) |\n")
        f.write("|---|---:|---:|---:|---|---|\n")
        for spec in a.variant:
            name = spec.partition("=")[0]
            mine = [r for r in rows if r["variant"] == name]
            done = sum(1 for r in mine if r["finished"] == r["files"])
            med = statistics.median(sum(r["frames"]) / len(r["frames"]) for r in mine)
            share = statistics.mean(statistics.mean(r["replica_share"]) for r in mine)
            per = "; ".join(" ".join(f"{x:.0f} ({m:.0f}, {100 * s:.0f} %)"
                                     for x, m, s in zip(r["frames"], r["replica_median"], r["replica_share"]))
                            for r in mine)
            firsts = ", ".join("-" if r["first"] is None else str(r["first"]) for r in mine)
            f.write(f"| {name} | {done} of {len(mine)} | {med:.1f} | {100 * share:.0f} % | {firsts} | {per} |\n")
    print(f"wrote {a.out}.md", file=sys.stderr)


if __name__ == "__main__":
    main()
