"""Drive a hydrosoft control scene from Python: start it, send targets, read the answers.

    import sys; sys.path.insert(0, "python")        # or PYTHONPATH=<prefix>/share/hydrosoft/python
    from hydrosoft_control import Scene, TargetRefused

    with Scene("input/pendulum.yaml", ranks=1) as scene:
        answer = scene.reach([0.0015, 0.0, -0.1011])          # the first effector
        print(answer.reached, answer.error_m, answer.actuation)
        scene.reach([0.0, 0.0015, -0.1011], effector="bottom")
    print(scene.summary["input"])                              # summary.json of the run

A Scene runs `[mpirun -np RANKS] hydrosoft DECK --targets -` and speaks its protocol
(docs/control.md, "Interactive use"): one target a line on its standard input, one JSON
line in return on its standard output, the answer or why the line was refused. Closing the
input ends the run, which then writes its output folder as any run does. Numbers are SI
(m, Pa, N); positions come back as numpy arrays. Needs numpy only (Debian's python3-numpy).
"""
import json
import os
import shutil
import signal
import subprocess
import tempfile
import time
import weakref

import numpy as np

__all__ = ["Scene", "Answer", "TargetRefused", "SceneError", "find_executable"]

_ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


class SceneError(RuntimeError):
    """The scene could not start, or stopped without answering (its messages are quoted)."""


class TargetRefused(ValueError):
    """hydrosoft refused a target line; the scene goes on from where it was."""

    def __init__(self, message, line):
        super().__init__(message)
        self.line = line


class Answer:
    """One answered target: where the effector should go and where it went.

    effector, target (m), reached (m, the equilibrium at the final actuation), error_m (over
    the steered directions; for a contact-force effector target and reached are forces in N,
    error_m is None and error_N its error), actuation (Pa or N per actuator), saturated (per actuator: a
    bound active), limit_point, step (the output step in the run's .h5), step_ms (the last
    control step's time), answer_ms (all the target set's steps: the time the line waited
    for its answer inside hydrosoft), round_trip_ms (sent to read, as the client saw it),
    line (its input line), raw (the JSON object as hydrosoft wrote it).
    """

    def __init__(self, raw, line, round_trip_ms):
        self.raw = raw
        self.line = line
        self.round_trip_ms = round_trip_ms
        self.effector = raw["effector"]
        self.target = np.array(raw["target"], dtype=float)
        self.reached = np.array(raw["reached"], dtype=float)
        self.error_m = raw.get("error_m")
        self.error_N = raw.get("error_N")
        self.actuation = np.array(raw["actuation"], dtype=float)
        self.saturated = list(raw.get("saturated", []))
        self.limit_point = bool(raw.get("limit_point", False))
        self.step = raw.get("step")
        self.step_ms = raw.get("step_ms")
        self.answer_ms = raw.get("answer_ms")

    def __repr__(self):
        if self.error_m is None:
            return ("Answer(%s: target %s N, reached %s N, error %.3g N)"
                    % (self.effector, self.target, self.reached, self.error_N))
        return ("Answer(%s: target %s, reached %s, error %.3g mm)"
                % (self.effector, self.target, self.reached, 1e3 * self.error_m))


def find_executable():
    """$HYDROSOFT, else the source tree's build/bin/hydrosoft, else the install's
    PREFIX/bin/hydrosoft (this package in PREFIX/share/hydrosoft/python), else PATH's."""
    installed = os.path.join(_ROOT, os.pardir, os.pardir, "bin", "hydrosoft")
    for path in (os.environ.get("HYDROSOFT"), os.path.join(_ROOT, "build", "bin", "hydrosoft"),
                 os.path.normpath(installed), shutil.which("hydrosoft")):
        if path and os.access(path, os.X_OK):
            return path
    raise SceneError("no hydrosoft executable: set HYDROSOFT, build it (bash scripts/build.sh) "
                     "or put an installed bin/ on PATH")


