#!/usr/bin/env bash
# Hard requests (a benchmark, not a test): sizes that jump 10- to 400-fold across a line or
# swing every 0.1, channels 100 and 1,000 times longer than wide, holes and embedded lines
# 0.001 from a wall or from each other, curve sizes 50 times off the interior's, thin and open
# airfoils. Meshes each with the defaults (and with `--gradation G` added to every request, if
# given) and prints points, smallest angle and time. docs/benchmarks.md, "Fields the mesh
# cannot follow", has the figures. Usage: bench/hard/run.sh [--gradation G]
set -euo pipefail
cd "$(dirname "$0")/../.."
cli=build/cli/meshd-cli
[ -x "$cli" ] || scripts/build.sh release >/dev/null
gradation=""
[ "${1:-}" = "--gradation" ] && gradation="${2:?a ratio above 1}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for f in bench/hard/*.json; do
  name=$(basename "$f" .json)
  req="$f"
  if [ -n "$gradation" ]; then
    req="$tmp/$name.json"
    /usr/bin/python3 -c 'import json, sys; r = json.load(open(sys.argv[1])); r["density"]["gradation"] = float(sys.argv[2]); json.dump(r, open(sys.argv[3], "w"))' "$f" "$gradation" "$req"
  fi
  "$cli" "$req" -o "$tmp/out.json" --format json --quiet >/dev/null 2>&1 || { printf '%-28s refused or failed\n' "$name"; continue; }
  /usr/bin/python3 -c 'import json, sys; m = json.load(open(sys.argv[1]))["metrics"]; print("%-28s %8d points  %6.2f deg  %8.1f ms" % (sys.argv[2], m["points"], m["angle_deg"]["min"], m["timings_ms"]["total"]))' "$tmp/out.json" "$name"
done
