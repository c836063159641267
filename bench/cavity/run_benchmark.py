#!/usr/bin/python3
"""Cavity benchmark: refinement of the cylinder validation, time per step split into its
parts (cylinder and the ~100k-triangle sphere cavity), and the paper's linearized weight
coupling against the converged one.

    /usr/bin/python3 bench/cavity/run_benchmark.py [--repeats 3] [--parts refinement time coupling]

Writes bench/cavity/refinement.csv, bench/cavity/time_per_step.csv,
docs/figures/cavity_coupling.csv and docs/figures/cavity_coupling.png, and prints Markdown
tables (medians over the repeats) for docs/cavities.md and docs/benchmarks.md. Timings come
from each run's summary.json (time_s). Runs go to --out (default out/bench_cavity); with
--reuse a run whose summary.json is already there is not run again.

--export-obj writes the cavity surfaces of the benchmarked meshes (undeformed) to
bench/cavity/surfaces/*.obj for bench/cavity/run_device.sh (the GPU machine's fluid-weight
timings, kept in bench/cavity/gpu_fluidweight.jsonl, which the time table reads).
"""
import argparse
import csv
import json
import os
import platform
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
import msh_to_obj  # noqa: E402

CYLINDER_PARAMS = ["-setnumber", "R", "0.02", "-setnumber", "L", "0.15", "-setnumber", "t", "0.006",
                   "-setnumber", "e", "-0.002"]
MESHES = [(1, 0.011), (1, 0.006), (1, 0.004), (2, 0.011), (2, 0.006)]  # (order, h)
COUPLING_MESHES = [(1, 0.011), (1, 0.006), (1, 0.004)]
COUPLING_STEPS = [(1, 2), (2, 5), (4, 10), (8, 20)]  # (rest steps, inflated steps)
DECK_STEPS = (4, 10)                                 # the decks' own
SPHERE_DECK = """# Written by bench/cavity/run_benchmark.py: the sphere cavity of sphere_cavity.geo filled
# with water, the cube clamped on its bottom face, gravity -z; the water fills the cavity
# at rest, then 3 ml more are pumped in over {steps} steps.
mesh:
  file: {msh}
  order: 1
materials:
  - {{group: body, model: neo_hookean, E: 2.0e5, nu: 0.45, density: 1070}}
boundary:
  - {{group: fixed}}
loads:
  gravity: [0, 0, -9.81]
cavities:
  - group: cavity
    kind: hydraulic
    density: 1000
    fluid_weight: {{method: column, grid: 200, device: cpu, coupling: converged}}
states:
  - {{name: rest, steps: 1}}
  - {{name: inflated, steps: {steps}, cavities: {{cavity: {{added_volume: 3.0e-6}}}}}}
solver: {{preset: {preset}}}
"""


def mpirun(binary, deck, folder, sets, np=2):
    cmd = ["mpirun", "--oversubscribe", "-np", str(np)]
    if os.geteuid() == 0:
        cmd.append("--allow-run-as-root")
    cmd += [binary, deck, "--set", f"output.folder={folder}"]
    for s in sets:
        cmd += ["--set", s]
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    for _ in range(12):  # a build running beside the benchmark can remove the binary a moment
        r = subprocess.run(cmd, capture_output=True, text=True, env=env)
        if r.returncode == 0 or os.access(binary, os.X_OK):
            break
        time.sleep(10)
    if r.returncode != 0:
        sys.exit(f"run_benchmark: {' '.join(cmd)} failed:\n{r.stderr[-3000:]}{r.stdout[-2000:]}")


_done = {}  # key -> summaries: a run shared by two parts runs once


def runs(args, key, deck, sets, repeats):
    """Summaries of `repeats` runs of deck with the overrides, each in its own folder."""
    if key in _done:
        return _done[key]
    out = []
    for k in range(repeats):
        folder = os.path.join(args.out, "runs", f"{key}_{k}")
        summary = os.path.join(folder, "summary.json")
        if not (args.reuse and os.path.exists(summary)):
            mpirun(args.binary, deck, folder, sets)
        with open(summary) as f:
            s = json.load(f)
        s["_folder"] = folder
        out.append(s)
    _done[key] = out
    return out


def med(summaries, f):
    return statistics.median(f(s) for s in summaries)


def state(s, name):
    return next(x for x in s["states"] if x["name"] == name)


