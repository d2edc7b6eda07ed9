#!/usr/bin/env bash
# Load run (a benchmark, not a test): a meshd server on a loopback port, wrk posting a small
# mesh request (about 5,000 triangles) at 64 connections for 30 s. Prints requests per
# second, p50/p99 latency, the count of 5xx answers, the server's CPU per answer and the same
# mesh's time without HTTP before and after the run. Usage: scripts/load.sh [seconds]
set -euo pipefail
cd "$(dirname "$0")/.."
secs="${1:-30}"
command -v wrk >/dev/null || { sudo=""; [ "$(id -u)" -ne 0 ] && sudo=sudo; $sudo apt-get install -y -qq wrk; }
scripts/build.sh release >/dev/null
# The pipeline alone on one core, before and after the run (BM_SmallRequest: this request's
# mesh without HTTP): these VMs change speed by a quarter or more from one quarter of an hour
# to the next, and a load figure means little without the machine's speed in the same minutes.
yardstick() {
  [ -x build/bench/meshd_bench ] || { echo "n/a"; return; }
  build/bench/meshd_bench --benchmark_filter='^BM_SmallRequest$' --benchmark_min_time=1 2>/dev/null |
    awk '/^BM_SmallRequest/ { printf "%s %s", $2, $3 }'
}
before=$(yardstick)
port=18181
# Room for every connection in the queue: the load measures throughput, not refusals.
build/server/meshd --port "$port" --workers "$(nproc)" --queue 64 --log-level warn &
pid=$!
trap 'kill $pid 2>/dev/null || true' EXIT
for _ in $(seq 50); do curl -fs "http://127.0.0.1:$port/healthz" >/dev/null && break; sleep 0.1; done
curl -fs -X POST -H 'Content-Type: application/json' --data-binary @bench/load/small_square.json \
  "http://127.0.0.1:$port/v1/meshes" | python3 -c 'import json,sys; m=json.load(sys.stdin)["metrics"]; print("mesh:", m["points"], "points,", m["triangles"], "triangles")'
# The server's CPU time and answered meshes around the run: what one answer costs the server,
# and so the rate the cores would make if the server had them to itself (wrk and the kernel's
# side of loopback take the rest).
counts() {
  awk '/^process_cpu_seconds_total / { cpu = $2 }
       /^meshd_http_requests_total\{route="\/v1\/meshes",status="200"\}/ { ok = $2 }
       END { printf "%s %d\n", cpu, ok }' <<<"$1"
}
read -r cpu0 ok0 < <(counts "$(curl -fs "http://127.0.0.1:$port/metrics")")
MESHD_LOAD_REQUEST=bench/load/small_square.json wrk -t 4 -c 64 -d "${secs}s" --latency -s bench/load/post.lua \
  "http://127.0.0.1:$port/v1/meshes"
after=$(curl -fs "http://127.0.0.1:$port/metrics")
read -r cpu1 ok1 < <(counts "$after")
grep -E '^meshd_http_requests_total\{route="/v1/meshes"' <<<"$after"
awk -v c0="$cpu0" -v c1="$cpu1" -v n0="$ok0" -v n1="$ok1" -v cores="$(nproc)" 'BEGIN {
  n = n1 - n0; if (n <= 0) exit
  ms = 1000 * (c1 - c0) / n
  printf "server CPU per answered mesh: %.2f ms (%d answers); %d cores make at most %.0f requests/s at that cost\n", ms, n, cores, 1000 * cores / ms
}'
kill -TERM $pid
wait $pid
echo "server exited $?"
echo "the same mesh without HTTP on one core (BM_SmallRequest): $before before the run, $(yardstick) after"
