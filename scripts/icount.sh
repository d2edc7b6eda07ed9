#!/usr/bin/env bash
# Instructions a request costs (a benchmark, not a test): callgrind's counts for the CLI
# meshing it and writing the JSON answer, as the server's sync route does, which do not drift
# with the machine's speed as times do, so that a change to the code's constant factors can
# be judged in one run on a noisy VM. Prints the pipeline (generate_mesh), the JSON answer
# (write_json), reading the request (parse_request) and the whole (main; the CLI's own start
# and the first use of static tables included).
# Usage: scripts/icount.sh [request.json ...]   (default: the load run's square)
set -euo pipefail
cd "$(dirname "$0")/.."
command -v valgrind >/dev/null || { sudo=""; [ "$(id -u)" -ne 0 ] && sudo=sudo; $sudo apt-get install -y -qq valgrind; }
scripts/build.sh release >/dev/null
[ $# -gt 0 ] || set -- bench/load/small_square.json
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
for request in "$@"; do
  valgrind --tool=callgrind --callgrind-out-file="$out/cg" --toggle-collect='main' \
    build/cli/meshd-cli "$request" -o "$out/mesh.json" --format json --quiet >/dev/null 2>&1
  callgrind_annotate --inclusive=yes --threshold=100 "$out/cg" | awk -v r="$request" '
    function count(s) { gsub(",", "", s); return s + 0 }
    /PROGRAM TOTALS/ { total = count($1) }
    /meshd::core::generate_mesh\(meshd::core::Domain const&/ && !mesh { mesh = count($1) }
    /meshd::api::write_json\(/ && !json { json = count($1) }
    /meshd::api::parse_request\(/ && !parse { parse = count($1) }
    END { printf "%s: generate_mesh %d, write_json %d, parse_request %d, main %d instructions\n", r, mesh, json, parse, total }'
done
