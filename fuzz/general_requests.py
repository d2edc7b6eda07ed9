#!/usr/bin/python3
"""Writes N mesh requests without boundary layers, drawn across what a request may combine:
outer loops of lines, arcs, splines through points and closed B-splines, a half domain on a
NACA section's upper surface; holes of every curve type (circles, polygons, NACA sections,
`.dat` airfoils, closed splines and B-splines), near-touching ones among them; embedded lines
from the outer loop, cuts to a hole, free-standing lines and T junctions; sizes constant,
graded, swinging, jumping, given on curves with eq. 6.1 inside, with gradations and clamps;
every smoothing count, both triangulators, `min_angle_deg` and second-order elements. Each
request is small (fuzz_request meshes those forecast under 3,000 points and holds the mesh to
check_mesh):

    fuzz/general_requests.py DIR N [FIRST_SEED]
    build-fuzz/fuzz/fuzz_request -runs=0 -timeout=30 DIR    # after scripts/fuzz.sh built it

Request k comes from seed FIRST_SEED + k alone, so a finding is written again by its seed.
The layered twin of this generator is fuzz/layered_requests.py."""
import math
import random

from request_files import write_requests


def r4(v):
    return round(v, 4)


def naca4_selig(code, n):
    """The text of a Selig .dat file for a NACA 4-digit section (closed trailing edge): upper
    surface from the trailing edge to the leading edge, then the lower one back."""
    m, p, t = int(code[0]) / 100.0, int(code[1]) / 10.0, int(code[2:]) / 100.0
    xs = [0.5 * (1 - math.cos(math.pi * i / n)) for i in range(n + 1)]

    def surface(x, sign):
        yt = 5 * t * (0.2969 * math.sqrt(x) - 0.1260 * x - 0.3516 * x ** 2 + 0.2843 * x ** 3 - 0.1036 * x ** 4)
        if m == 0 or p == 0:
            yc, dy = 0.0, 0.0
        elif x < p:
            yc, dy = m / p ** 2 * (2 * p * x - x * x), 2 * m / p ** 2 * (p - x)
        else:
            yc, dy = m / (1 - p) ** 2 * (1 - 2 * p + 2 * p * x - x * x), 2 * m / (1 - p) ** 2 * (p - x)
        th = math.atan(dy)
        return x - sign * yt * math.sin(th), yc + sign * yt * math.cos(th)

    upper = [surface(x, 1) for x in reversed(xs)]
    lower = [surface(x, -1) for x in xs[1:]]
    lines = ["NACA %s" % code] + ["%.6f %.6f" % pt for pt in upper + lower]
    return "\n".join(lines) + "\n"


class Builder:
    def __init__(self, r):
        self.r = r
        self.points, self.curves, self.loops, self.embedded = {}, {}, [], []
        self.tags = []

    def point(self, name, xy):
        self.points[name] = [xy[0], xy[1]]
        return name

    def tag(self, c, default):
        t = self.r.choice([default, default, "wall", "farfield", "inlet", None])
        if t:
            c["tag"] = t
            self.tags.append(t)
        return c


