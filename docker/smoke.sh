#!/usr/bin/env bash
# Smoke test of the image: starts a container on a loopback port, waits for /healthz, posts
# the NACA 0012 example, checks the mesh and /metrics, sends SIGTERM while a job runs and
# checks that the container drains (finishes that job) and exits 0. Also checks it runs as
# a non-root user and holds no compiler. Usage: docker/smoke.sh [tag]
set -euo pipefail
cd "$(dirname "$0")/.."
tag="${1:-localhost/meshd:latest}"
sudo=""
[ "$(id -u)" -ne 0 ] && sudo=sudo
port=18480
name="meshd-smoke-$$"
fail() { echo "SMOKE FAIL: $*" >&2; $sudo podman logs "$name" >&2 || true; exit 1; }
cleanup() { $sudo podman rm -f "$name" >/dev/null 2>&1 || true; }
trap cleanup EXIT

start=$(date +%s.%N)
$sudo podman run -d --name "$name" -p "127.0.0.1:$port:8080" "$tag" --workers 1 --drain-s 30 >/dev/null
for _ in $(seq 100); do curl -fs "http://127.0.0.1:$port/healthz" >/dev/null 2>&1 && break; sleep 0.1; done
curl -fs "http://127.0.0.1:$port/healthz" >/dev/null || fail "no /healthz"
ready=$(date +%s.%N)
python3 -c "import sys; print(\"started and healthy in %.2f s\" % (float(sys.argv[2]) - float(sys.argv[1])))" "$start" "$ready"
$sudo podman healthcheck run "$name" >/dev/null || fail "HEALTHCHECK failed"

# Non-root, no compiler.
uid=$($sudo podman exec "$name" id -u)
[ "$uid" != "0" ] || fail "runs as root"
if $sudo podman exec "$name" sh -c 'command -v cc || command -v gcc || command -v g++ || command -v c++' >/dev/null 2>&1; then
  fail "the image holds a compiler"
fi

# The web page, from the binary.
page=$(curl -fs "http://127.0.0.1:$port/") || fail "no page at /"
grep -q '<title>meshd' <<<"$page" || fail "the page at / is not meshd's"
curl -fs "http://127.0.0.1:$port/ui/app.js" >/dev/null || fail "no /ui/app.js"

# The example mesh.
out=$(mktemp)
code=$(curl -s -o "$out" -w '%{http_code}' -X POST -H 'Content-Type: application/json' \
  --data-binary @examples/naca0012.json "http://127.0.0.1:$port/v1/meshes")
[ "$code" = 200 ] || fail "POST /v1/meshes answered $code"
python3 - "$out" <<'PY' || fail "the mesh is not right"
import json, sys
r = json.load(open(sys.argv[1]))
m, k = r["mesh"], r["metrics"]
assert len(m["triangles"]) == k["triangles"] > 1000, "triangle count"
assert len(m["points"]) == k["points"], "point count"
assert set(m["boundaries"]) == {"wall", "farfield"}, "tags"
assert all(0 <= i < len(m["points"]) for t in m["triangles"] for i in t), "indices"
assert k["quality"]["mean"] > 0.9, "quality"
print("mesh:", k["points"], "points,", k["triangles"], "triangles, mean radius ratio", round(k["quality"]["mean"], 3))
PY
metrics=$(curl -fs "http://127.0.0.1:$port/metrics")
grep -q 'meshd_jobs_total{status="succeeded"} 1' <<<"$metrics" || fail "/metrics does not count the job"

# A job that runs a few seconds, then SIGTERM: it must finish, and the container exit 0.
slow='{"geometry":{"points":{"A":[0,0],"B":[1,0],"C":[1,1],"D":[0,1]},"curves":{"b":{"type":"line","from":"A","to":"B"},"r":{"type":"line","from":"B","to":"C"},"t":{"type":"line","from":"C","to":"D"},"l":{"type":"line","from":"D","to":"A"}},"loops":[["b","r","t","l"]]},"density":{"size":0.002}}'
id=$(curl -fs -X POST -H 'Content-Type: application/json' -d "$slow" "http://127.0.0.1:$port/v1/jobs" | python3 -c 'import json,sys; print(json.load(sys.stdin)["id"])')
sleep 0.3
$sudo podman stop -t 60 "$name" >/dev/null
status=$($sudo podman inspect "$name" --format '{{.State.ExitCode}}')
[ "$status" = 0 ] || fail "exit code $status after SIGTERM"
logs=$($sudo podman logs "$name" 2>&1)
grep -q "job $id succeeded" <<<"$logs" || fail "the running job was not finished before exit"
echo "drained: job $id finished, exit code 0"
echo "SMOKE OK"
