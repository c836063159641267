"""Runs one mutated case of hydrosoft and says which class its outcome is in.

accepted   exit 0 (and, for a real run, every number of its results finite)
rejected   exit 1 or 2 (3 for a real run that fails to converge) with ONE line on standard
           error, `hydrosoft: error: FILE: KEY: reason (line N)`, FILE the deck or the mesh;
           a failed run adds one indented line on what it kept, and warnings may come before
time_limit a real run still going at its time limit (a valid deck may ask for many steps)
defect     anything else: a signal, an abort, exit 4 (an exception that is not an input
           error), a PETSc error dump, several lines of error, a message that does not start
           with its file, exit 0 with a NaN in the results, --check past its time limit, the
           memory limit
"""
import json
import math
import os
import re
import resource
import subprocess

# Lines a clean refusal may print beside its one error line.
BENIGN_PREFIXES = ("hydrosoft: warning:", "hydrosoft: step ")
# Words of an exception's own text that reached the user instead of a reason.
LIBRARY_TEXTS = ("[json.exception", "bad_alloc", "basic_string", "std::", "terminate called", "what():")
# The line a failed run (exit 3) adds under its error: what it kept of its steps.
KEPT_LINE = re.compile(r"  (no step had converged: nothing was kept"
                       r"|the \d+ converged output steps are in .+"
                       r"|a checkpoint to restart from is in .+)$")


def _limit_memory(megabytes):
    """Limits the address space (none for 0: a sanitized build reserves terabytes of it)."""

    def apply():
        if megabytes > 0:
            limit = megabytes * 1024 * 1024
            resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))

    return apply


def _non_finite_in_results(folder):
    """A description of the first non-finite number in summary.json or the .h5, or ''."""
    summary = os.path.join(folder, "summary.json")
    if not os.path.exists(summary):
        return "no summary.json"
    with open(summary) as f:
        text = f.read()
    try:
        data = json.loads(text, parse_constant=lambda c: float("nan"))
    except ValueError as e:
        return f"summary.json is not JSON: {e}"

    def walk(node, path):
        if isinstance(node, float) and not math.isfinite(node):
            return path
        items = node.items() if isinstance(node, dict) else enumerate(node) if isinstance(node, list) else []
        for k, v in items:
            found = walk(v, f"{path}.{k}")
            if found:
                return found
        return ""

    found = walk(data, "summary")
    if found:
        return f"{found} is not finite"
    try:
        import h5py
        import numpy
    except ImportError:
        return ""
    for name in os.listdir(folder):
        if name.endswith(".h5"):
            bad = []

            def visit(path, obj):
                if isinstance(obj, h5py.Dataset) and obj.dtype.kind == "f" and not bad:
                    if not numpy.isfinite(obj[()]).all():
                        bad.append(path)

            with h5py.File(os.path.join(folder, name), "r") as h5:
                h5.visititems(visit)
            if bad:
                return f"{name}:{bad[0]} holds a non-finite number"
    return ""


def classify(returncode, stderr, files, real_run, results_folder):
    """(class, reason) of one finished case."""
    lines = [l for l in stderr.splitlines() if l.strip()]
    errors = [l for l in lines if l.startswith("hydrosoft: error:")]
    noise = [l for l in lines if not l.startswith(BENIGN_PREFIXES) and l not in errors]
    if returncode == 3 and len(errors) == 1 and lines[-1] != errors[0]:
        if lines[-2] == errors[0] and KEPT_LINE.match(lines[-1]):
            noise.remove(lines[-1])
    if returncode < 0:
        return "defect", f"signal {-returncode}"
    if any("PETSC ERROR" in l for l in lines):
        return "defect", "PETSc error dump"
    if returncode == 0:
        if real_run:
            bad = _non_finite_in_results(results_folder)
            if bad:
                return "defect", f"exit 0 but {bad}"
        return "accepted", ""
    clean_codes = (1, 2, 3) if real_run else (1, 2)
    if returncode not in clean_codes:
        return "defect", f"exit {returncode}: " + (errors[0] if errors else (lines or [""])[-1])[:300]
    if len(errors) != 1 or noise:
        return "defect", f"{len(errors)} error lines and {len(noise)} other lines on stderr"
    message = errors[0][len("hydrosoft: error: ") :]
    if any(text in message for text in LIBRARY_TEXTS):
        return "defect", "a library's exception, not a reason: " + message[:300]
    # FILE: KEY: reason (line N), or FILE: reason: the message starts with the file it is about.
    if not names_a_file(message, files):
        return "defect", "the message does not start with the file: " + message[:300]
    return "rejected", ""