def cylinder(args, fluid, order, h, steps=DECK_STEPS, coupling="converged", repeats=None):
    deck = os.path.join(ROOT, "input", f"cylinder_{fluid}.yaml")
    sets = [f"mesh.order={order}", f"mesh.parameters.h={h}", f"states[0].steps={steps[0]}",
            f"states[1].steps={steps[1]}"]
    if fluid == "water":
        sets.append(f"cavities[0].fluid_weight.coupling={coupling}")
    key = f"cylinder_{fluid}_p{order}_h{h}_s{steps[0]}-{steps[1]}_{coupling if fluid == 'water' else 'air'}"
    return runs(args, key, deck, sets, repeats or args.repeats)


def time_split(s):
    """Per-run split of the stepping (total - setup) into disjoint parts (s)."""
    t = s["time_s"]
    stepping = t["total"] - t["setup"]
    parts = dict(assembly=t["assembly"], linear=t["constraint"], fluid_weight=t["fluid_weight"])
    parts["rest"] = stepping - sum(parts.values())
    parts["stepping"] = stepping
    return parts


def refinement(args):
    rows = []
    for fluid in ("air", "water"):
        for order, h in MESHES:
            ss = cylinder(args, fluid, order, h)
            s = ss[0]
            rest, infl = state(s, "rest"), state(s, "inflated")
            row = dict(fluid=fluid, order=order, h=h, nodes=s["nodes"], dofs=s["dofs"],
                       rest_angle_deg=rest["tip"]["inclination_deg"], inflated_angle_deg=infl["tip"]["inclination_deg"],
                       pressure_pa=infl["cavities"][0]["pressure"],
                       weight_n=infl["cavities"][0]["fluid_weight_total"],
                       steps=s["steps"], newton=s["newton_iterations"], runs=len(ss),
                       total_s=med(ss, lambda x: x["time_s"]["total"]))
            rows.append(row)
            print(json.dumps(row), flush=True)
    write_csv(os.path.join(HERE, "refinement.csv"), rows)
    print("\n| fluid | order | h (m) | nodes | dofs | rest angle (deg) | inflated angle (deg) | "
          "pressure (Pa) | liquid weight (N) | Newton its | wall time (s) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['fluid']} | P{r['order']} | {r['h']} | {r['nodes']:,} | {r['dofs']:,} | "
              f"{r['rest_angle_deg']:.2f} | {r['inflated_angle_deg']:.2f} | {r['pressure_pa']:.0f} | "
              f"{r['weight_n']:.3f} | {r['newton']} | {r['total_s']:.1f} |")


def gpu_times():
    """fluidweight CLI times per surface file and run kind (ms), from run_device.sh."""
    path = os.path.join(HERE, "gpu_fluidweight.jsonl")
    t = {}
    if os.path.exists(path):
        with open(path) as f:
            for line in f:
                if line.strip():
                    j = json.loads(line)
                    t[(os.path.basename(j["mesh"]), j["run"])] = j
    return t


def sphere_msh(args):
    msh = args.sphere_msh or os.path.join(args.out, "sphere_cavity.msh")
    if not os.path.exists(msh):
        os.makedirs(os.path.dirname(msh), exist_ok=True)
        subprocess.run(["gmsh", "-3", os.path.join(HERE, "sphere_cavity.geo"), "-o", msh],
                       check=True, capture_output=True)
    return msh


