#!/usr/bin/python3
"""The MSH files of meshd-cli loaded by dolfinx (gmshio.model_to_mesh, as a FEniCS user loads
a gmsh model): the mesh has the points and triangles of meshd's JSON answer, and its facet
tags put every boundary and embedded edge under its own tag, edge for edge. The examples, then
the first-order ones among the first N requests of fuzz/general_requests.py (default 40).

usage: dolfinx_tags.py MESHD_CLI EXAMPLES_DIR [FUZZ_DIR [N]]"""
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import check, dolfinx_mesh, finish, generated, generated_arguments, write_cut_to_hole  # noqa: E402

cli, examples = sys.argv[1], sys.argv[2]
fuzz_dir, count = generated_arguments(examples)


def edge_key(p, q):
    a, b = tuple(np.round(p[:2], 12)), tuple(np.round(q[:2], 12))
    return (a, b) if a <= b else (b, a)


def compare(msh, answer, name):
    ref = json.load(open(answer))["mesh"]
    pts = np.array(ref["points"])
    mesh, facet_tags, names = dolfinx_mesh(msh)
    check(mesh.topology.index_map(0).size_local == len(pts), f"{name}: points")
    check(mesh.topology.index_map(2).size_local == len(ref["triangles"]), f"{name}: triangles")
    # Facet -> vertices -> geometry nodes (their coordinates), through the cells.
    x = mesh.geometry.x
    mesh.topology.create_connectivity(1, 0)
    mesh.topology.create_connectivity(2, 0)
    c2v, f2v, dofs = mesh.topology.connectivity(2, 0), mesh.topology.connectivity(1, 0), mesh.geometry.dofmap
    node_of = {}
    for c in range(mesh.topology.index_map(2).size_local):
        for v, g in zip(c2v.links(c), dofs.links(c)):
            node_of[int(v)] = int(g)
    got = {}
    for value, facet in zip(facet_tags.values, facet_tags.indices):
        a, b = (node_of[int(v)] for v in f2v.links(facet))
        got.setdefault(names.get(int(value), f"#{value}"), set()).add(edge_key(x[a], x[b]))
    want = {tag: {edge_key(pts[a], pts[b]) for a, b in edges} for tag, edges in ref["boundaries"].items()}
    check(set(got) == set(want), f"{name}: facet tags {sorted(got)} against {sorted(want)}")
    for tag in want:
        check(got.get(tag) == want[tag], f"{name}: the facets tagged {tag} are its edges")


with tempfile.TemporaryDirectory() as tmp:
    cut = write_cut_to_hole(tmp)
    for name, request in [("naca0012", os.path.join(examples, "naca0012.json")),
                          ("fig11", os.path.join(examples, "fig11.json")), ("cut-to-hole", cut)]:
        msh, answer = os.path.join(tmp, name + ".msh"), os.path.join(tmp, name + ".json")
        subprocess.run([cli, request, "-o", msh, "--quiet"], check=True)
        subprocess.run([cli, request, "-o", answer, "--quiet"], check=True)
        compare(msh, answer, name)
    # The first requests of fuzz/general_requests.py that are first order (dolfinx's mesh of a
    # second-order file has fewer vertices than points, and it takes no quads): holes of every
    # kind, cuts, T junctions and untagged curves, each edge under its tag.
    read = 0
    for name, request in generated(fuzz_dir, count, ("general",)):
        if request.get("options", {}).get("order", 1) != 1:
            continue
        path = os.path.join(tmp, name + ".request.json")
        with open(path, "w") as f:
            json.dump(request, f)
        msh, answer = os.path.join(tmp, name + ".msh"), os.path.join(tmp, name + ".json")
        if subprocess.run([cli, path, "-o", answer, "--quiet"], capture_output=True).returncode != 0:
            continue  # a domain the generator drew badly (generated_requests.py holds those)
        subprocess.run([cli, path, "-o", msh, "--quiet"], check=True)
        compare(msh, answer, name)
        read += 1

finish(f"dolfinx facet tags: all checks passed (the examples and {read} generated meshes)")
