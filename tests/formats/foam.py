"""What the OpenFOAM scripts of tests/formats share: a foam archive of meshd-cli unpacked into a
case directory with the few system files the tools read, and an OpenFOAM tool run on it."""
import os
import subprocess
import tarfile

POLYMESH = ["constant/polyMesh/" + n for n in ("boundary", "faces", "neighbour", "owner", "points")]

SYSTEM = {
    "controlDict": "application simpleFoam; startFrom startTime; startTime 0; stopAt endTime; endTime 1;\n"
                   "deltaT 1; writeControl timeStep; writeInterval 1;\n",
    "fvSchemes": "ddtSchemes { default steadyState; } gradSchemes { default Gauss linear; }\n"
                 "divSchemes { default none; } laplacianSchemes { default Gauss linear corrected; }\n"
                 "interpolationSchemes { default linear; } snGradSchemes { default corrected; }\n",
    "fvSolution": "",
}


def case_of(archive, where):
    """Unpacks the archive into the case `where` and writes its system files; returns the
    archive's file names, sorted."""
    with tarfile.open(archive) as t:
        names = sorted(m.name for m in t.getmembers() if m.isfile())
        t.extractall(where)
    os.makedirs(os.path.join(where, "system"), exist_ok=True)
    for name, body in SYSTEM.items():
        with open(os.path.join(where, "system", name), "w") as f:
            f.write("FoamFile { version 2.0; format ascii; class dictionary; object %s; }\n%s" % (name, body))
    return names


def run_tool(command, case):
    """`command -case case` in Debian's OpenFOAM environment (e.g. "checkMesh")."""
    return subprocess.run(["bash", "-c", "source /usr/share/openfoam/etc/bashrc >/dev/null 2>&1; "
                           + command + " -case '" + case + "'"], capture_output=True, text=True)
