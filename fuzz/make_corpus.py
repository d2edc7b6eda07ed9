#!/usr/bin/python3
"""Writes the seed corpora of the fuzz harnesses (fuzz/corpus/<harness>/) from the examples,
the bad-request catalogue and a few generated inputs. Run from anywhere; rewrites the seeds."""
import json
import math
import os
import shutil
import struct

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
out = os.path.join(root, "fuzz", "corpus")


def put(harness, name, data):
    d = os.path.join(out, harness)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


shutil.rmtree(out, ignore_errors=True)

# Requests: the examples, every case of the bad-request catalogue, small meshes of each curve type.
examples = os.path.join(root, "examples")
for n in sorted(os.listdir(examples)):
    if n.endswith(".json"):
        with open(os.path.join(examples, n), "rb") as f:
            put("request", "example-" + n, f.read())
catalogue = json.load(open(os.path.join(root, "tests", "data", "bad_requests.json")))
for i, case in enumerate(catalogue["cases"]):
    body = case["raw"] if "raw" in case else json.dumps(case["body"])
    put("request", "bad-%03d.json" % i, body)
square = {"points": {"A": [0, 0], "B": [1, 0], "C": [1, 1], "D": [0, 1]},
          "curves": {"b": {"type": "line", "from": "A", "to": "B", "tag": "wall"},
                     "r": {"type": "line", "from": "B", "to": "C"},
                     "t": {"type": "line", "from": "C", "to": "D"},
                     "l": {"type": "line", "from": "D", "to": "A"}},
          "loops": [["b", "r", "t", "l"]]}
put("request", "square.json", json.dumps({"geometry": square, "density": {"size": 0.1}}))
holes = json.loads(json.dumps(square))
holes["points"]["P"] = [0.6, 0.5]
holes["curves"]["h"] = {"type": "arc", "from": "P", "to": "P", "center": [0.5, 0.5]}
holes["curves"]["s"] = {"type": "spline", "through": [[0.1, 0.1], [0.2, 0.3], [0.3, 0.1], [0.1, 0.1]]}
holes["curves"]["w"] = {"type": "bspline", "control_points": [[0.7, 0.2], [0.9, 0.2], [0.9, 0.4], [0.7, 0.2]], "degree": 2}
holes["points"]["E"] = [0.5, 0.9]
holes["curves"]["e"] = {"type": "line", "from": "D", "to": "E", "tag": "wake"}
holes["loops"] += [["h"], ["s"], ["w"]]
holes["embedded"] = ["e"]
put("request", "holes.json", json.dumps({"geometry": holes, "density": {
    "size": "0.02 + 0.1*sqrt((x-0.5)^2+(y-0.5)^2)", "gradation": 1.3},
    "options": {"triangulator": "advancing_front", "min_angle_deg": 25}}))

layered = json.loads(json.dumps(square))
layered["points"]["P"] = [0.7, 0.5]
layered["curves"]["h"] = {"type": "arc", "from": "P", "to": "P", "center": [0.5, 0.5], "tag": "hole"}
layered["loops"] += [["h"]]
put("request", "layers.json", json.dumps({"geometry": layered, "density": {"size": 0.05},
    "boundary_layers": [{"curves": ["hole", "b"], "first_height": 0.002, "growth": 1.3, "layers": 6},
                        {"curves": ["l"], "first_height": 0.01, "thickness": 0.04, "cells": "triangles"}]}))

# Expressions.
for i, e in enumerate(["0.1", "x < 0.5 ? 0.1*sqrt(x^2+y^2)+0.007 : 0.1*sqrt((x-1)^2+y^2)+0.006",
                       "0.4*sqrt(x^2+y^2)+0.2", "max(0.01, min(0.2, abs(sin(3*x)*cos(2*y))))",
                       "exp(-((x-1)^2+y^2)/0.1) + log(2 + x*x) - tanh(y)", "2^-3^2", "-(-x)",
                       "x > 0 && y > 0 || !(x == y) ? pow(x, 2) : atan2(y, x)", "1e308*1e308",
                       "((((((((((x))))))))))", "floor(x) + ceil(y) + hypot(x, y)"]):
    put("expression", "e%02d" % i, e)

# Airfoil files: Selig and Lednicer layouts of NACA 0012.
def naca(upper, n, a4):
    pts = []
    for i in range(n + 1):
        b = math.pi * i / n
        x = 0.5 * (1 - math.cos(b))
        yt = 0.6 * (0.2969 * math.sqrt(x) - 0.1260 * x - 0.3516 * x * x + 0.2843 * x ** 3 - a4 * x ** 4)
        pts.append((x, yt if upper else -yt))
    return pts


up, lo = naca(True, 30, 0.1015), naca(False, 30, 0.1015)
selig = "NACA 0012\n" + "".join("  %.6f  %.6f\n" % p for p in reversed(up)) + \
    "".join("  %.6f  %.6f\n" % p for p in lo[1:])
put("airfoil_dat", "selig.dat", selig)
led = "NACA 0012 LEDNICER\n       31.       31.\n\n" + "".join(" %.6f %.6f\n" % p for p in up) + "\n" + \
    "".join(" %.6f %.6f\n" % p for p in lo)
put("airfoil_dat", "lednicer.dat", led)
put("airfoil_dat", "closed.dat", "".join("%.5f %.5f\n" % p for p in reversed(naca(True, 12, 0.1036))) +
    "".join("%.5f %.5f\n" % p for p in naca(False, 12, 0.1036)[1:]))

# Triangulation inputs: a full grid; a grid with perturbed points and a fan of segments.
grid = b"".join(bytes([x, y]) for x in range(16) for y in range(16))
put("triangulation", "grid", grid)
pert = b"".join(bytes([x, y | ((x * 7 + y) % 6) << 4]) for x in range(0, 16, 2) for y in range(0, 16, 3))
fan = b"".join(bytes([0x80 | 0, k]) for k in range(1, 30, 3))
put("triangulation", "perturbed-fan", pert + fan)
put("triangulation", "diagonal", bytes([0, 0, 5, 5, 10, 10, 15, 15, 0x80, 3, 0x81, 2, 3, 12, 12, 3]))
