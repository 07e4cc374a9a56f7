"""The sweep's dask clusters: a local one (``local_client``, with ``DASK_CONFIG``), a running
scheduler (``connect_scheduler``, probed first by ``probe_scheduler``), and the checks made
before any scene is sent (``check_workers``: at least one worker, every worker on this version).
"""
from __future__ import annotations

import os
import sys
import time

from ..errors import InputError
from .table import EXTRA
from .table import package_version as _version

__all__ = ["connect_scheduler", "probe_scheduler", "check_workers", "local_client", "DASK_CONFIG",
           "WORKER_ENV", "WORKERS_PER_CORE", "max_workers", "default_workers", "have_dask",
           "need_dask"]


def default_workers() -> int:
    """The usable cores."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


def have_dask() -> bool:
    try:
        import distributed  # noqa: F401
    except ModuleNotFoundError:
        return False
    return True


# --- engines ------------------------------------------------------------------------------------
def need_dask():
    try:
        import distributed  # noqa: F401
    except ModuleNotFoundError:
        raise InputError(f"the local and external engines need dask.distributed: {EXTRA} "
                         "(or run with --serial)") from None


WORKER_ENV = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}


def connect_scheduler(address: str, timeout: float = 10.0):
    """A dask Client on a running scheduler; InputError (naming --scheduler) if unreachable."""
    need_dask()
    import logging

    from distributed import Client

    if not isinstance(address, str) or "://" not in address and ":" not in address:
        raise InputError(f"--scheduler must be an address such as tcp://HOST:PORT; got {address!r}")
    probe_scheduler(address, timeout)
    logging.getLogger("distributed").setLevel(logging.CRITICAL)
    client = None
    old_hook = sys.unraisablehook  # a half-made Client's __del__ times out noisily: keep quiet
    sys.unraisablehook = lambda unraisable: None
    try:
        client = Client(address, timeout=timeout, set_as_default=False)
        return client
    except Exception as exc:  # noqa: BLE001 -- whatever the peer did: one line
        msg = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise InputError(f"--scheduler {address}: unreachable ({msg[:160]})") from None
    finally:
        if client is None:
            import gc

            gc.collect()
        sys.unraisablehook = old_hook



WORKERS_PER_CORE = 2
"""--workers is bounded by this many per usable core (each worker is one process with one
thread: more only adds start-up time and memory; 1000 never started on 2 cores)."""
_HANDSHAKE_MAX = 1 << 20  # a dask handshake is ~100 bytes; 1 MiB is nothing a scheduler sends


def max_workers() -> int:
    """The bound of --workers: WORKERS_PER_CORE x the usable cores."""
    return WORKERS_PER_CORE * default_workers()



def probe_scheduler(address: str, timeout: float) -> None:
    """Check, with a raw socket and a hard ``timeout``, that a tcp:// ``address`` speaks dask's
    protocol before a Client is made: a dask server writes its handshake first (8-byte length,
    then ~100 bytes).  Something else (an HTTP server: silent; random bytes: a "length" of
    exabytes) is an InputError naming --scheduler, within ``timeout``."""
    import socket
    import struct

    scheme, _, rest = address.rpartition("://")
    if scheme not in ("", "tcp"):
        return  # tls://, inproc://, ...: left to dask
    host, _, port = rest.rpartition(":")
    host = host.strip("[]")
    try:
        port_n = int(port)
    except ValueError:
        port_n = -1
    if not host or not 0 < port_n < 65536:
        raise InputError(f"--scheduler must be an address such as tcp://HOST:PORT (PORT in 1 ... "
                         f"65535); got {address!r}")
    deadline = time.monotonic() + timeout

    def recv(sock, n):
        data = b""
        while len(data) < n:
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError
            sock.settimeout(left)
            chunk = sock.recv(n - len(data))
            if not chunk:
                raise ConnectionError("closed by the peer")
            data += chunk
        return data

    try:
        with socket.create_connection((host, port_n), timeout=timeout) as sock:
            (n,) = struct.unpack("<Q", recv(sock, 8))
            if not 0 < n <= _HANDSHAKE_MAX:
                raise InputError(f"--scheduler {address}: not a dask scheduler (its first bytes "
                                 f"announce a message of {n:.3g} bytes; dask's handshake is ~100)")
            recv(sock, n)
    except TimeoutError:
        raise InputError(f"--scheduler {address}: no dask handshake within --scheduler-timeout "
                         f"{timeout:g} s (not a dask scheduler, or not answering)") from None
    except OSError as exc:
        raise InputError(f"--scheduler {address}: unreachable ({exc.strerror or exc})") from None


def _worker_version():
    try:
        from spectral_contact._version import __version__
    except Exception as exc:  # noqa: BLE001 -- reported to the client as the reason
        return f"cannot import spectral_contact ({type(exc).__name__}: {exc})"
    return __version__


def check_workers(client, what: str, timeout: float = 10.0) -> int:
    """Wait (up to ``timeout`` s) for at least one worker and check that every worker runs this
    package version (a scene's key holds the version); returns the worker threads.  InputError
    naming ``what`` otherwise."""
    t_end = time.monotonic() + timeout
    while not client.nthreads():
        if time.monotonic() > t_end:
            raise InputError(f"{what}: no workers joined the scheduler in {timeout:g} s")
        time.sleep(0.1)
    versions = client.run(_worker_version)
    mine = _version()
    for addr, v in sorted(versions.items()):
        if v != mine:
            raise InputError(f"{what}: worker {addr} runs spectral_contact {v} (this is {mine}); "
                             "install the same version on every worker")
    return sum(client.nthreads().values())


# dask settings of the sweep's LocalCluster (its scheduler and nannies in this process, and the
# worker processes, which get the nannies' copy): its periodic work costs CPU on the cores that
# solve.  Measured on 2 cores, 400 2D scenes of ~10 ms (studies/benchmark_sweep.py): the workers'
# statistical profiler (it takes the GIL from the solve every 10 ms to walk its stack) and the
# 20 ms event-loop tick, the system and memory monitors cost an idle 2-worker cluster 0.066 core
# s per s (0.015 with these settings); the profiler feeds only the dashboard, which is off.
# glibc: the nannies set MALLOC_TRIM_THRESHOLD_=65536 in the workers, which also freezes glibc's
# mmap threshold at 128 KiB: every array above it is mmap'd and faulted in anew (91000 page
# faults in the workers for those 400 scenes, 14000 without); None leaves glibc's defaults, as in
# the serial engine (unless this process's environment has the variable: a dask Nanny started
# here with dask's default config writes it into os.environ, and the workers inherit it).
# Together, the solving thread's CPU went from 1.01-1.05 to 0.93-0.97 x a plain process's main
# thread's (1 worker, the same scenes in alternation; profiler alone -3 %, glibc alone -3.5 %).
DASK_CONFIG = {
    "distributed.worker.profile.enabled": False,
    "distributed.admin.tick.interval": "1s",
    "distributed.admin.system-monitor.interval": "10s",
    "distributed.worker.memory.monitor-interval": "500ms",
    "distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None,
}


def local_client(workers: int | None = None):
    """A dask LocalCluster of ``workers`` processes (default: the cores), one thread each, BLAS
    pinned to one thread, with ``DASK_CONFIG`` (this process's dask config is left as it was);
    returns (client, cluster): close both when done."""
    need_dask()
    workers = workers or default_workers()
    import logging

    import dask
    from distributed import Client, LocalCluster  # before dask.config.set: its defaults first

    # on 127.0.0.1 only; no dashboard; the scheduler's health page on a free port (not 8787)
    with dask.config.set(DASK_CONFIG):
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                               host="127.0.0.1", dashboard_address=None,
                               scheduler_kwargs={"dashboard": False, "dashboard_address": "127.0.0.1:0"},
                               silence_logs=logging.CRITICAL, env=dict(WORKER_ENV))
    return Client(cluster, set_as_default=False), cluster