def outer(b):
    """An outer loop holding the disk of radius 0.3 about the origin; returns a point of it from
    which an embedded line may start (or None)."""
    r = b.r
    kind = r.choice(["polygon", "polygon", "circle", "spline", "bspline", "mixed"])
    if kind == "polygon":
        m = r.choice([3, 4, 5, 6, 8])
        while True:
            angles = sorted(r.uniform(0, 2 * math.pi) for _ in range(m))
            gaps = [q - p for p, q in zip(angles, angles[1:] + [angles[0] + 2 * math.pi])]
            if max(gaps) < max(0.6 * math.pi, 2 * math.pi / m + 0.2):  # three corners need more
                break
        names = []
        for i, a in enumerate(angles):
            rad = r.uniform(0.65, 1.0)
            names.append(b.point("P%d" % i, [r4(rad * math.cos(a)), r4(rad * math.sin(a))]))
        loop = []
        for i in range(m):
            c = b.tag({"type": "line", "from": names[i], "to": names[(i + 1) % m]}, "side")
            b.curves["o%d" % i] = c
            loop.append("o%d" % i if r.random() < 0.7 else "-o%d" % i)
        # A loop given in any direction, curves possibly reversed: run it as a chain.
        if any(s.startswith("-") for s in loop):
            loop = ["-o%d" % i for i in reversed(range(m))]
        b.loops.append(loop)
        return names[0]
    if kind == "circle":
        R = r.uniform(0.6, 1.2)
        b.point("F", [R, 0.0])
        b.curves["outer"] = b.tag({"type": "arc", "from": "F", "to": "F", "center": [0.0, 0.0],
                                   "direction": r.choice(["ccw", "cw"])}, "farfield")
        b.loops.append(["outer"])
        return "F"
    if kind == "spline":
        m = r.choice([4, 5, 7])
        pts = []
        for i in range(m):
            a = 2 * math.pi * (i + r.uniform(-0.2, 0.2)) / m
            rad = r.uniform(0.75, 1.0)
            pts.append([r4(rad * math.cos(a)), r4(rad * math.sin(a))])
        pts.append(pts[0])
        b.curves["outer"] = b.tag({"type": "spline", "through": pts}, "farfield")
        b.loops.append(["outer"])
        return None
    if kind == "bspline":
        m = r.choice([5, 6, 8])
        ctrl = []
        for i in range(m):
            a = 2 * math.pi * i / m
            rad = r.uniform(0.9, 1.2)
            ctrl.append([r4(rad * math.cos(a)), r4(rad * math.sin(a))])
        ctrl.append(ctrl[0])
        b.curves["outer"] = b.tag({"type": "bspline", "control_points": ctrl,
                                   "degree": r.choice([2, 3, 3, 4])}, "farfield")
        b.loops.append(["outer"])
        return None
    # A rectangle whose top is an arc and whose right side is a spline bowed outwards.
    w, h = r.uniform(0.6, 1.2), r.uniform(0.45, 0.8)
    b.point("A", [-w, -h])
    b.point("B", [w, -h])
    b.point("C", [w, h])
    b.point("D", [-w, h])
    b.curves["bottom"] = b.tag({"type": "line", "from": "A", "to": "B"}, "wall")
    bow = r.uniform(0.0, 0.3)
    b.curves["right"] = b.tag({"type": "spline", "from": "B", "to": "C",
                               "through": [[w, -h], [r4(w + bow), 0.0], [w, h]]}, "outlet")
    # The arc through C and D about a centre below the middle.
    cy = r4(h - r.uniform(0.8, 3.0) * w)
    b.curves["top"] = b.tag({"type": "arc", "from": "C", "to": "D", "center": [0.0, cy]}, "wall")
    # D is on that circle only if |D - centre| = |C - centre|: symmetric about x = 0, it is.
    b.curves["left"] = b.tag({"type": "line", "from": "D", "to": "A"}, "inlet")
    b.loops.append(["bottom", "right", "top", "left"])
    return "A"


