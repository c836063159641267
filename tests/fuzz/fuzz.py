#!/usr/bin/python3
"""Fuzzes hydrosoft's input: mutated decks of input/, mutated .msh meshes and --set overrides,
each run with `hydrosoft --check` and a sample also for real; mutated surface files
(.obj, .off, .stl, .msh) run through `fluidweight`; and the families of families.py (.geo
files that merge others, binary .msh, .h5 meshes, checkpoints, full disks, interactive clients
that close their pipes, linked lock and staging folders), on 1 or 2 ranks. Each outcome is
classified (classify.py). Deterministic: case i of seed s is the same on every machine and can
be run alone (--only i; surface case i: --only s<i>; family case i: --only <family><i>).

    tests/fuzz/fuzz.py --hydrosoft build/bin/hydrosoft --out /tmp/fuzz --seed 1 --cases 3000 \
        --surfaces 2000 --family geo:500 --family checkpoint:300 --ranks-share 0.1

Needs /usr/bin/python3's standard library only, and the executables: the base meshes of the
mesh cases are read from tests/fuzz/base_meshes/ (--base-meshes; --make-base-meshes remakes
them with the gmsh command), the surfaces are written by surface_mutations.py.

Writes OUT/report.json (counts per class and per mutation, every defect), OUT/cases.csv (one
row a case) and OUT/defects/<id>/ (the mutated deck and mesh, the command, its stderr);
nothing into the source tree. Exit status 1 if a defect was found.
"""
import argparse
import concurrent.futures
import csv
import glob
import json
import os
import random
import re
import shutil
import subprocess
import sys
import time
import traceback

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from classify import run_case, run_surface_case  # noqa: E402
from deck_mutations import mutate_deck, override_mutation  # noqa: E402
import families  # noqa: E402
from launch import Launcher  # noqa: E402
import mini_yaml  # noqa: E402
from mesh_mutations import mutate_msh  # noqa: E402
from surface_mutations import mutate_surface  # noqa: E402

SOURCE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# Decks whose real run ends in seconds: the sample of real runs is drawn from these.
FAST_DECKS = {"cantilever_gravity", "hydrostatic_patch", "bimaterial_bar", "lame_sphere", "gent_sphere",
              "cantilever_dynamic", "neo_hookean_sphere", "finger_cable", "cylinder_air"}

# The deck of the mesh cases: a block held at its bottom under its own weight.
MESH_DECK = """mesh:
  file: mesh.msh
  order: {order}
materials:
  - {{group: body, model: neo_hookean, E: 1.0e6, nu: 0.3, density: 1000}}
boundary:
  - {{group: bottom}}
loads:
  gravity: [0, 0, -9.81]
time: {{type: static, steps: 1}}
solver: {{preset: mumps}}
"""

# The base meshes: (name, gmsh arguments, order of the deck). The ASCII ones are the mesh
# cases' bases, the binary ones (`_bin`) the binary .msh family's (families.py).
BASE_MESHES = [
    ("block_v41", ["-format", "msh41"], 1),
    ("block_v22", ["-format", "msh22"], 1),
    ("block_v41_p2", ["-format", "msh41", "-order", "2"], 2),
]
BINARY_BASE_MESHES = [
    ("block_v41_bin", ["-format", "msh41", "-bin"], 1),
    ("block_v22_bin", ["-format", "msh22", "-bin"], 1),
    ("block_v41_p2_bin", ["-format", "msh41", "-bin", "-order", "2"], 2),
    ("block_v22_p2_bin", ["-format", "msh22", "-bin", "-order", "2"], 2),
]


BASE_MESH_FOLDER = os.path.join(SOURCE, "tests", "fuzz", "base_meshes")


