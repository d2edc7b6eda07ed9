#!/usr/bin/env bash
# Redraws the pictures of docs/ from the examples (whole meshes, as the CLI draws them), and
# the README's close-ups of boundary layers.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh release >/dev/null
for name in fig9 fig10 fig11 naca0012; do
  build/cli/meshd-cli "examples/$name.json" -o "docs/$name.svg" --quiet
done
echo "wrote docs/fig9.svg docs/fig10.svg docs/fig11.svg docs/naca0012.svg"

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# The NACA 0012 example with layers: first height 1e-4, growth 1.15, 30 layers.
/usr/bin/python3 - "$tmp/naca_layers.json" <<'PY'
import json, sys
r = json.load(open("examples/naca0012.json"))
r["boundary_layers"] = [{"curves": ["wing"], "first_height": 1e-4, "growth": 1.15, "layers": 30}]
json.dump(r, open(sys.argv[1], "w"))
PY
# Three holes of radius 0.3, 0.02 apart, whose layers may reach 0.05.
cat > "$tmp/holes.json" <<'JSON'
{
  "geometry": {
    "points": { "A": [0, 0], "B": [4, 0], "C": [4, 2], "D": [0, 2],
                "h0": [1.68, 1.0], "h1": [2.3, 1.0], "h2": [2.92, 1.0] },
    "curves": {
      "bottom": { "type": "line", "from": "A", "to": "B" },
      "right": { "type": "line", "from": "B", "to": "C" },
      "top": { "type": "line", "from": "C", "to": "D" },
      "left": { "type": "line", "from": "D", "to": "A" },
      "h0": { "type": "arc", "from": "h0", "to": "h0", "center": [1.38, 1.0], "tag": "hole" },
      "h1": { "type": "arc", "from": "h1", "to": "h1", "center": [2.0, 1.0], "tag": "hole" },
      "h2": { "type": "arc", "from": "h2", "to": "h2", "center": [2.62, 1.0], "tag": "hole" }
    },
    "loops": [ ["bottom", "right", "top", "left"], ["h0"], ["h1"], ["h2"] ]
  },
  "density": { "size": "0.02" },
  "boundary_layers": [ { "curves": ["hole"], "first_height": 1e-3, "growth": 1.1, "thickness": 0.05 } ]
}
JSON
draw() { build/cli/meshd-cli "$1" -o "docs/$2.svg" --format svg --view "$3" --quiet; echo "wrote docs/$2.svg"; }
draw "$tmp/naca_layers.json" layers-leading-edge -0.015,-0.03,0.03,0.015
draw "$tmp/naca_layers.json" layers-trailing-edge 0.92,-0.0714,1.12,0.0714
draw examples/high_lift_layers.json layers-slat-gap -0.09,-0.11,0.03,0.01
draw "$tmp/holes.json" layers-cut-back 1.62,0.93,1.76,1.07