def hole(b, k, cx, cy, rad):
    """Hole k of radius about `rad` centred at (cx, cy). Returns (a point name on it for a cut
    to end at, or None)."""
    r = b.r
    name = "h%d" % k
    kind = r.choice(["circle", "circle", "polygon", "naca", "airfoil", "spline", "bspline"])
    if kind == "circle":
        p = b.point("H%d" % k, [r4(cx + rad), r4(cy)])
        b.curves[name] = b.tag({"type": "arc", "from": p, "to": p, "center": [r4(cx), r4(cy)]}, name)
        b.loops.append([name])
        return p
    if kind == "polygon":
        m = r.choice([3, 4, 5, 6])
        phase = r.uniform(0, 2 * math.pi)
        names = [b.point("H%d_%d" % (k, i), [r4(cx + rad * math.cos(phase + 2 * math.pi * i / m)),
                                              r4(cy + rad * math.sin(phase + 2 * math.pi * i / m))]) for i in range(m)]
        loop = []
        for i in range(m):
            cname = "%s_%d" % (name, i)
            b.curves[cname] = b.tag({"type": "line", "from": names[i], "to": names[(i + 1) % m]}, name)
            loop.append(cname)
        b.loops.append(loop)
        return names[0]
    if kind in ("naca", "airfoil"):
        chord = 2 * rad
        c = {"chord": r4(chord), "leading_edge": [r4(cx - rad), r4(cy)], "angle_deg": round(r.uniform(-30, 30), 1)}
        if kind == "naca":
            c.update({"type": "naca", "code": r.choice(["0012", "2412", "4415", "23012", "0006", "6409"]),
                      "trailing_edge": r.choice(["closed", "open"])})
        else:
            c.update({"type": "airfoil", "coordinates": naca4_selig(r.choice(["0012", "2412", "4418"]), r.choice([12, 30, 60])),
                      "trailing_edge": r.choice(["closed", "open"])})
        b.curves[name] = b.tag(c, "wall")
        b.loops.append([name])
        return None
    m = r.choice([4, 5, 6])
    pts = [[r4(cx + rad * r.uniform(0.7, 1.0) * math.cos(2 * math.pi * i / m)),
            r4(cy + rad * r.uniform(0.7, 1.0) * math.sin(2 * math.pi * i / m))] for i in range(m)]
    pts.append(pts[0])
    if kind == "spline":
        b.curves[name] = b.tag({"type": "spline", "through": pts}, name)
    else:
        b.curves[name] = b.tag({"type": "bspline", "control_points": pts, "degree": r.choice([2, 3])}, name)
    b.loops.append([name])
    return None


def half_domain(b):
    """A NACA section's upper surface on a symmetry line, a half circle about it."""
    r = b.r
    R = r.uniform(1.5, 6.0)
    b.point("TE", [1.0, 0.0])
    b.point("LE", [0.0, 0.0])
    b.point("A", [r4(0.5 - R), 0.0])
    b.point("B", [r4(0.5 + R), 0.0])
    b.curves["upper"] = {"type": "naca", "code": r.choice(["0012", "0006", "0030"]), "surface": "upper",
                         "from": "TE", "to": "LE", "tag": "wall"}
    b.curves["front"] = {"type": "line", "from": "LE", "to": "A", "tag": "symmetry"}
    b.curves["far"] = {"type": "arc", "from": "B", "to": "A", "center": [0.5, 0.0], "tag": "farfield"}
    b.curves["back"] = {"type": "line", "from": "B", "to": "TE", "tag": "symmetry"}
    b.loops.append(["upper", "front", "-far", "back"])
    if r.random() < 0.4:
        # A line from the trailing edge at 35 to 80 degrees to the symmetry line: a smaller
        # angle is an input corner that no mesh can give 30-degree triangles beside.
        a = math.radians(r.uniform(35, 80))
        length = r.uniform(0.2, 0.7) * (R - 0.5)
        b.point("W", [r4(1.0 + length * math.cos(a)), r4(length * math.sin(a))])
        b.curves["wake"] = {"type": "line", "from": "TE", "to": "W", "tag": "wake"}
        b.embedded.append("wake")
    size = r.uniform(0.02, 0.1)
    return {"size": "%g + %g*sqrt((x-0.5)^2+y^2)" % (size, r.uniform(0.05, 0.4))}


