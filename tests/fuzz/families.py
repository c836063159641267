"""The case families of issue 29, beside fuzz.py's decks, meshes and surfaces: each case is
made from its own generator, `Random("SEED/FAMILY/i")`, and judged by classify.py.

  geo          a .geo that Includes, Merges or Opens helper files and option files
               (geo_mutations.py): --check, a real run or `hydrosoft mesh DECK OUT.h5`
  binmsh       a binary .msh, formats 4.1 and 2.2, P1 and P2 (binary_msh_mutations.py)
  h5mesh       an .h5 mesh made by `hydrosoft mesh` at the start, mutated (h5_mutations.py)
  checkpoint   a checkpoint made by a run stopped by SIGTERM at the start, mutated
               (checkpoint_mutations.py), then `--restart`
  disk         a real run whose output folder lies on a tiny tmpfs (or under a file size limit)
  interactive  `--targets -` whose client sends lines and garbage and closes its pipes
  lock         the output folder's .lock, .partial, .failed or itself a link to a victim;
               two runs at once on a folder and its .partial
  obstacle     a surface obstacle's file (obstacles: [{type: surface, file: ...}]), STL or
               OBJ, mutated by surface_mutations.py: --check
The last three are made and run by system_families.py; the decks are family_decks.py's.

A share of the cases (`--ranks-share`, drawn from a generator of its own so that the case
stays the same) runs on 2 ranks under mpiexec. Each case lives in OUT/work/<id>/: `run/` (the
run's folder, its working directory), `outside/` (where a payload that climbs out would write)
and `ompi/` (Open MPI's session folder).
"""
import os
import random
import shutil
import signal
import subprocess
import time

import classify
import system_families
from binary_msh_mutations import mutate_binary_msh
from checkpoint_mutations import mutate_checkpoint
from family_decks import CHECKPOINT_STEPS, block_deck, checkpoint_deck, h5_deck
from geo_mutations import make_geo_case
from h5_mutations import mutate_h5_mesh
from launch import finish, wait_for
from surface_mutations import mutate_surface

NAMES = ["geo", "binmsh", "h5mesh", "checkpoint", "disk", "interactive", "lock", "obstacle"]


class Context:
    """What every case of a campaign shares: the launcher, the limits, the bases."""

    def __init__(self, launcher, out, source, check_timeout, run_timeout, ranks_share):
        self.launcher, self.out, self.source = launcher, out, source
        self.check_timeout, self.run_timeout, self.ranks_share = check_timeout, run_timeout, ranks_share
        self.geo = os.path.join(source, "meshes", "block.geo")
        self.bases = {}
        self.tmpfs = False


# ---- the bases, made once at the start of a campaign ----

def unmount_leftovers(out):
    """A campaign killed in a full-disk case leaves its tmpfs mounted under OUT/work."""
    try:
        with open("/proc/mounts") as f:
            points = [line.split()[1] for line in f]
    except OSError:
        return
    work = os.path.join(out, "work") + "/"
    for point in sorted(points, reverse=True):
        if point.startswith(work):
            subprocess.run(["umount", "-l", point], stderr=subprocess.DEVNULL)


def prepare(names, ctx, base_meshes, binary_names):
    unmount_leftovers(ctx.out)
    folder = os.path.join(ctx.out, "bases")
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    b = ctx.bases
    with open(ctx.geo) as f:
        b["block_geo"] = f.read()
    with open(os.path.join(base_meshes, "block_v41.msh")) as f:
        b["mesh_text"] = f.read()
    b["binary"] = {}
    for name, order in binary_names:
        with open(os.path.join(base_meshes, name + ".msh"), "rb") as f:
            b["binary"][name] = (f.read(), order)
    if "h5mesh" in names:
        for order in (1, 2):
            _h5_base(ctx, folder, order)
    if "checkpoint" in names:
        _checkpoint_base(ctx, folder)
    if "disk" in names:
        ctx.tmpfs = _tmpfs_works(folder)
    interactive = os.path.join(ctx.source, "input", "finger_hydraulic.yaml")
    if "interactive" in names and not os.path.exists(interactive):
        raise SystemExit(f"fuzz: the interactive cases need {interactive}")
    b["interactive_deck"] = interactive


def _must(ok, what, code, err):
    if not ok:
        raise SystemExit(f"fuzz: making the bases: {what} (exit {code}):\n{err[-2000:]}")


