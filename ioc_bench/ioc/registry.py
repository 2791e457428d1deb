"""The algorithm registry: decorated classes in this session, plus installed plugins.

Third-party packages declare algorithms in the entry-point group ``ioc_bench.algorithms``
(``name = "package.module:AlgorithmClass"``); they are found without being imported and
loaded only when asked for. A plugin that fails to import is reported by name and
skipped; a name that clashes with one already registered is refused with a message.
"""

from __future__ import annotations

import importlib.metadata
import warnings
from collections.abc import Callable
from typing import Any

from ioc_bench.ioc.algorithm import IOCAlgorithm

ENTRY_POINT_GROUP = "ioc_bench.algorithms"

_REGISTRY: dict[str, type[IOCAlgorithm]] = {}
#: Built-in algorithms, registered by name (not by import side effect, which happens once).
_BUILTINS = {
    "log-barrier": "ioc_bench.ioc.log_barrier:LogBarrier",
    "analytic-center": "ioc_bench.ioc.analytic_center:AnalyticCenter",
    "inverse-kkt": "ioc_bench.ioc.inverse_kkt:InverseKKT",
}


class AlgorithmError(ValueError):
    """An unknown, clashing or broken algorithm."""


class PluginWarning(UserWarning):
    """A plugin could not be loaded and was skipped."""


def register_algorithm(name: str) -> Callable[[type[IOCAlgorithm]], type[IOCAlgorithm]]:
    """Class decorator registering an :class:`IOCAlgorithm` subclass under ``name``."""

    def decorate(cls: type[IOCAlgorithm]) -> type[IOCAlgorithm]:
        _add(name, cls, origin=f"{cls.__module__}.{cls.__qualname__}")
        return cls

    return decorate


def _add(name: str, cls: Any, origin: str) -> None:
    if not (isinstance(cls, type) and issubclass(cls, IOCAlgorithm)):
        raise AlgorithmError(f"algorithm {name!r} from {origin} is not an IOCAlgorithm subclass")
    existing = _REGISTRY.get(name)
    if existing is not None and existing is not cls:
        raise AlgorithmError(
            f"algorithm name {name!r} is already registered by {existing.__module__}.{existing.__qualname__}; "
            f"choose another name for {origin}"
        )
    cls.name = name
    _REGISTRY[name] = cls


def _load_builtins() -> None:
    for name, target in _BUILTINS.items():
        if name not in _REGISTRY:
            module, attr = target.split(":")
            _add(name, getattr(importlib.import_module(module), attr), origin=target)


def _plugin_entry_points() -> list[importlib.metadata.EntryPoint]:
    return list(importlib.metadata.entry_points(group=ENTRY_POINT_GROUP))


def _load_plugin(ep: importlib.metadata.EntryPoint) -> bool:
    """Register one plugin; warn and return False if it cannot be loaded or clashes."""
    try:
        cls = ep.load()
    except Exception as exc:  # a plugin's import may fail in any way
        warnings.warn(
            f"IOC plugin {ep.name!r} ({ep.value}) failed to import and was skipped: {exc}", PluginWarning, stacklevel=3
        )
        return False
    if _REGISTRY.get(ep.name) is cls:
        return True
    try:
        _add(ep.name, cls, origin=f"plugin {ep.value}")
    except AlgorithmError as exc:
        warnings.warn(f"IOC plugin {ep.name!r} skipped: {exc}", PluginWarning, stacklevel=3)
        return False
    return True


def algorithms() -> list[str]:
    """Names of every available algorithm: built-in, registered, and installed plugins."""
    _load_builtins()
    names = list(_REGISTRY)
    names += [ep.name for ep in _plugin_entry_points() if ep.name not in _REGISTRY]
    return names


def get_algorithm(name: str) -> type[IOCAlgorithm]:
    """The algorithm class registered as ``name`` (loading its plugin if needed)."""
    _load_builtins()
    if name not in _REGISTRY:
        for ep in _plugin_entry_points():
            if ep.name == name and _load_plugin(ep):
                break
    if name not in _REGISTRY:
        raise AlgorithmError(f"unknown algorithm {name!r}; valid: {', '.join(algorithms())}")
    return _REGISTRY[name]


def make_algorithm(name: str, **config: Any) -> IOCAlgorithm:
    """An instance of algorithm ``name`` with config overrides (unknown fields raise)."""
    cls = get_algorithm(name)
    try:
        return cls(**config)
    except TypeError as exc:
        raise AlgorithmError(f"bad config for algorithm {name!r}: {exc}") from None


def describe_algorithms() -> dict[str, str]:
    """Name -> one-line description, loading plugins (broken ones are reported and left out)."""
    out = {}
    for name in algorithms():
        try:
            out[name] = get_algorithm(name).description or "(no description)"
        except AlgorithmError:
            continue
    return out
