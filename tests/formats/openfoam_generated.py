#!/usr/bin/python3
"""Random requests (fuzz/general_requests.py and fuzz/layered_requests.py, seeds 1 to N of each)
as OpenFOAM cases, checked by checkMesh (Debian's openfoam). Without layers (second order
asked for is dropped: foam holds first-order cells), "Mesh OK" and no failed check: holes,
embedded cuts as internal faces, T junctions. Layers have aspect ratios over checkMesh's 1000
by design; every other check must pass, but for the one thing acute corners do to layered cells
(docs/api.md, "Acute corners"): faces beside a concave corner of angle theta between two
layered walls, or beside a sliding end column at an acute angle, have OpenFOAM skewness of
about 2.5 cot(theta / 2) or 2.5 cot(theta), above checkMesh's 4 below 64 (32) degrees.

So where checkMesh reports highly skew faces, the script computes OpenFOAM's face skewness
itself from the mesh (primitiveMeshTools' formula: the offset of the face centre from where the
line between the cell centres crosses the face, over the face's extent that way or a fifth of
that line; for boundary faces, the foot of the perpendicular from the cell centre, and two
fifths), checks that its largest is the one checkMesh reports, and that every face above 4
lies within 0.05 of an input corner whose angle in the domain is below 64 degrees (or
within the corner's column: the layers' greatest thickness over sin(theta / 2)), with a
skewness no more than 1.15 times 2.5 cot(theta / 2). A face skewed anywhere else, a cell
checkMesh refuses, or any other failed check fails the script.

usage: openfoam_generated.py MESHD_CLI FUZZ_DIR [N]"""
import concurrent.futures
import json
import math
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import foam  # noqa: E402
from common import check, finish, generated  # noqa: E402

cli, fuzz_dir = sys.argv[1], sys.argv[2]
count = int(sys.argv[3]) if len(sys.argv) > 3 else 150

REFUSALS = {"/v1/problems/curves-cross", "/v1/problems/too-many-points"}
SKEW_LIMIT = 4.0        # checkMesh's
ACUTE_DEG = 64.0        # 2.5 cot(theta / 2) = 4 at 64 degrees
NEAR_CORNER = 0.05      # the requests' domains are about 2 across
FORMULA_SLACK = 1.15


def centroid(pts):
    x, y = pts[:, 0], pts[:, 1]
    x1, y1 = np.roll(x, -1), np.roll(y, -1)
    cr = x * y1 - x1 * y
    a = cr.sum() / 2
    return np.array([((x + x1) * cr).sum() / (6 * a), ((y + y1) * cr).sum() / (6 * a)])


def skewness(mesh):
    """OpenFOAM's skewness of every side face of the extruded mesh: (skew, face centre)."""
    P = np.array(mesh["points"])
    cells = [t[:3] for t in mesh["triangles"]] + [q[:4] for q in mesh.get("quads", [])]
    centres = [centroid(P[c]) for c in cells]
    faces = {}
    for ci, c in enumerate(cells):
        for i in range(len(c)):
            a, b = c[i], c[(i + 1) % len(c)]
            faces.setdefault((min(a, b), max(a, b)), []).append(ci)
    out = []
    for (a, b), owners in faces.items():
        fc = 0.5 * (P[a] + P[b])
        t = P[b] - P[a]
        area = np.array([t[1], -t[0]])
        cpf = fc - centres[owners[0]]
        if len(owners) == 2:
            d, share = centres[owners[1]] - centres[owners[0]], 0.2
        else:
            n = area / np.linalg.norm(area)
            d, share = n * (n @ cpf), 0.4
        sv = cpf - (area @ cpf) / (area @ d) * d
        size = np.linalg.norm(sv)
        along = sv / size if size > 0 else sv
        reach = max(share * np.linalg.norm(d), abs(along @ (P[a] - fc)), abs(along @ (P[b] - fc)))
        out.append((size / reach, fc))
    return out


def thickest(request):
    """The most any layers of the request may stand above their wall."""
    most = 0.0
    for e in request["boundary_layers"]:
        if "thickness" in e:
            most = max(most, e["thickness"])
            continue
        g, n = e.get("growth", 1.2), e["layers"]
        most = max(most, e["first_height"] * (n if g == 1.0 else (g ** n - 1.0) / (g - 1.0)))
    return most


