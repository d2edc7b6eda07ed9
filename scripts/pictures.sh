#!/usr/bin/env bash
# Redraws the pictures of docs/ from the examples (whole meshes, as the CLI draws them).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh release >/dev/null
for name in fig9 fig10 fig11 naca0012; do
  build/cli/meshd-cli "examples/$name.json" -o "docs/$name.svg" --quiet
done
echo "wrote docs/fig9.svg docs/fig10.svg docs/fig11.svg docs/naca0012.svg"
