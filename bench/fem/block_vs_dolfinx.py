#!/usr/bin/python3
"""The nearly incompressible block under partial compression (input/compressed_block.yaml;
Reese, Wriggers and Reddy 2000, deal.II's step-44): hydrosoft's locking-free elements against
dolfinx's Taylor-Hood P2-P1 mixed form of the same law on the identical mesh.

    /usr/bin/python3 bench/fem/block_vs_dolfinx.py [--sizes 0.25,0.125,0.0625] [--ranks 2]
        [--p2-sizes 0.25,0.125] [--only hydrosoft|dolfinx]

For each size h (in units of the block's edge) gmsh meshes meshes/compressed_block.geo once (P1 tetrahedra, a .msh that both
read). hydrosoft runs the deck on it as P1 (`formulation: auto`, the nodal-pressure element),
P1 with the displacement element, and at the --p2-sizes P2 (`auto`, the F-bar element; the
.msh's straight tetrahedra given their mid-edge nodes); dolfinx solves the stationary point of
    Pi(u, p) = int mu/2 (I1 - 3) - mu ln J + p ln J - p^2 / (2 lambda) dx - int t . u ds,
the compressible neo-Hookean law of hydrosoft with its volumetric term through p (at the
stationary point p = lambda ln J), P2 displacements and P1 pressures, in 4 load steps per
level (Newton, MUMPS LU). Reported: unknowns, the top centre's u_z at p/p0 = 20, 40, 60, 80,
its error at p/p0 = 80 against --reference, Newton iterations and the wall time.
OPENBLAS_NUM_THREADS=1. Needs python3-dolfinx (Debian), for this benchmark only.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

from same_mesh import REPO, mpirun, run_deck_on_msh, run_dolfinx_script


def mesh(h, folder):
    """h in units of the block's edge (1 mm)."""
    path = os.path.join(folder, f"block_h{h:g}.msh")
    subprocess.run(["gmsh", "-3", "-setnumber", "h", str(1e-3 * h), "-format", "msh4", "-o", path,
                    os.path.join(REPO, "meshes", "compressed_block.geo")], check=True, capture_output=True)
    return path


def run_hydrosoft(msh, folder, ranks, overrides):
    s, out, wall = run_deck_on_msh("compressed_block", msh, folder, launcher=mpirun(ranks),
                                   overrides=overrides)
    import h5py
    import numpy as np
    with h5py.File(os.path.join(out, "compressed_block.h5"), "r") as f:
        at = int(np.argmax(f["mesh/group_centre"][:] == 1))
        uz = [float(f[f"step_{k}/displacement"][:].reshape(-1, 3)[at, 2]) for k in range(4)]
    return {"unknowns": s["dofs"], "uz": uz, "newton_iterations": s["newton_iterations"],
            "cutbacks": s["cutbacks"], "wall_s": wall, "element": s["materials"][0]["formulation"]}


