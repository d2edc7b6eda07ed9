#!/usr/bin/python3
"""gmsh 2D on the benchmark case: NACA 0012 (chord 1, leading edge at the origin, closed
trailing edge, 2 x 200 points from the formula joined by splines) in a circle of radius 20
about (0.5, 0), the paper's Fig. 10 density times s as a MathEval background field (evaluated
inside gmsh, no Python callback), one thread. Prints one JSON line with the meshing time and
the same quality figures meshd reports.

usage: gmsh_naca.py S ALGORITHM     (ALGORITHM: 6 Frontal-Delaunay, 5 Delaunay)"""
import json
import math
import sys
import time

import gmsh
import numpy as np

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
geo = gmsh.model.geo
n = 200


def thickness(x):
    return 0.6 * (0.2969 * math.sqrt(x) - 0.1260 * x - 0.3516 * x * x + 0.2843 * x ** 3 - 0.1036 * x ** 4)


te = geo.addPoint(1, 0, 0)
le = geo.addPoint(0, 0, 0)
upper, lower = [te], [le]
for i in range(1, n):
    x = 0.5 * (1 + math.cos(math.pi * i / n))  # from the trailing edge to the leading edge
    upper.append(geo.addPoint(x, thickness(x), 0))
upper.append(le)
for i in range(1, n):
    x = 0.5 * (1 - math.cos(math.pi * i / n))
    lower.append(geo.addPoint(x, -thickness(x), 0))
lower.append(te)
c1 = geo.addSpline(upper)
c2 = geo.addSpline(lower)
centre = geo.addPoint(0.5, 0, 0)
ring = [geo.addPoint(0.5 + 20 * math.cos(k * math.pi / 2), 20 * math.sin(k * math.pi / 2), 0) for k in range(4)]
arcs = [geo.addCircleArc(ring[k], centre, ring[(k + 1) % 4]) for k in range(4)]
outer = geo.addCurveLoop(arcs)
hole = geo.addCurveLoop([c1, c2])
geo.addPlaneSurface([outer, hole])
geo.synchronize()

field = gmsh.model.mesh.field
f = field.add("MathEval")
a = f"(0.1*Sqrt(x*x+y*y)+0.007)*{s}"
b = f"(0.1*Sqrt((x-1.008930411365)*(x-1.008930411365)+y*y)+0.006)*{s}"
# Step at x = 0.5 without a conditional: (1 + sign) / 2 with sign = t / |t|.
field.setString(f, "F", f"{a}*(1-(x-0.5)/Fabs(x-0.5+1e-30))/2 + {b}*(1+(x-0.5)/Fabs(x-0.5+1e-30))/2")
field.setAsBackgroundMesh(f)
gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
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
