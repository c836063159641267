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
from binary_msh_mutations import mutate_binary_msh
from checkpoint_mutations import mutate_checkpoint
from geo_mutations import make_geo_case
from h5_mutations import mutate_h5_mesh
from launch import Pipes, finish, kill_group, wait_for

NAMES = ["geo", "binmsh", "h5mesh", "checkpoint", "disk", "interactive", "lock"]
CHECKPOINT_STEPS = 20

BLOCK = """mesh:
  file: {file}
{order}{parameters}materials:
  - {{group: body, model: neo_hookean, E: {E}, nu: 0.3, density: 1000}}
boundary:
  - {{group: bottom}}
loads:
  gravity: [0, 0, -9.81]
{pressure}time: {time}
solver: {{preset: mumps}}
{output}"""


def block_deck(geo, h=0.5, order=1, E="1.0e6", pressure="", time="{type: static, steps: 1}", output="", file=None):
    parameters = f"  parameters: {{h: {h}}}\n" if file is None else ""
    order = f"  order: {order}\n" if order else ""  # an .h5 mesh has the order it was meshed at
    return BLOCK.format(file=file or geo, order=order, parameters=parameters, E=E, pressure=pressure, time=time,
                        output=output)


def checkpoint_deck(geo):
    """A block that sags in 20 load steps, a checkpoint after each."""
    return block_deck(geo, h=0.2, E="2.0e5", time=f"{{type: static, steps: {CHECKPOINT_STEPS}}}",
                      output="output:\n  checkpoint: {every: 1}\n")


def h5_deck(mesh, order):
    """The .h5 cases' deck: a pressure on the top face, so that a face's orientation matters."""
    return block_deck(None, order=None, file=mesh, pressure="  pressure:\n    - {group: top, value: 2.0e4}\n")


FAIL_TIME = "{type: static, steps: 3, schedule: [0.5, 1.0, 1000], max_cutbacks: 0}"  # step 3 inverts


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
    globals()["_make_" + family](rng, case, ctx.bases)
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


def _make_disk(rng, case, bases):
    deck = rng.choice(["one", "steps", "checkpoint"])
    tmpfs_kb = rng.choice([8, 16, 32, 64, 128, 256, 512, 1024, 2048])
    fsize = rng.choice([1024, 4096, 16384, 65536, 262144, 1048576])
    filler = rng.choice([0, 0, 4096, 32768, 200000])
    case.update(source=deck, kind="disk:" + deck, deck_kind=deck, tmpfs_kb=tmpfs_kb, fsize=fsize, filler=filler,
                use_tmpfs=rng.random() < 0.7, earlier=rng.randrange(10**9), mode="run")


TARGET_Z = [-0.012, -0.003, 0.010, -0.0175, -0.008, -0.030]
GARBAGE = [b"abc", b"", b"   ", b"nan 0 0", b"1e999 0 0", b"0.09 0", b"0.09 0 1e300", b"unknown 0.09 0 0",
           b"\x00\x01\x02", b"\xff\xfe 0 0", b"0.09\t0\t-0.01", b"\r", b"x" * 5000, b"1 2 3 4 5", b"-0 -0 -0"]


def _make_interactive(rng, case, bases):
    """A script: send lines (targets, garbage), read some answers, sleep, and close stdin or
    stdout (or both, or neither until the end) at a random point, often mid-step."""
    plan, sent = [], 0
    for _ in range(rng.randint(1, 6)):
        if rng.random() < 0.7:
            z = rng.choice(TARGET_Z) + rng.uniform(-0.002, 0.002)
            line = (f"tip 0.09 0 {z:.5f}" if rng.random() < 0.3 else f"0.09 0 {z:.5f}").encode()
        elif rng.random() < 0.9:
            line = rng.choice(GARBAGE)
        else:
            line = bytes(rng.randrange(1, 256) for _ in range(rng.randint(1, 300))).replace(b"\n", b" ")
        plan.append(("send", line + b"\n"))
        sent += 1
        if rng.random() < 0.6:
            plan.append(("read", sent))
    ending = rng.choice(["stdin", "stdout", "stdout_then_stdin", "both", "stdin_mid", "partial_line"])
    pause = round(rng.uniform(0.0, 0.08), 3)
    if ending == "stdin_mid":  # one more target, and stdin closed while it is being solved
        plan += [("send", b"0.09 0 -0.010\n"), ("sleep", pause), ("close_stdin",)]
        sent += 1
    elif ending == "partial_line":  # a last line without its newline
        plan += [("send", b"0.09 0 -0.011"), ("close_stdin",)]
        sent += 1
    elif ending == "stdout":  # stops reading, keeps sending, then ends the input
        plan += [("sleep", pause), ("close_stdout",), ("send", b"0.09 0 -0.009\n"), ("send", b"0.09 0 -0.02\n"),
                 ("sleep", pause), ("close_stdin",)]
    elif ending == "stdout_then_stdin":
        plan += [("send", b"0.09 0 -0.013\n"), ("sleep", pause), ("close_stdout",), ("sleep", pause), ("close_stdin",)]
    elif ending == "both":
        plan += [("send", b"0.09 0 -0.014\n"), ("sleep", pause), ("close_stdout",), ("close_stdin",)]
    else:
        plan += [("sleep", pause), ("close_stdin",)]
        sent += 0
    case.update(source="finger_hydraulic.yaml", kind="interactive:" + ending, plan=plan, mode="run",
                detail=" ".join(a[0] + ("" if len(a) == 1 else f"({a[1]!r:.30})") for a in plan)[:300])


