#!/usr/bin/python3
"""meshd's CGNS files read back by three readers that share no code with its writer: the CGNS
project's own cgnscheck (no error, no warning), VTK's CGNS reader (its own cgio: the zone's
points and triangles, one boundary patch per loop tag with that tag's edges, the same
coordinates as the JSON mesh), and h5py on the raw HDF5 tree (the node types and the values
CGNS prescribes: the base's dimensions, the element types, BC_t FamilySpecified with its
FamilyName, the family's FamilyBC typed from patch_types, GridLocation EdgeCenter, element
ranges that tile 1..n). The examples, then the first N requests of each generator in fuzz/
(default 40).

usage: cgns_check.py MESHD_CLI EXAMPLES_DIR [FUZZ_DIR [N]]"""
import json
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np
import vtk

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import CUT_TO_HOLE, check, finish, generated, generated_arguments  # noqa: E402

cli, examples = sys.argv[1], sys.argv[2]
fuzz_dir, count = generated_arguments(examples)

TRI_3, BAR_2, TRI_6, BAR_3, QUAD_4 = 5, 3, 6, 4, 7  # CGNS ElementType_t values
VTK_TRIANGLE, VTK_LINE, VTK_QUADRATIC_TRIANGLE, VTK_QUADRATIC_EDGE, VTK_QUAD = 5, 3, 22, 21, 9


def text(node):
    """The characters of a CGNS node's data (C1 arrays), as a string."""
    return bytes(np.asarray(node[" data"]).astype(np.uint8)).decode()


def label(node):
    """A CGNS node's label (SIDS type), or "" for HDF5 objects that are not nodes."""
    if not isinstance(node, h5py.Group) or "label" not in node.attrs:
        return ""
    value = node.attrs["label"]
    return (value.decode() if isinstance(value, bytes) else str(np.asarray(value).tobytes(), "ascii")).rstrip("\0")


def meshes(request, where, name, may_refuse=False):
    """The request meshed by the CLI as JSON and as CGNS: (json mesh, cgns path); with
    `may_refuse`, (None, None) when the CLI refuses the request."""
    path = os.path.join(where, name + ".json")
    with open(path, "w") as f:
        json.dump(request, f)
    out_json, out_cgns = os.path.join(where, name + ".out.json"), os.path.join(where, name + ".cgns")
    got = subprocess.run([cli, path, "-q", "-o", out_json], capture_output=True, text=True)
    if got.returncode != 0 and may_refuse:
        return None, None
    check(got.returncode == 0, f"{name}: meshed ({got.stderr[:200]})")
    subprocess.run([cli, path, "-q", "-o", out_cgns], check=True)
    with open(out_json) as f:
        return json.load(f)["mesh"], out_cgns


