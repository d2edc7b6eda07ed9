#!/usr/bin/python3
"""Meshes the examples with meshd-cli in every format and reads the files back with the
readers of each ecosystem: meshio (VTK, SU2, MSH), VTK's own Python module (VTK), and gmsh
(MSH). Checks counts, tags and coordinates against the JSON output of the same run; with
boundary layers, the quads in each.

usage: readback.py MESHD_CLI EXAMPLES_DIR"""
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
from common import check, finish  # noqa: E402

cli, examples = sys.argv[1], sys.argv[2]


with tempfile.TemporaryDirectory() as tmp:
    request = os.path.join(examples, "naca0012.json")
    out = {}
    for fmt in ("json", "vtk", "su2", "msh"):
        path = os.path.join(tmp, "mesh." + fmt)
        subprocess.run([cli, request, "-o", path, "--quiet"], check=True)
        out[fmt] = path
    ref = json.load(open(out["json"]))["mesh"]
    pts = np.array(ref["points"])
    tris = np.array(ref["triangles"])
    nedges = sum(len(v) for v in ref["boundaries"].values())
    tags = list(ref["boundaries"].keys())

    # meshio: VTK
    m = meshio.read(out["vtk"])
    check(np.array_equal(m.points[:, :2], pts), "vtk/meshio: coordinates")
    cells = {c.type: c.data for c in m.cells}
    check(np.array_equal(cells["triangle"], tris), "vtk/meshio: triangles")
    check(len(cells["line"]) == nedges, "vtk/meshio: line cells")
    check("quality" in m.cell_data and "tag" in m.cell_data, "vtk/meshio: cell data arrays")
    check("target_size" in m.point_data, "vtk/meshio: point data")
    q = np.concatenate([np.asarray(a) for a in m.cell_data["quality"]])
    check(q[: len(tris)].min() > 0 and q[: len(tris)].max() <= 1, "vtk/meshio: quality in (0, 1]")

    # VTK itself
    r = vtk.vtkUnstructuredGridReader()
    r.SetFileName(out["vtk"])
    r.ReadAllScalarsOn()
    r.Update()
    g = r.GetOutput()
    check(g.GetNumberOfPoints() == len(pts), "vtk: points")
    check(g.GetNumberOfCells() == len(tris) + nedges, "vtk: cells")
    vp = vtk_to_numpy(g.GetPoints().GetData())
    check(np.array_equal(vp[:, :2], pts), "vtk: coordinates")
    tag = vtk_to_numpy(g.GetCellData().GetArray("tag"))
    check(set(tag[len(tris):].tolist()) == set(range(len(tags))), "vtk: every tag on line cells")
    check(g.GetPointData().GetArray("target_size") is not None, "vtk: target_size")

    # meshio: SU2
    s = meshio.read(out["su2"])
    check(len(s.points) == len(pts), "su2/meshio: points")
    check(np.allclose(s.points[:, :2], pts, rtol=0, atol=0), "su2/meshio: coordinates")
    scells = {c.type: c.data for c in s.cells}
    check(np.array_equal(scells["triangle"], tris), "su2/meshio: triangles")
    marker_names = [l.split("=", 1)[1].strip() for l in open(out["su2"]) if l.startswith("MARKER_TAG=")]
    check(marker_names == tags, "su2: one marker per tag, named by the tag")

    # meshio: MSH
    h = meshio.read(out["msh"])
    check(len(h.points) == len(pts), "msh/meshio: points")
    check(sum(len(c.data) for c in h.cells if c.type == "triangle") == len(tris), "msh/meshio: triangles")
    check(set(h.field_data.keys()) >= set(tags) | {"domain"}, "msh/meshio: physical names")

    # gmsh itself
    import gmsh
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.open(out["msh"])
    groups = {gmsh.model.getPhysicalName(d, t): (d, t) for d, t in gmsh.model.getPhysicalGroups()}
    check(set(groups) == set(tags) | {"domain"}, "gmsh: physical groups named by tags")
    for name in tags:
        d, t = groups[name]
        n = 0
        for e in gmsh.model.getEntitiesForPhysicalGroup(d, t):
            types, elems, _ = gmsh.model.mesh.getElements(d, e)
            n += sum(len(x) for x in elems)
        check(n == len(ref["boundaries"][name]), f"gmsh: edges of {name}")
    types, elems, _ = gmsh.model.mesh.getElements(2)
    check(sum(len(x) for x in elems) == len(tris), "gmsh: triangles")
    gmsh.finalize()

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