class Scene:
    """A running control scene. Collective work happens in hydrosoft; this object only talks.

    deck: the deck file (with a `control` section); ranks: MPI ranks (1 runs without mpirun);
    overrides: ["key=value", ...] as --set; output_folder: where the run writes (default: a
    new temporary folder, see .folder, removed with what is in it when the scene ends:
    close(), kill(), an exception in its `with` block, or the interpreter's exit; keep=True
    keeps it); executable: hydrosoft (find_executable()).
    The resolved configuration, the progress and the final report go to `log` (a file path;
    default: OUTPUT_FOLDER.log beside the folder).
    """

    def __init__(self, deck, ranks=1, overrides=(), output_folder=None, executable=None,
                 log=None, timeout_s=600, keep=False):
        self.deck = os.path.abspath(deck)
        if not os.path.isfile(self.deck):
            raise SceneError("%s: no such deck" % deck)
        self._temporary = None
        self._last_messages = None
        if output_folder is None:
            self._temporary = tempfile.mkdtemp(prefix="hydrosoft_scene_")
            output_folder = os.path.join(self._temporary, "run")
        self._keep = keep
        self.folder = os.path.abspath(output_folder)
        self.log_path = log or self.folder + ".log"
        self.timeout_s = timeout_s
        self.summary = None
        self._lines = 0
        exe = executable or find_executable()
        cmd = []
        if ranks > 1:
            cmd = [shutil.which("mpirun") or "mpirun", "--oversubscribe", "-np", str(ranks)]
            if os.geteuid() == 0:
                cmd.append("--allow-run-as-root")
        # The folder's path goes in as a YAML string in double quotes (JSON's are YAML's):
        # bare, a ' #' in it would start a comment and cut the path there.
        cmd += [exe, self.deck, "--targets", "-",
                "--set", "output.folder=" + json.dumps(self.folder, ensure_ascii=False)]
        for kv in overrides:
            cmd += ["--set", kv]
        env = dict(os.environ)
        env.setdefault("OPENBLAS_NUM_THREADS", "1")
        self._log = open(self.log_path, "w")
        self._mpirun = ranks > 1
        try:
            self._proc = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                          stderr=self._log, text=True, bufsize=1, env=env)
        except OSError:
            self._log.close()
            self._remove_temporary()
            raise
        # A scene never closed (no `with`, the interpreter exiting) still stops its run and
        # removes its temporary folder; the finalizer holds no reference to the scene.
        self._finalizer = weakref.finalize(self, _end_abandoned, self._proc, self._log,
                                           None if keep else self._temporary)

    def __enter__(self):
        return self

    def __exit__(self, kind, value, traceback):
        if kind is None:
            self.close()
        else:
            self.kill()
        return False

    def _messages(self):
        if self._last_messages is not None:  # the log went with the temporary folder
            return self._last_messages
        if not self._log.closed:
            self._log.flush()
        with open(self.log_path, errors="replace") as f:
            tail = f.read()[-2000:]
        return tail.strip() or "(none)"

    def reach(self, target, effector=None):
        """Sends one target (3 numbers, m) for `effector` (default: the deck's first) and waits
        for its answer. Raises TargetRefused for a refused line (the scene goes on) and
        SceneError when hydrosoft stopped."""
        # Refused here, before anything is sent: the scene goes on as for a refused line.
        try:
            position = [float(v) for v in target]
        except (TypeError, ValueError):
            raise TargetRefused("a target is 3 numbers (x, y, z in m), got %r" % (target,), None)
        if len(position) != 3:
            raise TargetRefused("a target is 3 numbers (x, y, z in m), got %d: %r"
                                % (len(position), position), None)
        words = "%.17g %.17g %.17g" % tuple(position)
        return self.send_line(words if effector is None else "%s %s" % (effector, words))

    def send_line(self, text):
        """Sends one raw protocol line (no newline in it) and returns its Answer."""
        if "\n" in text:
            raise ValueError("one line at a time")
        if self._proc.poll() is not None:
            raise SceneError("hydrosoft has stopped (exit %d); its messages:\n%s"
                             % (self._proc.returncode, self._messages()))
        sent = time.perf_counter()
        try:
            self._proc.stdin.write(text + "\n")
            self._proc.stdin.flush()
        except BrokenPipeError:
            raise SceneError("hydrosoft stopped reading; its messages:\n%s" % self._messages())
        self._lines += 1
        reply = self._proc.stdout.readline()
        if not reply:
            self._proc.wait()
            raise SceneError("hydrosoft stopped before answering line %d (exit %s); its "
                             "messages:\n%s" % (self._lines, self._proc.returncode,
                                                self._messages()))
        message = json.loads(reply)
        if "error" in message:
            raise TargetRefused(message["error"], message.get("line", self._lines))
        return Answer(message["answer"], message.get("line", self._lines),
                      1e3 * (time.perf_counter() - sent))

    def close(self):
        """Ends the input; waits for the run to write its folder; returns summary.json."""
        if self.summary is not None:
            return self.summary
        self._proc.stdin.close()
        try:
            code = self._proc.wait(timeout=self.timeout_s)
        except subprocess.TimeoutExpired:
            self.kill()
            raise SceneError("hydrosoft did not end within %g s of its input's end"
                             % self.timeout_s)
        self._release()
        try:
            if code != 0:
                raise SceneError("hydrosoft ended with exit %d; its messages:\n%s"
                                 % (code, self._messages()))
            with open(os.path.join(self.folder, "summary.json")) as f:
                self.summary = json.load(f)
        finally:
            self._remove_temporary()
        return self.summary

    def kill(self):
        """Stops the run at once: SIGTERM, on which hydrosoft keeps its answered steps in
        FOLDER.failed (summary.json "status": "failed"); SIGKILL after 30 s. A temporary
        folder (no output_folder, keep=False) is removed with them.

        Under mpirun the signal goes to the ranks themselves: mpirun, signalled, first closes
        their standard input, which ends the session as its client's end would, and the run
        was kept as a good result before mpirun passed the signal on (a second later)."""
        if self._proc.poll() is None:
            for pid in (self._ranks() if self._mpirun else []) or [self._proc.pid]:
                try:
                    os.kill(pid, signal.SIGTERM)
                except ProcessLookupError:
                    pass
            try:
                self._proc.wait(timeout=30)
            except subprocess.TimeoutExpired:
                self._proc.kill()
                self._proc.wait()
        self._release()
        self._remove_temporary()

    def _ranks(self):
        """The processes mpirun started on this machine (its children, from /proc), or []."""
        children = []
        try:
            tasks = os.listdir("/proc/%d/task" % self._proc.pid)
            for task in tasks:
                with open("/proc/%d/task/%s/children" % (self._proc.pid, task)) as f:
                    children += [int(pid) for pid in f.read().split()]
        except (OSError, ValueError):
            return []
        return children

    def _remove_temporary(self):
        if self._temporary and not self._keep and self._last_messages is None:
            self._last_messages = self._messages()
            shutil.rmtree(self._temporary, ignore_errors=True)

    def _release(self):
        for stream in (self._proc.stdin, self._proc.stdout, self._log):
            if stream and not stream.closed:
                try:
                    stream.close()
                except BrokenPipeError:
                    pass


def _end_abandoned(proc, log, temporary):
    """Ends a scene left running (SIGTERM, then SIGKILL after 30 s) and removes its temporary
    folder once nothing writes there any more."""
    if proc.poll() is None:
        proc.terminate()
        try:
            proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
    for stream in (proc.stdin, proc.stdout, log):
        if stream and not stream.closed:
            try:
                stream.close()
            except BrokenPipeError:
                pass
    if temporary:
        shutil.rmtree(temporary, ignore_errors=True)
