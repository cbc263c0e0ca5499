"""The process-tree sampling of ``scripts/bench_memory.py --corpus``."""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

pytestmark = pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="Linux /proc")


def bench_memory():
    spec = importlib.util.spec_from_file_location("bench_memory",
                                                  ROOT / "scripts" / "bench_memory.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_tree_holds_a_child_and_its_child():
    bench = bench_memory()
    code = "import subprocess, sys; subprocess.run([sys.executable, '-c', " \
           "'import time; print(1, flush=True); time.sleep(30)'])"
    child = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE)
    try:
        assert child.stdout is not None and child.stdout.readline().strip() == b"1"
        tree = bench._tree(os.getpid())
        assert tree[0] == os.getpid() and child.pid in tree
        assert len(tree) >= 3  # this process, the child, the grandchild
    finally:
        child.kill()
        child.wait()


def test_memory_of_a_living_and_a_finished_process():
    bench = bench_memory()
    rss, peak = bench._memory(os.getpid())
    assert 0 < rss <= peak
    done = subprocess.Popen([sys.executable, "-c", "pass"])
    done.wait()
    assert bench._memory(done.pid) is None