def _h5_base(ctx, folder, order):
    deck = os.path.join(folder, f"mesh_p{order}.yaml")
    with open(deck, "w") as f:
        f.write(block_deck(ctx.geo, order=order))
    mesh = os.path.join(folder, f"mesh_p{order}.h5")
    code, _, err, _ = ctx.launcher.run(["mesh", deck, mesh], folder, folder, 1, ctx.run_timeout)
    _must(code == 0, f"hydrosoft mesh {deck}", code, err)
    run = os.path.join(folder, f"h5_p{order}.yaml")
    with open(run, "w") as f:
        f.write(h5_deck(mesh, order))
    result = os.path.join(folder, f"h5_p{order}")
    code, _, err, _ = ctx.launcher.run([run, "-q", "--set", "output.folder=" + result], folder, folder, 1,
                                       ctx.run_timeout)
    _must(code == 0, f"the run of {run}", code, err)
    with open(mesh, "rb") as f:
        ctx.bases[f"h5_p{order}"] = (mesh, f.read(), classify.last_displacement(result))


def _checkpoint_base(ctx, folder):
    """The uninterrupted run (the reference), and a run stopped by SIGTERM once its first
    checkpoint is written: its .failed holds the base checkpoint (the step it stopped at
    depends on the machine's speed; the mutations do not)."""
    deck = os.path.join(folder, "sag.yaml")  # not checkpoint.yaml: its results would be checkpoint.h5
    with open(deck, "w") as f:
        f.write(checkpoint_deck(ctx.geo))
    full = os.path.join(folder, "full")
    code, _, err, _ = ctx.launcher.run([deck, "-q", "--set", "output.folder=" + full], folder, folder, 1,
                                       ctx.run_timeout)
    _must(code == 0, "the uninterrupted checkpoint run", code, err)
    reference = classify.last_displacement(full)
    stopped = os.path.join(folder, "stopped")
    for attempt in range(5):
        shutil.rmtree(stopped + ".failed", ignore_errors=True)
        process = ctx.launcher.start([deck, "-q", "--set", "output.folder=" + stopped], folder, folder, 1)
        if wait_for(lambda: os.path.exists(stopped + ".partial/checkpoint.h5"), ctx.run_timeout):
            process.send_signal(signal.SIGTERM)
        code, _, err = finish(process, ctx.run_timeout)
        if code == 128 + signal.SIGTERM and os.path.exists(stopped + ".failed/checkpoint.h5"):
            break
        shutil.rmtree(stopped, ignore_errors=True)
    _must(code == 128 + signal.SIGTERM, "a checkpoint run stopped by SIGTERM before its end", code, err)
    with open(stopped + ".failed/checkpoint.h5", "rb") as f:
        data = f.read()
    # The unmutated checkpoint must restart to the reference, or no case can be judged.
    check = os.path.join(folder, "restarted")
    code, _, err, _ = ctx.launcher.run([deck, "--restart", stopped + ".failed", "-q", "--set",
                                        "output.folder=" + check], folder, folder, 1, ctx.run_timeout)
    _must(code == 0, "the restart of the unmutated checkpoint", code, err)
    bad = classify.displacement_defect(check, reference, 1e-12)
    _must(not bad, "the restart of the unmutated checkpoint: " + bad, code, err)
    ctx.bases["checkpoint"] = (data, stopped + ".failed", reference)


