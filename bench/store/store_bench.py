#!/usr/bin/python3
"""The cost of the shared job store (a benchmark, not a test).

Runs the same asynchronous load (16 clients, each submitting bench/load/small_square.json as a
job, polling it every 10 ms until it ends, then fetching its mesh as SU2) against:
  memory store, one replica; Redis store, one replica; Redis with 2 and 3 replicas behind
  docker/haproxy.cfg (a real haproxy). Then one job of about a million triangles through each
  store: the time to store its result (the finish operation) and to fetch it (GET .../mesh).

Prints a Markdown table. Usage: bench/store/store_bench.py [jobs per run] (build first).
"""
import http.client
import json
import os
import re
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
MESHD = os.path.join(ROOT, "build", "server", "meshd")
SMALL = open(os.path.join(ROOT, "bench", "load", "small_square.json"), "rb").read()
JOBS = int(sys.argv[1]) if len(sys.argv) > 1 else 400
CLIENTS = 16


def free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    p = s.getsockname()[1]
    s.close()
    return p


def wait_http(port, path="/healthz", seconds=20):
    end = time.time() + seconds
    while time.time() < end:
        try:
            c = http.client.HTTPConnection("127.0.0.1", port, timeout=2)
            c.request("GET", path)
            if c.getresponse().status == 200:
                return
        except OSError:
            pass
        time.sleep(0.05)
    raise RuntimeError(f"nothing answers on {port}{path}")


class Procs:
    def __init__(self):
        self.procs = []
        self.dir = tempfile.mkdtemp(prefix="meshd-store-bench-")

    def start(self, args, **kw):
        p = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, **kw)
        self.procs.append(p)
        return p

    def redis(self):
        port = free_port()
        self.start(["redis-server", "--port", str(port), "--bind", "127.0.0.1", "--save", "", "--appendonly", "no",
                    "--dir", self.dir])
        end = time.time() + 10
        while time.time() < end:
            try:
                socket.create_connection(("127.0.0.1", port), timeout=1).close()
                return f"redis://127.0.0.1:{port}/0"
            except OSError:
                time.sleep(0.05)
        raise RuntimeError("redis-server did not start")

    def meshd(self, store, workers):
        port, probe = free_port(), free_port()
        self.start([MESHD, "--port", str(port), "--probe-port", str(probe), "--workers", str(workers), "--queue", "1000",
                    "--store", store, "--log-level", "warn"])
        wait_http(port)
        return port, probe

    def haproxy(self, replicas):
        cfg = open(os.path.join(ROOT, "docker", "haproxy.cfg")).read()
        port = free_port()
        cfg = cfg.replace("bind :8080", f"bind 127.0.0.1:{port}").replace("option httplog\n", "")
        cfg = re.sub(r"^\s*log stdout.*\n", "", cfg, flags=re.M)
        cfg = re.sub(r"^\s*server meshd-\d+ meshd-\d+:8080\n", "", cfg, flags=re.M)
        for i, (p, probe) in enumerate(replicas):
            cfg += f"    server meshd-{i + 1} 127.0.0.1:{p} port {probe}\n"
        path = os.path.join(self.dir, "haproxy.cfg")
        open(path, "w").write(cfg)
        self.start(["haproxy", "-db", "-f", path])
        wait_http(port, "/readyz")
        time.sleep(4.5)  # until every server has passed its two health checks (inter 2 s, rise 2)
        return port

    def stop(self):
        for p in self.procs:
            p.send_signal(signal.SIGKILL)
            p.wait()
        subprocess.run(["rm", "-rf", self.dir])


def one_job(conn, body, fmt="su2"):
    conn.request("POST", "/v1/jobs", body, {"Content-Type": "application/json"})
    r = conn.getresponse()
    created = json.loads(r.read())
    if r.status != 202:
        raise RuntimeError(f"submit: {r.status} {created}")
    jid = created["id"]
    while True:
        conn.request("GET", f"/v1/jobs/{jid}")
        r = conn.getresponse()
        st = json.loads(r.read())["status"]
        if st not in ("queued", "running"):
            break
        time.sleep(0.01)
    if st != "succeeded":
        raise RuntimeError(f"job {jid} {st}")
    t0 = time.perf_counter()
    conn.request("GET", f"/v1/jobs/{jid}/mesh?format={fmt}")
    r = conn.getresponse()
    data = r.read()
    if r.status != 200:
        raise RuntimeError(f"mesh: {r.status}")
    return time.perf_counter() - t0, len(data)


