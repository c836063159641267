#!/usr/bin/python3
"""hydrosoft against dolfinx on the identical mesh: the neo-Hookean cantilever of
docs/benchmarks.md (0.1 x 0.01 x 0.01 m, E 1 MPa, nu 0.45, rho 1070, clamped at x = 0,
gravity -z, one load step, P1).

    /usr/bin/python3 bench/fem/cantilever_vs_dolfinx.py [--sizes 50,100] [--ranks 1,2]
        [--solvers mumps,gamg] [--repeats 3] [--csv bench/fem/cantilever_vs_dolfinx.csv]

For each size N the mesh is dolfinx's create_box with N x N/5 x N/5 boxes of 6 tetrahedra,
written to a gmsh .msh (format 4.1) that hydrosoft reads: the same nodes and tetrahedra for
both. Both solve with the same linear solver options (the hydrosoft preset's, passed to
dolfinx's Newton KSP), the same compressible neo-Hookean energy
psi = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2 and the same stopping test (the residual
below 1e-8 of the first one). Reported: Newton iterations, the Newton solve time (assembly + linear
solves; hydrosoft's time_s.assembly + time_s.solve, dolfinx's NewtonSolver.solve), the
whole run's wall time and the tip deflection u_z at (L, 0, 0). OPENBLAS_NUM_THREADS=1.
Needs python3-dolfinx (Debian), for this benchmark only.
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

L, H = 0.1, 0.01
E, NU, RHO, G = 1.0e6, 0.45, 1070.0, 9.81
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# The hydrosoft presets' options (solvers/newton_solver.cpp), for a symmetric tangent that may
# be indefinite; dolfinx's Newton KSP gets the same.
KSP_OPTIONS = {
    "mumps": {"ksp_type": "preonly", "pc_type": "cholesky",
              "pc_factor_mat_solver_type": "mumps"},
    "gamg": {"ksp_type": "minres", "pc_type": "gamg", "ksp_rtol": "1e-10",
             "ksp_max_it": "2000", "pc_gamg_threshold": "0.01",
             "mg_levels_ksp_type": "chebyshev", "mg_levels_pc_type": "jacobi"},
}


def box(comm, n):
    import numpy as np
    from dolfinx import mesh
    return mesh.create_box(comm, [np.array([0.0, -H / 2, -H / 2]), np.array([L, H / 2, H / 2])],
                           [n, n // 5, n // 5], mesh.CellType.tetrahedron)


def write_msh(n, path):
    """The box as gmsh 4.1 ASCII: volume group body, surface group clamped (x = 0)."""
    import numpy as np
    from mpi4py import MPI
    from dolfinx import mesh as dmesh
    domain = box(MPI.COMM_SELF, n)
    x = domain.geometry.x
    cells = domain.geometry.dofmap.array.reshape(-1, 4)
    domain.topology.create_connectivity(2, 3)
    facets = dmesh.locate_entities_boundary(domain, 2, lambda p: np.isclose(p[0], 0.0))
    f2v = domain.topology.connectivity(2, 0)
    # Topology and geometry numberings agree for P1 vertices through the cell maps.
    c2v = domain.topology.connectivity(3, 0)
    vertex_to_node = np.empty(x.shape[0], dtype=np.int64)
    for c in range(cells.shape[0]):
        vertex_to_node[c2v.links(c)] = cells[c]
    tris = np.array([vertex_to_node[f2v.links(f)] for f in facets])
    with open(path, "w") as out:
        out.write("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n")
        out.write('$PhysicalNames\n2\n2 1 "clamped"\n3 2 "body"\n$EndPhysicalNames\n')
        out.write("$Entities\n0 0 1 1\n")
        out.write(f"1 0 {-H / 2} {-H / 2} 0 {H / 2} {H / 2} 1 1 0\n")
        out.write(f"1 0 {-H / 2} {-H / 2} {L} {H / 2} {H / 2} 1 2 0\n$EndEntities\n")
        nn = x.shape[0]
        out.write(f"$Nodes\n1 {nn} 1 {nn}\n3 1 0 {nn}\n")
        out.write("".join(f"{i + 1}\n" for i in range(nn)))
        out.write("".join(f"{p[0]:.17g} {p[1]:.17g} {p[2]:.17g}\n" for p in x))
        out.write("$EndNodes\n")
        nt, nc = len(tris), cells.shape[0]
        out.write(f"$Elements\n2 {nt + nc} 1 {nt + nc}\n2 1 2 {nt}\n")
        out.write("".join(f"{k + 1} {t[0] + 1} {t[1] + 1} {t[2] + 1}\n" for k, t in enumerate(tris)))
        out.write(f"3 1 4 {nc}\n")
        out.write("".join(f"{nt + k + 1} {c[0] + 1} {c[1] + 1} {c[2] + 1} {c[3] + 1}\n"
                          for k, c in enumerate(cells)))
        out.write("$EndElements\n")
    print(json.dumps({"nodes": int(nn), "tets": int(nc), "dofs": 3 * int(nn)}))


def solve_dolfinx(n, solver):
    """One dolfinx run (under mpirun); prints its figures as JSON on rank 0."""
    t_start = time.perf_counter()
    import numpy as np
    import ufl
    from mpi4py import MPI
    from petsc4py import PETSc
    from dolfinx import fem, mesh as dmesh
    import dolfinx.fem.petsc
    import dolfinx.nls.petsc
    comm = MPI.COMM_WORLD
    domain = box(comm, n)
    V = fem.VectorFunctionSpace(domain, ("Lagrange", 1))
    facets = dmesh.locate_entities_boundary(domain, 2, lambda p: np.isclose(p[0], 0.0))
    bc = fem.dirichletbc(np.zeros(3, dtype=PETSc.ScalarType),
                         fem.locate_dofs_topological(V, 2, facets), V)
    u, v = fem.Function(V), ufl.TestFunction(V)
    F = ufl.Identity(3) + ufl.grad(u)
    J = ufl.det(F)
    mu, lam = E / (2 * (1 + NU)), E * NU / ((1 + NU) * (1 - 2 * NU))
    psi = mu / 2 * (ufl.tr(F.T * F) - 3) - mu * ufl.ln(J) + lam / 2 * ufl.ln(J) ** 2
    b = fem.Constant(domain, PETSc.ScalarType((0.0, 0.0, -RHO * G)))
    Pi = psi * ufl.dx - ufl.dot(b, u) * ufl.dx
    problem = dolfinx.fem.petsc.NonlinearProblem(ufl.derivative(Pi, u, v), u, [bc])
    newton = dolfinx.nls.petsc.NewtonSolver(comm, problem)
    # hydrosoft's test: the residual below 1e-8 of the first one. dolfinx's rtol divides by
    # another norm, so both get that absolute bound.
    problem.F(u.vector, newton.b)
    newton.convergence_criterion = "residual"
    newton.rtol, newton.atol, newton.max_it = 1e-14, 1e-8 * newton.b.norm(), 50
    ksp = newton.krylov_solver
    opts = PETSc.Options()
    prefix = ksp.getOptionsPrefix() or ""
    for k, val in KSP_OPTIONS[solver].items():
        opts[prefix + k] = val
    ksp.setFromOptions()
    if solver == "gamg":  # the six rigid-body modes, as hydrosoft gives GAMG
        xs = V.tabulate_dof_coordinates()[: V.dofmap.index_map.size_local]
        functions, modes = [], []  # the functions own the vectors' memory: keep them
        for k in range(6):
            w = fem.Function(V)
            functions.append(w)
            a = w.x.array.reshape(-1, 3)[: xs.shape[0]]
            if k < 3:
                a[:, k] = 1.0
            else:
                i, j = [(0, 1), (1, 2), (2, 0)][k - 3]
                a[:, i], a[:, j] = -xs[:, j], xs[:, i]
            w.x.scatter_forward()
            modes.append(w.vector)
        dolfinx.la.orthonormalize(modes)
        newton.A.setNearNullSpace(PETSc.NullSpace().create(vectors=modes, comm=comm))
    comm.Barrier()
    t0 = time.perf_counter()
    if os.environ.get("NEWTON_LOG"):
        from dolfinx import log
        log.set_log_level(log.LogLevel.INFO)
    its, converged = newton.solve(u)
    solve_s = time.perf_counter() - t0
    # u_z at (L, 0, 0): the node there belongs to some rank.
    xs = V.tabulate_dof_coordinates()
    at = np.where(np.all(np.isclose(xs, [L, 0.0, 0.0], atol=1e-9), axis=1))[0]
    tip = u.x.array.reshape(-1, 3)[at[0], 2] if len(at) else np.nan
    tips = [t for t in comm.gather(tip, root=0) or [] if not np.isnan(t)]
    total = time.perf_counter() - t_start
    import resource
    peak = comm.allreduce(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, op=MPI.MAX)
    if comm.rank == 0:
        print(json.dumps({"newton_iterations": int(its), "converged": bool(converged),
                          "solve_s": solve_s, "total_s": total, "tip": float(tips[0]),
                          "peak_rank_mb": peak}))


def last_json(text):
    return json.loads([line for line in text.splitlines() if line.startswith("{")][-1])


def mpirun(ranks):
    flags = ["mpirun", "--oversubscribe", "-np", str(ranks)]
    if os.geteuid() == 0:
        flags.insert(1, "--allow-run-as-root")
    return flags


def deck_text(mesh_path, solver, workdir):
    return (f"mesh: {{file: {mesh_path}}}\n"
                  f"materials:\n  - {{group: body, model: neo_hookean, E: {E}, nu: {NU}, "
                  f"density: {RHO}}}\n"
                  "boundary:\n  - {group: clamped}\n"
                  f"loads: {{gravity: [0, 0, {-G}]}}\n"
                  "time: {type: static, steps: 1}\n"
            f"solver: {{preset: {solver}}}\n"
            f"output: {{folder: {workdir}/out}}\n")


def mesh_once(binary, msh_path, workdir):
    """The .msh as a hydrosoft mesh file (hydrosoft mesh), as a user meshes once for many
    runs; returns its path and the seconds it took."""
    deck = os.path.join(workdir, "convert.yaml")
    with open(deck, "w") as out:
        out.write(deck_text(msh_path, "mumps", workdir))
    h5 = msh_path[:-4] + ".h5"
    t0 = time.perf_counter()
    subprocess.run([binary, "mesh", deck, h5], check=True, capture_output=True, text=True)
    return h5, time.perf_counter() - t0


def run_hydrosoft(binary, mesh_path, ranks, solver, workdir):
    deck = os.path.join(workdir, "cantilever.yaml")
    with open(deck, "w") as out:
        out.write(deck_text(mesh_path, solver, workdir))
    t0 = time.perf_counter()
    subprocess.run(mpirun(ranks) + [binary, deck], check=True, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    with open(os.path.join(workdir, "out", "summary.json")) as f:
        s = json.load(f)
    return {"newton_iterations": s["newton_iterations"],
            "solve_s": s["time_s"]["assembly"] + s["time_s"]["solve"], "total_s": wall,
            "peak_rank_mb": s["memory_mb"]["peak_rank_max"],
            "tip": tip_from_output(os.path.join(workdir, "out"))}


def tip_from_output(folder):
    import h5py
    import numpy as np
    path = [f for f in os.listdir(folder) if f.endswith(".h5")][0]
    with h5py.File(os.path.join(folder, path)) as h5:
        x = h5["mesh/coordinates"][()]
        steps = sorted((k for k in h5 if k.startswith("step_")), key=lambda k: int(k[5:]))
        u = h5[steps[-1] + "/displacement"][()]
    at = np.where(np.all(np.isclose(x, [L, 0.0, 0.0], atol=1e-9), axis=1))[0][0]
    return float(u[at, 2])


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--write-mesh":
        return write_msh(int(sys.argv[2]), sys.argv[3])
    if len(sys.argv) > 1 and sys.argv[1] == "--dolfinx":
        return solve_dolfinx(int(sys.argv[2]), sys.argv[3])
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--sizes", default="50,100")
    p.add_argument("--ranks", default="1,2")
    p.add_argument("--solvers", default="mumps,gamg")
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--binary", default=os.path.join(REPO, "build", "bin", "hydrosoft"))
    p.add_argument("--csv", default=os.path.join(REPO, "bench", "fem", "cantilever_vs_dolfinx.csv"))
    a = p.parse_args()
    os.environ["OPENBLAS_NUM_THREADS"] = "1"
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in map(int, a.sizes.split(",")):
            msh_path = os.path.join(tmp, f"cantilever_{n}.msh")
            info = last_json(subprocess.run([sys.executable, __file__, "--write-mesh", str(n),
                                             msh_path], check=True, capture_output=True,
                                            text=True).stdout)
            mesh_path, mesh_s = mesh_once(a.binary, msh_path, tmp)
            print(json.dumps({"dofs": info["dofs"], "hydrosoft_mesh_s": mesh_s}), flush=True)
            for solver in a.solvers.split(","):
                for ranks in map(int, a.ranks.split(",")):
                    runs = {"hydrosoft": [], "dolfinx": []}
                    for _ in range(a.repeats):  # alternated, so both meet the same machine
                        runs["hydrosoft"].append(run_hydrosoft(a.binary, mesh_path, ranks,
                                                               solver, tmp))
                        t0 = time.perf_counter()
                        out = subprocess.run(mpirun(ranks) + [sys.executable, __file__,
                                                              "--dolfinx", str(n), solver],
                                             check=True, capture_output=True, text=True)
                        d = last_json(out.stdout)
                        d["total_s"] = time.perf_counter() - t0
                        runs["dolfinx"].append(d)
                    for code, rs in runs.items():
                        row = {"code": code, "dofs": info["dofs"], "tets": info["tets"],
                               "ranks": ranks, "solver": solver, "runs": len(rs),
                               "newton_iterations": rs[0]["newton_iterations"],
                               "solve_s": statistics.median(r["solve_s"] for r in rs),
                               "total_s": statistics.median(r["total_s"] for r in rs),
                               "tip_m": rs[0]["tip"],
                               "peak_rank_mb": max(r["peak_rank_mb"] for r in rs)}
                        rows.append(row)
                        print(json.dumps(row), flush=True)
    with open(a.csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


if __name__ == "__main__":
    main()
