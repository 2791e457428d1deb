"""The ``ray`` executor: cases as tasks on a Ray cluster, for suites that outgrow one machine.

The driver prepares the demonstrations and ships each case with its demonstration, so
workers need no shared disk; results come back to the driver, which writes them exactly
as for the local executor. Ray is an optional extra (``pip install 'ioc-bench[ray]'``).

Without ``address`` a private Ray instance is started on this machine. With one, the
driver joins that cluster; because a client that cannot authenticate retries forever
(Ray 2.52+ with token authentication), :meth:`RayExecutor.check` first connects from a
child process with a deadline and turns any failure into one line.
"""

from __future__ import annotations

import logging
import os
import re
import socket
import subprocess
import sys
import time
from typing import Any

from ioc_bench.runner.executor import Job, execute, failure_of
from ioc_bench.runner.protocol import Record
from ioc_bench.validation import check_count

logger = logging.getLogger(__name__)

#: Seconds the connection check may take before the cluster counts as unreachable.
CONNECT_TIMEOUT = float(os.environ.get("IOC_BENCH_RAY_CONNECT_TIMEOUT", "60"))
_HOST_PORT = re.compile(r"(?:ray://)?(?P<host>[^:/\s]+):(?P<port>[0-9]{1,5})")
_PROBE = (
    "import sys, ray\n"
    "ray.init(address=sys.argv[1], log_to_driver=False, logging_level='ERROR')\n"
    "print(int(ray.cluster_resources().get('CPU', 0)))\n"
)
_AUTH_HINT = (
    "if the cluster uses token authentication, export RAY_AUTH_MODE=token and its RAY_AUTH_TOKEN (see docs/cluster.md)"
)


class RayExecutor:
    """Ray tasks of one CPU each; at most ``workers`` in flight (default: the cluster's CPUs)."""

    def __init__(self, workers: int | None = None, address: str | None = None):
        self.workers = check_count(workers, "workers", optional=True)
        if address is not None and (not isinstance(address, str) or not address.strip()):
            raise ValueError(f"a Ray address looks like 127.0.0.1:6379, got {address!r}")
        self.address = address
        self._ray: Any = None
        self._remote: Any = None
        self._started_here = False
        self._running: dict[Any, Job] = {}

    def check(self) -> None:
        """Ray is installed and, with an address, the cluster answers within :data:`CONNECT_TIMEOUT`."""
        _import_ray()
        if self.address is not None:
            _check_cluster(self.address, CONNECT_TIMEOUT)

    def start(self) -> int:
        ray = self._ray = _import_ray()
        self._started_here = not ray.is_initialized()
        if self._started_here:
            num_cpus = self.workers if self.address is None else None
            ray.init(address=self.address, num_cpus=num_cpus, log_to_driver=False, logging_level="ERROR")
        self._remote = ray.remote(num_cpus=1)(execute)
        return self.workers or max(1, int(ray.cluster_resources().get("CPU", 1)))

    def submit(self, job: Job) -> Any:
        ref = self._remote.remote(job)
        self._running[ref] = job
        return ref

    def poll(self, timeout: float) -> list[tuple[Any, Record]]:
        if not self._running:
            time.sleep(timeout)
            return []
        ready, _ = self._ray.wait(list(self._running), num_returns=len(self._running), timeout=timeout)
        done = []
        for ref in ready:
            job = self._running.pop(ref)
            try:
                result = self._ray.get(ref)
            except Exception as exc:  # a worker crash surfaces as a Ray error
                reason = f"ray task failed: {type(exc).__name__}: {_one_line(exc)}"
                logger.warning("case %s: %s", job.spec.key, reason)
                result = failure_of(job.spec, reason)
            done.append((ref, result))
        return done

    def cancel(self, handle: Any) -> None:
        if self._running.pop(handle, None) is not None:
            self._ray.cancel(handle, force=True)

    def stop(self) -> None:
        for ref in list(self._running):
            self.cancel(ref)
        if self._started_here and self._ray is not None:
            self._ray.shutdown()
            self._started_here = False


def _import_ray() -> Any:
    try:
        import ray
    except ImportError:
        raise ValueError("the ray executor needs Ray: pip install 'ioc-bench[ray]'") from None
    return ray


def _check_cluster(address: str, timeout: float) -> None:
    """Raise ``ValueError`` (one line) unless a Ray client can join ``address`` within ``timeout`` s."""
    match = _HOST_PORT.fullmatch(address.strip())
    if match:  # fail fast when nothing listens there
        if not 0 < int(match["port"]) < 65536:
            raise ValueError(f"cannot reach a Ray cluster at {address}: {match['port']} is not a port number")
        try:
            socket.create_connection((match["host"], int(match["port"])), timeout=min(5.0, timeout)).close()
        except OSError as exc:
            raise ValueError(f"cannot reach a Ray cluster at {address}: {_one_line(exc)}") from None
    try:
        proc = subprocess.run(
            [sys.executable, "-c", _PROBE, address], capture_output=True, text=True, timeout=timeout, check=False
        )
    except subprocess.TimeoutExpired:
        raise ValueError(f"could not join the Ray cluster at {address} within {timeout:g} s; {_AUTH_HINT}") from None
    if proc.returncode != 0:
        lines = [line for line in proc.stderr.splitlines() if line.strip()]
        reason = _one_line(lines[-1])[:300] if lines else f"exit code {proc.returncode}"
        if re.search(r"InvalidAuthToken|AuthenticationError|Unauthenticated", proc.stderr):
            reason += f" (the cluster refused our authentication token; {_AUTH_HINT})"
        raise ValueError(f"could not join the Ray cluster at {address}: {reason}")


def _one_line(text: object) -> str:
    return " ".join(str(text).split())
