"""Run the CLI in a child process that file modes bind, also as root.

Root reads and writes whatever a file's mode says (CI runs as root), so a permission test
in the test process itself proves nothing there. The child drops ``CAP_DAC_OVERRIDE`` and
``CAP_DAC_READ_SEARCH`` from its capability bounding set before ``exec``: a root process
then gets its capabilities from that set only, and a file of mode 0 or a folder of mode
0o555 stops it as it stops any user. For other users file modes already apply and nothing
is dropped.
"""

from __future__ import annotations

import ctypes
import os
import subprocess
import sys
from pathlib import Path

_PR_CAPBSET_DROP = 24  # prctl(2)
_CAP_DAC_OVERRIDE = 1  # capabilities(7)
_CAP_DAC_READ_SEARCH = 2


def _drop_file_mode_overrides() -> None:  # runs in the child, before exec
    libc = ctypes.CDLL(None, use_errno=True)
    for cap in (_CAP_DAC_OVERRIDE, _CAP_DAC_READ_SEARCH):
        if libc.prctl(_PR_CAPBSET_DROP, cap, 0, 0, 0) != 0:
            raise OSError(ctypes.get_errno(), "prctl(PR_CAPBSET_DROP) failed")


def run_cli_bound_by_file_modes(argv: list[str], cwd: Path,
                                env: dict[str, str] | None = None,
                                timeout: float = 120.0) -> subprocess.CompletedProcess[str]:
    """``python -m urdfinertia.cli ARGV`` in a child that cannot override file modes."""
    preexec = _drop_file_mode_overrides if os.geteuid() == 0 else None
    return subprocess.run([sys.executable, "-m", "urdfinertia.cli", *argv], cwd=cwd,
                          env={**os.environ, **(env or {})}, capture_output=True, text=True,
                          timeout=timeout, preexec_fn=preexec)


def file_modes_bind() -> bool:
    """Whether a child started by :func:`run_cli_bound_by_file_modes` is stopped by a mode 0
    file (False where the kernel refuses to drop the capabilities)."""
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        probe = Path(tmp) / "probe"
        probe.write_bytes(b"x")
        probe.chmod(0)
        preexec = _drop_file_mode_overrides if os.geteuid() == 0 else None
        try:
            done = subprocess.run([sys.executable, "-c", f"open({str(probe)!r}).read()"],
                                  capture_output=True, preexec_fn=preexec, timeout=60)
        except (OSError, subprocess.SubprocessError):
            return False
        return done.returncode != 0 and b"PermissionError" in done.stderr
