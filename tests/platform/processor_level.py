#!/usr/bin/env python3
"""The x86-64 level of the build (CMakeLists.txt, MESHD_ARCH) on other processors, emulated by
qemu-user: on one older than the level, the CLI and the server refuse to start with a sentence
naming the level and the way to build for that processor (exit status 70), not a SIGILL; on the
oldest processor of the level, the CLI meshes the load run's square exactly as it does here.

Usage: processor_level.py LEVEL CLI SERVER SOURCE_DIR
"""
import os
import subprocess
import sys
import tempfile

# The newest processor model below each level, and the oldest of the level, that qemu knows
# (its emulation stops short of AVX-512: no x86-64-v4 here).
BELOW = {"x86-64-v2": "core2duo", "x86-64-v3": "Nehalem"}
AT = {"x86-64-v2": "Nehalem", "x86-64-v3": "Haswell"}


def run(args):
    return subprocess.run(args, capture_output=True, text=True, timeout=120)


def main():
    level, cli, server, source = sys.argv[1:5]
    failures = []
    request = os.path.join(source, "bench", "load", "small_square.json")
    with tempfile.TemporaryDirectory() as tmp:
        for program, args in ((cli, [request, "-o", os.path.join(tmp, "x.msh"), "--format", "msh"]),
                              (server, ["--openapi"])):
            r = run(["qemu-x86_64", "-cpu", BELOW[level], program, *args])
            name = os.path.basename(program)
            if r.returncode != 70:
                failures.append(f"{name} on {BELOW[level]}: exit status {r.returncode}, expected 70")
            for words in (f"built for {level}", "-DMESHD_ARCH=x86-64"):
                if words not in r.stderr:
                    failures.append(f"{name} on {BELOW[level]}: stderr lacks {words!r}: {r.stderr!r}")

        here, there = os.path.join(tmp, "here.msh"), os.path.join(tmp, "there.msh")
        r = run([cli, request, "-o", here, "--format", "msh", "--quiet"])
        if r.returncode != 0:
            failures.append(f"the CLI failed here: {r.stderr}")
        r = run(["qemu-x86_64", "-cpu", AT[level], cli, request, "-o", there, "--format", "msh", "--quiet"])
        if r.returncode != 0:
            failures.append(f"the CLI on {AT[level]}: exit status {r.returncode}: {r.stderr}")
        elif open(here, "rb").read() != open(there, "rb").read():
            failures.append(f"the CLI on {AT[level]} wrote another mesh than here")

    for f in failures:
        print("FAIL:", f)
    if failures:
        sys.exit(1)
    print(f"ok: refused below {level} ({BELOW[level]}), the same mesh at it ({AT[level]})")


if __name__ == "__main__":
    main()
