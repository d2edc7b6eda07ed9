"""What the read-back scripts of tests/formats share: the checks they count, and a domain
with an embedded cut that ends on a hole's circle (the circle split there)."""
import json
import os
import sys

failures = []


def check(cond, what):
    """Records a failed check (the script goes on, to report every failure)."""
    if not cond:
        failures.append(what)
        print("FAIL:", what)


def finish(passed):
    """Exits 1 after any failed check, else prints `passed`."""
    if failures:
        print(f"{len(failures)} checks failed")
        sys.exit(1)
    print(passed)


CUT_TO_HOLE = {
    "geometry": {
        "points": {"A": [0, 0], "B": [4, 0], "C": [4, 2], "D": [0, 2], "H": [2.5, 1],
                   "T": [2.0, 1.5], "Q": [2.0, 1.9]},
        "curves": {
            "bottom": {"type": "line", "from": "A", "to": "B", "tag": "wall"},
            "right": {"type": "line", "from": "B", "to": "C", "tag": "outlet"},
            "top": {"type": "line", "from": "C", "to": "D", "tag": "wall"},
            "left": {"type": "line", "from": "D", "to": "A", "tag": "inlet"},
            "hole": {"type": "arc", "from": "H", "to": "H", "center": [2, 1], "tag": "cylinder"},
            "cut": {"type": "line", "from": "T", "to": "Q", "tag": "cut"}},
        "loops": [["bottom", "right", "top", "left"], ["hole"]],
        "embedded": ["cut"]},
    "density": {"size": 0.08}}


def dolfinx_mesh(msh):
    """An MSH file loaded into dolfinx as a FEniCS user loads a gmsh model (through gmsh and
    gmshio.model_to_mesh): (mesh, facet tags, physical names of the curves by tag)."""
    import gmsh
    from dolfinx.io import gmshio
    from mpi4py import MPI

    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.open(msh)
    names = {t: gmsh.model.getPhysicalName(1, t) for _, t in gmsh.model.getPhysicalGroups(1)}
    mesh, _, facets = gmshio.model_to_mesh(gmsh.model, MPI.COMM_WORLD, 0, gdim=2)
    gmsh.finalize()
    return mesh, facets, names


def write_cut_to_hole(directory):
    """CUT_TO_HOLE as a request file in `directory`; its path."""
    path = os.path.join(directory, "cut.json")
    with open(path, "w") as f:
        json.dump(CUT_TO_HOLE, f)
    return path


def generated_arguments(examples, default_count=40):
    """The request generators' directory and how many seeds of each, from the optional third
    and fourth command-line arguments (fuzz/ beside `examples` and `default_count` without)."""
    fuzz_dir = sys.argv[3] if len(sys.argv) > 3 else os.path.join(examples, "..", "fuzz")
    count = int(sys.argv[4]) if len(sys.argv) > 4 else default_count
    return fuzz_dir, count


def generated(fuzz_dir, count, kinds=("general", "layered")):
    """(name, request) for seeds 1 to `count` of each request generator of fuzz/ named in
    `kinds` (fuzz/general_requests.py, fuzz/layered_requests.py), named like "general-7"."""
    sys.path.insert(0, fuzz_dir)
    import general_requests
    import layered_requests
    makers = {"general": general_requests.request, "layered": layered_requests.request}
    for kind in kinds:
        for seed in range(1, count + 1):
            yield f"{kind}-{seed}", makers[kind](seed)