def make_base_meshes(folder):
    """Meshes meshes/block.geo with the gmsh command into `folder` (4.8.4 made the stored ones)."""
    os.makedirs(folder, exist_ok=True)
    for name, args, _ in BASE_MESHES + BINARY_BASE_MESHES:
        path = os.path.join(folder, name + ".msh")
        subprocess.run(["gmsh", "-3", "-setnumber", "h", "0.5", "-nt", "1", *args, "-o", path,
                        os.path.join(SOURCE, "meshes", "block.geo")],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def load_base_meshes(folder):
    meshes = {}
    for name, _, order in BASE_MESHES:
        with open(os.path.join(folder, name + ".msh")) as f:
            meshes[name] = (f.read(), order)
    return meshes


def load_decks(pattern):
    decks = {}
    for path in sorted(glob.glob(pattern)):
        with open(path) as f:
            text = f.read()
        # The mutated deck lives elsewhere: its mesh is named by its absolute path.
        text = re.sub(r"(file:\s*)\.\./meshes/", r"\g<1>" + os.path.join(SOURCE, "meshes") + "/", text)
        decks[os.path.splitext(os.path.basename(path))[0]] = text
    for name, text in decks.items():
        try:
            mini_yaml.load(text)
        except (ValueError, IndexError) as e:
            sys.exit(f"fuzz: tests/fuzz/mini_yaml.py cannot read {name}.yaml ({e}): extend it")
    try:  # where PyYAML is installed: the harness's own reader must see the same trees
        import yaml
    except ImportError:
        return decks
    for name, text in decks.items():
        if mini_yaml.shape(mini_yaml.load(text)) != mini_yaml.shape(yaml.safe_load(text)):
            sys.exit(f"fuzz: tests/fuzz/mini_yaml.py reads {name}.yaml otherwise than PyYAML: "
                     "extend it to the YAML that deck uses")
    return decks


def make_case(seed, i, decks, meshes, run_share, mesh_share):
    """The case i of `seed`: what to write and how to run it, from its own generator."""
    rng = random.Random(f"{seed}/{i}")
    case = {"id": i, "overrides": [], "mesh": None}
    draw = rng.random()
    if draw < mesh_share:
        name = rng.choice(sorted(meshes))
        text, order = meshes[name]
        case["source"] = name
        case["kind"], case["detail"], case["mesh"] = mutate_msh(rng, text)
        case["deck"] = MESH_DECK.format(order=order)
    else:
        name = rng.choice(sorted(decks))
        case["source"] = name
        if draw < mesh_share + 0.08:
            case["kind"], case["detail"] = "override", ""
            case["deck"] = decks[name]
            case["overrides"] = [override_mutation(rng, decks[name])]
            case["detail"] = case["overrides"][0][:80]
        else:
            case["kind"], case["detail"], case["deck"] = mutate_deck(rng, decks[name])
    fast = case["mesh"] is not None or case["source"] in FAST_DECKS
    case["real_run"] = fast and rng.random() < run_share
    return case


def make_surface_case(seed, i):
    """Surface case i of `seed`, from its own generator (apart from the deck cases')."""
    rng = random.Random(f"{seed}/surface/{i}")
    base, fmt, kind, detail, expect, volume, ext, data = mutate_surface(rng)
    return {"id": f"s{i}", "source": f"{base}.{fmt}", "kind": "surface:" + kind, "detail": detail,
            "real_run": False, "expect": expect, "volume": volume, "file": "surface." + ext,
            "data": data}


def run_surface_one(i, args):
    case = make_surface_case(args.seed, i)  # made here: a case may hold megabytes
    folder = os.path.join(args.out, "work", case["id"])
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    with open(os.path.join(folder, case["file"]), "wb") as f:
        f.write(case["data"])
    start = time.monotonic()
    outcome = run_surface_case(args.fluidweight, case["file"], folder, args.check_timeout,
                               case["expect"], case["volume"])
    return finish(case, outcome, folder, start, args)


def run_family_one(case, ctx, args):
    start = time.monotonic()
    try:
        outcome = families.run_case(case, ctx)
    except Exception:  # the harness's own fault: kept and counted, the campaign goes on
        outcome = ("harness_error", "the harness failed: see stderr.txt", None, traceback.format_exc(), ["#"])
    return finish(case, outcome, os.path.join(args.out, "work", case["id"]), start, args)


def parse_families(specs, only):
    """{family: [case numbers]} from --family NAME:COUNT[:FIRST] and --only NAME<i>."""
    chosen = {}
    for spec in specs or []:
        name, _, rest = spec.partition(":")
        count, _, first = rest.partition(":")
        if name not in families.NAMES or not count.isdigit() or (first and not first.isdigit()):
            sys.exit(f"fuzz: --family {spec}: expected NAME:COUNT[:FIRST], NAME one of {', '.join(families.NAMES)}")
        chosen.setdefault(name, []).extend(range(int(first or 0), int(first or 0) + int(count)))
    for item in only or []:
        m = re.fullmatch(r"([a-z0-9]+?)(\d+)", item)
        if m and m.group(1) in families.NAMES:
            chosen.setdefault(m.group(1), []).append(int(m.group(2)))
    return chosen


def write_case(case, folder):
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "deck.yaml"), "w", encoding="utf-8", errors="surrogateescape") as f:
        f.write(case["deck"])
    if case["mesh"] is not None:
        with open(os.path.join(folder, "mesh.msh"), "w") as f:
            f.write(case["mesh"])


