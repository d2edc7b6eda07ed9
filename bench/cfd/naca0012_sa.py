#!/usr/bin/python3
"""NACA 0012 at Re 6e6 with Spalart-Allmaras in OpenFOAM's simpleFoam, on meshd's foam output
with no glue of the user's own: the request names the wall's patch type, meshd-cli writes
constant/polyMesh, this script adds what any OpenFOAM case needs (fields, schemes, solver
settings, a forceCoeffs function object) and runs simpleFoam. Prints Cl and Cd at each angle
(a benchmark, minutes per angle; not a test).

Two meshes: isotropic (the wall takes nutUSpaldingWallFunction, y+ far above 1), or with
--layers, meshd's boundary layers (first height 1e-5 chord, growth 1.15, up to 40 layers: y+
about 1, no wall function: nutLowReWallFunction). The far field is the example's circle of
radius 20 chords unless --far=R gives another radius (the TMR's grids reach 500 chords); the
example's density grows with the distance from the wing, so a far field of 500 chords costs a few
hundred cells more. Prints y+ on the wing (OpenFOAM's yPlus function object) and how much Cl and
Cd still moved over the last 10% of the iterations (the convergence that matters for a table of
coefficients, whatever the residual targets say).

--nutilda=upwind convects nuTilda with first-order upwinding (default linearUpwind, second
order), which can let its residual fall where the second-order scheme stalls.

--relax=F sets the under-relaxation of U and nuTilda (default 0.9 with SIMPLEC; lower damps the
limit cycle a coarse far field or a steep gradient limiter can leave in the coefficients).

usage: bench/cfd/naca0012_sa.py [--layers] [--far=R] [--iterations=N] [--relax=F] [--nutilda=upwind] [scale [angle ...]]
scale: the example's sizes times this (default 0.5); angles in degrees (default 0 4)"""
import json
import math
import os
import re
import subprocess
import sys
import tarfile
import tempfile

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
CLI = os.path.join(ROOT, "build", "cli", "meshd-cli")
LAYERS = "--layers" in sys.argv
ARGS = [a for a in sys.argv[1:] if not a.startswith("--")]
SCALE = float(ARGS[0]) if ARGS else 0.5
ANGLES = [float(a) for a in ARGS[1:]] or [0.0, 4.0]
NU = 1.0 / 6e6  # Re 6e6 with a chord of 1 and a speed of 1
OPTIONS = dict(a[2:].split("=", 1) for a in sys.argv[1:] if a.startswith("--") and "=" in a)
FAR = float(OPTIONS.get("far", 20))
ITERATIONS = int(OPTIONS.get("iterations", 3000))
RELAX = float(OPTIONS.get("relax", 0.9))
NUTILDA_SCHEME = {"linearUpwind": "linearUpwind grad(nuTilda)", "upwind": "upwind"}[OPTIONS.get("nutilda", "linearUpwind")]


def header(cls, obj):
    return "FoamFile { version 2.0; format ascii; class %s; object %s; }\n" % (cls, obj)