def domain_angles(mesh):
    """The angle of the domain at each point: its cells' corner angles summed (degrees)."""
    P = np.array(mesh["points"])
    total = np.zeros(len(P))
    for c in [t[:3] for t in mesh["triangles"]] + [q[:4] for q in mesh.get("quads", [])]:
        for i in range(len(c)):
            u, w = P[c[(i + 1) % len(c)]] - P[c[i]], P[c[i - 1]] - P[c[i]]
            total[c[i]] += math.degrees(math.atan2(abs(u[0] * w[1] - u[1] * w[0]), u @ w))
    return total


def run(job):
    """Meshes one request as JSON and as a foam case and runs checkMesh; returns what the checks need."""
    name, request, tmp = job
    path = os.path.join(tmp, name + ".json")
    with open(path, "w") as f:
        json.dump(request, f)
    answer, archive, case = path + ".out", path + ".tar", os.path.join(tmp, name)
    got = subprocess.run([cli, path, "-o", answer, "--format", "json", "--quiet"], capture_output=True, text=True)
    if got.returncode != 0:
        return name, request, None, got.returncode, got.stderr, ""
    subprocess.run([cli, path, "-o", archive, "--format", "foam", "--quiet"], check=True)
    foam.case_of(archive, case)
    checked = foam.run_tool("checkMesh", case)
    return name, request, json.load(open(answer))["mesh"], checked.returncode, got.stderr, checked.stdout + checked.stderr


checked = skewed = 0
with tempfile.TemporaryDirectory() as tmp:
    jobs = []
    for name, request in generated(fuzz_dir, count):
        request.get("options", {}).pop("order", None)  # foam holds first-order cells
        jobs.append((name, request, tmp))
    with concurrent.futures.ThreadPoolExecutor(2) as pool:
        for name, request, mesh, code, stderr, out in pool.map(run, jobs):
            if mesh is None:
                try:
                    kind = json.loads(stderr)["type"]
                except (ValueError, KeyError):
                    kind = None
                check(code == 3 and kind in REFUSALS, f"{name}: an answer or an allowed refusal (exit {code}: {stderr[:200]})")
                continue
            checked += 1
            failed = [line.strip() for line in out.splitlines() if line.strip().startswith("***")]
            if "boundary_layers" not in request:
                check(code == 0 and "\nMesh OK." in out and not failed, f"{name}: checkMesh says Mesh OK ({failed})")
                continue
            others = [f for f in failed if "High aspect ratio" not in f and "skewness" not in f]
            check(code == 0 and "FOAM FATAL" not in out and not others,
                  f"{name}: checkMesh passes every check but the aspect ratio and skewness ({others})")
            reported = [float(m.group(1)) for f in failed if (m := re.search(r"Max skewness = ([0-9.eE+-]+)", f))]
            if not reported:
                continue
            skewed += 1
            faces = skewness(mesh)
            largest = max(s for s, _ in faces)
            check(abs(largest - reported[0]) <= 0.01 * reported[0],
                  f"{name}: the skewness computed here ({largest:.4f}) is checkMesh's ({reported[0]})")
            corners = np.array(list(request["geometry"]["points"].values()), dtype=float)
            P = np.array(mesh["points"])
            angle = domain_angles(mesh)
            for s, at in faces:
                if s <= SKEW_LIMIT:
                    continue
                k = int(np.argmin(np.linalg.norm(corners - at, axis=1)))
                gap = float(np.linalg.norm(corners[k] - at))
                theta = float(angle[int(np.argmin(np.linalg.norm(P - corners[k], axis=1)))])
                bound = FORMULA_SLACK * 2.5 / math.tan(math.radians(theta / 2))
                # The corner's own column runs H / sin(theta / 2) along its bisector.
                reach = max(NEAR_CORNER, 1.1 * thickest(request) / math.sin(math.radians(theta / 2)))
                beside_acute = gap <= reach and theta < ACUTE_DEG and s <= bound
                check(beside_acute, f"{name}: a face of skewness {s:.2f} at {at} is {gap:.3g} from the nearest input "
                                    f"corner, of {theta:.1f} degrees (acute corners' bound {bound:.2f})")
                if not beside_acute:
                    break  # one report a mesh

check(checked >= count, f"most requests meshed ({checked} of {2 * count})")
finish(f"openfoam: {checked} random meshes through checkMesh; {skewed} layered ones with skew faces, "
       "all beside acute input corners at the skewness their angle gives")