DOLFINX = r'''
import json, sys, time
start = time.perf_counter()
import numpy as np, ufl
from mpi4py import MPI
from petsc4py import PETSc
from dolfinx import fem, mesh, nls
import dolfinx.fem.petsc
MU, LAM, TRACTION = 80.194e6, 4.00889806e11, 320e6  # Pa: input/compressed_block.yaml
LEVELS = [0.25, 0.5, 0.75, 1.0]
sys.path.insert(0, BENCH)
from same_mesh import read_msh
cells, points = read_msh(sys.argv[1])
substeps = 4  # load steps per level: Newton from the last level's solution
domain = mesh.create_mesh(MPI.COMM_WORLD, cells, points, ufl.Mesh(ufl.VectorElement("Lagrange", ufl.tetrahedron, 1)))
cell = domain.ufl_cell()
W = fem.FunctionSpace(domain, ufl.MixedElement([ufl.VectorElement("Lagrange", cell, 2), ufl.FiniteElement("Lagrange", cell, 1)]))
w, dw = fem.Function(W), ufl.TestFunction(W)
u, p = ufl.split(w)
F = ufl.Identity(3) + ufl.grad(u)
J = ufl.det(F)
fdim = 2
eps = 1e-9  # m
on = lambda x, i, v: np.abs(x[i] - v) < eps
patch = mesh.locate_entities_boundary(domain, fdim, lambda x: on(x, 2, 1e-3) & (x[0] <= 5e-4 + eps) & (x[1] <= 5e-4 + eps))
tags = mesh.meshtags(domain, fdim, patch, np.full(len(patch), 1, dtype=np.int32))
ds = ufl.Measure("ds", domain=domain, subdomain_data=tags)
load = fem.Constant(domain, PETSc.ScalarType(0.0))
Pi = (MU / 2 * (ufl.tr(F.T * F) - 3) - MU * ufl.ln(J) + p * ufl.ln(J) - p * p / (2 * LAM)) * ufl.dx \
    + load * u[2] * ds(1)
R = ufl.derivative(Pi, w, dw)
bcs = []
for comps, where in (((0,), lambda x: on(x, 0, 0)), ((1,), lambda x: on(x, 1, 0)),
                     ((2,), lambda x: on(x, 2, 0)), ((0, 1), lambda x: on(x, 2, 1e-3))):
    facets = mesh.locate_entities_boundary(domain, fdim, where)
    for c in comps:
        Vc, _ = W.sub(0).sub(c).collapse()
        zero = fem.Function(Vc)
        bcs.append(fem.dirichletbc(zero, fem.locate_dofs_topological((W.sub(0).sub(c), Vc), fdim, facets), W.sub(0).sub(c)))
problem = dolfinx.fem.petsc.NonlinearProblem(R, w, bcs)
newton = nls.petsc.NewtonSolver(MPI.COMM_WORLD, problem)
newton.rtol, newton.atol, newton.max_it = 1e-10, 1e-8, 50  # atol in N (the load: 80 N)
newton.convergence_criterion = "residual"
ksp = newton.krylov_solver
ksp.setType("preonly"); ksp.getPC().setType("lu"); ksp.getPC().setFactorSolverType("mumps")
V, vmap = W.sub(0).collapse()
x = V.tabulate_dof_coordinates()
at = np.where((np.abs(x[:, 0]) < 1e-9) & (np.abs(x[:, 1]) < 1e-9) & (np.abs(x[:, 2] - 1e-3) < 1e-9))[0]
out, its, prev = [], 0, 0.0
solve_start = time.perf_counter()
for level in LEVELS:
    for k in range(1, substeps + 1):
        load.value = TRACTION * (prev + (level - prev) * k / substeps)
        n, ok = newton.solve(w)
        its += n
    prev = level
    uz = w.x.array[np.array(vmap)].reshape(-1, 3)[at, 2]
    out.append(MPI.COMM_WORLD.allreduce(float(uz[0]) if len(uz) else np.inf, op=MPI.MIN))
if MPI.COMM_WORLD.rank == 0:
    print(json.dumps({"unknowns": W.dofmap.index_map.size_global * W.dofmap.index_map_bs, "uz": out,
                      "newton_iterations": its, "solve_s": time.perf_counter() - solve_start,
                      "wall_s": time.perf_counter() - start}))
'''


def run_dolfinx(msh, folder, ranks):
    result = run_dolfinx_script(DOLFINX, "block_dolfinx", msh, folder, ranks)
    result["cutbacks"] = 0
    return result


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--sizes", default="0.25,0.125,0.0625")
    p.add_argument("--ranks", type=int, default=2)
    p.add_argument("--p2-sizes", default="0.25,0.125", help="the sizes hydrosoft also runs on P2")
    p.add_argument("--only", choices=["hydrosoft", "dolfinx"])
    p.add_argument("--reference", type=float, default=0.695662,
                   help="the descent at p/p0 = 80 (mm) the errors are against; the default is "
                        "dolfinx's at h/a = 0.0625 (92,864 unknowns)")
    args = p.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for h in [float(x) for x in args.sizes.split(",")]:
            msh = mesh(h, folder)
            runs = []
            if args.only != "dolfinx":
                runs += [("hydrosoft P1, nodal pressure (auto)", lambda: run_hydrosoft(msh, folder, args.ranks, [])),
                         ("hydrosoft P1, displacement", lambda: run_hydrosoft(
                             msh, folder, args.ranks, ["materials[0].formulation=displacement"]))]
                if h in [float(x) for x in args.p2_sizes.split(",")]:
                    runs += [("hydrosoft P2, F-bar (auto)", lambda: run_hydrosoft(
                        msh, folder, args.ranks, ["mesh.order=2"]))]
            if args.only != "hydrosoft":
                runs += [("dolfinx Taylor-Hood P2-P1", lambda: run_dolfinx(msh, folder, args.ranks))]
            for name, run in runs:
                r = run()
                rows.append((h, name, r))
                print(json.dumps({"h": h, "run": name, **r}), file=sys.stderr, flush=True)
    reference = -1e-3 * args.reference
    print("| h/a | code, element | unknowns | descent (mm) at p/p0 = 20, 40, 60, 80 | error at 80 | Newton its / cutbacks | wall (s) |")
    print("|---|---|---|---|---|---|---|")
    for h, name, r in rows:
        error = f"{100 * (r['uz'][3] / reference - 1):+.2f} %"
        print(f"| {h:g} | {name} | {r['unknowns']:,} | {', '.join(f'{-1e3 * v:.4f}' for v in r['uz'])} | {error} | "
              f"{r['newton_iterations']} / {r['cutbacks']} | {r['wall_s']:.1f} |")


if __name__ == "__main__":
    sys.exit(main())
