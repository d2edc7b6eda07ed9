#!/usr/bin/python3
"""A finite-element convergence study on meshd's meshes, in dolfinx as a FEniCS user runs it:
the annulus 0.5 < r < 1, -Laplace(u) = 0 with u = log r given per boundary tag (a constant on
each circle), meshes of meshd-cli as MSH files loaded through gmsh (gmshio.model_to_mesh),
three sizes halving. The rates of the L2 and H1-seminorm errors against log r must be those
of the theory: P1 on straight (order 1) meshes about 2 and 1; P2 on second-order meshes
(edge nodes on the circles) about 3 and 2; P2 on straight meshes falls short of 3 (the
polygonal boundary's error, what options.order 2 is for).

usage: dolfinx_convergence.py MESHD_CLI"""
import json
import math
import os
import subprocess
import sys
import tempfile

import ufl
from dolfinx import fem
from dolfinx.fem import petsc as fem_petsc
from petsc4py import PETSc

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import check, dolfinx_mesh, finish  # noqa: E402

cli = sys.argv[1]
R_IN, R_OUT = 0.5, 1.0
SIZES = [0.2, 0.1, 0.05]


def annulus(size, order):
    return {"geometry": {"points": {"O": [R_OUT, 0], "I": [R_IN, 0]},
                         "curves": {"outer": {"type": "arc", "from": "O", "to": "O", "center": [0, 0], "tag": "outer"},
                                    "inner": {"type": "arc", "from": "I", "to": "I", "center": [0, 0], "tag": "inner"}},
                         "loops": [["outer"], ["inner"]]},
            "density": {"size": size}, "options": {"order": order}}


def errors(msh, degree):
    mesh, facets, names = dolfinx_mesh(msh)
    V = fem.FunctionSpace(mesh, ("CG", degree))
    x = ufl.SpatialCoordinate(mesh)
    exact = ufl.ln(ufl.sqrt(x[0] ** 2 + x[1] ** 2))
    bcs = []
    for tag, name in names.items():
        value = 0.0 if name == "outer" else math.log(R_IN)  # log r on each circle
        dofs = fem.locate_dofs_topological(V, 1, facets.find(tag))
        bcs.append(fem.dirichletbc(PETSc.ScalarType(value), dofs, V))
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    zero = fem.Constant(mesh, PETSc.ScalarType(0.0))
    problem = fem_petsc.LinearProblem(ufl.inner(ufl.grad(u), ufl.grad(v)) * ufl.dx, zero * v * ufl.dx, bcs=bcs,
                                      petsc_options={"ksp_type": "preonly", "pc_type": "lu"})
    uh = problem.solve()
    dx = ufl.dx(metadata={"quadrature_degree": 8})
    l2 = math.sqrt(fem.assemble_scalar(fem.form((uh - exact) ** 2 * dx)))
    h1 = math.sqrt(fem.assemble_scalar(fem.form(ufl.inner(ufl.grad(uh - exact), ufl.grad(uh - exact)) * dx)))
    return l2, h1


def rates(errs):
    return [math.log(errs[i] / errs[i + 1]) / math.log(SIZES[i] / SIZES[i + 1]) for i in range(len(errs) - 1)]


results = {}
with tempfile.TemporaryDirectory() as tmp:
    for order in (1, 2):
        files = []
        for size in SIZES:
            req = os.path.join(tmp, f"annulus_{order}_{size}.json")
            with open(req, "w") as f:
                json.dump(annulus(size, order), f)
            out = os.path.join(tmp, f"annulus_{order}_{size}.msh")
            subprocess.run([cli, req, "-q", "-o", out], check=True)
            files.append(out)
        for degree in (1, 2):
            if order == 2 and degree == 1:
                continue
            e = [errors(f, degree) for f in files]
            l2, h1 = rates([a for a, _ in e]), rates([b for _, b in e])
            results[(degree, order)] = (l2, h1)
            print(f"P{degree} on order-{order} meshes: L2 errors {[f'{a:.3e}' for a, _ in e]} rates {[f'{r:.2f}' for r in l2]};"
                  f" H1 errors {[f'{b:.3e}' for _, b in e]} rates {[f'{r:.2f}' for r in h1]}")

l2, h1 = results[(1, 1)]
check(min(l2) > 1.8 and min(h1) > 0.9, f"P1, order 1: rates L2 {l2}, H1 {h1} (theory 2, 1)")
l2, h1 = results[(2, 2)]
check(min(l2) > 2.7 and min(h1) > 1.8, f"P2, order 2: rates L2 {l2}, H1 {h1} (theory 3, 2)")
l2_straight, h1_straight = results[(2, 1)]
check(l2_straight[-1] < 2.6, f"P2 on straight meshes is held back by the polygonal boundary (L2 rate {l2_straight})")
finish("convergence rates as the theory says")
