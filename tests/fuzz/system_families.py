"""The families of families.py that put a run's surroundings to the test rather than its
input files: a full disk under its output folder, an interactive client that closes its pipes,
output folders whose lock, staging or failed folder is a link, two runs at once."""
import os
import shutil
import subprocess
import time

import classify
from family_decks import FAIL_TIME, block_deck, checkpoint_deck
from launch import Pipes, finish, kill_group, wait_for


def make_disk(rng, case, bases):
    deck = rng.choice(["one", "steps", "checkpoint"])
    tmpfs_kb = rng.choice([8, 16, 32, 64, 128, 256, 512, 1024, 2048])
    fsize = rng.choice([1024, 4096, 16384, 65536, 262144, 1048576])
    filler = rng.choice([0, 0, 4096, 32768, 200000])
    case.update(source=deck, kind="disk:" + deck, deck_kind=deck, tmpfs_kb=tmpfs_kb, fsize=fsize, filler=filler,
                use_tmpfs=rng.random() < 0.7, earlier=rng.randrange(10**9), mode="run")


TARGET_Z = [-0.012, -0.003, 0.010, -0.0175, -0.008, -0.030]
GARBAGE = [b"abc", b"", b"   ", b"nan 0 0", b"1e999 0 0", b"0.09 0", b"0.09 0 1e300", b"unknown 0.09 0 0",
           b"\x00\x01\x02", b"\xff\xfe 0 0", b"0.09\t0\t-0.01", b"\r", b"x" * 5000, b"1 2 3 4 5", b"-0 -0 -0"]


def make_interactive(rng, case, bases):
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
    case.update(source="finger_hydraulic.yaml", kind="interactive:" + ending, plan=plan, mode="run",
                detail=" ".join(a[0] + ("" if len(a) == 1 else f"({a[1]!r:.30})") for a in plan)[:300])


LOCK_KINDS = ["lock_to_file", "lock_dangling", "lock_to_folder", "lock_fifo", "lock_folder", "partial_to_folder",
              "failed_to_folder", "folder_to_folder", "stale_partial", "concurrent_partial", "concurrent_same",
              "concurrent_reversed"]


def make_lock(rng, case, bases):
    kind = rng.choice(LOCK_KINDS)
    case.update(source="block.geo", kind="lock:" + kind, lock_kind=kind, marked=rng.random() < 0.7,
                fails=kind == "failed_to_folder" or rng.random() < 0.15, victim=rng.randrange(10**9), mode="run",
                detail=kind)


def _earlier_result(folder, case):
    """A good result of an earlier run in `folder`, hydrosoft's marker in it."""
    os.makedirs(folder)
    with open(os.path.join(folder, ".hydrosoft_output"), "w") as f:
        f.write("Written by hydrosoft. The next run with this output folder replaces the folder.\n")
    with open(os.path.join(folder, "summary.json"), "w") as f:
        f.write('{"status": "ok", "earlier": %d}\n' % case["earlier"])
    with open(os.path.join(folder, "filler.bin"), "wb") as f:
        f.write(bytes(case["filler"]))


def run_disk(case, ctx, root, run, outside):
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
        ranks = case["ranks"] if tmpfs else 1  # Open MPI's launcher fails under a file size limit
        code, out, err, command = ctx.launcher.run(argv, run, root, ranks, ctx.run_timeout,
                                                   file_size=None if tmpfs else case["fsize"])
        judged = classify.judge_full_disk(code, err, ranks, disk, "results", earlier, code is None)
        if judged[0] == "defect":  # the tmpfs goes with its mount: keep a copy as the reproducer's
            shutil.copytree(disk, os.path.join(root, "disk_after"), symlinks=True)
        how = (f"# first: mount -t tmpfs -o size={case['tmpfs_kb']}k tmpfs disk (and an earlier result in disk/results)"
               if tmpfs else f"# first: trap '' XFSZ; ulimit -f {case['fsize'] // 1024} (and an earlier result in disk/results)")
        return judged[0], judged[1], code, err, command + [how]
    finally:
        if tmpfs:
            if subprocess.run(["umount", disk], stderr=subprocess.DEVNULL).returncode != 0:
                subprocess.run(["umount", "-l", disk], stderr=subprocess.DEVNULL)


def run_interactive(case, ctx, root, run, outside):
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


def run_lock(case, ctx, root, run, outside):
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
        return judged_outcome(classify.judge_lock(runs, run, victims, marker), code, err, command)
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
    return judged_outcome(classify.judge_lock(runs, run, victims, marker), code1 if code1 else code2, err, command)


def judged_outcome(judged, code, err, command):
    return judged[0], judged[1], code, err, command
