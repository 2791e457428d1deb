"""The old home of :func:`~ioc_bench.synthetic.observe.observe`, kept for plugin authors' scripts."""

from ioc_bench.synthetic.observe import observe

__all__ = ["observe"]