def run_one(case, args):
    folder = os.path.join(args.out, "work", str(case["id"]))
    shutil.rmtree(folder, ignore_errors=True)
    write_case(case, folder)
    files = ["deck.yaml", "mesh.msh"] + re.findall(r"meshes/(\w+\.geo)", case["deck"])
    start = time.monotonic()
    outcome = run_case(args.hydrosoft, "deck.yaml", case["overrides"], files, False, folder,
                       args.check_timeout, args.memory_mb)
    if case["real_run"] and outcome[0] == "accepted":
        outcome = run_case(args.hydrosoft, "deck.yaml", case["overrides"], files, True, folder,
                           args.run_timeout, args.memory_mb)
    return finish(case, outcome, folder, start, args)


def finish(case, outcome, folder, start, args):
    """The case's row of the report; a defect's (or time limit's) folder kept as its reproducer."""
    cls, reason, code, stderr, command = outcome
    result = {k: case[k] for k in ("id", "source", "kind", "detail", "real_run")}
    result["family"] = case.get("family", "surface" if case["kind"].startswith("surface:") else "deck")
    result["ranks"] = case.get("ranks", 1)
    result.update({"class": cls, "reason": reason, "exit": code, "seconds": round(time.monotonic() - start, 2)})
    if cls in ("defect", "harness_error") or (cls == "time_limit" and args.keep_time_limits):
        kept = os.path.join(args.out, {"defect": "defects", "harness_error": "harness_errors"}.get(cls, "time_limits"),
                            str(case["id"]))
        shutil.rmtree(kept, ignore_errors=True)
        os.makedirs(os.path.dirname(kept), exist_ok=True)  # a rename, not a copy: Open MPI leaves fifos
        if "family" not in case:  # a family case keeps its results: they are the evidence
            shutil.rmtree(os.path.join(folder, "results"), ignore_errors=True)
        shutil.move(folder, kept)
        where = os.path.join(kept, "run") if "family" in case else kept
        notes = [c for c in command if c.startswith("# ")]  # what the command alone does not say
        with open(os.path.join(kept, "command.txt"), "w") as f:
            f.write("cd " + where + " && " + " ".join(repr(c) if " " in c else c for c in command if c not in notes)
                    + "\n" + "".join(n + "\n" for n in notes))
        with open(os.path.join(kept, "stderr.txt"), "w") as f:
            f.write(stderr)
        result["reproducer"] = kept
        result["stderr_tail"] = stderr[-2000:]
    else:
        shutil.rmtree(folder, ignore_errors=True)
    return result


