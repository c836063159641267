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
    # FILE: KEY: reason (line N), or FILE: reason: the message starts with the file it is about.
    head = message.split(": ", 1)[0]
    if not any(head == f or head.endswith("/" + f) for f in files) or ": " not in message:
        return "defect", "the message does not start with the file: " + message[:300]
    return "rejected", ""


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
