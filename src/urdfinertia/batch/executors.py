"""Where batch work runs: this process, a local process pool, or a Dask cluster."""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import threading
from collections.abc import Iterator
from typing import TYPE_CHECKING

from urdfinertia.errors import UrdfInertiaError

if TYPE_CHECKING:
    import multiprocessing.context


class ClusterError(UrdfInertiaError):
    """The Dask cluster cannot be used (optional dependency missing, no scheduler)."""


def _mp_context() -> multiprocessing.context.BaseContext:
    """fork when it is safe (no threads to inherit), else forkserver or spawn."""
    import multiprocessing  # only with workers: a serial or warm run does not need it

    methods = multiprocessing.get_all_start_methods()
    if "fork" in methods and threading.active_count() == 1:
        return multiprocessing.get_context("fork")
    if "forkserver" in methods:
        return multiprocessing.get_context("forkserver")
    return multiprocessing.get_context("spawn")


@contextlib.contextmanager
def open_executor(jobs: int, dask: str | None) -> Iterator[cf.Executor | None]:
    """None (this process), a process pool, or a Dask cluster's executor."""
    if dask:
        client = connect_dask(dask)
        try:
            yield client.get_executor(pure=False)
        finally:
            client.close()
    elif jobs > 1:
        pool = cf.ProcessPoolExecutor(max_workers=jobs, mp_context=_mp_context())
        try:
            yield pool
        except BaseException:
            pool.shutdown(wait=True, cancel_futures=True)
            raise
        pool.shutdown(wait=True)
    else:
        yield None


def connect_dask(address: str, timeout: str = "20s"):
    """A `distributed.Client` for the scheduler at `address`."""
    try:
        from distributed import Client
    except ImportError:
        raise ClusterError("--dask needs the optional dependency: "
                           "pip install 'urdfinertia[dask]'") from None
    try:
        return Client(address, timeout=timeout)
    except (OSError, TimeoutError, ValueError) as exc:
        raise ClusterError(f"cannot connect to the Dask scheduler at {address!r}: "
                           f"{exc}") from None


def submit(pool: cf.Executor, fn, *args) -> cf.Future:
    """`pool.submit(fn, *args)`, or a failed future when the pool is broken.

    Parameters
    ----------
    pool : Executor
        The pool.
    fn : callable
        The task.
    *args
        Its arguments.

    Returns
    -------
    Future
        The task's future (holding the pool's error when it could not be submitted).
    """
    try:
        return pool.submit(fn, *args)
    except Exception as exc:  # noqa: BLE001 - a broken pool fails the remaining tasks
        fut: cf.Future = cf.Future()
        fut.set_exception(exc)
        return fut