def density(b):
    r = b.r
    s = 10 ** r.uniform(-1.35, -0.5)
    kind = r.choice(["const", "radial", "linear", "swing", "jump", "curves", "interpolate"])
    d = {}
    if kind == "const":
        d["size"] = s
    elif kind == "radial":
        d["size"] = "%g + %g*sqrt(x^2+y^2)" % (s * r.uniform(0.3, 1.0), r.uniform(0.05, 0.3))
    elif kind == "linear":
        d["size"] = "%g*(1 + %g*abs(x))" % (s, r.uniform(0, 4))
    elif kind == "swing":
        d["size"] = "%g*(1.5 + sin(%g*x + %g*y))" % (s, r.uniform(1, 12), r.uniform(0, 8))
    elif kind == "jump":
        d["size"] = "x < %g ? %g : %g" % (r.uniform(-0.5, 0.5), s, s * r.choice([2, 4, 10]))
    else:
        tag = r.choice(b.tags) if b.tags else None
        if tag:
            d["curves"] = {tag: s * r.uniform(0.2, 1.0)}
        if kind == "curves":
            d["size"] = s
        else:
            d["interior"] = "interpolate"
            if r.random() < 0.5:
                d["size"] = s  # on the curves no entry names
            else:
                # Every curve by name, each its own size (eq. 6.1 spreads them inside).
                d["curves"] = {name: s * r.uniform(0.2, 1.5) for name in b.curves}
    if r.random() < 0.2:
        d["gradation"] = round(r.uniform(1.1, 3.0), 2)
    if r.random() < 0.1:
        d["min"] = s * 0.5
    if r.random() < 0.1:
        d["max"] = s * 2
    return d


def request(seed):
    r = random.Random(seed)
    b = Builder(r)
    if r.random() < 0.12:
        dens = half_domain(b)
    else:
        start = outer(b)
        n = r.choice([0, 1, 1, 2, 3])
        cut_to = None
        if n == 1:
            cut_to = hole(b, 0, r.uniform(-0.05, 0.05), r.uniform(-0.05, 0.05), r.uniform(0.05, 0.25))
        else:
            phase = r.uniform(0, 2 * math.pi)
            for k in range(n):
                a = phase + 2 * math.pi * k / n
                rad = r.uniform(0.03, 0.14 if n == 2 else 0.08)
                hole(b, k, 0.17 * math.cos(a), 0.17 * math.sin(a), rad)
        if r.random() < 0.35:
            # A line from the outer loop inwards, to a hole's point (a cut) or ending free; a
            # T junction on its middle now and then.
            if start is not None:
                p = b.points[start]
                if cut_to is not None and r.random() < 0.5:
                    end = cut_to
                else:
                    f = r.uniform(0.35, 0.6) / max(math.hypot(*p), 1e-9)
                    end = b.point("E", [r4(p[0] * f), r4(p[1] * f)])
                b.curves["emb"] = {"type": "line", "from": start, "to": end, "tag": "interface"}
                b.embedded.append("emb")
                if r.random() < 0.3 and end == "E":
                    e = b.points["E"]
                    mid = [(p[0] + e[0]) / 2, (p[1] + e[1]) / 2]
                    b.point("M", mid)
                    # Perpendicular to the line, away a little.
                    nx, ny = -(e[1] - p[1]), e[0] - p[0]
                    l = math.hypot(nx, ny)
                    b.point("T", [r4(mid[0] + 0.15 * nx / l), r4(mid[1] + 0.15 * ny / l)])
                    b.curves["tee"] = {"type": "line", "from": "M", "to": "T"}
                    b.embedded.append("tee")
            else:
                # A free-standing line beyond the holes.
                a = r.uniform(0, 2 * math.pi)
                b.point("E0", [r4(0.35 * math.cos(a)), r4(0.35 * math.sin(a))])
                b.point("E1", [r4(0.55 * math.cos(a + 0.3)), r4(0.55 * math.sin(a + 0.3))])
                b.curves["emb"] = {"type": "line", "from": "E0", "to": "E1"}
                b.embedded.append("emb")
        dens = density(b)
    geometry = {"points": b.points, "curves": b.curves, "loops": b.loops}
    if b.embedded:
        geometry["embedded"] = b.embedded
    options = {"max_points": 3000}
    if r.random() < 0.3:
        options["smoothing_iterations"] = r.choice([0, 1, 2, 20])
    if r.random() < 0.15:
        options["triangulator"] = "advancing-front"
    if r.random() < 0.2:
        options["min_angle_deg"] = r.choice([15, 25, 30, 33, 34])
    if r.random() < 0.12:
        options["order"] = 2
    return {"geometry": geometry, "density": dens, "options": options}


def main():
    write_requests(__doc__, "general", request)


if __name__ == "__main__":
    main()
