#!/usr/bin/python3
"""The manufactured incompressible twist (input/twisted_block.yaml, nu = 0.5;
docs/verification.md): hydrosoft's locking-free elements against dolfinx's Taylor-Hood P2-P1
mixed form of the same law on the identical mesh, their errors in the displacement and the
pressure against the exact solution, and their times.

    /usr/bin/python3 bench/fem/twist_vs_dolfinx.py [--sizes 0.125,0.0833] [--ranks 1]
        [--only hydrosoft|dolfinx]

For each size h gmsh meshes meshes/block.geo once (P1 tetrahedra, a .msh that both read).
hydrosoft runs the deck on it as P1 (the nodal-pressure element) and P2 (F-bar, the .msh's
straight tetrahedra given their mid-edge nodes) and reports summary.json's errors. dolfinx
solves the stationary point of
    Pi(u, q) = int mu/2 (I1 - 3) - mu ln J + q ln J - B . u dx,
the incompressible neo-Hookean law of hydrosoft with q the volume's multiplier, P2
displacements and P1 multipliers, under the body force B = -Div P of the exact solution
(UFL differentiates the same closed form), held at the bottom, in the deck's 2 load steps
(Newton, MUMPS LU). Its errors are those of hydrosoft's summary: the L2 norms of u - u_exact
and of the mean stress -mu (tr b - 3)/3 - q against the exact one, each over the exact's norm.
OPENBLAS_NUM_THREADS=1. Needs python3-dolfinx (Debian), for this benchmark only.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

from same_mesh import REPO, mpirun, run_deck_on_msh, run_dolfinx_script

MU, TWIST, Q0 = 1e5, 0.5, 1.0  # input/twisted_block.yaml: E = 3e5 at nu = 0.5, twist, q


def mesh(h, folder):
    path = os.path.join(folder, f"block_h{h:g}.msh")
    subprocess.run(["gmsh", "-3", "-setnumber", "h", str(h), "-format", "msh4", "-o", path,
                    os.path.join(REPO, "meshes", "block.geo")], check=True, capture_output=True)
    return path


def run_hydrosoft(msh, folder, ranks, overrides):
    s, _, wall = run_deck_on_msh("twisted_block", msh, folder, launcher=mpirun(ranks),
                                 overrides=overrides)
    return {"unknowns": s["dofs"], "u_error": s["error"]["l2_relative"],
            "p_error": s["error"]["pressure_l2_relative"],
            "newton_iterations": s["newton_iterations"], "wall_s": wall}


DOLFINX = r'''
import json, sys, time
start = time.perf_counter()
import numpy as np, ufl
from mpi4py import MPI
from petsc4py import PETSc
from dolfinx import fem, mesh, nls
import dolfinx.fem.petsc
MU, TWIST, Q0 = PARAMETERS
sys.path.insert(0, BENCH)
from same_mesh import read_msh
cells, points = read_msh(sys.argv[1])
domain = mesh.create_mesh(MPI.COMM_WORLD, cells, points, ufl.Mesh(ufl.VectorElement("Lagrange", ufl.tetrahedron, 1)))
cell = domain.ufl_cell()
W = fem.FunctionSpace(domain, ufl.MixedElement([ufl.VectorElement("Lagrange", cell, 2), ufl.FiniteElement("Lagrange", cell, 1)]))
w, dw = fem.Function(W), ufl.TestFunction(W)
u, q = ufl.split(w)
I = ufl.Identity(3)

# The exact solution (src/verification/twisted_block.cpp) in UFL.
X = ufl.SpatialCoordinate(domain)
x, y = X[0] - 0.5, X[1] - 0.5
rho2 = (x * x + y * y) / 0.25
g = ufl.conditional(ufl.lt(rho2, 1), (1 - rho2) ** 4, 0)
theta = TWIST * g * ufl.sin(ufl.pi * X[2]) ** 2
u_exact = ufl.as_vector([ufl.cos(theta) * x - ufl.sin(theta) * y - x,
                         ufl.sin(theta) * x + ufl.cos(theta) * y - y, 0])
q_exact = Q0 * MU * ufl.sin(ufl.pi * X[0]) * ufl.sin(ufl.pi * X[1]) * ufl.sin(ufl.pi * X[2])
F_exact = I + ufl.grad(u_exact)
P_exact = MU * (F_exact - ufl.inv(F_exact).T) + q_exact * ufl.inv(F_exact).T
B = -ufl.div(P_exact)
load = fem.Constant(domain, PETSc.ScalarType(0.0))

F = I + ufl.grad(u)
J = ufl.det(F)
Pi = (MU / 2 * (ufl.tr(F.T * F) - 3) - MU * ufl.ln(J) + q * ufl.ln(J) - load * ufl.dot(B, u)) * ufl.dx(metadata={"quadrature_degree": 6})
R = ufl.derivative(Pi, w, dw)
facets = mesh.locate_entities_boundary(domain, 2, lambda x: np.abs(x[2]) < 1e-9)
V0, _ = W.sub(0).collapse()
zero = fem.Function(V0)
bcs = [fem.dirichletbc(zero, fem.locate_dofs_topological((W.sub(0), V0), 2, facets), W.sub(0))]
problem = dolfinx.fem.petsc.NonlinearProblem(R, w, bcs)
newton = nls.petsc.NewtonSolver(MPI.COMM_WORLD, problem)
newton.rtol, newton.atol, newton.max_it = 1e-10, 1e-10, 50
newton.convergence_criterion = "residual"
ksp = newton.krylov_solver
ksp.setType("preonly"); ksp.getPC().setType("lu"); ksp.getPC().setFactorSolverType("mumps")
its = 0
solve_start = time.perf_counter()
for s in (0.5, 1.0):
    load.value = s
    n, ok = newton.solve(w)
    its += n
solve_s = time.perf_counter() - solve_start

def norm(e):
    return np.sqrt(MPI.COMM_WORLD.allreduce(fem.assemble_scalar(fem.form(e * ufl.dx(metadata={"quadrature_degree": 8}))), op=MPI.SUM))
b = F * F.T
b_exact = F_exact * F_exact.T
p_h = -MU * (ufl.tr(b) - 3) / 3 - q
p_exact = -MU * (ufl.tr(b_exact) - 3) / 3 - q_exact
du = u - u_exact
result = {"unknowns": W.dofmap.index_map.size_global * W.dofmap.index_map_bs,
          "u_error": norm(ufl.dot(du, du)) / norm(ufl.dot(u_exact, u_exact)),
          "p_error": norm((p_h - p_exact) ** 2) / norm(p_exact ** 2),
          "newton_iterations": its, "solve_s": solve_s, "wall_s": time.perf_counter() - start}
if MPI.COMM_WORLD.rank == 0:
    print(json.dumps(result))
'''


def run_dolfinx(msh, folder, ranks):
    result = run_dolfinx_script(DOLFINX.replace("PARAMETERS", repr((MU, TWIST, Q0))), "twist_dolfinx", msh, folder, ranks)
    return result


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--sizes", default="0.125,0.0833")
    p.add_argument("--ranks", type=int, default=1)
    p.add_argument("--only", choices=["hydrosoft", "dolfinx"])
    args = p.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for h in [float(x) for x in args.sizes.split(",")]:
            msh = mesh(h, folder)
            runs = []
            if args.only != "dolfinx":
                runs += [("hydrosoft, P1 nodal pressure", lambda: run_hydrosoft(msh, folder, args.ranks, [])),
                         ("hydrosoft, P2 F-bar", lambda: run_hydrosoft(msh, folder, args.ranks, ["mesh.order=2"]))]
            if args.only != "hydrosoft":
                runs += [("dolfinx, Taylor-Hood P2-P1", lambda: run_dolfinx(msh, folder, args.ranks))]
            for name, run in runs:
                r = run()
                rows.append((h, name, r))
                print(json.dumps({"h": h, "run": name, **r}), file=sys.stderr, flush=True)
    print("| h | code, element | unknowns | displacement L2 | pressure L2 | Newton its | wall (s) |")
    print("|---|---|---|---|---|---|---|")
    for h, name, r in rows:
        print(f"| {h:g} | {name} | {r['unknowns']:,} | {r['u_error']:.4f} | {r['p_error']:.4f} | "
              f"{r['newton_iterations']} | {r['wall_s']:.1f} |")


if __name__ == "__main__":
    sys.exit(main())
