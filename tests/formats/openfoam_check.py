#!/usr/bin/python3
"""The foam archives of meshd-cli unpacked into OpenFOAM cases and checked by OpenFOAM's own
checkMesh (Debian's openfoam): "Mesh OK", a prism per triangle and a hexahedron per quad (the
NACA 0012 with boundary layers; a half airfoil whose layers slide on its symmetry line), the
volume the cells' area times the slab's thickness, one patch per tag with as many faces as the tag has edges
(embedded edges are internal faces), frontAndBack empty with two faces per triangle; and
potentialFoam runs on the NACA 0012 case.

usage: openfoam_check.py MESHD_CLI EXAMPLES_DIR"""
import json
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import foam  # noqa: E402
from common import check, finish, write_cut_to_hole  # noqa: E402

cli, examples = sys.argv[1], sys.argv[2]

def case_of(archive, where):
    check(foam.case_of(archive, where) == foam.POLYMESH, f"{archive}: the five polyMesh files")


def patches(case):
    text = open(os.path.join(case, "constant/polyMesh/boundary")).read()
    return {m.group(1): (m.group(2), int(m.group(3)))
            for m in re.finditer(r"(\S+)\s*\{\s*type\s+(\w+);[^}]*?nFaces\s+(\d+);", text)}


def slab(case):
    text = open(os.path.join(case, "constant/polyMesh/points")).read()
    zs = [float(z) for z in re.findall(r"\(\S+ \S+ (\S+)\)", text)]
    return max(zs)


with tempfile.TemporaryDirectory() as tmp:
    cut = write_cut_to_hole(tmp)
    walls = json.load(open(os.path.join(examples, "naca0012.json")))
    walls.setdefault("options", {}).update({"patch_types": {"wall": "wall"}, "slab_thickness": 0.5})
    typed = os.path.join(tmp, "walls.json")
    json.dump(walls, open(typed, "w"))
    layered = dict(walls, boundary_layers=[{"curves": ["wing"], "first_height": 1e-5, "growth": 1.2, "layers": 30}])
    layered_path = os.path.join(tmp, "layers.json")
    json.dump(layered, open(layered_path, "w"))
    half = json.load(open(os.path.join(examples, "fig10.json")))
    half["boundary_layers"] = [{"curves": ["wing"], "first_height": 1e-4, "growth": 1.2, "layers": 20}]
    half["options"] = {"patch_types": {"wall": "wall", "symmetry": "symmetryPlane"}}
    half_path = os.path.join(tmp, "half.json")
    json.dump(half, open(half_path, "w"))
    for name, request in [("naca0012", os.path.join(examples, "naca0012.json")),
                          ("fig11", os.path.join(examples, "fig11.json")), ("cut-to-hole", cut),
                          ("naca0012 with a wall patch, slab 0.5", typed),
                          ("naca0012 with boundary layers", layered_path),
                          ("half airfoil with layers sliding on the symmetry line", half_path)]:
        stem = re.sub(r"[^A-Za-z0-9]+", "-", name)
        archive, answer, case = (os.path.join(tmp, stem + ext) for ext in (".tar", ".json", ""))
        subprocess.run([cli, request, "-o", archive, "--format", "foam", "--quiet"], check=True)
        subprocess.run([cli, request, "-o", answer, "--quiet"], check=True)
        again = archive + ".again"
        subprocess.run([cli, request, "-o", again, "--format", "foam", "--quiet"], check=True)
        check(open(archive, "rb").read() == open(again, "rb").read(), f"{name}: the same archive twice")
        case_of(archive, case)
        run = foam.run_tool("checkMesh", case)
        out = run.stdout + run.stderr
        if "boundary_layers" in json.load(open(request)):
            # Cells a thousandth as tall as wide are what layers at y+ 1 are: checkMesh counts
            # its aspect-ratio check (threshold 1000) failed; every other check must pass.
            failed = [line for line in out.splitlines() if line.strip().startswith("***")]
            check(run.returncode == 0 and all("High aspect ratio" in line for line in failed)
                  and ("\nMesh OK." in out or "Failed 1 mesh checks" in out) and "FOAM FATAL" not in out,
                  f"{name}: checkMesh passes every check but the aspect ratio ({failed})")
        else:
            check(run.returncode == 0 and "\nMesh OK." in out, f"{name}: checkMesh says Mesh OK")
        ref = json.load(open(answer))["mesh"]
        pts, tris = np.array(ref["points"]), np.array(ref["triangles"])
        quads = np.array(ref.get("quads", []), dtype=int).reshape(-1, 4)
        prisms = re.search(r"prisms:\s+(\d+)", out)
        check(prisms is not None and int(prisms.group(1)) == len(tris), f"{name}: a prism per triangle")
        hexes = re.search(r"hexahedra:\s+(\d+)", out)
        check(len(quads) == (int(hexes.group(1)) if hexes else 0), f"{name}: a hexahedron per quad")
        if "boundary_layers" in json.load(open(request)):
            check(len(quads) > 0, f"{name}: the layers made quads")
        # Areas by the shoelace formula over every cell's corners.
        area = 0.0
        for cells in (tris, quads):
            if len(cells) == 0:
                continue
            x, y = pts[cells][:, :, 0], pts[cells][:, :, 1]
            area += 0.5 * np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y)
        vol = re.search(r"Total volume = (\S+)\.", out)
        check(vol is not None and abs(float(vol.group(1)) - area * slab(case)) <= 1e-4 * area * slab(case),
              f"{name}: volume = area x thickness")
        got = patches(case)
        check(got.get("frontAndBack") == ("empty", 2 * (len(tris) + len(quads))),
              f"{name}: frontAndBack empty, two faces per cell")
        options = json.load(open(request)).get("options", {})
        if "slab_thickness" in options:
            check(slab(case) == options["slab_thickness"], f"{name}: the slab as thick as asked")
        types = options.get("patch_types", {})
        embedded = {"cut"} if name == "cut-to-hole" else set()
        for tag, edges in ref["boundaries"].items():
            if tag in embedded:
                check(tag not in got, f"{name}: embedded {tag} edges are internal faces")
            else:
                want = (types.get(tag, "patch"), len(edges))
                check(got.get(tag) == want, f"{name}: patch {tag} is {want}, got {got.get(tag)}")