def case_files(u, thickness):
    ux, uy = u
    far_nut = 3 * NU
    field = lambda dims, internal, wall, far: (  # noqa: E731
        f"dimensions {dims}; internalField uniform {internal};\n"
        f"boundaryField {{ wall {{ {wall} }} farfield {{ {far} }} frontAndBack {{ type empty; }} }}\n")
    return {
        "0/U": (header("volVectorField", "U") + field(
            "[0 1 -1 0 0 0 0]", f"({ux} {uy} 0)", "type noSlip;",
            f"type freestreamVelocity; freestreamValue uniform ({ux} {uy} 0);")),
        "0/p": header("volScalarField", "p") + field(
            "[0 2 -2 0 0 0 0]", "0", "type zeroGradient;", "type freestreamPressure; freestreamValue uniform 0;"),
        "0/nuTilda": header("volScalarField", "nuTilda") + field(
            "[0 2 -1 0 0 0 0]", f"{far_nut}", "type fixedValue; value uniform 0;",
            f"type freestream; freestreamValue uniform {far_nut};"),
        "0/nut": header("volScalarField", "nut") + field(
            "[0 2 -1 0 0 0 0]", f"{far_nut}",
            f"type {'nutLowReWallFunction' if LAYERS else 'nutUSpaldingWallFunction'}; value uniform 0;",
            f"type freestream; freestreamValue uniform {far_nut};"),
        "constant/transportProperties": header("dictionary", "transportProperties") +
            f"transportModel Newtonian; nu [0 2 -1 0 0 0 0] {NU};\n",
        "constant/turbulenceProperties": header("dictionary", "turbulenceProperties") +
            "simulationType RAS; RAS { RASModel SpalartAllmaras; turbulence on; printCoeffs off; }\n",
        "system/controlDict": header("dictionary", "controlDict") +
            f"application simpleFoam; startFrom startTime; startTime 0; stopAt endTime; endTime {ITERATIONS};\n"
            f"deltaT 1; writeControl timeStep; writeInterval {ITERATIONS}; writeFormat ascii;\n"
            "functions { coeffs { type forceCoeffs; libs (\"libforces.so\"); writeControl timeStep; writeInterval 1;\n"
            "  patches (wall); rho rhoInf; rhoInf 1; CofR (0.25 0 0);\n"
            f"  liftDir ({-uy} {ux} 0); dragDir ({ux} {uy} 0); pitchAxis (0 0 1);\n"
            f"  magUInf 1; lRef 1; Aref {thickness}; }}\n"
            "  yplus { type yPlus; libs (\"libfieldFunctionObjects.so\"); writeControl writeTime; }\n"
            "  residuals { type solverInfo; libs (\"libutilityFunctionObjects.so\"); fields (p U nuTilda); } }\n",
        "system/fvSchemes": header("dictionary", "fvSchemes") +
            "ddtSchemes { default steadyState; } gradSchemes { default Gauss linear; grad(U) cellLimited Gauss linear 1; }\n"
            "divSchemes { default none; div(phi,U) bounded Gauss linearUpwind grad(U);\n"
            f"  div(phi,nuTilda) bounded Gauss {NUTILDA_SCHEME}; div((nuEff*dev2(T(grad(U))))) Gauss linear; }}\n"
            "laplacianSchemes { default Gauss linear corrected; } interpolationSchemes { default linear; }\n"
            "snGradSchemes { default corrected; } wallDist { method meshWave; }\n",
        "system/fvSolution": header("dictionary", "fvSolution") +
            "solvers { p { solver GAMG; smoother GaussSeidel; tolerance 1e-7; relTol 0.05; }\n"
            "  \"(U|nuTilda)\" { solver smoothSolver; smoother GaussSeidel; nSweeps 2; tolerance 1e-8; relTol 0.1; } }\n"
            "SIMPLE { nNonOrthogonalCorrectors 1; consistent yes;\n"
            "  residualControl { p 1e-6; U 1e-7; nuTilda 1e-7; } }\n"
            f"relaxationFactors {{ equations {{ U {RELAX}; nuTilda {min(RELAX, 0.8)}; }} fields {{ p 1; }} }}\n",
    }


