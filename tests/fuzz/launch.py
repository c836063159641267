"""Starting hydrosoft for the families of families.py: on 1 rank (an Open MPI singleton) or
on 2 under mpiexec, in its own process group (a time limit ends the launcher and its ranks
together), under an address-space limit and, for the full-disk cases, a file-size limit.
"""
import os
import resource
import select
import signal
import subprocess
import time


class Launcher:
    def __init__(self, hydrosoft, mpiexec, memory_mb):
        self.hydrosoft, self.mpiexec, self.memory_mb = hydrosoft, mpiexec, memory_mb

    def command(self, argv, ranks):
        if ranks == 1:
            return [self.hydrosoft] + argv
        root = ["--allow-run-as-root"] if os.geteuid() == 0 else []
        return [self.mpiexec, "-np", str(ranks), "--oversubscribe"] + root + [self.hydrosoft] + argv

    def environment(self, case_root, ranks):
        """Each case its own Open MPI session folder (16 at once must not share one)."""
        session = os.path.join(case_root, "ompi")
        os.makedirs(session, exist_ok=True)
        env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1",
                   OMPI_MCA_orte_tmpdir_base=session, OMPI_MCA_rmaps_base_oversubscribe="1")
        if ranks == 1:  # no daemon for a singleton
            env["OMPI_MCA_ess_singleton_isolated"] = "1"
        return env

    def limits(self, file_size=None):
        memory_mb = self.memory_mb

        def apply():
            if memory_mb > 0:
                resource.setrlimit(resource.RLIMIT_AS, (memory_mb << 20, memory_mb << 20))
            resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
            if file_size is not None:
                # A write past the limit then fails with EFBIG, as on a full disk, instead of
                # killing the process with SIGXFSZ (an ignored signal stays ignored across exec).
                signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
                resource.setrlimit(resource.RLIMIT_FSIZE, (file_size, file_size))

        return apply

    def start(self, argv, cwd, case_root, ranks, stdin=subprocess.DEVNULL, file_size=None, stderr=subprocess.PIPE):
        command = self.command(argv, ranks)
        process = subprocess.Popen(command, cwd=cwd, env=self.environment(case_root, ranks), stdin=stdin,
                                   stdout=subprocess.PIPE, stderr=stderr, start_new_session=True,
                                   preexec_fn=self.limits(file_size))
        process.command = command
        return process

    def run(self, argv, cwd, case_root, ranks, timeout, file_size=None):
        """(exit code or None past the time limit, stdout, stderr, command)."""
        process = self.start(argv, cwd, case_root, ranks, file_size=file_size)
        code, out, err = finish(process, timeout)
        return code, out, err, process.command


def finish(process, timeout):
    """Waits for the process; past `timeout` ends its whole group. (code or None, out, err)."""
    try:
        out, err = process.communicate(timeout=timeout)
        return process.returncode, (out or b"").decode("utf-8", "replace"), (err or b"").decode("utf-8", "replace")
    except subprocess.TimeoutExpired:
        kill_group(process)
        out, err = process.communicate()
        return None, (out or b"").decode("utf-8", "replace"), (err or b"").decode("utf-8", "replace")


def kill_group(process):
    try:
        os.killpg(process.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


def wait_for(condition, timeout, step=0.005):
    """Polls `condition` until it holds or `timeout` seconds pass; returns whether it held."""
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if condition():
            return True
        time.sleep(step)
    return condition()


class Pipes:
    """The client's ends of an interactive run's standard input and output, used without
    threads: answers are read as they come (select), either end can be closed at any moment."""

    def __init__(self, process):
        self.process = process
        self.stdin = process.stdin.fileno()
        self.stdout = process.stdout.fileno()
        os.set_blocking(self.stdout, False)
        self.buffer = b""
        self.answers = []
        self.broken = False  # a write found the reading end closed

    def pump(self, timeout=0.0):
        """Reads what has come within `timeout`; returns False once standard output is closed."""
        if self.stdout is None:
            return False
        ready, _, _ = select.select([self.stdout], [], [], timeout)
        if not ready:
            return True
        try:
            chunk = os.read(self.stdout, 65536)
        except BlockingIOError:
            return True
        if not chunk:
            self.close_stdout()
            return False
        self.buffer += chunk
        *lines, self.buffer = self.buffer.split(b"\n")
        self.answers += [line.decode("utf-8", "replace") for line in lines]
        return True

    def send(self, data):
        if self.stdin is None or self.broken:
            return False
        view = memoryview(data)
        while view:
            self.pump()
            try:
                _, writable, _ = select.select([], [self.stdin], [], 1.0)
                if writable:
                    view = view[os.write(self.stdin, view[:65536]) :]
                elif self.process.poll() is not None:
                    self.broken = True
                    return False
            except (BrokenPipeError, OSError):
                self.broken = True
                return False
        return True

    def wait_answers(self, count, timeout):
        end = time.monotonic() + timeout
        while len(self.answers) < count and time.monotonic() < end:
            if not self.pump(0.05):
                break

    def close_stdin(self):
        if self.stdin is not None:
            self.process.stdin.close()
            self.stdin = None

    def close_stdout(self):
        if self.stdout is not None:
            self.process.stdout.close()
            self.stdout = None
