#!/usr/bin/python3
"""Boundary layers on the NACA 0012 case, meshd against gmsh's BoundaryLayer field, one run,
side by side: the same wing (closed trailing edge), far field (circle of radius 20 about
(0.5, 0)) and density (the example's, as a MathEval field in gmsh), the same first height,
growth and number of layers, quads, a fan at the trailing edge. Both meshes are then measured
by the same code: cells, meshing time, the worst scaled Jacobian (at each corner the sine of
its angle over the sine of the ideal one: 60 degrees in a triangle, 90 in a quad), the largest aspect ratio of a quad, and the largest jump between neighbouring cells
between neighbouring layers (the larger over the smaller aspect ratio of two quads that meet
along their longer sides: one stacked on the other).

usage: bench/layers/compare_gmsh.py [first_height growth layers]   (default 1e-5 1.15 30)"""
import json
import math
import os
import subprocess
import sys
import tempfile
import time

import gmsh
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "compare"))
from gmsh_case import add_naca_case  # noqa: E402

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
CLI = os.path.join(ROOT, "build", "cli", "meshd-cli")
FIRST, GROWTH, LAYERS = (float(sys.argv[1]), float(sys.argv[2]), int(sys.argv[3])) if len(sys.argv) > 3 else (1e-5, 1.15, 30)


def gmsh_mesh(path):
    """gmsh 4.8 on the benchmark case (bench/compare/gmsh_case.py), the BoundaryLayer field on
    the wing with a fan at the trailing edge; seconds to mesh."""
    gmsh.model.add("gmsh")
    wing, te = add_naca_case(1.0)
    field = gmsh.model.mesh.field
    bl = field.add("BoundaryLayer")
    field.setNumbers(bl, "CurvesList", wing)
    field.setNumber(bl, "Size", FIRST)
    field.setNumber(bl, "Ratio", GROWTH)
    field.setNumber(bl, "NbLayers", LAYERS)
    field.setNumber(bl, "Quads", 1)
    field.setNumbers(bl, "FanPointsList", [te])
    field.setAsBoundaryLayer(bl)
    t0 = time.perf_counter()
    gmsh.model.mesh.generate(2)
    secs = time.perf_counter() - t0
    gmsh.write(path)
    gmsh.model.remove()
    return secs


def measure(path):
    """The figures of the mesh in an MSH file, as gmsh loads it."""
    gmsh.open(path)
    types, tags, nodes = gmsh.model.mesh.getElements(2)
    counts = {int(t): len(e) for t, e in zip(types, tags)}
    node_tags, coords, _ = gmsh.model.mesh.getNodes()
    xy = dict(zip(node_tags, coords.reshape(-1, 3)[:, :2]))
    worst = 1.0
    for kind, corners, ideal in ((2, 3, math.sin(math.pi / 3)), (3, 4, 1.0)):
        if kind not in counts:
            continue
        cells = np.array([[xy[v] for v in c] for c in nodes[list(types).index(kind)].reshape(-1, corners)])
        for i in range(corners):
            e1 = cells[:, (i + 1) % corners] - cells[:, i]
            e0 = cells[:, (i - 1) % corners] - cells[:, i]
            sine = np.cross(e1, e0) / (np.linalg.norm(e1, axis=1) * np.linalg.norm(e0, axis=1))
            worst = min(worst, float((sine / ideal).min()))
    quads = nodes[list(types).index(3)].reshape(-1, 4) if 3 in counts else np.zeros((0, 4), int)
    aspect, long_sides = [], []
    for q in quads:
        p = [xy[v] for v in q]
        sides = [np.linalg.norm(p[(i + 1) % 4] - p[i]) for i in range(4)]
        aspect.append(max(sides) / min(sides))
        # The two longer sides: along the wall, where a layer meets the next.
        order = sorted(range(4), key=lambda i: -sides[i])[:2]
        long_sides.append({tuple(sorted((q[i], q[(i + 1) % 4]))) for i in order})
    aspect = np.array(aspect)
    owner = {}
    jump = 1.0
    for k, q in enumerate(quads):
        for e in long_sides[k]:
            if e in owner and e in long_sides[owner[e]]:
                a, b = aspect[owner[e]], aspect[k]
                jump = max(jump, max(a, b) / min(a, b))
            owner[e] = k
    gmsh.model.remove()
    return {"triangles": counts.get(2, 0), "quads": counts.get(3, 0), "min_scaled_jacobian": worst,
            "aspect_ratio_max": float(aspect.max()) if len(aspect) else 0.0, "neighbour_aspect_jump_max": jump}


def main():
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        with open(os.path.join(ROOT, "examples", "naca0012.json")) as f:
            request = json.load(f)
        request["boundary_layers"] = [{"curves": ["wing"], "first_height": FIRST, "growth": GROWTH, "layers": LAYERS}]
        req, out = os.path.join(tmp, "req.json"), os.path.join(tmp, "meshd.msh")
        json.dump(request, open(req, "w"))
        run = subprocess.run([CLI, req, "-o", os.path.join(tmp, "meshd.json")], capture_output=True, text=True, check=True)
        subprocess.run([CLI, req, "-o", out, "--quiet"], check=True)
        metrics = json.load(open(os.path.join(tmp, "meshd.json")))["metrics"]
        rows.append(("meshd", metrics["timings_ms"]["total"] / 1000, measure(out), metrics["boundary_layers"][0]))
        path = os.path.join(tmp, "gmsh.msh")
        secs = gmsh_mesh(path)
        rows.append(("gmsh 4.8 BoundaryLayer", secs, measure(path), None))
    gmsh.finalize()
    print(f"first height {FIRST:g}, growth {GROWTH:g}, {LAYERS} layers\n")
    print("| mesher | triangles | quads | time (s) | worst scaled Jacobian | largest quad aspect ratio | largest aspect ratio jump between layers |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name, secs, m, _ in rows:
        print(f"| {name} | {m['triangles']} | {m['quads']} | {secs:.3f} | {m['min_scaled_jacobian']:.3f} | "
              f"{m['aspect_ratio_max']:.0f} | {m['neighbour_aspect_jump_max']:.2f} |")
    layers = rows[0][3]
    print(f"\nmeshd's layers: {layers['layers']['min']}..{layers['layers']['max']} per column, first height "
          f"{layers['first_height']['min']:.4g}..{layers['first_height']['max']:.4g}, {layers['cut_back']['columns']} columns cut back")


if __name__ == "__main__":
    main()
