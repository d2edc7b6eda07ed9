#!/usr/bin/python3
"""The MSH files of meshd-cli read by gmsh as a model with its topology: point entities at the
curve ends, curve entities bounded by them and holding their nodes and their line elements as
one chain, a surface bounded by closed, oriented loops of curves, every
node classified once. Domains: the NACA 0012 example (closed curves), the half airfoil of
Fig. 10 (open curves meeting at corners), Fig. 11 (two holes) and a plate whose embedded cut
ends on a hole's circle (the circle split there). Then each file extruded one layer by gmsh,
as a user makes an OpenFOAM slab of it: a prism per triangle and the side patches (not the
plate with the cut: gmsh 4.8 aborts extruding a surface with an embedded curve, its own files
included). The same on the first N requests of each generator in fuzz/ (default 40; three-node
lines at second order), extruded where first order, of triangles alone and without cuts.

usage: msh_topology.py MESHD_CLI EXAMPLES_DIR [FUZZ_DIR [N]]"""
import json
import os
import subprocess
import sys
import tempfile

import gmsh

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import check, finish, generated, generated_arguments, write_cut_to_hole  # noqa: E402


def topology(path, name):
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.open(path)
    total = 0
    seen = set()
    for dim in (0, 1, 2):
        for _, t in gmsh.model.getEntities(dim):
            tags, _, _ = gmsh.model.mesh.getNodes(dim, t, includeBoundary=False)
            total += len(tags)
            seen.update(int(x) for x in tags)
    _, coords, _ = gmsh.model.mesh.getNodes()
    npoints = len(coords) // 3
    check(total == npoints and len(seen) == npoints, f"{name}: every node classified on exactly one entity")

    point_node = {}
    for _, t in gmsh.model.getEntities(0):
        tags, _, _ = gmsh.model.mesh.getNodes(0, t)
        check(len(tags) == 1, f"{name}: point entity {t} holds one node")
        point_node[t] = int(tags[0])
    ends = {}
    on_curves = set()
    for _, t in gmsh.model.getEntities(1):
        bound = gmsh.model.getBoundary([(1, t)], oriented=True, combined=False)
        check(len(bound) == 2, f"{name}: curve {t} is bounded by two points")
        if len(bound) != 2:
            continue
        begin, end = point_node[abs(bound[0][1])], point_node[abs(bound[1][1])]
        ends[t] = (begin, end)
        tags, _, _ = gmsh.model.mesh.getNodes(1, t, includeBoundary=False)
        on_curves.update(int(x) for x in tags)
        # Its line elements: one chain from its begin point to its end point through its nodes
        # (at second order, three-node lines: their ends chain, and their middles are the
        # curve's other nodes).
        types, elems, nodes = gmsh.model.mesh.getElements(1, t)
        check(list(types) in ([1], [8]), f"{name}: curve {t} holds line elements")
        per = 3 if list(types) == [8] else 2
        pairs = [(int(nodes[0][per * i]), int(nodes[0][per * i + 1])) for i in range(len(elems[0]))]
        middles = {int(nodes[0][per * i + 2]) for i in range(len(elems[0]))} if per == 3 else set()
        adj = {}
        for a, b in pairs:
            adj.setdefault(a, []).append(b)
            adj.setdefault(b, []).append(a)
        path, prev, cur = [begin], None, begin
        while len(path) <= len(pairs):
            nxt = [x for x in adj.get(cur, []) if x != prev]
            if not nxt:
                break
            prev, cur = cur, nxt[0]
            path.append(cur)
        check(len(path) == len(pairs) + 1 and path[-1] == end and set(path[1:-1]) | middles == set(int(x) for x in tags),
              f"{name}: curve {t}'s elements chain from its begin to its end point")
    # The surface: its bounding curves, oriented, close into loops.
    bound = [t for _, t in gmsh.model.getBoundary([(2, 1)], oriented=True, combined=False)]
    loops, start, prev_end = 0, None, None
    for t in bound:
        if abs(t) not in ends:
            check(False, f"{name}: the surface is bounded by curve {abs(t)}, which has no end points")
            break
        b, e = ends[abs(t)] if t > 0 else ends[abs(t)][::-1]
        if prev_end is None:
            start = b
        else:
            check(b == prev_end, f"{name}: the surface's curves follow each other")
        prev_end = e
        if e == start:
            loops += 1
            prev_end = None
    check(prev_end is None, f"{name}: the surface's last loop closes")
    gmsh.finalize()
    return loops


