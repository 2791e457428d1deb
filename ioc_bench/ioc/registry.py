"""The algorithm registry: decorated classes in this session, plus installed plugins.

Third-party packages declare algorithms in the entry-point group ``ioc_bench.algorithms``
(``name = "package.module:AlgorithmClass"``); they are found without being imported and
loaded only when asked for. A plugin that fails to import is reported by name and
skipped; a name that clashes with one already registered is refused with a message.
Names become folder names of result files, so they are restricted to letters, digits and
``-._`` (see :data:`NAME_PATTERN`).

Configs are checked here, before any work: :func:`make_algorithm` refuses unknown fields,
values of the wrong type (against the ``Config`` dataclass's annotations) and values its
``__post_init__`` rejects, all as one-line :class:`AlgorithmError`. :func:`canonical_config`
reduces a config to the fields that differ from the defaults, so that configs with the
same effect have the same identity.
"""

from __future__ import annotations

import dataclasses
import importlib.metadata
import re
import typing
import warnings
from collections.abc import Callable, Mapping
from typing import Any

from ioc_bench.fileio import to_jsonable
from ioc_bench.ioc.algorithm import FAMILIES, IOCAlgorithm
from ioc_bench.validation import TypeMismatch, coerce, shown

ENTRY_POINT_GROUP = "ioc_bench.algorithms"
#: What an algorithm name may look like (it names a folder of result files).
NAME_PATTERN = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]{0,99}")

