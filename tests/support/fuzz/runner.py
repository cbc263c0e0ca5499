"""Run ``urdf-inertia`` commands on fuzz cases: fast, isolated, bounded.

A server process (:func:`serve`, started by :class:`Runner`) imports the package and the
libraries it reads with once, then forks one child per command: the child runs
``urdfinertia.cli.main`` in a process group of its own, with standard output and error in
files, an address-space limit (``RLIMIT_AS``) and a wall-clock alarm. A child still alive
past the timeout is a hang; its process group is killed. The server is single-threaded
(numerical libraries are held to one thread), so forking it is safe, and each command
starts from the same freshly imported state. Reading an output back
(:func:`support.fuzz.classify.inspect_output`) runs in a forked child too, so that a
reader failing on a written file cannot take the run down.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

_TESTS = Path(__file__).resolve().parents[2]
_SRC = _TESTS.parent / "src"
#: Exit code of a child whose command raised past ``cli.main`` (a crash of the CLI shell).
EXIT_ESCAPED = 70
#: One thread per numerical library: the server must be single-threaded to fork safely.
SINGLE_THREAD = {name: "1" for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS",
                                          "MKL_NUM_THREADS", "NUMEXPR_NUM_THREADS")}


@dataclass(frozen=True)
class RunResult:
    """What one command did."""

    code: int | None  # exit code, None when killed by a signal
    signal: int | None
    timed_out: bool
    seconds: float  # wall clock
    cpu: float  # user + system, s
    max_rss_mb: float
    stdout: str
    stderr: str


class Runner:
    """A fork server for commands, with ``timeout`` s and ``memory_mb`` per command.

    ``src``: the folder the ``urdfinertia`` package is imported from (default: this
    checkout's ``src``), e.g. an older revision's, to measure it on the same cases.
    """

    def __init__(self, timeout: float = 60.0, memory_mb: int = 4096,
                 env: dict[str, str] | None = None, src: Path | None = None) -> None:
        self.timeout = timeout
        self.memory_mb = memory_mb
        full = {**os.environ, **SINGLE_THREAD, **(env or {}), "COLUMNS": "120"}
        full["PYTHONPATH"] = os.pathsep.join(
            [str(_TESTS), str(src or _SRC), *filter(None, [os.environ.get("PYTHONPATH")])])
        self._proc = subprocess.Popen(
            [sys.executable, "-c", "from support.fuzz.runner import serve; serve()"],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, env=full, text=True)
        ready = self._proc.stdout.readline() if self._proc.stdout else ""
        if not ready.startswith("ready "):
            raise RuntimeError(f"fuzz server did not start: {ready!r}")
        #: the folder of the package the commands run
        self.package = ready.removeprefix("ready ").strip()

    def _ask(self, request: dict) -> dict:
        assert self._proc.stdin is not None and self._proc.stdout is not None
        self._proc.stdin.write(json.dumps(request) + "\n")
        self._proc.stdin.flush()
        line = self._proc.stdout.readline()
        if not line:
            raise RuntimeError("fuzz server died")
        return json.loads(line)

    def run(self, argv: list[str], folder: Path, name: str) -> RunResult:
        out, err = folder / f"{name}.stdout", folder / f"{name}.stderr"
        reply = self._ask({"op": "run", "argv": argv, "cwd": str(folder),
                           "stdout": str(out), "stderr": str(err),
                           "timeout": self.timeout, "memory_mb": self.memory_mb})
        return RunResult(reply["code"], reply["signal"], reply["timed_out"],
                         reply["seconds"], reply["cpu"], reply["max_rss_mb"],
                         _text(out), _text(err))

    def inspect(self, path: Path, reply_path: Path, timeout: float | None = None) -> dict:
        """:func:`support.fuzz.classify.inspect_output` of ``path`` in a child."""
        reply = self._ask({"op": "inspect", "path": str(path), "reply": str(reply_path),
                           "timeout": timeout or self.timeout,
                           "memory_mb": self.memory_mb})
        if reply["timed_out"] or reply["code"] != 0 or not reply_path.is_file():
            return {"readable": False, "error": f"reading the output back failed: {reply}",
                    "links": {}, "problems": []}
        return json.loads(reply_path.read_text())

    def close(self) -> None:
        if self._proc.poll() is None:
            assert self._proc.stdin is not None
            self._proc.stdin.close()
            try:
                self._proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self._proc.kill()
                self._proc.wait()

    def __enter__(self) -> Runner:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _text(path: Path) -> str:
    try:
        return path.read_bytes().decode("utf-8", errors="replace")
    except OSError:
        return ""


# --- the server ----------------------------------------------------------------------

def _preload() -> None:
    """Import what commands use, so that each forked child starts warm."""
    import urdfinertia.cli  # noqa: F401
    import urdfinertia.cli.check  # noqa: F401
    import urdfinertia.cli.fix  # noqa: F401
    from urdfinertia.descriptions.formats import registered_formats

    registered_formats()
    for module in ("trimesh", "collada", "scipy.spatial", "manifold3d", "lxml.etree",
                   "urdfinertia.link.fix", "urdfinertia.analysis.check",
                   "urdfinertia.mesh.repair.pipeline", "xacro", "yaml", "pxr.Usd",
                   "support.fuzz.classify"):
        try:
            __import__(module)
        except Exception:  # an optional library: the command imports (or misses) it itself
            pass


def serve() -> None:
    """Answer requests (one JSON object a line on stdin) until stdin closes."""
    proto = os.fdopen(os.dup(1), "w")
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, 1)  # anything the server itself prints stays out of the protocol
    _preload()
    import urdfinertia

    proto.write(f"ready {Path(urdfinertia.__file__).parent}\n")
    proto.flush()
    for line in sys.stdin:
        request = json.loads(line)
        sys.stdout.flush()
        sys.stderr.flush()
        proto.write(json.dumps(_fork(request, proto)) + "\n")
        proto.flush()


def _fork(request: dict, proto) -> dict:  # noqa: ANN001 - a text file
    start = time.monotonic()
    pid = os.fork()
    if pid == 0:  # the child: never returns
        proto.close()
        _child(request)
    timeout = float(request["timeout"])
    status = None
    usage = None
    timed_out = False
    while True:
        done, status, usage = os.wait4(pid, os.WNOHANG)
        if done:
            break
        if time.monotonic() - start > timeout + 5:  # the alarm did not end it
            timed_out = True
            _kill_group(pid)
        time.sleep(0.005)
    _kill_group(pid)  # what the command started (workers) goes with it
    seconds = time.monotonic() - start
    sig = os.WTERMSIG(status) if os.WIFSIGNALED(status) else None
    timed_out = timed_out or sig == signal.SIGALRM
    return {"code": os.WEXITSTATUS(status) if os.WIFEXITED(status) else None,
            "signal": sig, "timed_out": timed_out, "seconds": seconds,
            "cpu": usage.ru_utime + usage.ru_stime, "max_rss_mb": usage.ru_maxrss / 1024}


def _kill_group(pid: int) -> None:
    try:
        os.killpg(pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


def _child(request: dict) -> None:
    import resource

    code = EXIT_ESCAPED
    try:
        os.setpgid(0, 0)
        null = os.open(os.devnull, os.O_RDONLY)
        os.dup2(null, 0)  # the server's stdin is the protocol
        os.close(null)
        limit = int(request["memory_mb"]) << 20
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
        signal.signal(signal.SIGALRM, signal.SIG_DFL)
        signal.alarm(max(1, int(round(float(request["timeout"])))))
        if request["op"] != "run":  # what reading an output back prints goes nowhere
            null = os.open(os.devnull, os.O_WRONLY)
            os.dup2(null, 1)
            os.dup2(null, 2)
            os.close(null)
        if request["op"] == "run":
            for fd, key in ((1, "stdout"), (2, "stderr")):
                target = os.open(request[key], os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o644)
                os.dup2(target, fd)
                os.close(target)
            os.chdir(request["cwd"])
            from urdfinertia import cli

            sys.argv = ["urdf-inertia", *request["argv"]]
            try:
                code = int(cli.main(request["argv"]))
            except SystemExit as exc:  # argparse: usage errors and --help
                code = exc.code if isinstance(exc.code, int) else 2
        else:
            from support.fuzz.classify import inspect_output

            found = inspect_output(Path(request["path"]))
            Path(request["reply"]).write_text(json.dumps(found))
            code = 0
    except BaseException:  # the command's shell let an exception through: a crash
        import traceback

        traceback.print_exc()
        code = EXIT_ESCAPED
    finally:
        try:
            sys.stdout.flush()
            sys.stderr.flush()
        finally:
            os._exit(code)
