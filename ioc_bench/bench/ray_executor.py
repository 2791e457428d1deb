"""Run cases on a Ray cluster (``--executor ray``), for suites that outgrow one machine.

The driver prepares the demonstrations and ships each case with its demonstration, so
workers need no shared disk; results come back to the driver, which writes them exactly
as the local runner does. At most ``workers`` cases are in flight, so a case's time
limit counts from (about) when it starts. Ray is an optional extra.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence

from ioc_bench.bench.case import CaseResult
from ioc_bench.bench.results import CaseSpec
from ioc_bench.demo import Demonstration


def _ray():
    try:
        import ray
    except ImportError:
        raise ValueError("the ray executor needs Ray: pip install 'ioc-bench[ray]'") from None
    return ray


def run_ray(
    pending: Sequence[CaseSpec],
    demos: dict[tuple, Demonstration],
    workers: int | None,
    time_limit: float,
    address: str | None,
    finish: Callable[[CaseSpec, CaseResult], None],
) -> None:
    """Run ``pending`` on Ray (a new local instance if ``address`` is None)."""
    from ioc_bench.bench.runner import _fail, demo_for, execute

    ray = _ray()
    started_here = not ray.is_initialized()
    if started_here:
        ray.init(address=address, num_cpus=workers if address is None else None, log_to_driver=False)
    remote = ray.remote(num_cpus=1)(execute)
    slots = workers or max(1, int(ray.cluster_resources().get("CPU", 1)))
    queue, running = list(pending), {}
    try:
        while queue or running:
            while queue and len(running) < slots:
                spec = queue.pop(0)
                running[remote.remote(spec, demo_for(spec, demos))] = (spec, time.monotonic())
            done, _ = ray.wait(list(running), num_returns=1, timeout=0.5)
            for ref in done:
                spec, _t = running.pop(ref)
                try:
                    finish(spec, ray.get(ref))
                except Exception as exc:  # a worker crash surfaces as a Ray error
                    finish(spec, _fail(spec, f"ray task failed: {type(exc).__name__}: {exc}"))
            for ref, (spec, t) in list(running.items()):
                if time.monotonic() - t > time_limit:
                    ray.cancel(ref, force=True)
                    running.pop(ref)
                    finish(spec, _fail(spec, f"timed out after {time_limit:g} s"))
    finally:
        for ref in running:
            ray.cancel(ref, force=True)
        if started_here:
            ray.shutdown()