LOCK_KINDS = ["lock_to_file", "lock_dangling", "lock_to_folder", "lock_fifo", "lock_folder", "partial_to_folder",
              "failed_to_folder", "folder_to_folder", "stale_partial", "concurrent_partial", "concurrent_same",
              "concurrent_reversed"]


def _make_lock(rng, case, bases):
    kind = rng.choice(LOCK_KINDS)
    case.update(source="block.geo", kind="lock:" + kind, lock_kind=kind, marked=rng.random() < 0.7,
                fails=kind == "failed_to_folder" or rng.random() < 0.15, victim=rng.randrange(10**9), mode="run",
                detail=kind)


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
    return globals()["_run_" + case["family"]](case, ctx, *case_folders(ctx, case))


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


def _earlier_result(folder, case):
    """A good result of an earlier run in `folder`, hydrosoft's marker in it."""
    os.makedirs(folder)
    with open(os.path.join(folder, ".hydrosoft_output"), "w") as f:
        f.write("Written by hydrosoft. The next run with this output folder replaces the folder.\n")
    with open(os.path.join(folder, "summary.json"), "w") as f:
        f.write('{"status": "ok", "earlier": %d}\n' % case["earlier"])
    with open(os.path.join(folder, "filler.bin"), "wb") as f:
        f.write(bytes(case["filler"]))


def _run_disk(case, ctx, root, run, outside):
    disk = os.path.join(run, "disk")
    os.makedirs(disk)
    tmpfs = case["use_tmpfs"]
    if tmpfs and subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={case['tmpfs_kb']}k", "tmpfs", disk],
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode != 0:
        tmpfs = False
    try:
        try:
            _earlier_result(os.path.join(disk, "results"), case)
        except OSError:  # it does not fit: an empty earlier folder then
            shutil.rmtree(os.path.join(disk, "results"), ignore_errors=True)
            os.makedirs(os.path.join(disk, "results"))
        earlier = classify.tree_digest(os.path.join(disk, "results"))
        kind = case["deck_kind"]
        deck = {"one": block_deck(ctx.geo), "steps": block_deck(ctx.geo, h=0.2, E="2.0e5", time="{type: static, steps: 20}"),
                "checkpoint": checkpoint_deck(ctx.geo)}[kind]
        with open(os.path.join(run, "deck.yaml"), "w") as f:
            f.write(deck)
        argv = ["deck.yaml", "-q", "--set", "output.folder=disk/results"]
        code, out, err, command = ctx.launcher.run(argv, run, root, case["ranks"], ctx.run_timeout,
                                                   file_size=None if tmpfs else case["fsize"])
        judged = classify.judge_full_disk(code, err, case["ranks"], disk, "results", earlier, code is None)
        if judged[0] == "defect":  # the tmpfs goes with its mount: keep a copy as the reproducer's
            shutil.copytree(disk, os.path.join(root, "disk_after"), symlinks=True)
        how = (f"# first: mount -t tmpfs -o size={case['tmpfs_kb']}k tmpfs disk (and an earlier result in disk/results)"
               if tmpfs else f"# first: trap '' XFSZ; ulimit -f {case['fsize'] // 1024} (and an earlier result in disk/results)")
        return judged[0], judged[1], code, err, command + [how]
    finally:
        if tmpfs:
            if subprocess.run(["umount", disk], stderr=subprocess.DEVNULL).returncode != 0:
                subprocess.run(["umount", "-l", disk], stderr=subprocess.DEVNULL)