def time_per_step(args):
    gpu = gpu_times()
    deck = os.path.join(args.out, "sphere_cavity.yaml")
    os.makedirs(args.out, exist_ok=True)
    with open(deck, "w") as f:
        f.write(SPHERE_DECK.format(msh=os.path.abspath(sphere_msh(args)), steps=args.sphere_steps,
                                   preset=args.sphere_preset))
    ss = runs(args, f"sphere_{args.sphere_preset}_s{args.sphere_steps}", deck, [], args.sphere_repeats)
    scenes = [("sphere cavity in a cube (P1)", "sphere_cavity.obj", ss)]  # first: the longest
    for order, h, label in [(1, 0.011, "coarse"), (1, 0.004, "refined"), (2, 0.006, "refined P2")]:
        ss = cylinder(args, "water", order, h)
        scenes.insert(-1, (f"cylinder water, {label} (P{order}, h {h})",
                           f"cylinder_p{order}_h{h}.obj", ss))

    rows = []
    for name, obj, ss in scenes:
        s = ss[0]
        steps = s["steps"]
        calls = s["parts"]["fluid_weight"]["calls"]
        per_step = lambda part: 1e3 * med(ss, lambda x: time_split(x)[part]) / steps
        row = dict(scene=name, nodes=s["nodes"], dofs=s["dofs"], steps=steps,
                   newton=s["newton_iterations"], fluid_weight_calls=calls, runs=len(ss),
                   step_ms=per_step("stepping"), assembly_ms=per_step("assembly"),
                   linear_ms=per_step("linear"), fluid_weight_ms=per_step("fluid_weight"),
                   rest_ms=per_step("rest"),
                   fluid_weight_call_ms=1e3 * med(ss, lambda x: x["time_s"]["fluid_weight"]) / calls)
        for run, col in [("cpu one core", "h100_host_cpu_call_ms"), ("cuda", "gpu_call_ms"),
                         ("cuda", "gpu_kernels_ms")]:
            j = gpu.get((obj, run))
            row[col] = (j["gpu_time_ms"] if col == "gpu_kernels_ms" else j["time_ms"]) if j else ""
        row["cavity_triangles"] = gpu[(obj, "cuda")]["triangles"] if (obj, "cuda") in gpu else ""
        rows.append(row)
        print(json.dumps(row), flush=True)
    write_csv(os.path.join(HERE, "time_per_step.csv"), rows)
    print("\n| scene | dofs | cavity triangles | steps | Newton its | step (ms) | assembly | "
          "linear solves | fluid weight (CPU) | rest | fluid weight per call, CPU (ms) | "
          "per call, H100 (ms) | H100 kernels (ms) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    f = lambda x: f"{x:.3g}" if x != "" else "-"
    for r in rows:
        print(f"| {r['scene']} | {r['dofs']:,} | {r['cavity_triangles']:,} | {r['steps']} | "
              f"{r['newton']} | {r['step_ms']:.0f} | {r['assembly_ms']:.0f} | {r['linear_ms']:.0f} | "
              f"{r['fluid_weight_ms']:.1f} | {r['rest_ms']:.1f} | {f(r['fluid_weight_call_ms'])} | "
              f"{f(r['gpu_call_ms'])} | {f(r['gpu_kernels_ms'])} |")


def final_displacement(folder):
    import h5py
    import numpy as np
    h5 = [f for f in os.listdir(folder) if f.endswith(".h5")][0]
    with h5py.File(os.path.join(folder, h5)) as f:
        last = max(int(k.split("_")[1]) for k in f if k.startswith("step_"))
        return np.asarray(f[f"step_{last}/displacement"])


def coupling(args):
    import numpy as np
    rows = []
    for order, h in COUPLING_MESHES:
        ref = cylinder(args, "water", order, h)  # converged coupling, the decks' steps
        u_ref = final_displacement(ref[0]["_folder"])
        ref_angle = {n: state(ref[0], n)["tip"]["inclination_deg"] for n in ("rest", "inflated")}
        for coupling_name in ("linearized", "converged"):
            for steps in COUPLING_STEPS:
                if coupling_name == "converged" and steps not in ((1, 2), DECK_STEPS):
                    continue
                ss = cylinder(args, "water", order, h, steps, coupling_name)
                s = ss[0]
                u = final_displacement(s["_folder"])
                row = dict(order=order, h=h, nodes=s["nodes"], coupling=coupling_name,
                           rest_steps=steps[0], inflated_steps=steps[1],
                           inflated_angle_deg=state(s, "inflated")["tip"]["inclination_deg"],
                           angle_error_deg=state(s, "inflated")["tip"]["inclination_deg"] - ref_angle["inflated"],
                           rest_angle_error_deg=state(s, "rest")["tip"]["inclination_deg"] - ref_angle["rest"],
                           displacement_error=float(np.linalg.norm(u - u_ref) / np.linalg.norm(u_ref)),
                           newton=s["newton_iterations"], fluid_weight_calls=s["parts"]["fluid_weight"]["calls"],
                           runs=len(ss), total_s=med(ss, lambda x: x["time_s"]["total"]))
                rows.append(row)
                print(json.dumps(row), flush=True)
    figures = os.path.join(ROOT, "docs", "figures")
    write_csv(os.path.join(figures, "cavity_coupling.csv"), rows)
    plot_coupling(rows, os.path.join(figures, "cavity_coupling.png"))
    print("\n| mesh | coupling | steps (rest + inflated) | inflated angle (deg) | error (deg) | "
          "rest error (deg) | displacement error | Newton its | weight calls | wall time (s) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| P{r['order']} h {r['h']} ({r['nodes']:,} nodes) | {r['coupling']} | "
              f"{r['rest_steps']} + {r['inflated_steps']} | {r['inflated_angle_deg']:.3f} | "
              f"{r['angle_error_deg']:+.2e} | {r['rest_angle_error_deg']:+.2e} | "
              f"{r['displacement_error']:.1e} | {r['newton']} | {r['fluid_weight_calls']} | "
              f"{r['total_s']:.2f} |")


def plot_coupling(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    floor = 1e-7
    fig, axes = plt.subplots(1, 2, figsize=(11, 5))
    colors = ["tab:blue", "tab:orange", "tab:green", "tab:red"]
    for c, (order, h) in enumerate(COUPLING_MESHES):
        for coupling_name, marker, ls in (("linearized", "o", "-"), ("converged", "s", ":")):
            rr = [r for r in rows if (r["order"], r["h"]) == (order, h) and r["coupling"] == coupling_name]
            if not rr:
                continue
            t = [r["total_s"] for r in rr]
            label = f"P{order} h {h} ({rr[0]['nodes']} nodes), {coupling_name}"
            for ax, key in zip(axes, ("angle_error_deg", "displacement_error")):
                e = [max(abs(r[key]), floor) for r in rr]
                ax.plot(t, e, marker=marker, ls=ls, color=colors[c], label=label,
                        mfc="none" if coupling_name == "converged" else colors[c])
                if coupling_name == "linearized":
                    for r, x, y in zip(rr, t, e):
                        ax.annotate(f"{r['rest_steps']}+{r['inflated_steps']}", (x, y), fontsize=7,
                                    xytext=(3, 3), textcoords="offset points")
    axes[0].set_ylabel("|inflated tip angle - converged| (deg)")
    axes[1].set_ylabel("||u - u_converged|| / ||u_converged||, inflated")
    for ax in axes:
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall time of the run (s, median, 2 ranks)")
        ax.grid(True, which="both", alpha=0.3)
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=7)
    fig.suptitle("Water cylinder: the paper's linearized weight against the converged coupling\n"
                 "labels: rest + inflated steps; reference: converged, 4 + 10 steps; "
                 f"errors below {floor:g} drawn at {floor:g}", fontsize=9)
    fig.tight_layout(rect=(0, 0.1, 1, 1))
    fig.savefig(path, dpi=130)


def export_obj(args):
    folder = os.path.join(HERE, "surfaces")
    os.makedirs(folder, exist_ok=True)
    tmp = os.path.join(args.out, "meshes")
    os.makedirs(tmp, exist_ok=True)
    for order, h in [(1, 0.011), (1, 0.004), (2, 0.006)]:
        msh = os.path.join(tmp, f"cylinder_p{order}_h{h}.msh")
        subprocess.run(["gmsh", "-3", "-order", str(order), os.path.join(ROOT, "meshes", "cylinder.geo")]
                       + CYLINDER_PARAMS + ["-setnumber", "h", str(h), "-o", msh], check=True,
                       capture_output=True)
        print(msh_to_obj.convert(msh, os.path.join(folder, f"cylinder_p{order}_h{h}.obj")))
    print(msh_to_obj.convert(sphere_msh(args), os.path.join(folder, "sphere_cavity.obj")))


def write_csv(path, rows):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)


