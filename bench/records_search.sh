#!/usr/bin/env bash
# bench/records_search.sh CONFIG [NAME]: one record search for the record book
# (docs/races.md, "The record book"). Runs `sodaevo evolve CONFIG` into
# results/records/runs/NAME (resuming it if it was interrupted: searches may go on
# across days), exports its champion as results/records/candidates/NAME.xml, and
# writes NAME.json beside it: how it was found (config, seed, generations, wall
# time summed over the sessions). Then `sodaevo records` races it on every file.
#
#   bench/records_search.sh configs/records/race08.json
#   SODAEVO=build/sodaevo THREADS=1 bench/records_search.sh configs/records/race08.json race08_s2
set -euo pipefail
cd "$(dirname "$0")/.."
config=${1:?usage: bench/records_search.sh CONFIG [NAME]}
name=${2:-$(basename "$config" .json)}
bin=${SODAEVO:-build/sodaevo}
threads=${THREADS:-0}
run=results/records/runs/$name
candidates=results/records/candidates
mkdir -p "$candidates" results/records/runs

start=$(date +%s)
if [ -f "$run/manifest.json" ] && [ ! -f "$run/.finished" ]; then
  "$bin" evolve --resume "$run" --threads "$threads" --quiet
elif [ ! -f "$run/.finished" ]; then
  "$bin" evolve "$config" --out "$run" --threads "$threads" --quiet --force
fi
end=$(date +%s)
touch "$run/.finished"
# Wall time over every session of this search.
previous=$(cat "$run/.wall_seconds" 2>/dev/null || echo 0)
echo $((previous + end - start)) > "$run/.wall_seconds"

rm -rf "$run/export"
"$bin" export "$run" --best 1 --out "$run/export" --threads "$threads" > /dev/null
cp "$run"/export/rank01_*.xml "$candidates/$name.xml"
generations=$(($(wc -l < "$run/generations.csv") - 1))
seed=$(/usr/bin/python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["seed"])' "$run/config.json")
printf '{"config": "%s", "seed": %s, "generations": %s, "wall_seconds": %s, "run": "%s"}\n' \
  "$config" "$seed" "$generations" "$(cat "$run/.wall_seconds")" "$run" > "$candidates/$name.json"
echo "$name: $(head -c 300 "$candidates/$name.xml" | grep -o 'race fitness[^)]*)' || true)"
