#!/usr/bin/python3
"""Writes the triangles of one physical surface group of a gmsh ASCII 4.1 .msh as a .obj.

    /usr/bin/python3 bench/cavity/msh_to_obj.py MESH.msh OUT.obj [--group cavity]

Only the group's nodes are written (renumbered in file order), faces with their orientation
as in the .msh (a cavity's faces point out of the body, into the cavity). Quadratic triangles
(Tri6) are split into four as the solver does (solvers/cavity_weight.cpp). Standard library
only, so the GPU machine can run it too.
"""
import argparse
import sys

# Tri6 corners 0-2, edge nodes 3:(0,1) 4:(1,2) 5:(2,0): four triangles of the same orientation.
TRI6_SPLIT = ((0, 3, 5), (3, 1, 4), (5, 4, 2), (3, 4, 5))


def read_group(path, group):
    """Returns (vertices [(x, y, z)], triangles [(a, b, c)] 0-based) of the group."""
    with open(path) as f:
        lines = iter(f.read().split("\n"))
    names, surface_tags, coords, tris = {}, set(), {}, []
    for line in lines:
        line = line.strip()
        if line == "$MeshFormat":
            version = next(lines).split()[0]
            if not version.startswith("4"):
                sys.exit(f"{path}: .msh version {version}, need ASCII 4.x")
        elif line == "$PhysicalNames":
            for _ in range(int(next(lines))):
                dim, tag, name = next(lines).split(maxsplit=2)
                names[(int(dim), name.strip('"'))] = int(tag)
            if (2, group) not in names:
                sys.exit(f"{path}: no physical surface '{group}'")
        elif line == "$Entities":
            counts = [int(x) for x in next(lines).split()]
            for _ in range(counts[0]):
                next(lines)
            for _ in range(counts[1]):
                next(lines)
            for _ in range(counts[2]):  # tag, box (6), nphys, phys..., nbound, bound...
                w = next(lines).split()
                nphys = int(w[7])
                if names[(2, group)] in (int(x) for x in w[8:8 + nphys]):
                    surface_tags.add(int(w[0]))
        elif line == "$Nodes":
            blocks = int(next(lines).split()[0])
            for _ in range(blocks):
                _, _, _, n = (int(x) for x in next(lines).split())
                tags = [int(next(lines)) for _ in range(n)]
                for t in tags:
                    coords[t] = next(lines)
        elif line == "$Elements":
            blocks = int(next(lines).split()[0])
            for _ in range(blocks):
                dim, tag, etype, n = (int(x) for x in next(lines).split())
                rows = [next(lines) for _ in range(n)]
                if dim != 2 or tag not in surface_tags:
                    continue
                if etype not in (2, 9):
                    sys.exit(f"{path}: group '{group}' has element type {etype}, need 2 or 9")
                for r in rows:
                    nodes = [int(x) for x in r.split()[1:]]
                    if etype == 2:
                        tris.append(tuple(nodes))
                    else:
                        tris += [tuple(nodes[a] for a in t) for t in TRI6_SPLIT]
    used = sorted({v for t in tris for v in t})
    index = {v: i for i, v in enumerate(used)}
    vertices = [tuple(float(x) for x in coords[v].split()[:3]) for v in used]
    return vertices, [tuple(index[v] for v in t) for t in tris]


def write_obj(path, vertices, triangles, comment=""):
    with open(path, "w") as f:
        if comment:
            f.write(f"# {comment}\n")
        f.writelines(f"v {x:.17g} {y:.17g} {z:.17g}\n" for x, y, z in vertices)
        f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in triangles)


def convert(msh, obj, group="cavity"):
    vertices, triangles = read_group(msh, group)
    write_obj(obj, vertices, triangles, f"group '{group}' of {msh}")
    return len(vertices), len(triangles)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("msh")
    p.add_argument("obj")
    p.add_argument("--group", default="cavity")
    a = p.parse_args()
    nv, nt = convert(a.msh, a.obj, a.group)
    print(f"{a.obj}: {nv} vertices, {nt} triangles")


if __name__ == "__main__":
    main()
