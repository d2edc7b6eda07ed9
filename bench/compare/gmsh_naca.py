#!/usr/bin/python3
"""gmsh 2D on the benchmark case: NACA 0012 (chord 1, leading edge at the origin, closed
trailing edge, 2 x 200 points from the formula joined by splines) in a circle of radius 20
about (0.5, 0), the paper's Fig. 10 density times s as a MathEval background field (evaluated
inside gmsh, no Python callback), one thread. Prints one JSON line with the meshing time and
the same quality figures meshd reports.

usage: gmsh_naca.py S ALGORITHM     (ALGORITHM: 6 Frontal-Delaunay, 5 Delaunay)"""
import json
import math
import os
import sys
import time

import gmsh
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gmsh_case import add_naca_case  # noqa: E402

s = float(sys.argv[1])
algo = int(sys.argv[2])


def rho(x, y):
    a = 0.1 * np.sqrt(x * x + y * y) + 0.007
    b = 0.1 * np.sqrt((x - 1.008930411365) ** 2 + y * y) + 0.006
    return np.where(x < 0.5, a, b) * s


gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.option.setNumber("General.NumThreads", 1)
gmsh.model.add("naca")
add_naca_case(s)
gmsh.option.setNumber("Mesh.Algorithm", algo)

t0 = time.perf_counter()
gmsh.model.mesh.generate(2)
secs = time.perf_counter() - t0

tags, coords, _ = gmsh.model.mesh.getNodes()
xyz = coords.reshape(-1, 3)[:, :2]
index = {t: i for i, t in enumerate(tags)}
types, _, nodes = gmsh.model.mesh.getElements(2)
tri = np.array([index[t] for t in nodes[list(types).index(2)]]).reshape(-1, 3)
gmsh.finalize()

p = xyz[tri]
la = np.linalg.norm(p[:, 1] - p[:, 2], axis=1)
lb = np.linalg.norm(p[:, 2] - p[:, 0], axis=1)
lc = np.linalg.norm(p[:, 0] - p[:, 1], axis=1)
area = 0.5 * np.abs(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]))
q = 16 * area * area / (la * lb * lc * (la + lb + lc))
cosines = [(lb ** 2 + lc ** 2 - la ** 2) / (2 * lb * lc), (la ** 2 + lc ** 2 - lb ** 2) / (2 * la * lc),
           (la ** 2 + lb ** 2 - lc ** 2) / (2 * la * lb)]
angle_min = float(np.degrees(np.arccos(np.clip(np.max(cosines), -1, 1))).min())
edges = np.unique(np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1), axis=0)
mid = 0.5 * (xyz[edges[:, 0]] + xyz[edges[:, 1]])
ratio = np.linalg.norm(xyz[edges[:, 0]] - xyz[edges[:, 1]], axis=1) / rho(mid[:, 0], mid[:, 1])
within = float(np.mean((ratio >= 1 / math.sqrt(2)) & (ratio <= math.sqrt(2))))
print(json.dumps({"tool": "gmsh " + {6: "Frontal-Delaunay", 5: "Delaunay"}.get(algo, str(algo)), "case": "naca", "s": s,
                  "points": int(len(xyz)), "triangles": int(len(tri)), "ms": round(secs * 1000, 1),
                  "quality_mean": round(float(q.mean()), 4), "quality_min": round(float(q.min()), 4),
                  "angle_min": round(angle_min, 2), "within_sqrt2": round(within, 4)}))
