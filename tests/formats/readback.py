#!/usr/bin/python3
"""Meshes the examples with meshd-cli in every format and reads the files back with the
readers of each ecosystem: meshio (VTK, SU2, MSH), VTK's own Python module (VTK), and gmsh
(MSH). Checks counts, tags and coordinates against the JSON output of the same run; with
boundary layers, the quads in each.

The same on the first N requests of each generator in fuzz/ (default 40).

usage: readback.py MESHD_CLI EXAMPLES_DIR [FUZZ_DIR [N]]"""
import json
import os
import subprocess
import sys
import tempfile

import meshio
import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import check, finish, generated, generated_arguments  # noqa: E402

cli, examples = sys.argv[1], sys.argv[2]
fuzz_dir, count = generated_arguments(examples)


def read_back(request, tmp, label):
    """Meshes `request` (a file) in every format that holds its order and checks each file
    against the JSON answer, as meshio, VTK and gmsh read it: points and their coordinates,
    triangles (six nodes at order 2) and quads, the boundary and embedded edges as line cells
    with their tags, SU2's markers and MSH's physical groups. Returns the problem when the
    request itself is refused (nothing checked), else None."""
    out = {}
    for fmt in ("json", "vtk", "su2", "msh"):
        path = os.path.join(tmp, "mesh." + fmt)
        got = subprocess.run([cli, request, "-o", path, "--format", fmt, "--quiet"], capture_output=True, text=True)
        if got.returncode == 0:
            out[fmt] = path
        elif fmt == "json":
            return got.stderr  # a domain the generator drew badly (generated_requests.py holds those)
        else:  # only SU2 may refuse, and only second order
            check(fmt == "su2" and "format-cannot-hold-order" in got.stderr, f"{label}: {fmt} written ({got.stderr[:200]})")
    ref = json.load(open(out["json"]))["mesh"]
    quadratic = ref.get("order", 1) == 2
    tri, line = ("triangle6", "line3") if quadratic else ("triangle", "line")
    pts = np.array(ref["points"])
    tris = np.array(ref["triangles"])
    quads = np.array(ref.get("quads", []), dtype=int).reshape(-1, 4)
    nedges = sum(len(v) for v in ref["boundaries"].values())
    tags = list(ref["boundaries"].keys())

    # meshio: VTK
    m = meshio.read(out["vtk"])
    check(np.array_equal(m.points[:, :2], pts), f"{label}: vtk/meshio: coordinates")
    cells = {c.type: c.data for c in m.cells}
    check(np.array_equal(cells.get(tri), tris), f"{label}: vtk/meshio: triangles")
    check(len(quads) == 0 or np.array_equal(cells.get("quad"), quads), f"{label}: vtk/meshio: quads")
    check(len(cells.get(line, [])) == nedges, f"{label}: vtk/meshio: line cells")
    # The line cells' tags (the `tag` cell data, the tag's index): each tag's edges, edge for edge.
    line_tags = [np.asarray(t).ravel() for c, t in zip(m.cells, m.cell_data.get("tag", [])) if c.type == line]
    if line_tags and line in cells:
        marker = np.concatenate(line_tags)
        for k, tag in enumerate(tags):
            got = {tuple(sorted(e)) for e in cells[line][marker == k].tolist()}
            check(got == {tuple(sorted(e)) for e in ref["boundaries"][tag]}, f"{label}: vtk/meshio: the lines tagged {tag} are its edges")
    check("quality" in m.cell_data and "tag" in m.cell_data, f"{label}: vtk/meshio: cell data arrays")
    check("target_size" in m.point_data, f"{label}: vtk/meshio: point data")
    q = np.concatenate([np.asarray(a) for a in m.cell_data["quality"]])
    check(q[: len(tris)].min() > 0 and q[: len(tris)].max() <= 1, f"{label}: vtk/meshio: quality in (0, 1]")

    # VTK itself
    r = vtk.vtkUnstructuredGridReader()
    r.SetFileName(out["vtk"])
    r.ReadAllScalarsOn()
    r.Update()
    g = r.GetOutput()
    check(g.GetNumberOfPoints() == len(pts), f"{label}: vtk: points")
    check(g.GetNumberOfCells() == len(tris) + len(quads) + nedges, f"{label}: vtk: cells")
    vp = vtk_to_numpy(g.GetPoints().GetData())
    check(np.array_equal(vp[:, :2], pts), f"{label}: vtk: coordinates")
    tag = vtk_to_numpy(g.GetCellData().GetArray("tag"))
    first_line = len(tris) + len(quads)
    check(set(tag[first_line:].tolist()) == set(range(len(tags))), f"{label}: vtk: every tag on line cells")
    check(g.GetPointData().GetArray("target_size") is not None, f"{label}: vtk: target_size")

    # meshio: SU2
    if "su2" in out:
        s = meshio.read(out["su2"])
        check(len(s.points) == len(pts), f"{label}: su2/meshio: points")
        check(np.array_equal(s.points[:, :2], pts), f"{label}: su2/meshio: coordinates")
        scells = {c.type: c.data for c in s.cells}
        check(np.array_equal(scells.get("triangle"), tris), f"{label}: su2/meshio: triangles")
        marker_names = [l.split("=", 1)[1].strip() for l in open(out["su2"]) if l.startswith("MARKER_TAG=")]
        check(marker_names == tags, f"{label}: su2: one marker per tag, named by the tag")
        # meshio numbers the markers 1, 2, ... in the file's order: each holds its tag's edges.
        lines = [(c.data, t) for c, t in zip(s.cells, s.cell_data.get("su2:tag", [])) if c.type == "line"]
        edges = np.concatenate([d for d, _ in lines]) if lines else np.zeros((0, 2), dtype=int)
        marker = np.concatenate([np.asarray(t) for _, t in lines]) if lines else np.zeros(0, dtype=int)
        for k, tag in enumerate(tags):
            got = {tuple(sorted(e)) for e in edges[marker == k + 1].tolist()}
            check(got == {tuple(sorted(e)) for e in ref["boundaries"][tag]}, f"{label}: su2/meshio: marker {tag} holds its edges")

    # meshio: MSH
    h = meshio.read(out["msh"])
    check(len(h.points) == len(pts), f"{label}: msh/meshio: points")
    check(sum(len(c.data) for c in h.cells if c.type == tri) == len(tris), f"{label}: msh/meshio: triangles")
    check(set(h.field_data.keys()) >= set(tags) | {"domain"}, f"{label}: msh/meshio: physical names")

    # gmsh itself
    import gmsh
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.open(out["msh"])
    groups = {gmsh.model.getPhysicalName(d, t): (d, t) for d, t in gmsh.model.getPhysicalGroups()}
    check(set(groups) == set(tags) | {"domain"}, f"{label}: gmsh: physical groups named by tags")
    for name in tags:
        d, t = groups.get(name, (1, -1))
        n = 0
        for e in (gmsh.model.getEntitiesForPhysicalGroup(d, t) if t >= 0 else []):
            types, elems, _ = gmsh.model.mesh.getElements(d, e)
            n += sum(len(x) for x in elems)
        check(n == len(ref["boundaries"][name]), f"{label}: gmsh: edges of {name}")
    types, elems, _ = gmsh.model.mesh.getElements(2)
    check(sum(len(x) for x in elems) == len(tris) + len(quads), f"{label}: gmsh: triangles and quads")
    gmsh.finalize()
    return None


