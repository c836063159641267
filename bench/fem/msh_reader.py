"""The nodes and 4-node tetrahedra of a gmsh 4.1 ASCII .msh (what hydrosoft reads), for the
dolfinx side of the benchmarks that solve on hydrosoft's meshes (dolfinx 0.5's own reader
needs the gmsh Python module)."""
import numpy as np


def read_msh(path):
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
