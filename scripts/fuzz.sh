#!/usr/bin/env bash
# Builds the libFuzzer harnesses (fuzz/) with Clang 16 under AddressSanitizer and
# UndefinedBehaviorSanitizer, and runs each on its seed corpus for SECONDS (default 60).
# Usage: scripts/fuzz.sh [SECONDS] [HARNESS...]
# New inputs found go to build-fuzz/corpus/<harness>/ (the seeds in fuzz/corpus/ are read
# only); a crash, a leak or a timeout stops the run with the input saved in build-fuzz/.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds="${1:-60}"
shift || true
harnesses=("$@")
[ ${#harnesses[@]} -gt 0 ] || harnesses=(request expression airfoil_dat triangulation)

CC=clang-16 CXX=clang++-16 cmake -S . -B build-fuzz -G Ninja \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMESHD_LTO=OFF -DMESHD_BUILD_FUZZ=ON \
  -DMESHD_SANITIZE=fuzzer-no-link,address,undefined \
  -DMESHD_BUILD_TESTS=OFF -DMESHD_BUILD_BENCH=OFF -DMESHD_BUILD_TOOLS=OFF >/dev/null
cmake --build build-fuzz -j "$(nproc 2>/dev/null || echo 2)" --target $(printf 'fuzz_%s ' "${harnesses[@]}")

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
# Stacks with function names where an LLVM symbolizer is installed (without one, addresses).
for s in /usr/lib/llvm-16/bin/llvm-symbolizer /usr/bin/llvm-symbolizer-16 /usr/bin/llvm-symbolizer; do
  if [ -x "$s" ]; then export ASAN_SYMBOLIZER_PATH="$s"; break; fi
done
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
for h in "${harnesses[@]}"; do
  mkdir -p "build-fuzz/corpus/$h"
  # The inputs of earlier findings first (each also a named test in tests/).
  regressions=(fuzz/regressions/"$h"-*)
  if [ -e "${regressions[0]}" ]; then
    "build-fuzz/fuzz/fuzz_$h" "${regressions[@]}" >/dev/null 2>&1 || {
      echo "fuzz: $h fails on a regression input" >&2; "build-fuzz/fuzz/fuzz_$h" "${regressions[@]}"; exit 1; }
  fi
  echo "fuzz: $h for ${seconds}s"
  (cd build-fuzz && "./fuzz/fuzz_$h" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 \
     -max_len=65536 -print_final_stats=1 "corpus/$h" "../fuzz/corpus/$h" 2>&1 | grep -E "^(stat::|#[0-9]+ +DONE|==|SUMMARY|INFO: seed|Done)" || true)
  # libFuzzer leaves crash-*, leak-*, timeout-* or oom-* in build-fuzz/ when it stops on a
  # finding.
  findings=$(find build-fuzz -maxdepth 1 \( -name 'crash-*' -o -name 'leak-*' -o -name 'timeout-*' -o -name 'oom-*' \))
  if [ -n "$findings" ]; then
    echo "fuzz: $h found a problem: $findings" >&2
    # A clean clone in CI keeps nothing after the run: the input goes into the log, base64
    # (save it with `base64 -d`), with what the harness says when it runs it again.
    for f in $findings; do
      echo "fuzz: the input $f, base64:" >&2
      base64 "$f" >&2
      echo "fuzz: the harness on it again:" >&2
      "build-fuzz/fuzz/fuzz_$h" "$f" 2>&1 | tail -n 60 >&2 || true
    done
    exit 1
  fi
done