# A solver on it: potentialFoam around the NACA 0012 at 4 degrees (slip wall, free stream on
# the far field) converges, with a continuity error near round-off.
POTENTIAL = {
    "0/U": "dimensions [0 1 -1 0 0 0 0]; internalField uniform (1 0.0699 0);\n"
           "boundaryField { wall { type slip; } farfield { type freestreamVelocity; freestreamValue uniform (1 0.0699 0); }\n"
           "frontAndBack { type empty; } }\n",
    "0/p": "dimensions [0 2 -2 0 0 0 0]; internalField uniform 0;\n"
           "boundaryField { wall { type zeroGradient; } farfield { type freestreamPressure; freestreamValue uniform 0; }\n"
           "frontAndBack { type empty; } }\n",
    "system/fvSchemes": "ddtSchemes { default steadyState; } gradSchemes { default Gauss linear; }\n"
                        "divSchemes { default none; div(phi,U) bounded Gauss linear; div(div(phi,U)) Gauss linear; }\n"
                        "laplacianSchemes { default Gauss linear corrected; } interpolationSchemes { default linear; }\n"
                        "snGradSchemes { default corrected; }\n",
    "system/fvSolution": "solvers { Phi { solver GAMG; smoother DIC; tolerance 1e-08; relTol 0; }\n"
                         "p { solver GAMG; smoother DIC; tolerance 1e-08; relTol 0; } }\n"
                         "potentialFlow { nNonOrthogonalCorrectors 3; }\n",
}
with tempfile.TemporaryDirectory() as tmp:
    archive, case = os.path.join(tmp, "naca.tar"), os.path.join(tmp, "naca")
    subprocess.run([cli, os.path.join(examples, "naca0012.json"), "-o", archive, "--format", "foam", "--quiet"], check=True)
    case_of(archive, case)
    os.makedirs(os.path.join(case, "0"))
    for path, body in POTENTIAL.items():
        kind = {"0/U": "volVectorField", "0/p": "volScalarField"}.get(path, "dictionary")
        with open(os.path.join(case, path), "w") as f:
            f.write("FoamFile { version 2.0; format ascii; class %s; object %s; }\n%s" % (kind, os.path.basename(path), body))
    run = foam.run_tool("potentialFoam -writep", case)
    out = run.stdout + run.stderr
    cont = re.search(r"Continuity error = (\S+)", out)
    check(run.returncode == 0 and "\nEnd" in out and cont is not None and float(cont.group(1)) < 1e-6,
          "potentialFoam runs on the NACA 0012 mesh: exit %d, %s" % (run.returncode, cont.group(0) if cont else out[-300:]))

finish("openfoam: checkMesh and potentialFoam, all checks passed")
