#!/usr/bin/python3
"""Writes N mesh requests with boundary layers drawn from the corners of what a request may ask:
layers as thick as the domain or thicker, growth 1, hundreds of layers, first heights from 1e-4
to 1 of the size, walls meeting at any angle, holes and embedded lines near and inside the
layers, curved walls, `min_angle_deg` now and then. Each request is small (its forecast under
fuzz_request's 3,000 points at most sizes), so the harness meshes it and holds the mesh to
check_mesh:

    fuzz/layered_requests.py DIR N [FIRST_SEED]
    build-fuzz/fuzz/fuzz_request -runs=0 -timeout=30 DIR    # after scripts/fuzz.sh built it

Request k comes from seed FIRST_SEED + k alone, so a finding is written again by its seed.
libFuzzer's own mutations seldom reach these: a CI run found the first such input (a layer
top sliding past its column's first point, fuzz/regressions/request-7e6d2a1c) in a minute
and longer campaigns had not; 3,000 of these found the next (request-d1abb269)."""
import math
import random

from request_files import write_requests


def airfoil(r):
    """A NACA section (sometimes two, a slat's gap apart) in a far field from 1.3 to 20 chords,
    layers on the wing or on everything."""
    code = r.choice(["0012", "0006", "2412", "4415", "23012", "0030"])
    te = r.choice(["closed", "open"])
    points = {"F": [r.uniform(1.3, 20.0), 0.0]}
    curves = {
        "wing": {"type": "naca", "code": code, "trailing_edge": te, "angle_deg": round(r.uniform(-20, 20), 2),
                 "leading_edge": [round(r.uniform(-0.3, 0.0), 3), 0.0], "tag": "wall"},
        "farfield": {"type": "arc", "from": "F", "to": "F", "center": [0.3, 0.0],
                     "tag": "wall" if r.random() < 0.2 else "farfield"},
    }
    points["F"][0] += 0.3
    loops = [["farfield"], ["wing"]]
    if r.random() < 0.3:
        curves["slat"] = {"type": "naca", "code": "0012", "chord": round(r.uniform(0.1, 0.3), 3),
                          "leading_edge": [round(r.uniform(-0.6, -0.35), 3), round(r.uniform(-0.08, 0.02), 3)],
                          "angle_deg": round(r.uniform(-40, 0), 1), "tag": "wall"}
        loops.append(["slat"])
    geometry = {"points": points, "curves": curves, "loops": loops}
    if r.random() < 0.3:
        # A wake line from near the trailing edge.
        points["W0"] = [1.02, 0.0]
        points["W1"] = [round(r.uniform(1.1, 1.2), 3), round(r.uniform(-0.1, 0.1), 3)]
        curves["wake"] = {"type": "line", "from": "W0", "to": "W1"}
        geometry["embedded"] = ["wake"]
    size = 10 ** r.uniform(-1.7, 0.0)
    density = {"size": "%g + %g*sqrt(x^2+y^2)" % (size * r.uniform(0.05, 1.0), r.uniform(0.05, 0.5))}
    return geometry, density