def main():
    with open(os.path.join(ROOT, "examples", "naca0012.json")) as f:
        request = json.load(f)
    request["density"]["size"] = f"{SCALE} * ({request['density']['size']})"
    # The far field is a circle about (0.5, 0) through F: its radius is F's distance from there.
    request["geometry"]["points"]["F"] = [0.5 + FAR, 0.0]
    request.setdefault("options", {})["patch_types"] = {"wall": "wall"}
    if LAYERS:
        request["boundary_layers"] = [{"curves": ["wing"], "first_height": 1e-5, "growth": 1.15, "layers": 40}]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        req = os.path.join(tmp, "naca.json")
        with open(req, "w") as f:
            json.dump(request, f)
        archive = os.path.join(tmp, "naca.tar")
        mesh = subprocess.run([CLI, req, "-o", archive, "--format", "foam"], capture_output=True, text=True, check=True).stderr.strip()
        print("mesh:", mesh)
        for angle in ANGLES:
            case = os.path.join(tmp, f"alpha{angle:g}")
            with tarfile.open(archive) as t:
                t.extractall(case)
            points = open(os.path.join(case, "constant/polyMesh/points")).read()
            thickness = max(float(z) for z in re.findall(r"\(\S+ \S+ (\S+)\)", points))
            a = math.radians(angle)
            for path, body in case_files((math.cos(a), math.sin(a)), thickness).items():
                os.makedirs(os.path.dirname(os.path.join(case, path)), exist_ok=True)
                with open(os.path.join(case, path), "w") as f:
                    f.write(body)
            run = subprocess.run(["bash", "-c", "source /usr/share/openfoam/etc/bashrc >/dev/null 2>&1; simpleFoam -case '" + case + "'"],
                                 capture_output=True, text=True)
            log = run.stdout + run.stderr
            coeffs = os.path.join(case, "postProcessing", "coeffs", "0", "coefficient.dat")
            if run.returncode != 0 or not os.path.exists(coeffs):
                print(log[-3000:])
                sys.exit(f"simpleFoam failed at {angle} degrees")
            # The function object's table: a header "# Time Cd Cs Cl ...", then a row per iteration.
            lines = open(coeffs).read().splitlines()
            names = [h for h in lines[[i for i, l in enumerate(lines) if l.startswith("#")][-1]].lstrip("#").split()]
            last = [float(v) for v in lines[-1].split()]
            value = dict(zip(names, last))
            table = [dict(zip(names, map(float, l.split()))) for l in lines if l and not l.startswith("#")]
            tail = table[-max(1, len(table) // 10):]
            drift = {k: max(r[k] for r in tail) - min(r[k] for r in tail) for k in ("Cl", "Cd")}
            mean = {k: sum(r[k] for r in tail) / len(tail) for k in ("Cl", "Cd")}
            converged = "SIMPLE solution converged" in log
            # yPlus.dat: "# Time patch min max average" rows; the wing's at the last write.
            yplus = (float("nan"),) * 3
            for root, _, files in os.walk(os.path.join(case, "postProcessing", "yplus")):
                for name in files:
                    for line in open(os.path.join(root, name)):
                        cols = line.split()
                        if len(cols) >= 5 and cols[1] == "wall":
                            yplus = tuple(float(c) for c in cols[2:5])
            rows.append((angle, value["Cl"], value["Cd"], int(last[0]), converged, yplus, drift))
            print(f"alpha {angle:g}: Cl {value['Cl']:.4f}, Cd {value['Cd']:.5f} after {int(last[0])} iterations"
                  f"{' (residuals met)' if converged else ''}; over the last {len(tail)}: Cl moved {drift['Cl']:.1e},"
                  f" Cd {drift['Cd']:.1e} (means {mean['Cl']:.4f}, {mean['Cd']:.5f}); y+ {yplus[0]:.3g}..{yplus[1]:.3g} (mean {yplus[2]:.3g})", flush=True)
    print(f"\nfar field {FAR:g} chords, {'layers' if LAYERS else 'isotropic'}")
    print("| alpha (deg) | Cl | Cd | iterations | residuals met | Cl, Cd moved over the last 10% | y+ min..max (mean) |\n"
          "|---:|---:|---:|---:|---|---|---|")
    for angle, cl, cd, it, converged, yp, drift in rows:
        print(f"| {angle:g} | {cl:.4f} | {cd:.5f} | {it} | {'yes' if converged else 'no'} | "
              f"{drift['Cl']:.1e}, {drift['Cd']:.1e} | {yp[0]:.3g}..{yp[1]:.3g} ({yp[2]:.3g}) |")


if __name__ == "__main__":
    main()
