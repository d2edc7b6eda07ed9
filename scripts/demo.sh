#!/usr/bin/env bash
# Builds meshd and runs it on the built-in NACA 0012 examples (the paper's Fig. 9 and
# Fig. 10 densities): graded boundary points per curve and how closely they follow rho.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/build.sh release >/dev/null
build/tools/meshd-boundary-report