def _tmpfs_works(folder):
    probe = os.path.join(folder, "tmpfs_probe")
    os.makedirs(probe)
    try:
        done = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=16k", "tmpfs", probe],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode == 0
    except OSError:
        return False
    if done:
        subprocess.run(["umount", probe], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return done


# ---- making a case ----

def make_case(family, seed, i, ctx):
    rng = random.Random(f"{seed}/{family}/{i}")
    ranks = 2 if random.Random(f"{seed}/{family}/{i}/ranks").random() < ctx.ranks_share else 1
    case = {"id": f"{family}{i}", "family": family, "ranks": ranks, "overrides": [], "mesh": None}
    MAKERS[family](rng, case, ctx.bases)
    if family == "disk":  # where mount is refused, every case limits the file size instead
        case["use_tmpfs"] = case["use_tmpfs"] and ctx.tmpfs
        if not case["use_tmpfs"]:  # Open MPI's launcher and session files fail under a file size limit
            case["ranks"] = 1
        case["detail"] = (f"tmpfs of {case['tmpfs_kb']} KB" if case["use_tmpfs"] else
                          f"file size limit {case['fsize']} B") + f"; an earlier result of {case['filler']} B"
    case["real_run"] = case.get("mode") == "run" or family in ("disk", "interactive", "lock", "checkpoint")
    return case


def _make_geo(rng, case, bases):
    kind, detail, files, deck, main, mode, nonblocking = make_geo_case(rng, bases["block_geo"], bases["mesh_text"])
    case.update(source="block.geo", kind="geo:" + kind, detail=detail, files=files, deck=deck, main=main,
                mode=mode, nonblocking=nonblocking)
    if mode == "mesh":
        case["ranks"] = 1


def _make_binmsh(rng, case, bases):
    name = rng.choice(sorted(bases["binary"]))
    data, order = bases["binary"][name]
    kind, detail, new, expect = mutate_binary_msh(rng, data)
    case.update(source=name, kind="binmsh:" + kind, detail=detail, data=new, order=order, expect=expect,
                mode="run" if rng.random() < 0.15 else "check")


def _make_h5mesh(rng, case, bases):
    order = rng.choice([1, 1, 2])
    _, data, _ = bases[f"h5_p{order}"]
    kind, detail, new, expect = mutate_h5_mesh(rng, data)
    mode = "run" if expect == "same" or rng.random() < 0.2 else "check"
    case.update(source=f"mesh_p{order}.h5", kind="h5mesh:" + kind, detail=detail, data=new, order=order,
                expect=expect, mode=mode)


def _make_checkpoint(rng, case, bases):
    data, _, _ = bases["checkpoint"]
    kind, detail, new, expect = mutate_checkpoint(rng, data, CHECKPOINT_STEPS)
    way = rng.choice(["folder", "file", "failed", "partial"])
    case.update(source="checkpoint.h5", kind="checkpoint:" + kind, detail=f"{detail} (--restart {way})",
                data=new, expect=expect, way=way, mode="run")


def _make_obstacle(rng, case, bases):
    base, fmt, kind, detail, expect, _, ext, data = mutate_surface(rng, ["obj", "stl", "stl_binary"])
    # A surface the fluid-weight readers take may still be refused as an obstacle (a flattened
    # one has triangles without area, a scaled one coordinates beyond 1e6 m): "accept" is "any".
    case.update(source=f"{base}.{fmt}", kind="obstacle:" + kind, detail=detail, data=data, ext=ext,
                expect="reject" if expect == "reject" else "any", mode="check")


# ---- running a case ----

def case_folders(ctx, case):
    root = os.path.join(ctx.out, "work", case["id"])
    shutil.rmtree(root, ignore_errors=True)
    run, outside = os.path.join(root, "run"), os.path.join(root, "outside")
    os.makedirs(run)
    os.makedirs(outside)
    return root, run, outside


def run_case(case, ctx):
    """(class, reason, exit code, stderr, command) of one case."""
    return RUNNERS[case["family"]](case, ctx, *case_folders(ctx, case))


def _outcome(judged, code, err, command):
    cls, reason = judged
    return cls, reason, code, err, command


def _mode_argv(mode, deck, overrides=()):
    extra = [a for o in overrides for a in ("--set", o)]
    if mode == "check":
        return ["--check", deck] + extra
    if mode == "mesh":
        return ["mesh", deck, "out.h5"] + extra
    return [deck, "-q", "--set", "output.folder=results"] + extra


def _timeout(ctx, mode):
    return ctx.run_timeout if mode == "run" else ctx.check_timeout


def _run_geo(case, ctx, root, run, outside):
    os.makedirs(os.path.join(run, "sub"))
    for path, data in case["files"].items():
        with open(os.path.join(run, path), "wb") as f:
            f.write(data.replace(b"@OUTSIDE@", outside.encode()))
    with open(os.path.join(run, "deck.yaml"), "w") as f:
        f.write(case["deck"])
    before = classify.snapshot(root)
    mode = case["mode"]
    code, out, err, command = ctx.launcher.run(_mode_argv(mode, "deck.yaml"), run, root, case["ranks"],
                                               _timeout(ctx, mode))
    if case["nonblocking"]:
        time.sleep(0.3)  # a NonBlockingSystemCall's shell may still be on its way

    def allowed(p):
        return p.split("/")[0] == "ompi" or p == "run/out.h5" or p.startswith(("run/results", "run/out.h5"))

    made = classify.new_files_defect(root, before, allowed)
    if made:
        return "defect", made, code, err, command
    if code is None:
        if mode == "run":
            return "time_limit", f"still running after {ctx.run_timeout} s", None, err, command
        return "defect", f"{mode} still running after {ctx.check_timeout} s", None, err, command
    names = ["deck.yaml", "out.h5"] + sorted(set(case["files"]) | {p.rsplit("/", 1)[-1] for p in case["files"]})
    folder = os.path.join(run, "out.h5" if mode == "mesh" else "results")
    return _outcome(classify.judge_file_case(code, err, out, names, mode, folder, case["ranks"], "any"),
                    code, err, command)


def _run_mesh_file(case, ctx, run, root, name, deck, overrides, reference):
    with open(os.path.join(run, name), "wb") as f:
        f.write(case["data"])
    with open(os.path.join(run, "deck.yaml"), "w") as f:
        f.write(deck)
    mode = case["mode"]
    code, out, err, command = ctx.launcher.run(_mode_argv(mode, "deck.yaml", overrides), run, root, case["ranks"],
                                               _timeout(ctx, mode))
    if code is None:
        if mode == "run":
            return "time_limit", f"still running after {ctx.run_timeout} s", None, err, command
        return "defect", f"--check still running after {ctx.check_timeout} s", None, err, command
    judged = classify.judge_file_case(code, err, out, ["deck.yaml", name], mode, os.path.join(run, "results"),
                                      case["ranks"], case["expect"], reference)
    return _outcome(judged, code, err, command)


def _run_binmsh(case, ctx, root, run, outside):
    deck = block_deck(None, order=case["order"], file="mesh.msh")
    return _run_mesh_file(case, ctx, run, root, "mesh.msh", deck, [], None)


def _run_h5mesh(case, ctx, root, run, outside):
    base, _, reference = ctx.bases[f"h5_p{case['order']}"]
    deck = h5_deck(base, case["order"])
    return _run_mesh_file(case, ctx, run, root, "mesh.h5", deck, ["mesh.file=mesh.h5"], reference)


def _run_obstacle(case, ctx, root, run, outside):
    name = "surface." + case["ext"]
    deck = (block_deck(ctx.geo) + f"obstacles:\n  - {{name: cup, type: surface, file: {name}}}\n"
            "contact: {surfaces: [top]}\n")
    return _run_mesh_file(case, ctx, run, root, name, deck, [], None)


def _run_checkpoint(case, ctx, root, run, outside):
    _, stopped, reference = ctx.bases["checkpoint"]
    way = case["way"]
    if way in ("failed", "partial"):  # the folder of a run stopped by a signal, or killed
        source = "results." + way
        shutil.copytree(stopped, os.path.join(run, source))
        target = os.path.join(run, source, "checkpoint.h5")
    else:
        source = "ckpt" if way == "folder" else "ckpt/checkpoint.h5"
        os.makedirs(os.path.join(run, "ckpt"))
        target = os.path.join(run, "ckpt", "checkpoint.h5")
    with open(target, "wb") as f:
        f.write(case["data"])
    with open(os.path.join(run, "deck.yaml"), "w") as f:
        f.write(checkpoint_deck(ctx.geo))
    argv = ["deck.yaml", "--restart", source, "-q", "--set", "output.folder=results"]
    code, out, err, command = ctx.launcher.run(argv, run, root, case["ranks"], ctx.run_timeout)
    if code is None:
        return "defect", f"restart still running after {ctx.run_timeout} s", None, err, command
    results = os.path.join(run, "results")
    names = ["deck.yaml", "checkpoint.h5", source, "results"]
    cls, reason = classify.judge_file_case(code, err, out, names, "run", results, case["ranks"], case["expect"],
                                           reference)
    if cls == "accepted":
        summary = classify.read_json(os.path.join(results, "summary.json"))
        if "restarted_from" not in summary:
            cls, reason = "defect", "a restarted run's summary.json without restarted_from"
        elif case["expect"] == "same" and summary.get("steps") != CHECKPOINT_STEPS:
            cls, reason = "defect", f"the restarted run counts {summary.get('steps')} steps, not {CHECKPOINT_STEPS}"
    return cls, reason, code, err, command


MAKERS = {"geo": _make_geo, "binmsh": _make_binmsh, "h5mesh": _make_h5mesh, "checkpoint": _make_checkpoint,
          "disk": system_families.make_disk, "interactive": system_families.make_interactive,
          "lock": system_families.make_lock, "obstacle": _make_obstacle}
RUNNERS = {"geo": _run_geo, "binmsh": _run_binmsh, "h5mesh": _run_h5mesh, "checkpoint": _run_checkpoint,
           "disk": system_families.run_disk, "interactive": system_families.run_interactive,
           "lock": system_families.run_lock, "obstacle": _run_obstacle}
