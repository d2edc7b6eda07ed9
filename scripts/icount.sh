#!/usr/bin/env bash
# Instructions the pipeline runs on a request (a benchmark, not a test): callgrind's count
# inside generate_mesh, which does not drift with the machine's speed as times do, so that
# a change to the code's constant factors can be judged in one run on a noisy VM.
# Usage: scripts/icount.sh [request.json ...]   (default: the load run's square)
set -euo pipefail
cd "$(dirname "$0")/.."
command -v valgrind >/dev/null || { sudo=""; [ "$(id -u)" -ne 0 ] && sudo=sudo; $sudo apt-get install -y -qq valgrind; }
scripts/build.sh release >/dev/null
[ $# -gt 0 ] || set -- bench/load/small_square.json
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
for request in "$@"; do
  valgrind --tool=callgrind --callgrind-out-file="$out/cg" \
    --toggle-collect='meshd::core::generate_mesh(meshd::core::Domain const&*' \
    build/cli/meshd-cli "$request" -o "$out/mesh.msh" --format msh --quiet >/dev/null 2>&1
  printf '%s: %s instructions\n' "$request" "$(callgrind_annotate "$out/cg" | awk '/PROGRAM TOTALS/ {print $1; exit}')"
done
