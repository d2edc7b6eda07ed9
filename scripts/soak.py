#!/usr/bin/python3
"""Soak: mixed traffic against a real meshd on loopback for a bounded time, at 64 connections.

Usage: scripts/soak.py [--seconds 180] [--connections 64] [--server build/server/meshd] [--out out/soak]

Starts the server itself (a free port, 2 workers, queue 64, finished jobs kept 30 s), then
each connection loops over: good meshes (sync), bad requests (the catalogue of
tests/data/bad_requests.json), async jobs (half of them cancelled midway, the rest fetched),
clients that go away early (half a body, or a whole request and no reading), and probes
(/healthz, /readyz, /metrics). It samples the server's resident memory every second.

At the end it waits for the queue to empty and reports: answers by status, 5xx (must be 0),
jobs left queued or running (must be 0), the server's job counters beside what the clients
saw, and memory after warm-up against the end (must stay flat). Writes summary.json,
summary.md and memory.svg to --out; exits 1 when a check fails.
"""
import argparse
import http.client
import json
import os
import random
import socket
import subprocess
import sys
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

SQUARE = {"points": {"A": [0, 0], "B": [1, 0], "C": [1, 1], "D": [0, 1]},
          "curves": {"b": {"type": "line", "from": "A", "to": "B", "tag": "wall"},
                     "r": {"type": "line", "from": "B", "to": "C", "tag": "outlet"},
                     "t": {"type": "line", "from": "C", "to": "D", "tag": "wall"},
                     "l": {"type": "line", "from": "D", "to": "A", "tag": "inlet"}},
          "loops": [["b", "r", "t", "l"]]}


def good_request(rng):
    kind = rng.random()
    if kind < 0.6:
        return {"geometry": SQUARE, "density": {"size": rng.choice([0.02, 0.03, 0.05])}}
    if kind < 0.9:
        with open(os.path.join(ROOT, "examples", "naca0012.json")) as f:
            return json.load(f)
    # A larger job, so that cancellations find it running.
    return {"geometry": SQUARE, "density": {"size": 0.004}}


def free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def rss_kb(pid):
    with open("/proc/%d/status" % pid) as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    return 0


class Tally:
    def __init__(self):
        self.lock = threading.Lock()
        self.status = {}
        self.kinds = {}
        self.pairs = {}
        self.errors = []
        self.async_succeeded = 0
        self.async_cancelled = 0
        self.sync_ok = 0

    def add(self, kind, status):
        with self.lock:
            self.status[status] = self.status.get(status, 0) + 1
            self.kinds[kind] = self.kinds.get(kind, 0) + 1
            self.pairs[(kind, status)] = self.pairs.get((kind, status), 0) + 1

    def error(self, what):
        with self.lock:
            if len(self.errors) < 20:
                self.errors.append(what)


