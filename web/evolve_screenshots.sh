#!/usr/bin/env bash
# The screenshots of Evolve mode in docs/: a GA run seeded with the Dainty Walker
# mid-run (chart, champion, strip) and a MAP-Elites archive filling in.
#
#   web/evolve_screenshots.sh SODAEVO_BINARY [OUT_DIR=docs]
set -euo pipefail
sodaevo=${1:?usage: web/evolve_screenshots.sh SODAEVO_BINARY [OUT_DIR]}
out=${2:-docs}
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$sodaevo" designer "$root/models/dainty_walker.xml" -o "$work/designer.html" > /dev/null
b64() { python3 -c 'import base64,sys; print(base64.urlsafe_b64encode(sys.stdin.buffer.read()).decode().rstrip("="))'; }
ga='{"name": "dainty", "seed": 7, "generations": 60, "population": {"size": 48, "seed_models": ["dainty_walker.xml"], "random_fraction": 0.3}, "fitness": {"frames": 1000, "settle_frames": 100}}'
me='{"name": "gallery", "seed": 1, "algorithm": "map-elites", "population": {"size": 100, "seed_models": ["dainty_walker.xml"], "random_fraction": 0.9, "random": {"masses_min": 3, "masses_max": 10}}, "fitness": {"frames": 800, "settle_frames": 100, "replicas": 2, "replicas_max": 4}, "map_elites": {"descriptors": ["width", "height"], "bins": [16, 12], "ranges": [[40, 300], [0, 100]], "iterations": 60, "batch_size": 60}}'
node "$root/web/chromium_wait.js" --run-links chromium "file://$work/designer.html#evolve=$(printf '%s' "$ga" | b64)&run" \
  "window.sodaEvolve && window.sodaEvolve.rows.length >= 25" "window.sodaEvolve.rows.length" 300 "$out/designer-evolve.png" 1300x1000
node "$root/web/chromium_wait.js" --run-links chromium "file://$work/designer.html#evolve=$(printf '%s' "$me" | b64)&run" \
  "document.documentElement.getAttribute('data-evolve-done') === '1'" "document.getElementById('ev-progress').textContent" 300 \
  "$out/designer-map-elites.png" 1300x760