def _run_interactive(case, ctx, root, run, outside):
    argv = [ctx.bases["interactive_deck"], "--targets", "-", "-q", "--set", "mesh.parameters.h=0.006",
            "--set", "control.steps_per_target=1", "--set", "output.folder=results"]
    with open(os.path.join(root, "stderr.txt"), "wb") as err_file:
        process = ctx.launcher.start(argv, run, root, case["ranks"], stdin=subprocess.PIPE, stderr=err_file)
        pipes = Pipes(process)
        sent, closed_stdout = 0, False
        for action in case["plan"]:
            if action[0] == "send":
                sent += pipes.send(action[1]) and 1
            elif action[0] == "read":
                pipes.wait_answers(action[1], ctx.run_timeout)
            elif action[0] == "sleep":
                time.sleep(action[1])
            elif action[0] == "close_stdin":
                pipes.close_stdin()
            elif action[0] == "close_stdout":
                pipes.close_stdout()
                closed_stdout = True
        pipes.close_stdin()
        end = time.monotonic() + ctx.run_timeout
        while pipes.stdout is not None and time.monotonic() < end and pipes.pump(0.1):
            pass
        timed_out = False
        try:
            process.wait(timeout=max(1.0, end - time.monotonic()))
        except subprocess.TimeoutExpired:
            kill_group(process)
            process.wait()
            timed_out = True
    pipes.close_stdout()
    with open(os.path.join(root, "stderr.txt"), encoding="utf-8", errors="replace") as f:
        err = f.read()
    answers = pipes.answers + ([pipes.buffer.decode("utf-8", "replace")] if pipes.buffer else [])
    judged = classify.judge_interactive(process.returncode, err, answers, sent, closed_stdout, run, "results",
                                        case["ranks"], timed_out)
    return judged[0], judged[1], process.returncode, err, process.command + ["# the client: " + case["detail"]]


def _run_lock(case, ctx, root, run, outside):
    kind = case["lock_kind"]
    # Two runs at once both take a few seconds: the first commits while the second still writes.
    long = block_deck(ctx.geo, h=0.15, E="2.0e5", time="{type: static, steps: 300}", output="output:\n  every: 10\n")
    with open(os.path.join(run, "deck.yaml"), "w") as f:
        f.write(long if kind.startswith("concurrent") else block_deck(ctx.geo, time=FAIL_TIME) if case["fails"]
                else block_deck(ctx.geo))
    with open(os.path.join(run, "other.yaml"), "w") as f:
        f.write(long)
    victim_file = os.path.join(run, "victim.txt")
    with open(victim_file, "w") as f:
        f.write(f"a file that is not the run's: {case['victim']}\n")
    victim_folder = os.path.join(run, "victim")
    os.makedirs(victim_folder)
    with open(os.path.join(victim_folder, "data.txt"), "w") as f:
        f.write(f"a folder that is not the run's: {case['victim']}\n")
    if case["marked"]:  # it even looks like an output folder
        with open(os.path.join(victim_folder, ".hydrosoft_output"), "w") as f:
            f.write("Written by hydrosoft. The next run with this output folder replaces the folder.\n")
    marker = None
    results = os.path.join(run, "results")
    if kind == "lock_to_file":
        os.symlink("victim.txt", results + ".lock")
    elif kind == "lock_dangling":
        marker = os.path.join(outside, "MARKER_lock")
        os.symlink(marker, results + ".lock")
    elif kind == "lock_to_folder":
        os.symlink("victim", results + ".lock")
    elif kind == "lock_fifo":
        os.mkfifo(results + ".lock")
    elif kind == "lock_folder":
        os.makedirs(results + ".lock")
    elif kind in ("partial_to_folder", "failed_to_folder", "folder_to_folder"):
        name = {"partial_to_folder": ".partial", "failed_to_folder": ".failed", "folder_to_folder": ""}[kind]
        os.symlink("victim", results + name)
    elif kind == "stale_partial":
        os.makedirs(results + ".partial")
        with open(os.path.join(results + ".partial", ".hydrosoft_output"), "w") as f:
            f.write("Written by hydrosoft.\n")
    victims = {victim_file: classify.tree_digest(victim_file), victim_folder: classify.tree_digest(victim_folder)}
    argv = ["deck.yaml", "-q", "--set", "output.folder=results"]
    if not kind.startswith("concurrent"):
        code, out, err, command = ctx.launcher.run(argv, run, root, case["ranks"], ctx.run_timeout)
        runs = [("deck", code, err, "results", case["ranks"], code is None)]
        return _outcome(classify.judge_lock(runs, run, victims, marker), code, err, command)
    # Two runs at once: the long one first, the second once the first has its staging folder.
    first_out, second_out = {"concurrent_partial": ("results", "results.partial"),
                             "concurrent_same": ("results", "results"),
                             "concurrent_reversed": ("results.partial", "results")}[kind]
    first = ctx.launcher.start(["other.yaml", "-q", "--set", "output.folder=" + first_out], run, root, case["ranks"])
    wait_for(lambda: os.path.exists(os.path.join(run, first_out + ".partial", "other.h5")) or first.poll() is not None,
             ctx.run_timeout)
    second = ctx.launcher.start(["deck.yaml", "-q", "--set", "output.folder=" + second_out], run, root, 1)
    code2, _, err2 = finish(second, ctx.run_timeout)
    code1, _, err1 = finish(first, ctx.run_timeout)
    runs = [("other", code1, err1, first_out, case["ranks"], code1 is None),
            ("deck", code2, err2, second_out, 1, code2 is None)]
    err = f"--- first run (other.yaml -> {first_out}), exit {code1}:\n{err1}\n--- second run (deck.yaml -> {second_out}), exit {code2}:\n{err2}"
    command = first.command + ["&"] + second.command
    return _outcome(classify.judge_lock(runs, run, victims, marker), code1 if code1 else code2, err, command)
