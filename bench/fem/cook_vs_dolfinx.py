#!/usr/bin/python3
"""Nearly incompressible on P1: hydrosoft's nodal-pressure element against dolfinx's
Taylor-Hood P2-P1 mixed form on the identical mesh. Cook's membrane (input/cook_membrane.yaml:
linear elastic, E 250, nu 0.4999, plane strain by u_z held on both faces, a shear traction
6.25 on x = 48), the corner's vertical deflection against the reference 7.771.

    /usr/bin/python3 bench/fem/cook_vs_dolfinx.py [--sizes 2,1] [--repeats 3]

For each size h, gmsh meshes meshes/cook.geo once (P1 tetrahedra, a .msh that both read).
hydrosoft runs `formulation: auto` on it (nodal pressure at this nu: 3 unknowns per node);
dolfinx solves the mixed form
    int 2 mu eps(u) : eps(v) - p div v - q div u - p q / lambda dx = int t . v ds
with P2 displacements and P1 pressures on the same tetrahedra (LinearProblem, MUMPS LU).
Reported per size: unknowns, the corner deflection and its error, the solve time (hydrosoft's
time_s.assembly + time_s.solve; dolfinx's assembly and solve) and the whole run's wall time,
medians over the repeats. OPENBLAS_NUM_THREADS=1, one rank. Needs python3-dolfinx (Debian),
for this benchmark only.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

from same_mesh import REPO, run_deck_on_msh
E, NU, TRACTION, REFERENCE, T = 250.0, 0.4999, 6.25, 7.771, 1.0


def mesh(h, folder):
    path = os.path.join(folder, f"cook_h{h:g}.msh")
    subprocess.run(["gmsh", "-3", "-setnumber", "h", str(h), "-setnumber", "t", str(T),
                    "-format", "msh4", "-o", path, os.path.join(REPO, "meshes", "cook.geo")],
                   check=True, capture_output=True)
    return path


def run_hydrosoft(msh, folder):
    """input/cook_membrane.yaml on the .msh (P1, no parameters)."""
    s, out, wall = run_deck_on_msh("cook_membrane", msh, folder, mesh_keys=", order: 1")
    import h5py
    import numpy as np
    with h5py.File(os.path.join(out, "cook_membrane.h5"), "r") as f:
        u = f["step_0/displacement"][:].reshape(-1, 3)
        corner = f["mesh/group_corner"][:]
    uy = float(u[np.argmax(corner == 1), 1])
    return {"unknowns": s["dofs"], "uy": uy, "solve_s": s["time_s"]["assembly"] + s["time_s"]["solve"],
            "wall_s": wall, "element": s["materials"][0]["formulation"]}


DOLFINX = r'''
import json, sys, time
start = time.perf_counter()
import numpy as np, ufl
from mpi4py import MPI
from petsc4py import PETSc
from dolfinx import fem, mesh
from dolfinx.fem.petsc import LinearProblem
from dolfinx.io import gmshio
E, NU, TRACTION, T = %(E)r, %(NU)r, %(TRACTION)r, %(T)r
sys.path.insert(0, %(bench)r)
from same_mesh import read_msh
cells, points = read_msh(sys.argv[1])
domain = mesh.create_mesh(MPI.COMM_WORLD, cells, points,
                          ufl.Mesh(ufl.VectorElement("Lagrange", ufl.tetrahedron, 1)))
mu, lam = E / (2 * (1 + NU)), E * NU / ((1 + NU) * (1 - 2 * NU))
cell = domain.ufl_cell()
W = fem.FunctionSpace(domain, ufl.MixedElement([ufl.VectorElement("Lagrange", cell, 2),
                                                ufl.FiniteElement("Lagrange", cell, 1)]))
(u, p), (v, q) = ufl.TrialFunctions(W), ufl.TestFunctions(W)
eps = lambda w: ufl.sym(ufl.grad(w))
fdim = domain.topology.dim - 1
loaded = mesh.locate_entities_boundary(domain, fdim, lambda x: np.isclose(x[0], 48.0))
tags = mesh.meshtags(domain, fdim, loaded, np.full(len(loaded), 1, dtype=np.int32))
ds = ufl.Measure("ds", domain=domain, subdomain_data=tags)
a = (2 * mu * ufl.inner(eps(u), eps(v)) - p * ufl.div(v) - q * ufl.div(u) - p * q / lam) * ufl.dx
L = ufl.inner(fem.Constant(domain, PETSc.ScalarType((0, TRACTION, 0))), v) * ds(1)
V, _ = W.sub(0).collapse()
zero = fem.Function(V)
clamped = mesh.locate_entities_boundary(domain, fdim, lambda x: np.isclose(x[0], 0.0))
bcs = [fem.dirichletbc(zero, fem.locate_dofs_topological((W.sub(0), V), fdim, clamped), W.sub(0))]
faces = mesh.locate_entities_boundary(domain, fdim, lambda x: np.isclose(x[2], 0.0) | np.isclose(x[2], T))
Vz, _ = W.sub(0).sub(2).collapse()
zero_z = fem.Function(Vz)
bcs.append(fem.dirichletbc(zero_z, fem.locate_dofs_topological((W.sub(0).sub(2), Vz), fdim, faces), W.sub(0).sub(2)))
problem = LinearProblem(a, L, bcs=bcs, petsc_options={"ksp_type": "preonly", "pc_type": "lu",
                                                      "pc_factor_mat_solver_type": "mumps"})
solve_start = time.perf_counter()
wh = problem.solve()
solve_s = time.perf_counter() - solve_start
uh = wh.sub(0).collapse()
x = V.tabulate_dof_coordinates()
at = np.where(np.isclose(x[:, 0], 48.0) & np.isclose(x[:, 1], 60.0))[0]
uy = float(np.mean(uh.x.array.reshape(-1, 3)[at, 1]))
print(json.dumps({"unknowns": W.dofmap.index_map.size_global * W.dofmap.index_map_bs, "uy": uy,
                  "solve_s": solve_s, "wall_s": time.perf_counter() - start}))
''' % {"E": E, "NU": NU, "TRACTION": TRACTION, "T": T,
     "bench": os.path.dirname(os.path.abspath(__file__))}


def run_dolfinx(msh, folder):
    script = os.path.join(folder, "cook_dolfinx.py")
    with open(script, "w") as f:
        f.write(DOLFINX)
    start = time.perf_counter()
    r = subprocess.run(["/usr/bin/python3", script, msh], check=True, capture_output=True, text=True,
                       env=dict(os.environ, OPENBLAS_NUM_THREADS="1"))
    result = json.loads(r.stdout.strip().splitlines()[-1])
    result["wall_s"] = time.perf_counter() - start  # the interpreter's start and imports included
    return result


def median(rows, key):
    return statistics.median(r[key] for r in rows)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--sizes", default="2,1")
    p.add_argument("--repeats", type=int, default=3)
    args = p.parse_args()
    print("| h | code, element | unknowns | u_y corner | error | solve (s) | wall (s) |")
    print("|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as folder:
        for h in [float(x) for x in args.sizes.split(",")]:
            msh = mesh(h, folder)
            for name, run in (("hydrosoft, P1 nodal pressure", run_hydrosoft),
                              ("dolfinx, Taylor-Hood P2-P1", run_dolfinx)):
                rows = [run(msh, folder) for _ in range(args.repeats)]
                uy = rows[0]["uy"]
                print(f"| {h:g} | {name} | {rows[0]['unknowns']:,} | {uy:.4f} | "
                      f"{100 * (uy / REFERENCE - 1):+.2f} % | {median(rows, 'solve_s'):.2f} | "
                      f"{median(rows, 'wall_s'):.2f} |", flush=True)


if __name__ == "__main__":
    sys.exit(main())