with tempfile.TemporaryDirectory() as tmp:
    refused = read_back(os.path.join(examples, "naca0012.json"), tmp, "naca0012")
    check(refused is None, f"naca0012: meshed ({refused})")

# The same on the first requests of each generator in fuzz/ (holes of every kind, embedded cuts
# and T junctions, untagged curves, second order, layers): the readers on meshes unlike the
# examples.
for name, request in generated(fuzz_dir, count):
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "request.json")
        json.dump(request, open(path, "w"))
        read_back(path, tmp, name)

# Boundary layers: the quads in every format, beside the triangles, as each reader sees them.
with tempfile.TemporaryDirectory() as tmp:
    request = json.load(open(os.path.join(examples, "naca0012.json")))
    request["boundary_layers"] = [{"curves": ["wing"], "first_height": 1e-4, "growth": 1.2, "layers": 15}]
    path = os.path.join(tmp, "layers.json")
    json.dump(request, open(path, "w"))
    out = {}
    for fmt in ("json", "vtk", "su2", "msh"):
        out[fmt] = os.path.join(tmp, "mesh." + fmt)
        subprocess.run([cli, path, "-o", out[fmt], "--quiet"], check=True)
    ref = json.load(open(out["json"]))["mesh"]
    tris, quads = np.array(ref["triangles"]), np.array(ref["quads"])
    check(len(quads) > 0, "layers: the JSON holds quads")
    pts = np.array(ref["points"])
    for fmt in ("vtk", "su2", "msh"):
        mesh = meshio.read(out[fmt])
        cells = {}
        for c in mesh.cells:
            cells.setdefault(c.type, []).append(c.data)
        got = {k: np.concatenate(v) for k, v in cells.items()}
        # By their corners' coordinates (meshio numbers MSH nodes in the file's order).
        check("quad" in got and np.array_equal(mesh.points[got["quad"]][:, :, :2], pts[quads]),
              f"layers/{fmt}/meshio: the quads")
        check(len(got.get("triangle", [])) == len(tris), f"layers/{fmt}/meshio: the triangles")
    r = vtk.vtkUnstructuredGridReader()
    r.SetFileName(out["vtk"])
    r.Update()
    g = r.GetOutput()
    kinds = [g.GetCellType(i) for i in range(g.GetNumberOfCells())]
    check(kinds.count(vtk.VTK_QUAD) == len(quads), "layers/vtk: VTK_QUAD cells")
    import gmsh
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.open(out["msh"])
    types, elems, _ = gmsh.model.mesh.getElements(2, 1)
    by_type = dict(zip(types, (len(e) for e in elems)))
    check(by_type.get(3) == len(quads) and by_type.get(2) == len(tris), "layers/gmsh: quads and triangles on the surface")
    gmsh.finalize()

finish("all formats read back")