def cpu_name():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor()


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--binary", default=os.path.join(ROOT, "build/bin/hydrosoft"))
    p.add_argument("--parts", nargs="+", default=["refinement", "time", "coupling"],
                   choices=["refinement", "time", "coupling"])
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--sphere-msh", help="the meshed sphere_cavity.geo (default: OUT/sphere_cavity.msh, "
                   "meshed with gmsh when missing)")
    p.add_argument("--sphere-steps", type=int, default=2, help="steps of the sphere's inflation")
    p.add_argument("--sphere-repeats", type=int, default=1,
                   help="runs of the sphere (one run takes minutes on 2 cores)")
    p.add_argument("--sphere-preset", default="gamg", help="solver preset of the sphere deck")
    p.add_argument("--out", default=os.path.join(ROOT, "out/bench_cavity"))
    p.add_argument("--reuse", action="store_true", help="keep runs whose summary.json exists")
    p.add_argument("--export-obj", action="store_true", help="only write bench/cavity/surfaces/*.obj")
    args = p.parse_args()
    if args.export_obj:
        export_obj(args)
        return
    print(f"Machine: {cpu_name()}, {os.cpu_count()} cores; 2 ranks; medians over {args.repeats} runs\n")
    for part in args.parts:
        {"refinement": refinement, "time": time_per_step, "coupling": coupling}[part](args)
        print()


if __name__ == "__main__":
    main()
