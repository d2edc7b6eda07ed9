#!/usr/bin/env bash
# Installs the Debian packages meshd builds, tests and benchmarks with.
# Safe to run again; needs root (or sudo) on a Debian 12 (bookworm) machine.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkgconf curl jq
  nlohmann-json3-dev libspdlog-dev libcpp-httplib-dev
  # the shared job store: the C client, and the server the tests start; SHA-256 of API keys;
  # the load balancer in front of replicas (docker/haproxy.cfg, tested for real)
  libhiredis-dev redis-server libssl-dev haproxy
  # CGNS (format=cgns) and what the tests check its files with
  libcgns-dev cgns-convert python3-h5py
  libgtest-dev libgmock-dev libbenchmark-dev
  # the readers the tests read our files back with
  python3 python3-numpy python3-meshio python3-vtk9 gmsh python3-gmsh python3-dolfinx
  openfoam
  # the browser the web page's tests drive (tests/web, puppeteer-core from npm)
  chromium
  # older and other x86-64 processors, emulated (tests/build: the build's instruction set)
  qemu-user
  # the fuzz harnesses (scripts/fuzz.sh): Clang with libFuzzer and its sanitizer runtimes
  clang-16 libfuzzer-16-dev libclang-rt-16-dev
)

# Node.js runs the OpenAPI check and the manifest validation (the machine's own, else Debian's).
command -v npm >/dev/null 2>&1 || packages+=(nodejs npm)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  echo "setup: installing ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# The npm packages of the OpenAPI check (pinned in its package-lock.json).
cd "$(dirname "$0")/.."
if [ ! -d tests/openapi/node_modules ]; then
  (cd tests/openapi && npm ci --no-audit --no-fund --silent)
fi
# puppeteer-core for the web page's tests (it drives Debian's chromium; it downloads no browser).
if [ ! -d tests/web/node_modules ]; then
  (cd tests/web && npm ci --no-audit --no-fund --silent)
fi
