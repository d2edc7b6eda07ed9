#!/usr/bin/python3
"""Runs the shell examples of a Markdown page against a real meshd and checks their answers.

Every ```sh block that talks to the server (it names localhost:8080) is run, in order, by
bash (-euo pipefail) in a scratch folder where `examples/` is the repository's, with
localhost:8080 pointed at a server this script starts on a free port. A block must exit 0. When the next block on the page (past blank lines only)
is a ```json block, it is the documented answer: the block's output must be JSON that holds
every member of it with the same value; a documented number with d decimals must equal the
actual one rounded to d decimals, so the page can show short figures; members the page does
not show are not compared.

usage: run_examples.py MESHD SOURCE_DIR PAGE.md [PAGE.md ...]"""
import json
import os
import re
import subprocess
import sys
import tempfile
import threading

meshd, source, pages = sys.argv[1], sys.argv[2], sys.argv[3:]
failures = []


def fail(what):
    failures.append(what)
    print("FAIL:", what)


def blocks(text):
    """(info, body, line) of every fenced block."""
    out = []
    for m in re.finditer(r"^```(\w*)\n(.*?)^```$", text, re.S | re.M):
        out.append((m.group(1), m.group(2), text.count("\n", 0, m.start()) + 1, m.start(), m.end()))
    return out


def decimals(token):
    return len(token.split(".")[1]) if "." in token else 0


def documented(body):
    """The documented answer, with each number kept as its text (for its precision)."""
    return json.loads(body, parse_float=lambda s: ("num", s), parse_int=lambda s: ("num", s))


def matches(doc, actual, where):
    if isinstance(doc, tuple):  # a number as written
        text = doc[1]
        if not isinstance(actual, (int, float)) or isinstance(actual, bool):
            return fail(f"{where}: expected a number {text}, got {actual!r}")
        d = decimals(text)
        if round(float(actual), d) != round(float(text), d):
            fail(f"{where}: documented {text}, actual {actual}")
    elif isinstance(doc, dict):
        if not isinstance(actual, dict):
            return fail(f"{where}: expected an object, got {actual!r}")
        for k, v in doc.items():
            if k not in actual:
                fail(f"{where}/{k}: documented but missing")
            else:
                matches(v, actual[k], f"{where}/{k}")
    elif isinstance(doc, list):
        if not isinstance(actual, list) or len(actual) != len(doc):
            return fail(f"{where}: documented {len(doc)} items, got {actual!r}"[:300])
        for i, (d, a) in enumerate(zip(doc, actual)):
            matches(d, a, f"{where}/{i}")
    elif doc != actual:
        fail(f"{where}: documented {doc!r}, actual {actual!r}")


def run_page(page, port):
    text = open(page, encoding="utf-8").read()
    found = blocks(text)
    ran, failed_before = 0, len(failures)
    with tempfile.TemporaryDirectory() as tmp:
        os.symlink(os.path.join(os.path.abspath(source), "examples"), os.path.join(tmp, "examples"))
        for i, (info, body, line, start, end) in enumerate(found):
            if info != "sh" or "localhost:8080" not in body:
                continue
            ran += 1
            script = body.replace("localhost:8080", "127.0.0.1:" + port)
            run = subprocess.run(["bash", "-euo", "pipefail", "-c", script], cwd=tmp, capture_output=True,
                                 text=True, timeout=300)
            where = f"{os.path.basename(page)}:{line}"
            if run.returncode != 0:
                fail(f"{where}: exit {run.returncode}: {run.stderr.strip()[:500]} {run.stdout.strip()[:500]}")
                continue
            following = found[i + 1] if i + 1 < len(found) else None
            if following and following[0] == "json" and text[end:following[3]].strip() == "":
                try:
                    actual = json.loads(run.stdout)
                except json.JSONDecodeError:
                    fail(f"{where}: the output is not JSON: {run.stdout[:300]!r}")
                    continue
                matches(documented(following[1]), actual, where)
    if ran == 0:
        fail(f"{page}: no shell examples found")
    n = len(failures) - failed_before
    print(f"{os.path.basename(page)}: {ran} examples run" + (f", {n} failures" if n else ""))


server = subprocess.Popen([meshd, "--host", "127.0.0.1", "--port", "0", "--workers", "2"],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
try:
    port = None
    for line in server.stdout:  # the server announces its port before it serves
        m = re.search(r"listening on 127\.0\.0\.1:(\d+)", line)
        if m:
            port = m.group(1)
            break
    if port is None:
        sys.exit("meshd did not start")
    # Keep reading its log, so that a full pipe never blocks it.
    threading.Thread(target=lambda: [None for _ in server.stdout], daemon=True).start()
    for page in pages:
        run_page(page, port)
finally:
    server.terminate()
    server.wait(timeout=60)
sys.exit(1 if failures else 0)