def request(seed):
    r = random.Random(seed)
    if r.random() < 0.25:
        geometry, density = airfoil(r)
        size = 0.05
        entries = [{"curves": ["wall"], "first_height": 10 ** r.uniform(-5, -0.5)}]
        if "slat" in geometry["curves"] and r.random() < 0.5:
            entries = [{"curves": ["wing"], "first_height": 10 ** r.uniform(-5, -1)},
                       {"curves": ["slat"], "first_height": 10 ** r.uniform(-5, -1)}]
        for e in entries:
            if r.random() < 0.7:
                e["layers"] = r.choice([1, 5, 20, 60, 200])
                e["growth"] = r.choice([1.0, 1.1, 1.2, 1.5, 3.0])
            else:
                e["thickness"] = 10 ** r.uniform(-3, 0)
        options = {"max_points": 3000}
        if r.random() < 0.2:
            options["min_angle_deg"] = r.choice([20, 28, 30, 33])
        return {"geometry": geometry, "density": density, "boundary_layers": entries, "options": options}
    m = r.choice([3, 4, 4, 5, 6])
    # A loop around the origin, star-shaped: its corners by angle.
    while True:
        angles = sorted(r.uniform(0, 2 * math.pi) for _ in range(m))
        gaps = [b - a for a, b in zip(angles, angles[1:] + [angles[0] + 2 * math.pi])]
        if max(gaps) < 0.8 * math.pi:  # the origin well inside
            break
    points, names = {}, []
    for i, a in enumerate(angles):
        rad = r.uniform(0.4, 1.0)
        names.append("P%d" % i)
        points[names[-1]] = [round(rad * math.cos(a), 4), round(rad * math.sin(a), 4)]
    curves, loop = {}, []
    for i in range(m):
        a, b = names[i], names[(i + 1) % m]
        c = {"type": "line", "from": a, "to": b}
        if r.random() < 0.15:
            # Bowed inwards or outwards through a point off the chord's middle.
            pa, pb = points[a], points[b]
            mid = [(pa[0] + pb[0]) / 2, (pa[1] + pb[1]) / 2]
            nx, ny = pa[1] - pb[1], pb[0] - pa[0]
            bow = r.uniform(-0.12, 0.2)
            c = {"type": "spline", "from": a, "to": b,
                 "through": [pa, [mid[0] + bow * nx, mid[1] + bow * ny], pb]}
        if i == 0 or r.random() < 0.4:
            c["tag"] = "wall"
        curves["e%d" % i] = c
        loop.append("e%d" % i)
    loops = [loop]
    hole = r.random() < 0.4
    if hole:
        rad = r.uniform(0.03, 0.15)
        cx, cy = r.uniform(-0.1, 0.1), r.uniform(-0.1, 0.1)
        points["H"] = [cx + rad, cy]
        curves["hole"] = {"type": "arc", "from": "H", "to": "H", "center": [cx, cy],
                          "tag": "wall" if r.random() < 0.7 else "hole"}
        loops.append(["hole"])
    geometry = {"points": points, "curves": curves, "loops": loops}
    if r.random() < 0.3:
        # An embedded line from a corner inwards, or a free-standing one.
        # Its end between the first corner and the middle (beyond any hole, which lies
        # within 0.25 of the middle).
        p0 = points[names[0]]
        along = r.uniform(0.15, 0.55) if hole else r.uniform(0.15, 0.95)
        points["E"] = [p0[0] * (1 - along) + r.uniform(-0.05, 0.05), p0[1] * (1 - along) + r.uniform(-0.05, 0.05)]
        start = names[0]
        if r.random() < 0.3:
            points["F"] = [p0[0] * 0.7, p0[1] * 0.7]
            start = "F"
        curves["emb"] = {"type": "line", "from": start, "to": "E"}
        geometry["embedded"] = ["emb"]
    size = 10 ** r.uniform(-1.3, 0.5)
    if r.random() < 0.5:
        density = {"size": size}
    else:
        density = {"size": "%g + %g*abs(x)" % (size, size * r.uniform(0, 3))}
    layers = {"curves": ["wall"], "first_height": 10 ** r.uniform(-4, 0) * size}
    if r.random() < 0.7:
        layers["layers"] = r.choice([1, 2, 3, 5, 10, 30, 200])
        layers["growth"] = r.choice([1.0, 1.0, 1.05, 1.2, 1.5, round(r.uniform(1.0, 2.0), 3)])
    else:
        layers["thickness"] = 10 ** r.uniform(-2, 0.3) * size
        layers["growth"] = r.choice([1.0, 1.1, 1.3])
    if r.random() < 0.2:
        layers["cells"] = "triangles"
    options = {"max_points": 3000}
    if r.random() < 0.2:
        options["min_angle_deg"] = r.choice([20, 28, 30, 33])
    return {"geometry": geometry, "density": density, "boundary_layers": [layers], "options": options}


def main():
    write_requests(__doc__, "layered", request)


if __name__ == "__main__":
    main()
