#!/usr/bin/env python3
"""Writes tests/data/bad_requests.json: requests that must be refused, with the status and
JSON pointer of the answer. Run it after changing the cases; the file is committed so that
the C++ tests and the HTTP tests read the same catalogue."""
import copy
import json
import os

BASE = {
    "geometry": {
        "points": {"A": [0, 0], "B": [1, 0], "C": [1, 1], "D": [0, 1]},
        "curves": {
            "bottom": {"type": "line", "from": "A", "to": "B", "tag": "wall"},
            "right": {"type": "line", "from": "B", "to": "C"},
            "top": {"type": "line", "from": "C", "to": "D", "tag": "wall"},
            "left": {"type": "line", "from": "D", "to": "A"},
        },
        "loops": [["bottom", "right", "top", "left"]],
    },
    "density": {"size": 0.1},
}

cases = []


def case(name, status, pointer, edit=None, raw=None):
    if raw is not None:
        cases.append({"name": name, "raw": raw, "status": status, "pointer": pointer})
        return
    body = copy.deepcopy(BASE)
    edit(body)
    cases.append({"name": name, "body": body, "status": status, "pointer": pointer})


def g(b):
    return b["geometry"]


def setp(path, value):
    def f(b):
        cur = b
        for k in path[:-1]:
            cur = cur[k]
        cur[path[-1]] = value
    return f


def delp(path):
    def f(b):
        cur = b
        for k in path[:-1]:
            cur = cur[k]
        del cur[path[-1]]
    return f


def hole(name, center, r, point):
    def f(b):
        g(b)["points"][point] = [center[0] + r, center[1]]
        g(b)["curves"][name] = {"type": "arc", "from": point, "to": point, "center": center}
        g(b)["loops"].append([name])
    return f


def chain(*fs):
    def f(b):
        for x in fs:
            x(b)
    return f


# Malformed documents
case("malformed JSON", 400, "", raw="{\"geometry\": ")
case("not an object", 400, "", raw="[1, 2, 3]")
case("NaN literal", 400, "", raw=json.dumps(BASE).replace("[1, 0]", "[NaN, 0]"))
case("trailing garbage", 400, "", raw=json.dumps(BASE) + " }")
case("deep nesting", 400, "", raw="[" * 5000 + "]" * 5000)
case("empty body", 400, "", raw="")
case("a member a line does not have", 400, "/geometry/curves/bottom/center",
     setp(["geometry", "curves", "bottom", "center"], [0, 0]))
case("a bspline degree that is not an integer", 400, "/geometry/curves/blob/degree",
     lambda b: g(b)["curves"].update({"blob": {"type": "bspline", "control_points": [[0.2, 0.2], [0.3, 0.3], [0.4, 0.2]],
                                               "degree": 1.5}}))
case("a number beyond a double", 400, "", raw=json.dumps(BASE).replace('"size": 0.1', '"size": 1e400'))
case("a NACA code as a number (it would lose its leading zeros)", 400, "/geometry/curves/wing/code",
     lambda b: g(b)["curves"].update({"wing": {"type": "naca", "code": 12}}))
case("a tag with a newline", 400, "/geometry/curves/bottom/tag", setp(["geometry", "curves", "bottom", "tag"], "wall\nx"))
case("a tag with a double quote", 400, "/geometry/curves/bottom/tag", setp(["geometry", "curves", "bottom", "tag"], 'wa"ll'))
case("an empty tag", 400, "/geometry/curves/bottom/tag", setp(["geometry", "curves", "bottom", "tag"], ""))
case("a tag of 257 characters", 400, "/geometry/curves/bottom/tag", setp(["geometry", "curves", "bottom", "tag"], "w" * 257))


def renamed(old, new):
    def f(b):
        c = g(b)["curves"]
        c[new] = c.pop(old)
        g(b)["loops"] = [[new if n == old else n for n in loop] for loop in g(b)["loops"]]
    return f


case("a curve named with a control character and no tag", 400, "/geometry/curves/ri\u0007ght",
     renamed("right", "ri\u0007ght"))
case("max_points beyond 2^28", 400, "/options/max_points", setp(["options"], {"max_points": 2**28 + 1}))
case("a curve in no loop", 422, "/geometry/curves/extra",
     lambda b: g(b)["curves"].update({"extra": {"type": "line", "from": "A", "to": "C"}}))
case("a spline point beyond 1e30", 422, "/geometry/curves/blob/through/2",
     lambda b: (g(b)["curves"].update({"blob": {"type": "spline", "through": [[0.2, 0.2], [0.4, 0.2], [1e300, 0.3],
                                                                              [0.2, 0.4], [0.2, 0.2]]}}),
                g(b)["loops"].append(["blob"])))