def extrusion(path, name):
    """meshd's MSH file extruded one layer by gmsh as a user turns a 2D mesh into an OpenFOAM
    slab: CreateTopology{0,1} (hands the file's entities to gmsh's own geometry kernel; this
    gmsh, 4.8, needs it for any mesh read from a file, its own files too), then Extrude
    {Surface; Layers{1}; Recombine}. A prism per triangle, a quad per boundary edge in the
    side patch of its curve, every node doubled, and gmsh reports no error."""
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.logger.start()
    gmsh.open(path)
    _, tri_tags, _ = gmsh.model.mesh.getElements(2, 1)
    triangles = len(tri_tags[0])
    edges_of = {t: len(gmsh.model.mesh.getElements(1, t)[1][0]) for _, t in gmsh.model.getEntities(1)}
    boundary = [abs(t) for _, t in gmsh.model.getBoundary([(2, 1)], oriented=False, combined=False)]
    nodes = len(gmsh.model.mesh.getNodes()[0])
    gmsh.model.mesh.createTopology(False, True)
    check(len(gmsh.model.getEntities(1)) == len(edges_of), f"{name}: CreateTopology kept the curves")
    out = gmsh.model.geo.extrude([(2, 1)], 0, 0, 0.05, [1], recombine=True)
    gmsh.model.geo.synchronize()
    gmsh.model.mesh.generate(3)
    # The top's curves come out twice in this gmsh (once from the top surface, once from the
    # sides: its own files do the same); Coherence Mesh, as a user would, merges them.
    gmsh.model.mesh.removeDuplicateNodes()
    errors = [m for m in gmsh.logger.get() if m.startswith("Error")]
    check(not errors, f"{name}: gmsh extruded with no error ({errors[:2]})")
    check([d for d, _ in out[:2]] == [2, 3], f"{name}: the extrusion gives the top surface and a volume")
    volume = out[1][1]
    types, elems, _ = gmsh.model.mesh.getElements(3, volume)
    check(list(types) == [6] and len(elems[0]) == triangles, f"{name}: a prism per triangle")
    sides = out[2:]
    check(len(sides) == len(boundary), f"{name}: a side patch per boundary curve")
    for curve, (dim, side) in zip(boundary, sides):
        types, elems, _ = gmsh.model.mesh.getElements(dim, side)
        check(list(types) == [3] and len(elems[0]) == edges_of[curve],
              f"{name}: the side of curve {curve} holds a quad per edge of the curve")
    check(len(gmsh.model.mesh.getNodes()[0]) == 2 * nodes, f"{name}: every node doubled")
    gmsh.logger.stop()
    gmsh.finalize()


def main():
    cli, examples = sys.argv[1], sys.argv[2]
    fuzz_dir, count = generated_arguments(examples)
    with tempfile.TemporaryDirectory() as tmp:
        cases = [("naca0012", os.path.join(examples, "naca0012.json"), 2),
                 ("fig10", os.path.join(examples, "fig10.json"), 1),
                 ("fig11", os.path.join(examples, "fig11.json"), 3)]
        cases.append(("cut-to-hole", write_cut_to_hole(tmp), 2))
        for name, request, loops in cases:
            path = os.path.join(tmp, name + ".msh")
            subprocess.run([cli, request, "-o", path, "--quiet"], check=True)
            check(topology(path, name) == loops, f"{name}: {loops} loops bound the surface")
            if name != "cut-to-hole":  # gmsh 4.8 aborts extruding any surface with an embedded
                extrusion(path, name)      # curve (its own files too): nothing to learn there
        # The first requests of each generator in fuzz/ (curves of every kind, holes, cuts,
        # T junctions, second order, layers): as many loops as the request; extruded where
        # the mesh is first order, of triangles alone and without an embedded curve.
        meshed = extruded = 0
        for name, request in generated(fuzz_dir, count):
            req_path, path = os.path.join(tmp, name + ".json"), os.path.join(tmp, name + ".msh")
            with open(req_path, "w") as f:
                json.dump(request, f)
            if subprocess.run([cli, req_path, "-o", path, "--quiet"], capture_output=True).returncode != 0:
                continue  # a domain the generator drew badly (generated_requests.py holds those)
            loops = len(request["geometry"]["loops"])
            check(topology(path, name) == loops, f"{name}: {loops} loops bound the surface")
            meshed += 1
            if (request.get("options", {}).get("order", 1) == 1 and "boundary_layers" not in request
                    and not request["geometry"].get("embedded")):
                extrusion(path, name)
                extruded += 1
    finish(f"msh topology: all checks passed ({meshed} generated meshes, {extruded} of them extruded)")


if __name__ == "__main__":
    main()