def names_a_file(message, files):
    """Whether an error message starts with one of `files` (or a path ending in one, or a path
    inside a folder of them, or `output folder 'F'`, or `--restart: F`)."""
    if message.startswith("--restart: "):
        message = message[len("--restart: ") :]
    if ": " not in message:
        return False
    head = message.split(": ", 1)[0]
    for f in files:
        if head == f or head.endswith("/" + f) or head.startswith(f + "/") or "/" + f + "/" in head:
            return True
        if head == f"output folder '{f}'" or (head.startswith("output folder '") and head.endswith("/" + f + "'")):
            return True
    return False


def run_case(hydrosoft, deck, overrides, files, real_run, work, timeout, memory_mb):
    """Runs one case in `work`; returns (class, reason, exit code, stderr)."""
    command = [hydrosoft] + ([] if real_run else ["--check"]) + [deck]
    for o in overrides:
        command += ["--set", o]
    results = os.path.join(work, "results")
    if real_run:
        command += ["-q", "--set", "output.folder=" + results]
    # Isolated singleton: no Open MPI daemon started for each of thousands of short processes.
    # Each case gets its own Open MPI session folder: singletons started at once share
    # /tmp/ompi.<host>.<uid>, and one that removes it as it ends makes another's orte_init fail
    # (seen with 16 jobs: 42 of 5,000 cases).
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", OMPI_MCA_ess_singleton_isolated="1",
               OMPI_MCA_orte_tmpdir_base=work)
    try:
        p = subprocess.run(command, cwd=work, env=env, stdin=subprocess.DEVNULL,
                           stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, timeout=timeout,
                           preexec_fn=_limit_memory(memory_mb))
    except subprocess.TimeoutExpired as e:
        stderr = (e.stderr or b"").decode("utf-8", "replace")
        if real_run:
            return "time_limit", f"still running after {timeout} s", None, stderr, command
        return "defect", f"--check still running after {timeout} s", None, stderr, command
    stderr = p.stderr.decode("utf-8", "replace")
    cls, reason = classify(p.returncode, stderr, files, real_run, results)
    return cls, reason, p.returncode, stderr, command


# ---- the fluidweight executable's cases (surface files) ----

SURFACE_MEMORY_FLOOR_MB = 256
SURFACE_MEMORY_PER_BYTE = 50
# The executable starts a worker thread a core (idle for small surfaces), each with an 8 MB
# stack reserved: address space that does not grow with the file.
THREAD_STACK_MB = 8