case("an arc centre beyond 1e30", 422, "/geometry/curves/hole/center",
     lambda b: (g(b)["points"].update({"H": [0.6, 0.5]}),
                g(b)["curves"].update({"hole": {"type": "arc", "from": "H", "to": "H", "center": [-1e31, 0.5]}}),
                g(b)["loops"].append(["hole"])))
case("a point named twice", 400, "/geometry/points/A",
     raw=json.dumps(BASE).replace('"A": [0, 0],', '"A": [0, 0], "A": [0.5, 0],'))
case("a curve member named twice", 400, "/geometry/curves/right/to",
     raw=json.dumps(BASE).replace('"to": "C"}', '"to": "C", "to": "D"}'))
case("an option named twice", 400, "/options/smoothing_iterations",
     raw=json.dumps(BASE)[:-1] + ', "options": {"smoothing_iterations": 1, "smoothing_iterations": 2}}')
# Shape of the request
case("unknown top-level field", 400, "/extra", setp(["extra"], 1))
case("missing geometry", 400, "/geometry", delp(["geometry"]))
case("missing density", 400, "/density", delp(["density"]))
case("geometry not an object", 400, "/geometry", setp(["geometry"], 5))
case("unknown geometry field", 400, "/geometry/lops", setp(["geometry", "lops"], []))
case("points not an object", 400, "/geometry/points", setp(["geometry", "points"], []))
case("point not a pair", 400, "/geometry/points/A", setp(["geometry", "points", "A"], [1]))
case("coordinate is a string", 400, "/geometry/points/A/0", setp(["geometry", "points", "A"], ["0", 0]))
case("curve without type", 400, "/geometry/curves/bottom/type", delp(["geometry", "curves", "bottom", "type"]))
case("unknown curve type", 400, "/geometry/curves/bottom/type", setp(["geometry", "curves", "bottom", "type"], "circle"))
case("typo in a curve field", 400, "/geometry/curves/bottom/form",
     chain(delp(["geometry", "curves", "bottom", "from"]), setp(["geometry", "curves", "bottom", "form"], "A")))
case("line without to", 400, "/geometry/curves/right/to", delp(["geometry", "curves", "right", "to"]))
case("arc without center", 400, "/geometry/curves/right/center", setp(["geometry", "curves", "right"], {"type": "arc", "from": "B", "to": "C"}))
case("arc direction invalid", 400, "/geometry/curves/right/direction",
     setp(["geometry", "curves", "right"], {"type": "arc", "from": "B", "to": "C", "center": [1, 0.5], "direction": "up"}))
case("loops not an array", 400, "/geometry/loops", setp(["geometry", "loops"], {"a": 1}))
case("loop entry not a string", 400, "/geometry/loops/0/1", setp(["geometry", "loops"], [["bottom", 7, "top", "left"]]))
case("bspline degree zero", 400, "/geometry/curves/top/degree",
     setp(["geometry", "curves", "top"], {"type": "bspline", "control_points": [[1, 1], [0.5, 1.2], [0, 1]], "degree": 0}))
case("density not an object", 400, "/density", setp(["density"], "fine"))
case("density without size or curves", 400, "/density", setp(["density"], {}))
case("density size wrong type", 400, "/density/size", setp(["density", "size"], True))
case("unknown density field", 400, "/density/sizes", setp(["density", "sizes"], 0.1))
case("options unknown field", 400, "/options/smoothing", setp(["options"], {"smoothing": 3}))
case("negative smoothing", 400, "/options/smoothing_iterations", setp(["options"], {"smoothing_iterations": -1}))
case("unknown triangulator", 400, "/options/triangulator", setp(["options"], {"triangulator": "voronoi"}))
case("negative timeout", 400, "/options/timeout_s", setp(["options"], {"timeout_s": -5}))
case("min angle too large", 400, "/options/min_angle_deg", setp(["options"], {"min_angle_deg": 50}))
case("max_points zero", 400, "/options/max_points", setp(["options"], {"max_points": 0}))
case("unknown patch type", 400, "/options/patch_types/wall", setp(["options"], {"patch_types": {"wall": "inlet"}}))
case("patch type not a string", 400, "/options/patch_types/wall", setp(["options"], {"patch_types": {"wall": 1}}))
case("patch types not an object", 400, "/options/patch_types", setp(["options"], {"patch_types": ["wall"]}))
case("zero slab thickness", 400, "/options/slab_thickness", setp(["options"], {"slab_thickness": 0}))
# Valid shape, invalid domain
case("unknown curve in a loop", 422, "/geometry/loops/0/1", setp(["geometry", "loops"], [["bottom", "rigth", "top", "left"]]))
case("unknown point", 422, "/geometry/curves/right/to", setp(["geometry", "curves", "right", "to"], "Z"))
case("open loop", 422, "/geometry/loops/0/0", setp(["geometry", "loops"], [["bottom", "right", "top"]]))
case("loop out of order", 422, "/geometry/loops/0/1", setp(["geometry", "loops"], [["bottom", "top", "right", "left"]]))
case("crossing curves", 422, "/geometry/curves/right",
     chain(setp(["geometry", "curves", "right"], {"type": "line", "from": "B", "to": "D"}),
           setp(["geometry", "curves", "left"], {"type": "line", "from": "C", "to": "A"}),
           setp(["geometry", "loops"], [["bottom", "right", "-top", "left"]])))