def base_checkpoint(ctx):
    """Where the checkpoint family's base stopped (the SIGTERM's moment depends on the machine)."""
    if ctx is None or "checkpoint" not in ctx.bases:
        return None
    import checkpoint_mutations
    from h5_layout import H5Layout

    data = ctx.bases["checkpoint"][0]
    return checkpoint_mutations.StateText(data, H5Layout(data)).state.get("position")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--hydrosoft", help="needed for deck cases (--cases)")
    parser.add_argument("--fluidweight", help="for the surface cases; default: beside --hydrosoft")
    parser.add_argument("--out", required=True, help="report and reproducers (not in the source tree)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--cases", type=int, default=300)
    parser.add_argument("--first", type=int, default=0, help="the first case's id")
    parser.add_argument("--surfaces", type=int, default=0, help="surface cases, run by fluidweight")
    parser.add_argument("--surfaces-first", type=int, default=0, help="the first surface case's id")
    parser.add_argument("--only", nargs="*", help="run these case ids alone: 12 (a deck case), s12 (a surface case)")
    parser.add_argument("--base-meshes", default=BASE_MESH_FOLDER, help="folder of the mesh cases' base meshes")
    parser.add_argument("--make-base-meshes", action="store_true", help="remake them with gmsh first")
    parser.add_argument("--decks", default=os.path.join(SOURCE, "input", "*.yaml"))
    parser.add_argument("--run-share", type=float, default=0.0, help="share of fast cases also run for real")
    parser.add_argument("--mesh-share", type=float, default=0.3)
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--check-timeout", type=float, default=60)
    parser.add_argument("--run-timeout", type=float, default=60)
    parser.add_argument("--memory-mb", type=int, default=4096, help="address-space limit, 0 for none")
    parser.add_argument("--keep-time-limits", action="store_true")
    parser.add_argument("--family", action="append", metavar="NAME:COUNT[:FIRST]",
                        help="COUNT cases of a family of families.py from case FIRST (default 0): "
                             + ", ".join(families.NAMES))
    parser.add_argument("--ranks-share", type=float, default=0.0, help="share of family cases run on 2 ranks")
    parser.add_argument("--mpiexec", help="the MPI launcher of the 2-rank cases (default: the mpiexec or mpirun "
                                          "beside --hydrosoft, as a bundle carries it, else on PATH)")
    args = parser.parse_args()
    if args.hydrosoft:
        args.hydrosoft = os.path.abspath(args.hydrosoft)
    if not args.mpiexec:
        beside = [os.path.join(os.path.dirname(args.hydrosoft or ""), name) for name in ("mpiexec", "mpirun")]
        args.mpiexec = next((p for p in beside if os.access(p, os.X_OK)), None) or shutil.which("mpiexec") \
            or shutil.which("mpirun") or "mpiexec"
    if not args.fluidweight and args.hydrosoft:
        args.fluidweight = os.path.join(os.path.dirname(args.hydrosoft), "fluidweight")
    if args.fluidweight:
        args.fluidweight = os.path.abspath(args.fluidweight)
    args.out = os.path.abspath(args.out)
    if os.path.commonpath([args.out, SOURCE]) == SOURCE and "/build" not in args.out:
        sys.exit("fuzz: --out must lie outside the source tree (or in a build folder)")
    for old in ("defects", "harness_errors"):
        shutil.rmtree(os.path.join(args.out, old), ignore_errors=True)
    os.makedirs(args.out, exist_ok=True)

    chosen = parse_families(args.family, args.only)
    if args.only:
        ids = [int(i) for i in args.only if i.isdigit()]
        surface_ids = [int(i[1:]) for i in args.only if re.fullmatch(r"s\d+", i)]
    else:
        ids = range(args.first, args.first + args.cases)
        surface_ids = range(args.surfaces_first, args.surfaces_first + args.surfaces)
    if (ids or chosen) and not args.hydrosoft:
        sys.exit("fuzz: deck and family cases need --hydrosoft (or --cases 0)")
    if surface_ids and not (args.fluidweight and os.access(args.fluidweight, os.X_OK)):
        sys.exit(f"fuzz: surface cases need the fluidweight executable (--fluidweight; {args.fluidweight})")
    cases = []
    if ids:
        if args.make_base_meshes:
            make_base_meshes(args.base_meshes)
        decks = load_decks(args.decks)
        meshes = load_base_meshes(args.base_meshes)
        cases = [make_case(args.seed, i, decks, meshes, args.run_share, args.mesh_share) for i in ids]
    cases += [("surface", i) for i in surface_ids]
    start = time.monotonic()
    ctx = None
    if chosen:
        ctx = families.Context(Launcher(args.hydrosoft, args.mpiexec, args.memory_mb), args.out, SOURCE,
                               args.check_timeout, args.run_timeout, args.ranks_share)
        binary = [(name, order) for name, _, order in BINARY_BASE_MESHES]
        families.prepare(chosen, ctx, args.base_meshes, binary)
        for name in families.NAMES:
            cases += [families.make_case(name, args.seed, i, ctx) for i in chosen.get(name, [])]
    results = []

    def run_any(case):
        if isinstance(case, tuple):
            return run_surface_one(case[1], args)
        return run_family_one(case, ctx, args) if "family" in case else run_one(case, args)

    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        for r in pool.map(run_any, cases):
            results.append(r)
            if len(results) % 500 == 0:  # a line now and then for the long campaign
                print(f"fuzz: {len(results)} of {len(cases)} cases, {time.monotonic() - start:.0f} s",
                      file=sys.stderr, flush=True)
    shutil.rmtree(os.path.join(args.out, "work"), ignore_errors=True)

    counts, by_kind, by_format, by_family = {}, {}, {}, {}
    for r in results:
        family = by_family.setdefault(r["family"], {})
        family[r["class"]] = family.get(r["class"], 0) + 1
        counts[r["class"]] = counts.get(r["class"], 0) + 1
        kind = by_kind.setdefault(r["kind"], {})
        kind[r["class"]] = kind.get(r["class"], 0) + 1
        if r["kind"].startswith("surface:"):
            fmt = by_format.setdefault(r["source"].split(".")[1], {})
            fmt[r["class"]] = fmt.get(r["class"], 0) + 1
    surfaces = [r for r in results if r["kind"].startswith("surface:")]
    surface_counts, deck_counts = {}, {}
    for r in results:
        if r["family"] in ("deck", "surface"):
            part = surface_counts if r["family"] == "surface" else deck_counts
            part[r["class"]] = part.get(r["class"], 0) + 1
    defects = [r for r in results if r["class"] == "defect"]
    report = {
        "seed": args.seed, "cases": len(results), "first": args.first,
        "real_runs": sum(r["real_run"] for r in results),
        "surface_cases": len(surfaces), "surface_first": args.surfaces_first,
        "seconds": round(time.monotonic() - start, 1), "jobs": args.jobs, "counts": counts,
        "deck_counts": deck_counts, "surface_counts": surface_counts, "by_family": by_family,
        "family_cases": sum(r["family"] not in ("deck", "surface") for r in results),
        "two_rank_cases": sum(r["ranks"] > 1 for r in results), "base_checkpoint": base_checkpoint(ctx),
        "by_kind": by_kind, "surfaces_by_format": by_format,
        "defects": defects,
        "time_limits": [r for r in results if r["class"] == "time_limit"],
    }
    with open(os.path.join(args.out, "report.json"), "w") as f:
        json.dump(report, f, indent=1)
    with open(os.path.join(args.out, "cases.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, ["id", "family", "source", "kind", "detail", "real_run", "ranks", "class", "exit",
                               "seconds", "reason"],
                           extrasaction="ignore")
        w.writeheader()
        w.writerows(results)
    print(f"fuzz: seed {args.seed}, {len(results)} cases ({report['real_runs']} also run, "
          f"{len(surfaces)} surfaces), {report['seconds']} s: "
          + ", ".join(f"{k} {v}" for k, v in sorted(counts.items()))
          + " (decks and meshes: " + (", ".join(f"{k} {v}" for k, v in sorted(deck_counts.items())) or "none")
          + "; surfaces: " + (", ".join(f"{k} {v}" for k, v in sorted(surface_counts.items())) or "none") + ")")
    for name in families.NAMES:
        if name in by_family:
            print(f"fuzz:   {name}: " + ", ".join(f"{k} {v}" for k, v in sorted(by_family[name].items())))
    for d in defects:
        print(f"fuzz: defect in case {d['id']} ({d['source']}, {d['kind']}: {d['detail']}): {d['reason']}"
              f"\n      reproducer: {d['reproducer']}")
    for r in results:
        if r["class"] == "harness_error":
            print(f"fuzz: the harness failed on case {r['id']}: {r['stderr_tail'].strip().splitlines()[-1]}"
                  f"\n      kept: {r['reproducer']}")
    return 1 if defects or counts.get("harness_error") else 0


if __name__ == "__main__":
    sys.exit(main())