def load(port, jobs):
    left = [jobs]
    lock = threading.Lock()
    errors = []

    def client():
        conn = http.client.HTTPConnection("127.0.0.1", port, timeout=120)
        while True:
            with lock:
                if left[0] == 0:
                    return
                left[0] -= 1
            try:
                one_job(conn, SMALL)
            except Exception as e:  # noqa: BLE001 - reported below
                errors.append(str(e))
                conn = http.client.HTTPConnection("127.0.0.1", port, timeout=120)

    t0 = time.perf_counter()
    threads = [threading.Thread(target=client) for _ in range(CLIENTS)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    secs = time.perf_counter() - t0
    if errors:
        print("errors:", errors[:3], file=sys.stderr)
    return jobs / secs, len(errors)


def store_seconds(port, op):
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
    c.request("GET", "/metrics")
    page = c.getresponse().read().decode()
    s = re.search(r'meshd_store_operation_duration_seconds_sum\{op="%s"\} (\S+)' % op, page)
    n = re.search(r'meshd_store_operation_duration_seconds_count\{op="%s"\} (\S+)' % op, page)
    return (float(s.group(1)), int(n.group(1))) if s and n else (0.0, 0)


def main():
    rows = []
    base = None
    for name, store, replicas in [("memory, 1 replica", "memory", 1), ("Redis, 1 replica", "redis", 1),
                                  ("Redis, 2 replicas + HAProxy", "redis", 2), ("Redis, 3 replicas + HAProxy", "redis", 3)]:
        procs = Procs()
        try:
            url = procs.redis() if store == "redis" else "memory"
            # The same two workers in all: the machine has two cores.
            workers = 2 // replicas if replicas <= 2 else 1
            reps = [procs.meshd(url, max(workers, 1)) for _ in range(replicas)]
            port = procs.haproxy(reps) if replicas > 1 else reps[0][0]
            load(port, 40)  # warm up
            rate, errs = load(port, JOBS)
            per_job_ms = 1000.0 / rate
            ops = {}
            for p, _ in reps:
                for op in ("submit", "status", "mesh", "finish"):
                    s, n = store_seconds(p, op)
                    a = ops.setdefault(op, [0.0, 0])
                    a[0] += s
                    a[1] += n
            if base is None:
                base = per_job_ms
            mean = {op: (s * 1000.0 / n if n else 0.0) for op, (s, n) in ops.items()}
            rows.append((name, rate, per_job_ms, per_job_ms - base, mean, errs))
        finally:
            procs.stop()
    print(f"{JOBS} jobs of {len(SMALL)} bytes (about 5,000 triangles), {CLIENTS} clients, 2 workers in all\n")
    print("| store | jobs/s | ms per job | over memory | submit | status | finish (result written) | mesh (read, decoded) | errors |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name, rate, per, over, mean, errs in rows:
        ops = " | ".join(f"{mean[op]:.2f} ms" if mean[op] else "-" for op in ("submit", "status", "finish", "mesh"))
        print(f"| {name} | {rate:.0f} | {per:.2f} | {over:+.2f} | {ops} | {errs} |")

    # A million triangles: time to store and to fetch.
    big = json.loads(SMALL)
    big["density"] = {"size": 0.0014}
    body = json.dumps(big).encode()
    print("\n| store | triangles | stored in (finish) | fetched as SU2 (GET .../mesh) | SU2 bytes |")
    print("|---|---:|---:|---:|---:|")
    for name, store in [("memory", "memory"), ("Redis", "redis")]:
        procs = Procs()
        try:
            url = procs.redis() if store == "redis" else "memory"
            port, _ = procs.meshd(url, 2)
            conn = http.client.HTTPConnection("127.0.0.1", port, timeout=300)
            fetch, size = one_job(conn, body)
            conn.request("GET", "/metrics")
            page = conn.getresponse().read().decode()
            tri = re.search(r"^meshd_triangles_total (\S+)", page, re.M).group(1)
            s, n = store_seconds(port, "finish")
            stored = f"{s * 1000:.0f} ms" if n else "(kept in memory)"
            print(f"| {name} | {int(float(tri)):,} | {stored} | {fetch * 1000:.0f} ms | {size:,} |")
        finally:
            procs.stop()


if __name__ == "__main__":
    main()