case("self-crossing bspline", 422, "/geometry/curves/top",
     setp(["geometry", "curves", "top"], {"type": "bspline", "from": "C", "to": "D",
                                           "control_points": [[1, 1], [-0.5, 2], [1.5, 2], [0, 1]]}))
case("coordinate 1e308", 422, "/geometry/points/C", setp(["geometry", "points", "C"], [1e308, 1]))
case("zero-length line", 422, "/geometry/curves/bottom",
     chain(setp(["geometry", "points", "B"], [0, 0])))
case("arc ends off the circle", 422, "/geometry/curves/right/center",
     setp(["geometry", "curves", "right"], {"type": "arc", "from": "B", "to": "C", "center": [1.2, 0.4]}))
case("too few control points", 422, "/geometry/curves/top/control_points",
     setp(["geometry", "curves", "top"], {"type": "bspline", "from": "C", "to": "D", "control_points": [[1, 1], [0, 1]]}))
case("knots of the wrong size", 422, "/geometry/curves/top/knots",
     setp(["geometry", "curves", "top"], {"type": "bspline", "from": "C", "to": "D", "degree": 2,
                                           "control_points": [[1, 1], [0.5, 1.2], [0, 1]], "knots": [0, 0, 1, 1]}))
case("bspline ends off its points", 422, "/geometry/curves/top/to",
     setp(["geometry", "curves", "top"], {"type": "bspline", "from": "C", "to": "D", "degree": 2,
                                           "control_points": [[1, 1], [0.5, 1.2], [0.1, 1]]}))
case("NACA code that does not exist", 422, "/geometry/curves/wing/code",
     chain(hole("wing", [0.5, 0.5], 0.1, "W"), setp(["geometry", "curves", "wing"], {"type": "naca", "code": "0099x", "chord": 0.3, "leading_edge": [0.3, 0.5]})))
case("airfoil text that is not an airfoil", 422, "/geometry/curves/wing/coordinates",
     chain(hole("wing", [0.5, 0.5], 0.1, "W"), setp(["geometry", "curves", "wing"], {"type": "airfoil", "coordinates": "hello\nworld\n"})))
case("hole outside", 422, "/geometry/loops/1", hole("h", [3, 3], 0.2, "H"))
case("holes inside each other", 422, "/geometry/loops/2", chain(hole("h1", [0.5, 0.5], 0.3, "H1"), hole("h2", [0.5, 0.5], 0.1, "H2")))
case("embedded curve outside", 422, "/geometry/embedded/0",
     chain(setp(["geometry", "points", "P"], [2, 2]), setp(["geometry", "points", "Q"], [3, 2]),
           setp(["geometry", "curves", "stray"], {"type": "line", "from": "P", "to": "Q"}), setp(["geometry", "embedded"], ["stray"])))
case("curve used twice", 422, "/geometry/embedded/0", setp(["geometry", "embedded"], ["top"]))
case("coincident named points", 422, "/geometry/points/E",
     chain(setp(["geometry", "points", "E"], [1, 1]), setp(["geometry", "curves", "top", "from"], "E")))
# Density
case("negative density", 422, "/density/size", setp(["density", "size"], -1))
case("zero density", 422, "/density/size", setp(["density", "size"], 0))
case("expression syntax error", 422, "/density/size", setp(["density", "size"], "0.1 * (x +"))
case("unknown function", 422, "/density/size", setp(["density", "size"], "foo(x)"))
case("division by zero", 422, "/density/size", setp(["density", "size"], "1 / (x - x)"))
case("negative somewhere", 422, "/density/size", setp(["density", "size"], "x - 0.5"))
case("NaN somewhere", 422, "/density/size", setp(["density", "size"], "sqrt(x - 2)"))
case("per-curve key that names nothing", 422, "/density/curves/nope", setp(["density", "curves"], {"nope": 0.1}))
case("gradation below one", 422, "/density/gradation", setp(["density", "gradation"], 0.5))
case("max below min", 422, "/density/max", chain(setp(["density", "min"], 0.2), setp(["density", "max"], 0.1)))
case("no density for a curve", 422, "/density/curves",
     chain(delp(["density", "size"]), setp(["density", "curves"], {"wall": 0.1})))
# Size
case("too many points", 413, "/options/max_points", chain(setp(["density", "size"], 0.0005), setp(["options"], {"max_points": 1000})))

out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "bad_requests.json")
with open(out, "w") as f:
    json.dump({"base": BASE, "cases": cases}, f, indent=1)
    f.write("\n")
print(f"{len(cases)} cases -> {out}")
