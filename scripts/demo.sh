#!/usr/bin/env bash
# Builds meshd and meshes the built-in NACA 0012 example (docs/api.md's request) with the CLI:
# the metrics go to the terminal, the mesh to out/naca0012.vtk (open it in ParaView) and a
# picture of the region around the airfoil to out/naca0012.svg.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh release >/dev/null
mkdir -p out
build/cli/meshd-cli examples/naca0012.json -o out/naca0012.vtk
build/cli/meshd-cli examples/naca0012.json -o out/naca0012.svg --view -0.3,-0.45,1.3,0.45 --quiet
echo "wrote out/naca0012.vtk and out/naca0012.svg"
