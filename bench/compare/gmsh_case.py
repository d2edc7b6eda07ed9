"""The benchmark case in gmsh, shared by the gmsh scripts of bench/: NACA 0012 (chord 1,
leading edge at the origin, closed trailing edge, 2 x 200 points from the formula joined by
splines) in a circle of radius 20 about (0.5, 0), and the paper's Fig. 10 density times s
as a MathEval background field (evaluated inside gmsh, no Python callback)."""
import math

import gmsh


def thickness(x):
    return 0.6 * (0.2969 * math.sqrt(x) - 0.1260 * x - 0.3516 * x * x + 0.2843 * x ** 3 - 0.1036 * x ** 4)


def add_naca_case(s, n=200):
    """Adds the case to the current model (built-in kernel, synchronized) and sets its
    density; returns (the wing's two curves, its trailing-edge point)."""
    geo = gmsh.model.geo
    te = geo.addPoint(1, 0, 0)
    le = geo.addPoint(0, 0, 0)
    upper, lower = [te], [le]
    for i in range(1, n):
        x = 0.5 * (1 + math.cos(math.pi * i / n))  # from the trailing edge to the leading edge
        upper.append(geo.addPoint(x, thickness(x), 0))
    upper.append(le)
    for i in range(1, n):
        x = 0.5 * (1 - math.cos(math.pi * i / n))
        lower.append(geo.addPoint(x, -thickness(x), 0))
    lower.append(te)
    wing = [geo.addSpline(upper), geo.addSpline(lower)]
    centre = geo.addPoint(0.5, 0, 0)
    ring = [geo.addPoint(0.5 + 20 * math.cos(k * math.pi / 2), 20 * math.sin(k * math.pi / 2), 0) for k in range(4)]
    arcs = [geo.addCircleArc(ring[k], centre, ring[(k + 1) % 4]) for k in range(4)]
    geo.addPlaneSurface([geo.addCurveLoop(arcs), geo.addCurveLoop(wing)])
    geo.synchronize()

    field = gmsh.model.mesh.field
    f = field.add("MathEval")
    a = f"(0.1*Sqrt(x*x+y*y)+0.007)*{s}"
    b = f"(0.1*Sqrt((x-1.008930411365)*(x-1.008930411365)+y*y)+0.006)*{s}"
    # Step at x = 0.5 without a conditional: (1 + sign) / 2 with sign = t / |t|.
    field.setString(f, "F", f"{a}*(1-(x-0.5)/Fabs(x-0.5+1e-30))/2 + {b}*(1+(x-0.5)/Fabs(x-0.5+1e-30))/2")
    field.setAsBackgroundMesh(f)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
    return wing, te
