"""What the benchmarks that run hydrosoft and dolfinx on the same gmsh .msh share: a shipped
deck run on the .msh (hydrosoft's side), and the .msh's nodes and tetrahedra (dolfinx's side:
dolfinx 0.5's own reader needs the gmsh Python module)."""
import json
import os
import subprocess
import sys
import time

import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def mpirun(ranks):
    """The launcher for `ranks` MPI ranks (as root, with --allow-run-as-root)."""
    flags = ["mpirun", "--oversubscribe", "-np", str(ranks)]
    return flags + (["--allow-run-as-root"] if os.geteuid() == 0 else [])


def run_dolfinx_script(source, name, msh, folder, ranks):
    """The dolfinx program `source` written to FOLDER/NAME.py (its BENCH replaced by this
    folder, for same_mesh's read_msh) and run on MSH under mpirun; its one JSON line, with
    `wall_s` the whole process (the interpreter's start and imports included)."""
    script = os.path.join(folder, name + ".py")
    with open(script, "w") as f:
        f.write(source.replace("BENCH", repr(os.path.dirname(os.path.abspath(__file__)))))
    start = time.perf_counter()
    r = subprocess.run(mpirun(ranks) + ["/usr/bin/python3", script, msh], capture_output=True,
                       text=True, env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
    if r.returncode != 0:
        sys.exit(f"dolfinx failed on {msh}:\n{r.stderr[-3000:]}")
    result = [json.loads(line) for line in r.stdout.splitlines() if line.startswith("{")][0]
    result["wall_s"] = time.perf_counter() - start
    return result


def run_deck_on_msh(deck, msh, folder, mesh_keys="", launcher=(), overrides=()):
    """input/DECK.yaml with its mesh block replaced by `mesh: {file: MSH<mesh_keys>}`, run
    quietly into FOLDER/hs (OPENBLAS_NUM_THREADS=1, under `launcher`, e.g. mpirun, with
    `--set` overrides). Returns the summary, the output folder and the wall time."""
    out = os.path.join(folder, "hs")
    with open(os.path.join(REPO, "input", deck + ".yaml")) as f:
        lines = f.read().splitlines()
    start, end = lines.index("mesh:"), lines.index("materials:")
    path = os.path.join(folder, deck + ".yaml")
    with open(path, "w") as f:
        f.write("\n".join(lines[:start] + [f"mesh: {{file: {msh}{mesh_keys}}}"] + lines[end:]) + "\n")
    cmd = list(launcher) + [os.path.join(REPO, "build", "bin", "hydrosoft"), path, "-q",
                            "--set", f"output.folder={out}"]
    for o in overrides:
        cmd += ["--set", o]
    start = time.perf_counter()
    subprocess.run(cmd, check=True, capture_output=True, env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
    wall = time.perf_counter() - start
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f), out, wall


def read_msh(path):
    """The nodes and 4-node tetrahedra of a gmsh 4.1 ASCII .msh (what hydrosoft reads)."""
    lines = iter(open(path).read().split("\n"))
    tags, x, tets = [], [], []
    for line in lines:
        if line == "$Nodes":
            blocks = int(next(lines).split()[0])
            for _ in range(blocks):
                n = int(next(lines).split()[3])
                tags += [int(next(lines)) for _ in range(n)]
                x += [[float(c) for c in next(lines).split()] for _ in range(n)]
        elif line == "$Elements":
            blocks = int(next(lines).split()[0])
            for _ in range(blocks):
                _, _, kind, n = (int(c) for c in next(lines).split())
                rows = [[int(c) for c in next(lines).split()[1:]] for _ in range(n)]
                if kind == 4:
                    tets += rows
    index = {t: i for i, t in enumerate(tags)}
    return np.array([[index[t] for t in tet] for tet in tets], dtype=np.int64), np.array(x)