def surface_memory_mb(file_bytes):
    """The address-space limit of one surface case: max(256 MB, 50 x the file) + the stacks."""
    per_file = -(-SURFACE_MEMORY_PER_BYTE * file_bytes // (1024 * 1024))
    return max(SURFACE_MEMORY_FLOOR_MB, per_file) + THREAD_STACK_MB * (os.cpu_count() or 1)


def classify_surface(returncode, stdout, stderr, file, expect, volume):
    """(class, reason) of one fluidweight run on `file`.

    accepted   exit 0, one JSON object with finite volumes and weight; where the mutation
               keeps the volume known, the volume it encloses
    rejected   exit 1 with ONE line on standard error, `fluidweight: error: FILE...: reason`
    defect     anything else, and an accepted case that had to be refused (an open surface, a
               NaN coordinate: a weight printed for it would be wrong) or the reverse
    """
    lines = [l for l in stderr.splitlines() if l.strip()]
    if returncode < 0:
        return "defect", f"signal {-returncode}"
    if returncode == 0:
        try:
            result = json.loads(stdout)
        except ValueError:
            return "defect", "exit 0 without one JSON object on standard output"
        for key in ("signed_volume", "volume", "total_weight"):
            if not isinstance(result.get(key), (int, float)):  # NaN and inf print as null
                return "defect", f"exit 0 but {key} is {result.get(key)}"
        if lines:
            return "defect", f"exit 0 with {len(lines)} lines on stderr: {lines[0][:200]}"
        if expect == "reject":
            return "defect", (f"accepted what must be refused: volume {result['volume']}, "
                              f"weight {result['total_weight']}")
        if volume is not None:
            tolerance = 1e-6 * abs(volume) if volume else 1e-12
            if abs(abs(result["signed_volume"]) - abs(volume)) > tolerance:
                return "defect", f"signed volume {result['signed_volume']}, expected +-{volume}"
            if abs(result["volume"] - abs(volume)) > max(0.01 * abs(volume), tolerance):
                return "defect", f"column volume {result['volume']}, expected {abs(volume)}"
        return "accepted", ""
    if returncode != 1:
        return "defect", f"exit {returncode}: " + (lines[-1] if lines else "")[:300]
    if len(lines) != 1 or not lines[0].startswith("fluidweight: error: "):
        return "defect", f"{len(lines)} lines on stderr: " + " | ".join(lines)[:300]
    message = lines[0][len("fluidweight: error: "):]
    if "bad_alloc" in message:
        return "defect", "the memory limit: " + message[:300]
    # FILE:LINE: reason or FILE: reason (the element or facet inside the reason).
    if not (message.startswith(file + ":") and len(message) > len(file) + 3):
        return "defect", "the message does not start with the file: " + message[:300]
    if expect == "accept":
        return "defect", "refused a valid surface: " + message[:300]
    return "rejected", ""


def run_surface_case(fluidweight, file, work, timeout, expect, volume):
    """Runs `fluidweight FILE --json` in `work`; returns (class, reason, exit, stderr, command)."""
    command = [fluidweight, file, "--json"]
    size = os.path.getsize(os.path.join(work, file))
    try:
        p = subprocess.run(command, cwd=work, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, timeout=timeout,
                           preexec_fn=_limit_memory(surface_memory_mb(size)))
    except subprocess.TimeoutExpired as e:
        return "defect", f"still running after {timeout} s", None, (e.stderr or b"").decode("utf-8", "replace"), command
    stdout = p.stdout.decode("utf-8", "replace")
    stderr = p.stderr.decode("utf-8", "replace")
    cls, reason = classify_surface(p.returncode, stdout, stderr, file, expect, volume)
    return cls, reason, p.returncode, stderr + ("\n--- stdout\n" + stdout if stdout else ""), command


# ---- the families of issue 29 (families.py): files a run must not make, folders it must keep ----

# Lines that Open MPI's launcher adds when a rank ends with a non-zero status: framed by dashes.
_DASHES = re.compile(r"^-{20,}$")
_ORTE_NOTE = re.compile(r"^\[[^\]\s]+:\d+\] ")
_RANK_SIGNAL = re.compile(r"exited on signal (\d+)")
_ABORT_CODE = re.compile(r"MPI_ABORT was invoked on rank \d+ in communicator \S+\s+with errorcode (\d+)")


def split_launcher(stderr):
    """(the ranks' own standard error, the launcher's banners) of a run under mpiexec."""
    own, banner, inside = [], [], False
    for line in stderr.splitlines():
        if _DASHES.match(line.strip()):
            inside = not inside
            banner.append(line)
        elif inside or _ORTE_NOTE.match(line):
            banner.append(line)
        else:
            own.append(line)
    return "\n".join(own) + "\n", "\n".join(banner)


def classify_ranks(returncode, stderr, files, real_run, results_folder, ranks):
    """classify() for a run on `ranks` ranks: the launcher's banners are its own, but a rank
    that died of a signal, or aborted with an error code that is not an input's, is a defect."""
    if ranks > 1:
        stderr, banner = split_launcher(stderr)
        died = _RANK_SIGNAL.search(banner)
        if died:
            return "defect", f"a rank died of signal {died.group(1)}"
        aborted = _ABORT_CODE.search(" ".join(banner.split()))
        if aborted and int(aborted.group(1)) not in (1, 2, 3):
            return "defect", f"MPI_Abort with error code {aborted.group(1)}"
    return classify(returncode, stderr, files, real_run, results_folder)


def snapshot(root):
    """Every path under `root` (files, folders, links), relative to it."""
    found = set()
    for folder, dirs, names in os.walk(root):
        for name in dirs + names:
            found.add(os.path.relpath(os.path.join(folder, name), root))
    return found


def new_files_defect(root, before, allowed):
    """A defect's reason for a file a run made that it had no business making, or ''.

    A name with MARKER is one a payload makes (a shell command, Printf > file, Save): the run
    reached the system. Any other new path under `root` that `allowed` (a function of the
    relative path) does not expect is a file left behind (gmsh's unzipped copy, an .opt it
    saved, ...)."""
    made = sorted(p for p in snapshot(root) - before if not allowed(p))
    markers = [p for p in made if "MARKER" in p]
    if markers:
        return "reached the system: " + ", ".join(markers)[:300]
    if made:
        return "left a file: " + ", ".join(made)[:300]
    return ""


def read_json(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.loads(f.read(), parse_constant=lambda c: float("nan"))
    except (OSError, ValueError):
        return None


def xmf_steps(folder):
    """The number of step grids the folder's .xmf names, or None without one."""
    for name in sorted(os.listdir(folder)):
        if name.endswith(".xmf"):
            with open(os.path.join(folder, name), encoding="utf-8", errors="replace") as f:
                return len(re.findall(r'<Grid Name="step_\d+"', f.read()))
    return None


def h5_steps(folder):
    """The step groups of the folder's result .h5 (the checkpoint aside), or None if it cannot
    be read with h5_layout (no such file, a layout it does not know)."""
    from h5_layout import H5Layout, H5LayoutError

    for name in sorted(os.listdir(folder)):
        if name.endswith(".h5") and name != "checkpoint.h5":
            try:
                with open(os.path.join(folder, name), "rb") as f:
                    layout = H5Layout(f.read())
            except (H5LayoutError, ValueError, IndexError, OSError):
                return None
            return sorted(int(g[len("/step_") :]) for g in layout.groups if re.fullmatch(r"/step_\d+", g))
    return None


def folder_defect(folder, status):
    """A reason why a results folder is not the whole result its summary says, or ''."""
    summary = read_json(os.path.join(folder, "summary.json"))
    if summary is None:
        return f"{os.path.basename(folder)}: no readable summary.json"
    if summary.get("status") != status:
        return f"{os.path.basename(folder)}: status {summary.get('status')!r}, expected {status!r}"
    bad = _non_finite_in_results(folder)
    if bad:
        return f"{os.path.basename(folder)}: {bad}"
    outputs = summary.get("outputs")
    grids = xmf_steps(folder)
    if grids != outputs:
        return f"{os.path.basename(folder)}: the .xmf names {grids} steps, summary.json's outputs {outputs}"
    steps = h5_steps(folder)
    if steps is not None and steps != list(range(len(steps))) or (steps is not None and len(steps) != outputs):
        return f"{os.path.basename(folder)}: the .h5 holds steps {steps[:5]}..., summary.json's outputs {outputs}"
    return ""


def last_displacement(folder):
    """{node id: (ux, uy, uz)} of the last step of the folder's result .h5, or None."""
    from h5_layout import H5Layout, H5LayoutError, read_rows

    for name in sorted(os.listdir(folder)):
        if name.endswith(".h5") and name != "checkpoint.h5":
            try:
                with open(os.path.join(folder, name), "rb") as f:
                    data = f.read()
                layout = H5Layout(data)
                steps = [int(g[len("/step_") :]) for g in layout.groups if re.fullmatch(r"/step_\d+", g)]
                u = read_rows(data, layout.datasets[f"/step_{max(steps)}/displacement"])
                ids = read_rows(data, layout.datasets["/mesh/node_ids"])
            except (H5LayoutError, ValueError, KeyError, IndexError, OSError):
                return None
            return {i: tuple(u[3 * k : 3 * k + 3]) for k, i in enumerate(ids)}
    return None


def displacement_defect(folder, reference, tolerance):
    """'' if the folder's last displacements equal `reference` to `tolerance` x its largest."""
    u = last_displacement(folder)
    if u is None:
        return "the result's .h5 cannot be read for its displacements"
    if set(u) != set(reference):
        return f"the result has {len(u)} nodes, the reference {len(reference)}"
    scale = max(max(abs(c) for c in v) for v in reference.values()) or 1.0
    worst = max(max(abs(a - b) for a, b in zip(u[i], reference[i])) for i in reference)
    if not worst <= tolerance * scale:  # NaN fails too
        return f"silent wrong result: the displacements differ from the reference by {worst:.3g} (of {scale:.3g})"
    return ""


def judge_file_case(returncode, stderr, stdout, files, mode, folder, ranks, expect, reference=None):
    """A case that gives hydrosoft one input file (a mesh, a checkpoint) and runs it:
    mode 'check' (--check: exit 0 must say the deck is valid), 'mesh' (hydrosoft mesh: exit 0
    must leave the .h5 at `folder`) or 'run' (a real run whose results are in `folder`).
    expect: 'reject' (refusing is the only right outcome), 'same' (refused cleanly, or the
    result's displacements are `reference`'s), 'any'."""
    cls, reason = classify_ranks(returncode, stderr, files, mode == "run", folder, ranks)
    if cls != "accepted":
        return cls, reason
    if mode == "check" and "nothing was solved" not in stdout:
        return "defect", "exit 0 without the check's report (did something end the process?)"
    if mode == "mesh":
        try:
            with open(folder, "rb") as f:
                if not f.read(8).startswith(b"\x89HDF"):
                    return "defect", "exit 0 but the mesh file is not HDF5"
        except OSError:
            return "defect", "exit 0 without the mesh file"
    if mode == "run":
        bad = folder_defect(folder, "ok")
        if bad:
            return "defect", "exit 0 but " + bad
    if expect == "reject":
        return "defect", "accepted an input that must be refused"
    if expect == "same" and mode == "run" and reference is not None:
        bad = displacement_defect(folder, reference, 1e-9)
        if bad:
            return "defect", bad
    return "accepted", ""


def tree_digest(path):
    """What a file or a folder holds (names, link targets, bytes), to see that it is untouched."""
    if os.path.islink(path):
        return ("link", os.readlink(path))
    if os.path.isfile(path):
        with open(path, "rb") as f:
            return ("file", f.read())
    if os.path.isdir(path):
        return ("folder", tuple((name, tree_digest(os.path.join(path, name))) for name in sorted(os.listdir(path))))
    return ("none",) if not os.path.lexists(path) else ("other", os.stat(path).st_mode)


def kept_defect(stderr, run_folder, output):
    """Whether what a failed run says it kept is there: the `.failed` that its last line names
    must hold that many steps and a summary with status failed. '' if so."""
    lines = [l for l in stderr.splitlines() if l.strip()]
    said = re.search(r"the (\d+) converged output steps are in (\S+?)/? \(summary", lines[-1]) if lines else None
    failed = os.path.join(run_folder, output + ".failed")
    if said:
        bad = folder_defect(failed, "failed")
        if bad:
            return "lost data: the run says it kept its steps, but " + bad
        summary = read_json(os.path.join(failed, "summary.json"))
        if summary.get("outputs") != int(said.group(1)):
            return f"lost data: the run says {said.group(1)} steps were kept, summary.json {summary.get('outputs')}"
    return ""


def judge_full_disk(returncode, stderr, ranks, run_folder, output, earlier, timed_out):
    """A real run whose output folder lies on a file system too small for it (or under a file
    size limit). Right: exit 0 with the whole result; or exit 1-3 with one line naming the
    file (or the output folder) and the reason, and, either way, nothing `.partial` left and
    the earlier good result (`earlier`, its tree_digest) untouched unless replaced by a whole
    new one; a `.failed` that the run says it kept must be whole."""
    if timed_out:
        return "defect", "hung on a full disk"
    final = os.path.join(run_folder, output)
    if os.path.lexists(final + ".partial"):
        return "defect", f"{output}.partial left behind"
    cls, reason = classify_ranks(returncode, stderr, [output, output + ".partial", output + ".failed",
                                                    output + ".lock", "deck.yaml"], True, final, ranks)
    if cls == "defect":
        return cls, reason
    if cls == "accepted":
        bad = folder_defect(final, "ok")
        return ("defect", "exit 0 but " + bad) if bad else ("accepted", "")
    if tree_digest(final) != earlier:
        return "defect", f"lost data: the earlier result in {output} changed"
    bad = kept_defect(stderr, run_folder, output)
    return ("defect", bad) if bad else ("rejected", "")


def judge_interactive(returncode, stderr, answers, sent_lines, closed_stdout, run_folder, output, ranks, timed_out):
    """An interactive run (`--targets -`) whose client sends target lines, garbage, and closes
    its end of the pipes at some moment. Right: the process ends; no signal, no dump, at most
    one error line; every answer the client read is one JSON line numbered in order; and the
    steps it answered are kept, in `output` (status ok) or `output.failed` (status failed), with
    summary.json's input.answered at least the answers read (all of the lines, and exactly
    the answers, when the client kept reading to the end)."""
    if timed_out:
        return "defect", "still running after its client closed its pipes"
    if ranks > 1:
        stderr, banner = split_launcher(stderr)
        died = _RANK_SIGNAL.search(banner)
        if died:
            return "defect", f"a rank died of signal {died.group(1)}"
    if returncode < 0:
        return "defect", f"signal {-returncode}"
    lines = [l for l in stderr.splitlines() if l.strip()]
    if any("PETSC ERROR" in l for l in lines):
        return "defect", "PETSc error dump"
    errors = [l for l in lines if l.startswith("hydrosoft: error:")]
    if returncode not in (0, 1, 2, 3) or len(errors) > 1:
        return "defect", f"exit {returncode} with {len(errors)} error lines: " + (errors or lines or [""])[0][:200]
    if errors and any(text in errors[0] for text in LIBRARY_TEXTS):
        return "defect", "a library's exception, not a reason: " + errors[0][:200]
    answered = 0
    for n, line in enumerate(answers, 1):
        try:
            answer = json.loads(line)
        except ValueError:
            return "defect", f"answer {n} is not JSON: {line[:100]!r}"
        if not isinstance(answer, dict) or answer.get("line") != n or not ("answer" in answer or "error" in answer):
            return "defect", f"answer {n} does not answer line {n}: {line[:100]!r}"
        answered += "answer" in answer
    kept = None
    for folder, status in ((output, "ok"), (output + ".failed", "failed")):
        path = os.path.join(run_folder, folder)
        summary = read_json(os.path.join(path, "summary.json"))
        if summary is not None and (kept is None or os.path.getmtime(path) > kept[2]):
            kept = (path, status, os.path.getmtime(path), summary)
    if kept is None:
        if answered:
            return "defect", f"lost data: {answered} answered steps and no summary.json"
        return ("accepted", "") if returncode == 0 else ("rejected", "")
    path, status, _, summary = kept
    bad = folder_defect(path, status)
    if bad:
        return "defect", ("lost data: " if answered else "") + bad
    got = summary.get("input") or {}
    if not isinstance(got.get("answered"), int) or got["answered"] < answered:
        return "defect", f"lost data: the client read {answered} answers, summary.json keeps {got.get('answered')}"
    if len(summary.get("targets") or []) != got["answered"]:
        return "defect", f"summary.json: {len(summary.get('targets') or [])} targets for {got['answered']} answered lines"
    if not closed_stdout and returncode == 0:
        if got.get("lines") != sent_lines or len(answers) != sent_lines or got["answered"] != answered:
            return "defect", (f"one line in, one line out: sent {sent_lines} lines, read {len(answers)} answers "
                              f"({answered} steps), summary.json input {got}")
    return ("accepted", "") if returncode == 0 else ("rejected", "")


def judge_lock(runs, run_folder, victims, outside_marker):
    """Runs on one output folder whose `.lock`, `.partial`, `.failed` or the folder itself
    was made a link to a victim (a file or folder that is not the run's), or two runs at once
    on a folder and its `.partial`. runs: [(name, returncode, stderr, output folder, ranks,
    timed_out)]. Right: every victim as it was; no file made where a dangling link pointed;
    each run ended, accepted with a whole result in its own folder or refused with one line."""
    for path, digest in victims.items():
        if tree_digest(path) != digest:
            return "defect", f"wrote through a link: {os.path.relpath(path, run_folder)} changed"
    if outside_marker and os.path.lexists(outside_marker):
        return "defect", f"reached the system: made {os.path.basename(outside_marker)} through a dangling link"
    outcomes = []
    for name, returncode, stderr, output, ranks, timed_out in runs:
        if timed_out:
            return "defect", f"run {name}: hung"
        folder = os.path.join(run_folder, output)
        cls, reason = classify_ranks(returncode, stderr, [output, output + ".partial", output + ".lock",
                                                          output + ".failed", "deck.yaml", "other.yaml"],
                                     True, folder, ranks)
        if cls == "defect":
            return cls, f"run {name}: {reason}"
        if cls == "accepted":
            bad = folder_defect(folder, "ok")
            if bad:
                return "defect", f"run {name}: exit 0 but {bad}"
            summary = read_json(os.path.join(folder, "summary.json"))
            if not str(summary.get("deck", "")).endswith(name + ".yaml"):
                return "defect", f"run {name}: exit 0, but {output} holds the result of {summary.get('deck')}"
        else:
            bad = kept_defect(stderr, run_folder, output)
            if bad:
                return "defect", f"run {name}: {bad}"
        outcomes.append(cls)
    return ("accepted", "") if all(c == "accepted" for c in outcomes) else ("rejected", "")
