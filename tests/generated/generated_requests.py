#!/usr/bin/python3
"""Meshes the first N requests of each request generator (fuzz/general_requests.py and
fuzz/layered_requests.py) with meshd-cli, two at a time, and holds every answer to what any
mesh must be:

- an answer, or a 4xx problem of the kinds a random domain can earn (curves that cross, a mesh
  over the requests' 3,000 points); never a crash or a 5xx;
- every cell counter-clockwise with positive area, every boundary and embedded edge an edge of
  a cell, V - E + F = 1 - holes over the cells' corners;
- without layers, with the default smoothing and `min_angle_deg` 0 or 30 and up, no free angle
  (one not between two boundary edges) below 30 degrees, except within four of its triangle's
  longest edges of an input corner sharper than 60 degrees (there no mesh avoids small
  angles: two constrained edges that meet at a few degrees).

usage: generated_requests.py MESHD_CLI FUZZ_DIR [N]"""
import concurrent.futures
import json
import math
import os
import subprocess
import sys
import tempfile
from collections import defaultdict

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "formats"))
from common import check, finish  # noqa: E402

cli, fuzz_dir = sys.argv[1], sys.argv[2]
count = int(sys.argv[3]) if len(sys.argv) > 3 else 150
sys.path.insert(0, fuzz_dir)
import general_requests  # noqa: E402
import layered_requests  # noqa: E402

REFUSALS = {"/v1/problems/curves-cross", "/v1/problems/too-many-points"}


def angle(p, a, b):
    ux, uy, wx, wy = a[0] - p[0], a[1] - p[1], b[0] - p[0], b[1] - p[1]
    return math.degrees(math.atan2(ux * wy - uy * wx, ux * wx + uy * wy))


def examine(name, request, mesh):
    """The checks of one mesh; returns the worst free angle found (or None)."""
    pts = mesh["points"]
    cells = [t[:3] for t in mesh["triangles"]] + [q[:4] for q in mesh.get("quads", [])]
    for c in cells:
        n = len(c)
        area2 = sum(pts[c[i]][0] * pts[c[(i + 1) % n]][1] - pts[c[(i + 1) % n]][0] * pts[c[i]][1] for i in range(n))
        if not area2 > 0.0:
            check(False, f"{name}: cell {c} is not counter-clockwise with positive area")
            return None
    edges = set()
    for c in cells:
        for i in range(len(c)):
            a, b = c[i], c[(i + 1) % len(c)]
            edges.add((min(a, b), max(a, b)))
    constrained = set()
    for tag, es in mesh["boundaries"].items():
        for e in es:
            key = (min(e[0], e[1]), max(e[0], e[1]))
            constrained.add(key)
            if key not in edges:
                check(False, f"{name}: boundary edge {e[:2]} ({tag}) is not a mesh edge")
                return None
    corners = {v for c in cells for v in c}
    holes = len(request["geometry"]["loops"]) - 1
    check(len(corners) - len(edges) + len(cells) == 1 - holes,
          f"{name}: V - E + F = {len(corners) - len(edges) + len(cells)}, not 1 - {holes}")

    options = request.get("options", {})
    bound = options.get("min_angle_deg", 0)
    if "boundary_layers" in request or options.get("smoothing_iterations", 5) < 5 or 0 < bound < 30:
        return None
    # Input corners: around each vertex, the sectors between its constrained edges.
    sectors = defaultdict(list)  # vertex -> (triangle's other two corners, angle)
    worst, worst_at, worst_tri = 180.0, None, None
    for t in mesh["triangles"]:
        v = t[:3]
        for i in range(3):
            p, a, b = v[i], v[(i + 1) % 3], v[(i + 2) % 3]
            g = angle(pts[p], pts[a], pts[b])
            sectors[p].append((a, b, g))
            if (min(p, a), max(p, a)) in constrained and (min(p, b), max(p, b)) in constrained:
                continue
            if g < worst:
                worst, worst_at, worst_tri = g, p, v
    if worst >= 30.0:
        return worst
    sharp = []
    for p, around in sectors.items():
        # Corners joined across free edges at p add up to a sector.
        parent = list(range(len(around)))

        def root(k):
            while parent[k] != k:
                parent[k] = parent[parent[k]]
                k = parent[k]
            return k

        by_end = defaultdict(list)
        for k, (a, b, _) in enumerate(around):
            by_end[a].append(k)
            by_end[b].append(k)
        for o, ks in by_end.items():
            if (min(p, o), max(p, o)) not in constrained:
                for k in ks[1:]:
                    parent[root(k)] = root(ks[0])
        sums = defaultdict(float)
        for k, (_, _, g) in enumerate(around):
            sums[root(k)] += g
        if min(sums.values()) < 60.0:
            sharp.append(p)
    longest = max(math.dist(pts[worst_tri[i]], pts[worst_tri[(i + 1) % 3]]) for i in range(3))
    near = any(math.dist(pts[p], pts[worst_at]) <= 4.0 * longest for p in sharp)
    check(near, f"{name}: a free angle of {worst:.2f} degrees at {pts[worst_at]}, "
                f"no input corner below 60 degrees near it")
    return None if near else worst


def run(job):
    name, request = job
    with tempfile.TemporaryDirectory() as tmp:
        path, out = os.path.join(tmp, "request.json"), os.path.join(tmp, "mesh.json")
        with open(path, "w") as f:
            json.dump(request, f)
        r = subprocess.run([cli, path, "-o", out, "--quiet"], capture_output=True, text=True, timeout=300)
        if r.returncode != 0:
            try:
                problem = json.loads(r.stderr)
            except ValueError:
                return name, request, None, f"exit {r.returncode}: {(r.stdout + r.stderr)[:300]}"
            if problem.get("type") in REFUSALS:
                return name, request, None, None
            return name, request, None, f"refused: {r.stderr[:300]}"
        with open(out) as f:
            return name, request, json.load(f)["mesh"], None


jobs = [(f"general-{s}", general_requests.request(s)) for s in range(1, count + 1)]
jobs += [(f"layered-{s}", layered_requests.request(s)) for s in range(1, count + 1)]
meshed, angles = 0, []
with concurrent.futures.ThreadPoolExecutor(2) as pool:
    for name, request, mesh, error in pool.map(run, jobs):
        check(error is None, f"{name}: {error}")
        if mesh is None:
            continue
        meshed += 1
        a = examine(name, request, mesh)
        if a is not None:
            angles.append(a)
check(meshed >= len(jobs) * 0.8, f"only {meshed} of {len(jobs)} requests meshed")
finish(f"generated requests: {meshed} of {len(jobs)} meshed and valid; {len(angles)} held to 30 degrees, "
       f"the least free angle {min(angles):.2f}")