def check_case(request, where, name, embedded_tags, bc_types, may_refuse=False):
    """The checks below on the request's files; False (nothing checked) when `may_refuse`
    and the CLI refused it."""
    mesh, path = meshes(request, where, name, may_refuse)
    if mesh is None:
        return False
    quadratic = mesh.get("order") == 2
    tri_type, bar_type = (TRI_6, BAR_3) if quadratic else (TRI_3, BAR_2)
    vtk_tri, vtk_line = (VTK_QUADRATIC_TRIANGLE, VTK_QUADRATIC_EDGE) if quadratic else (VTK_TRIANGLE, VTK_LINE)
    points = np.array(mesh["points"], dtype=float)
    quads = mesh.get("quads", [])
    ncells = len(mesh["triangles"]) + len(quads)
    loop_tags = [t for t in mesh["boundaries"] if t not in embedded_tags]

    # cgnscheck: the CGNS project's own checker.
    run = subprocess.run(["cgnscheck", path], capture_output=True, text=True)
    check(run.returncode == 0, f"{name}: cgnscheck exits 0 ({run.returncode})")
    bad = [line for line in run.stdout.splitlines() if "ERROR" in line or "WARNING" in line]
    check(not bad, f"{name}: cgnscheck reports {bad[:3]}")

    # VTK's reader: the zone and its boundary patches.
    reader = vtk.vtkCGNSReader()
    reader.SetFileName(path)
    reader.UpdateInformation()
    reader.EnableAllBases()
    reader.SetLoadBndPatch(1)
    reader.Update()
    zone = reader.GetOutput().GetBlock(0).GetBlock(0)
    blocks = {zone.GetMetaData(i).Get(vtk.vtkCompositeDataSet.NAME()): zone.GetBlock(i) for i in range(zone.GetNumberOfBlocks())}
    internal = blocks.get("Internal")
    check(internal is not None, f"{name}: VTK finds the zone's cells")
    if internal is not None:
        check(internal.GetNumberOfPoints() == len(points), f"{name}: {internal.GetNumberOfPoints()} points, JSON has {len(points)}")
        check(internal.GetNumberOfCells() == ncells, f"{name}: {internal.GetNumberOfCells()} cells")
        kinds = [internal.GetCellType(i) for i in range(internal.GetNumberOfCells())]
        check(kinds.count(vtk_tri) == len(mesh["triangles"]) and kinds.count(VTK_QUAD) == len(quads),
              f"{name}: the triangles and the quads")
        xy = np.array([internal.GetPoint(i)[:2] for i in range(internal.GetNumberOfPoints())])
        check(np.array_equal(xy, points), f"{name}: the coordinates are the JSON mesh's")
    patches = blocks.get("Patches")
    names = [patches.GetMetaData(i).Get(vtk.vtkCompositeDataSet.NAME()) for i in range(patches.GetNumberOfBlocks())] if patches else []
    check(sorted(names) == sorted(loop_tags), f"{name}: patches {names}, loop tags {loop_tags}")
    for i, tag in enumerate(names):
        patch = patches.GetBlock(i)
        expected = {tuple(sorted(map(tuple, points[list(e)].tolist()))) for e in mesh["boundaries"].get(tag, [])}
        got = set()
        for c in range(patch.GetNumberOfCells()):
            cell = patch.GetCell(c)
            check(patch.GetCellType(c) == vtk_line, f"{name}: patch {tag} holds lines")
            ids = [cell.GetPointId(k) for k in range(cell.GetNumberOfPoints())]
            got.add(tuple(sorted(tuple(patch.GetPoint(k)[:2]) for k in ids)))
        check(got == expected, f"{name}: patch {tag} has its {len(expected)} edges ({len(got)} read)")

    # The raw HDF5 tree.
    with h5py.File(path, "r") as f:
        base = f["Base"]
        check(list(np.asarray(base[" data"])) == [2, 2], f"{name}: a base of cell and physical dimension 2")
        check(text(base["DataClass"]) == "NormalizedByUnknownDimensional", f"{name}: lengths in the request's unit")
        z = base["Zone"]
        check(text(z["ZoneType"]) == "Unstructured", f"{name}: an unstructured zone")
        check(list(np.asarray(z[" data"]).ravel()) == [len(points), ncells, 0], f"{name}: the zone's sizes")
        sections = {k: z[k] for k in z if label(z[k]) == "Elements_t"}
        ranges = []
        for sname, s in sections.items():
            kind, _ = np.asarray(s[" data"])
            lo, hi = np.asarray(s["ElementRange"][" data"])
            ranges.append((lo, hi))
            conn = np.asarray(s["ElementConnectivity"][" data"]) - 1
            if sname == "Triangles":
                check(kind == tri_type, f"{name}: triangles of type {tri_type}")
                check(np.array_equal(conn.reshape(len(mesh["triangles"]), -1), np.array(mesh["triangles"])), f"{name}: the triangles of the JSON mesh")
            elif sname == "Quadrilaterals":
                check(kind == QUAD_4, f"{name}: quads of type QUAD_4")
                check(np.array_equal(conn.reshape(-1, 4), np.array(quads)), f"{name}: the quads of the JSON mesh")
            else:
                check(kind == bar_type, f"{name}: section {sname} is of type {bar_type}")
                check(sname in mesh["boundaries"] or sname.endswith("_embedded"), f"{name}: section {sname} is a tag")
                edges = sorted(map(tuple, conn.reshape(-1, 3 if quadratic else 2).tolist()))
                check(edges == sorted(map(tuple, mesh["boundaries"].get(sname, []))), f"{name}: section {sname} holds the tag's edges")
        ranges.sort()
        check(ranges[0][0] == 1 and all(b[0] == a[1] + 1 for a, b in zip(ranges, ranges[1:])), f"{name}: element ranges tile 1..n {ranges}")
        zbc = z["ZoneBC"]
        bcs = [k for k in zbc if label(zbc[k]) == "BC_t"]
        check(sorted(bcs) == sorted(loop_tags), f"{name}: a BC per loop tag, none for embedded curves ({sorted(bcs)})")
        for tag in bcs:
            bc = zbc[tag]
            check(text(bc) == "FamilySpecified", f"{name}: BC {tag} is FamilySpecified")
            check(text(bc["GridLocation"]) == "EdgeCenter", f"{name}: BC {tag} on edges")
            check(text(bc["FamilyName"]) == tag, f"{name}: BC {tag} in the family {tag}")
            lo, hi = np.asarray(bc["PointRange"][" data"]).ravel()
            slo, shi = np.asarray(z[tag]["ElementRange"][" data"])
            check((lo, hi) == (slo, shi), f"{name}: BC {tag} covers its section")
            check(text(base[tag]["FamBC"]) == bc_types.get(tag, "UserDefined"), f"{name}: family {tag} is {text(base[tag]['FamBC'])}")
    return True