_REGISTRY: dict[str, type[IOCAlgorithm]] = {}
#: Built-in algorithms, registered by name (not by import side effect, which happens once).
_BUILTINS = {
    "log-barrier": "ioc_bench.ioc.log_barrier:LogBarrier",
    "analytic-center": "ioc_bench.ioc.analytic_center:AnalyticCenter",
    "inverse-kkt": "ioc_bench.ioc.inverse_kkt:InverseKKT",
    "bilevel": "ioc_bench.ioc.bilevel:Bilevel",
    "single-level": "ioc_bench.ioc.single_level:SingleLevel",
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


def check_algorithm_name(name: Any) -> str:
    """``name`` if it is a valid algorithm name, else :class:`AlgorithmError`."""
    if not isinstance(name, str) or not NAME_PATTERN.fullmatch(name) or ".." in name:
        raise AlgorithmError(
            f"invalid algorithm name {name!r}: use letters, digits and -._ (it names a folder of results)"
        )
    return name


def _add(name: str, cls: Any, origin: str) -> None:
    check_algorithm_name(name)
    if not (isinstance(cls, type) and issubclass(cls, IOCAlgorithm)):
        raise AlgorithmError(f"algorithm {name!r} from {origin} is not an IOCAlgorithm subclass")
    if cls.family not in FAMILIES:
        raise AlgorithmError(
            f"algorithm {name!r} from {origin}: unknown family {cls.family!r}; valid: {', '.join(FAMILIES)}"
        )
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
    if ep.name in _REGISTRY:
        existing = _REGISTRY[ep.name]
        warnings.warn(
            f"IOC plugin {ep.name!r} ({ep.value}) skipped: name clash refused, {ep.name!r} is already "
            f"registered by {existing.__module__}.{existing.__qualname__}",
            PluginWarning,
            stacklevel=3,
        )
        return False
    try:
        _add(ep.name, cls, origin=f"plugin {ep.value}")
    except AlgorithmError as exc:
        warnings.warn(f"IOC plugin {ep.name!r} skipped: {exc}", PluginWarning, stacklevel=3)
        return False
    return True


#: Registered names whose plugins have been looked at for a clash (once per process: the
#: look costs a scan of the installed packages, some 5 ms).
_CLASH_CHECKED: set[str] = set()


def _refuse_clashes(name: str | None = None) -> None:
    """Report plugins (all, or those called ``name``) named like an algorithm already
    registered by another class (:class:`PluginWarning`): the registered one stays."""
    if name is not None and name in _CLASH_CHECKED:
        return
    for ep in _plugin_entry_points():
        if ep.name in _REGISTRY and (name is None or ep.name == name):
            _load_plugin(ep)
    _CLASH_CHECKED.update(_REGISTRY if name is None else (name,))


def algorithms() -> list[str]:
    """Names of every available algorithm: built-in, registered, and installed plugins.

    Plugins are listed without being imported; one named like a registered algorithm is
    reported (:class:`PluginWarning`, "name clash refused") and not listed twice.
    """
    _load_builtins()
    _refuse_clashes()
    names = list(_REGISTRY)
    names += [ep.name for ep in _plugin_entry_points() if ep.name not in _REGISTRY]
    return names


def get_algorithm(name: str) -> type[IOCAlgorithm]:
    """The algorithm class registered as ``name`` (loading its plugin if needed)."""
    if not isinstance(name, str):
        raise AlgorithmError(f"an algorithm name must be a string, got {type(name).__name__}")
    _load_builtins()
    if name in _REGISTRY:
        _refuse_clashes(name)
    else:
        for ep in _plugin_entry_points():
            if ep.name == name and _load_plugin(ep):
                break
    if name not in _REGISTRY:
        raise AlgorithmError(f"unknown algorithm {shown(name)}; valid: {', '.join(sorted(_loadable()))}")
    return _REGISTRY[name]


def _loadable() -> list[str]:
    """Names that load (plugins that fail to import or clash are left out), without warnings."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PluginWarning)
        names = list(_REGISTRY)
        for ep in _plugin_entry_points():
            if ep.name not in _REGISTRY and _load_plugin(ep):
                names.append(ep.name)
    return names


def make_algorithm(name: str, **config: Any) -> IOCAlgorithm:
    """An instance of algorithm ``name`` with config overrides.

    Raises :class:`AlgorithmError` (a ``ValueError``) for an unknown algorithm, an unknown
    field, a value of the wrong type or one the config rejects.
    """
    cls = get_algorithm(name)
    overrides = _checked_overrides(name, cls, config)
    try:
        return cls(**overrides)
    except (TypeError, ValueError) as exc:
        raise AlgorithmError(f"bad config for algorithm {name!r}: {_one_line(exc)}") from None


def check_config(config: Any) -> dict[str, Any]:
    """``config`` as a dict if it is a mapping from field names to values, else :class:`AlgorithmError`."""
    if config is None:
        return {}
    if not isinstance(config, Mapping) or not all(isinstance(k, str) for k in config):
        raise AlgorithmError(
            f"an algorithm config must be a mapping of field names to values, got {type(config).__name__}"
        )
    return dict(config)


def canonical_config(name: str, config: Mapping[str, Any] | None) -> dict[str, Any]:
    """The fields of ``config`` whose effective value differs from the algorithm's default.

    Configs that only spell out defaults, or give ``1`` for a float field that defaults
    to ``1.0``, reduce to the same dict; values are JSON-ready (tuples become lists).
    Raises :class:`AlgorithmError` as :func:`make_algorithm` does.
    """
    config = check_config(config)
    effective = _effective_config(name, config)
    if not effective:  # not a dataclass config: the overrides are all there is
        return {k: to_jsonable(v) for k, v in sorted(config.items())}
    return config_overrides(name, effective)


def config_overrides(name: str, effective: Mapping[str, Any]) -> dict[str, Any]:
    """The fields of an effective (full) config that differ from ``name``'s defaults."""
    defaults = _effective_config(name, {})
    return {k: to_jsonable(v) for k, v in sorted(effective.items()) if to_jsonable(defaults.get(k)) != to_jsonable(v)}


def _effective_config(name: str, config: Mapping[str, Any]) -> dict[str, Any]:
    """The full config ``config``'s overrides give algorithm ``name``, checked as
    :func:`make_algorithm` checks them, without building the algorithm (a case builds it
    once, to run it) unless it builds or reports its config its own way."""
    cls = get_algorithm(name)
    own_way = cls.__init__ is not IOCAlgorithm.__init__ or cls.config_dict is not IOCAlgorithm.config_dict
    if own_way or not (isinstance(cls.Config, type) and dataclasses.is_dataclass(cls.Config)):
        return make_algorithm(name, **config).config_dict()
    overrides = _checked_overrides(name, cls, config)
    try:
        return dataclasses.asdict(cls.Config(**overrides))
    except (TypeError, ValueError) as exc:
        raise AlgorithmError(f"bad config for algorithm {name!r}: {_one_line(exc)}") from None


def _checked_overrides(name: str, cls: type[IOCAlgorithm], config: Mapping[str, Any]) -> dict[str, Any]:
    """Overrides checked against the ``Config`` dataclass: known fields, right types.

    Ints are accepted (and converted) for float fields and lists for tuple fields, as JSON
    gives them; bools are not accepted as numbers.
    """
    config = check_config(config)
    target = cls.Config
    if not (isinstance(target, type) and dataclasses.is_dataclass(target)):
        return config
    fields = [f.name for f in dataclasses.fields(target) if f.init]
    unknown = [k for k in config if k not in fields]
    if unknown:
        raise AlgorithmError(
            f"bad config for algorithm {name!r}: unknown field(s) {', '.join(unknown)}; fields: {', '.join(fields)}"
        )
    try:
        hints = typing.get_type_hints(target)
    except Exception:  # unresolvable annotations: leave the values to the config itself
        return config
    out = {}
    for key, value in config.items():
        try:
            out[key] = coerce(value, hints.get(key, Any))
        except TypeMismatch as exc:
            raise AlgorithmError(f"bad config for algorithm {name!r}: {key} must be {exc}, got {value!r}") from None
    return out


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split())


def describe_algorithms() -> dict[str, str]:
    """Name -> one-line description, loading plugins (broken ones are reported and left out)."""
    out = {}
    for name in algorithms():
        try:
            out[name] = get_algorithm(name).description or "(no description)"
        except AlgorithmError:
            continue
    return out