def run_connection(port, deadline, rng, tally, catalogue):
    conn = http.client.HTTPConnection("127.0.0.1", port, timeout=60)

    def call(method, path, body=None, kind="other"):
        nonlocal conn
        headers = {"Content-Type": "application/json"} if body is not None else {}
        data = body if isinstance(body, (bytes, type(None))) else body.encode()
        try:
            conn.request(method, path, body=data, headers=headers)
            r = conn.getresponse()
            payload = r.read()
        except (OSError, http.client.HTTPException) as e:
            tally.error("%s %s: %r" % (method, path, e))
            conn.close()
            conn = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
            tally.add(kind, "connection error")
            return None, b""
        tally.add(kind, r.status)
        return r.status, payload

    def wait_for(job, tries):
        # Polls the job until it ends (or stops answering 200); its last answer.
        status, payload = None, b""
        for _ in range(tries):
            status, payload = call("GET", "/v1/jobs/" + job, None, "poll")
            if status != 200 or json.loads(payload)["status"] in ("cancelled", "succeeded", "failed"):
                break
            time.sleep(0.05)
        return status, payload

    while time.time() < deadline:
        x = rng.random()
        if x < 0.40:
            status, _ = call("POST", "/v1/meshes?format=json", json.dumps(good_request(rng)), "good sync")
            if status == 200:
                with tally.lock:
                    tally.sync_ok += 1
        elif x < 0.60:
            case = rng.choice(catalogue)
            body = case["raw"] if "raw" in case else json.dumps(case["body"])
            status, _ = call("POST", "/v1/meshes?format=json", body, "bad")
            if status is not None and status != case["status"] and status not in (429, 503):
                tally.error("%s: %s, expected %s" % (case["name"], status, case["status"]))
        elif x < 0.75:
            status, payload = call("POST", "/v1/jobs", json.dumps(good_request(rng)), "async")
            if status != 202:
                continue
            job = json.loads(payload)["id"]
            if rng.random() < 0.5:
                call("DELETE", "/v1/jobs/" + job, None, "cancel")
                status, payload = wait_for(job, 600)
                if status == 200 and json.loads(payload)["status"] == "cancelled":
                    with tally.lock:
                        tally.async_cancelled += 1
            else:
                status, payload = wait_for(job, 1200)
                if status == 200 and json.loads(payload)["status"] == "succeeded":
                    status, _ = call("GET", "/v1/jobs/%s/mesh?format=vtk" % job, None, "fetch")
                    if status == 200:
                        with tally.lock:
                            tally.async_succeeded += 1
        elif x < 0.85:
            # A client that goes away: half a body, or a whole request and no reading.
            body = json.dumps(good_request(rng)).encode()
            head = ("POST /v1/meshes?format=json HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
                    "Content-Length: %d\r\n\r\n" % len(body)).encode()
            try:
                s = socket.create_connection(("127.0.0.1", port), timeout=10)
                s.sendall(head + (body[: len(body) // 2] if rng.random() < 0.5 else body))
                s.close()
                tally.add("gone early", "closed")
            except OSError as e:
                tally.error("gone early: %r" % e)
        else:
            path = rng.choice(["/healthz", "/readyz", "/metrics"])
            call("GET", path, None, "probe " + path)
    conn.close()


def metrics(port):
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
    c.request("GET", "/metrics")
    text = c.getresponse().read().decode()
    c.close()
    out = {}
    for line in text.splitlines():
        if line and not line.startswith("#"):
            name, value = line.rsplit(" ", 1)
            out[name] = float(value)
    return out


def svg_plot(samples, path, warm):
    w, h, pad = 640, 260, 46
    t_max = max(t for t, _ in samples) or 1
    m_max = max(m for _, m in samples) * 1.1 or 1
    pts = " ".join("%.1f,%.1f" % (pad + (w - 2 * pad) * t / t_max, h - pad - (h - 2 * pad) * m / m_max)
                   for t, m in samples)
    xw = pad + (w - 2 * pad) * warm / t_max
    lines = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif" font-size="12">' % (w, h),
             '<rect width="100%" height="100%" fill="white"/>',
             '<line x1="%d" y1="%d" x2="%d" y2="%d" stroke="black"/>' % (pad, h - pad, w - pad, h - pad),
             '<line x1="%d" y1="%d" x2="%d" y2="%d" stroke="black"/>' % (pad, pad, pad, h - pad),
             '<line x1="%.1f" y1="%d" x2="%.1f" y2="%d" stroke="#999" stroke-dasharray="4"/>' % (xw, pad, xw, h - pad),
             '<text x="%.1f" y="%d" fill="#666">warm-up</text>' % (xw + 4, pad + 12),
             '<polyline fill="none" stroke="#1f77b4" stroke-width="1.5" points="%s"/>' % pts,
             '<text x="%d" y="%d" text-anchor="middle">time (s), 0 to %.0f</text>' % (w / 2, h - 12, t_max),
             '<text x="14" y="%d" transform="rotate(-90 14 %d)" text-anchor="middle">server RSS (MB), 0 to %.0f</text>' % (h / 2, h / 2, m_max),
             '<text x="%d" y="20">meshd resident memory under mixed traffic</text>' % pad,
             '</svg>']
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=float, default=180)
    ap.add_argument("--connections", type=int, default=64)
    ap.add_argument("--server", default=os.path.join(ROOT, "build", "server", "meshd"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "soak"))
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    catalogue = json.load(open(os.path.join(ROOT, "tests", "data", "bad_requests.json")))["cases"]
    # Cases whose answer depends on the server's own limits are left out.
    catalogue = [c for c in catalogue if c["status"] in (400, 415, 422)]

    port = free_port()
    server = subprocess.Popen([args.server, "--port", str(port), "--workers", "2", "--queue", "64",
                               "--http-threads", "96", "--job-ttl-s", "30", "--log-level", "error"])
    for _ in range(100):
        try:
            socket.create_connection(("127.0.0.1", port), timeout=1).close()
            break
        except OSError:
            time.sleep(0.05)

    tally = Tally()
    start = time.time()
    deadline = start + args.seconds
    samples = []
    stop = threading.Event()

    def sample():
        while not stop.is_set():
            samples.append((time.time() - start, rss_kb(server.pid) / 1024.0))
            stop.wait(1.0)

    sampler = threading.Thread(target=sample)
    sampler.start()
    threads = [threading.Thread(target=run_connection, args=(port, deadline, random.Random(i), tally, catalogue))
               for i in range(args.connections)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    # Drain: nothing queued or running once the clients are done.
    m = {}
    for _ in range(600):
        m = metrics(port)
        if m.get("meshd_queue_depth", 1) == 0 and m.get("meshd_workers_busy", 1) == 0:
            break
        time.sleep(0.1)
    stop.set()
    sampler.join()
    elapsed = time.time() - start
    server.terminate()
    server.wait(timeout=60)

    warm = min(30.0, args.seconds / 4)
    after_warm = [mb for t, mb in samples if t >= warm]
    warm_mb = after_warm[0] if after_warm else 0
    end_mb = samples[-1][1] if samples else 0
    peak_mb = max(mb for _, mb in samples) if samples else 0
    # Readiness is about draining only (API.md): a 503 from /readyz is an error here too.
    five = sum(n for (kind, st), n in tally.pairs.items() if isinstance(st, int) and st >= 500)
    summary = {
        "seconds": round(elapsed, 1), "connections": args.connections,
        "requests": sum(tally.kinds.values()), "by_kind": tally.kinds,
        "by_status": {str(k): v for k, v in sorted(tally.status.items(), key=lambda kv: str(kv[0]))},
        "answers_5xx": five,
        "jobs_left_queued_or_running": int(m.get("meshd_queue_depth", -1) + m.get("meshd_workers_busy", -1)),
        "server_jobs": {k: int(v) for k, v in m.items() if k.startswith("meshd_jobs_total")},
        "client_saw": {"sync meshes 200": tally.sync_ok, "async fetched": tally.async_succeeded,
                       "async cancelled": tally.async_cancelled},
        "rss_mb": {"after_warm_up": round(warm_mb, 1), "end": round(end_mb, 1), "peak": round(peak_mb, 1)},
        "client_errors": tally.errors,
    }
    succeeded = m.get('meshd_jobs_total{status="succeeded"}', 0)
    cancelled = m.get('meshd_jobs_total{status="cancelled"}', 0)
    checks = {
        "no 5xx": five == 0,
        "no job left queued or running": summary["jobs_left_queued_or_running"] == 0,
        "server counted every success the clients saw": succeeded >= tally.sync_ok + tally.async_succeeded,
        "server counted every cancellation the clients saw": cancelled >= tally.async_cancelled,
        "memory flat after warm-up (end within 1.5 x, +64 MB)": end_mb <= 1.5 * warm_mb + 64,
        "no client errors": not tally.errors,
    }
    summary["checks"] = checks
    with open(os.path.join(args.out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=2)
    svg_plot(samples, os.path.join(args.out, "memory.svg"), warm)
    rows = ["| figure | value |", "|---|---|"]
    rows.append("| duration, connections | %.0f s, %d |" % (elapsed, args.connections))
    rows.append("| requests (and early disconnects) | %d |" % summary["requests"])
    rows.append("| by kind | %s |" % ", ".join("%s %d" % kv for kv in sorted(tally.kinds.items())))
    rows.append("| by status | %s |" % ", ".join("%s: %d" % kv for kv in summary["by_status"].items()))
    rows.append("| 5xx answers | %d |" % five)
    rows.append("| jobs left queued or running | %d |" % summary["jobs_left_queued_or_running"])
    rows.append("| server's jobs (succeeded / failed / cancelled) | %d / %d / %d |" % (
        succeeded, m.get('meshd_jobs_total{status="failed"}', 0), cancelled))
    rows.append("| clients saw (sync 200, async fetched, async cancelled) | %d, %d, %d |" % (
        tally.sync_ok, tally.async_succeeded, tally.async_cancelled))
    rows.append("| server RSS after warm-up / end / peak | %.0f / %.0f / %.0f MB |" % (warm_mb, end_mb, peak_mb))
    with open(os.path.join(args.out, "summary.md"), "w") as f:
        f.write("\n".join(rows) + "\n")
    print("\n".join(rows))
    for name, ok in checks.items():
        print("%s: %s" % ("ok  " if ok else "FAIL", name))
    for e in tally.errors:
        print("client error:", e)
    sys.exit(0 if all(checks.values()) else 1)


if __name__ == "__main__":
    main()