with tempfile.TemporaryDirectory() as where:
    with open(os.path.join(examples, "naca0012.json")) as f:
        naca = json.load(f)
    naca.setdefault("options", {})["patch_types"] = {"wall": "wall"}
    check_case(naca, where, "naca0012", set(), {"wall": "BCWall"})
    cut = json.loads(json.dumps(CUT_TO_HOLE))
    cut["options"] = {"patch_types": {"cylinder": "wall", "wall": "symmetryPlane"}}
    check_case(cut, where, "cut_to_hole", {"cut"}, {"cylinder": "BCWall", "wall": "BCSymmetryPlane"})

    # Second order: 6-node triangles, the circles' edge nodes on the circles.
    ring = {"geometry": {"points": {"O": [1, 0], "I": [0.5, 0]},
                         "curves": {"outer": {"type": "arc", "from": "O", "to": "O", "center": [0, 0], "tag": "outer"},
                                    "inner": {"type": "arc", "from": "I", "to": "I", "center": [0, 0], "tag": "inner"}},
                         "loops": [["outer"], ["inner"]]},
            "density": {"size": 0.15}, "options": {"order": 2, "patch_types": {"inner": "wall"}}}
    check_case(ring, where, "annulus_order2", set(), {"inner": "BCWall"})
    # Boundary layers: a QUAD_4 section after the triangles.
    layered = json.loads(json.dumps(naca))
    layered["boundary_layers"] = [{"curves": ["wing"], "first_height": 1e-4, "growth": 1.2, "layers": 15}]
    check_case(layered, where, "naca0012_layers", set(), {"wall": "BCWall"})
    ring_mesh, _ = meshes(ring, where, "annulus_order2")
    pts = np.array(ring_mesh["points"])
    for tag, radius in (("outer", 1.0), ("inner", 0.5)):
        middles = [e[2] for e in ring_mesh["boundaries"][tag]]
        check(np.allclose(np.hypot(pts[middles, 0], pts[middles, 1]), radius, atol=1e-12), f"edge nodes of {tag} on its circle")

# The first requests of each generator in fuzz/: holes of every kind, cuts and T junctions
# (embedded tags), untagged curves, second order and layers.
read = 0
with tempfile.TemporaryDirectory() as where:
    for name, request in generated(fuzz_dir, count):
        curves = request["geometry"]["curves"]
        embedded = {curves[c].get("tag", c) for c in request["geometry"].get("embedded", [])}
        # A domain the generator drew badly is refused (generated_requests.py holds those).
        read += check_case(request, where, name, embedded, {}, may_refuse=True)

finish(f"CGNS read back by cgnscheck, VTK and h5py (the examples and {read} generated meshes)")
