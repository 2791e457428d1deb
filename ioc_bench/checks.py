"""Checks of values that arrive from outside: seeds, counts, JSON against type annotations.

Used where values arrive from users or files: seeds and worker counts of the Python API,
algorithm config overrides from the command line, case records read back from disk. A
bad value is a one-line ``ValueError`` saying what was expected.
"""

from __future__ import annotations

import math
import types
import typing
from typing import Any

import numpy as np


class TypeMismatch(ValueError):
    """A value does not match its annotation; the message says what was expected."""


def check_seed(seed: Any, what: str = "seed") -> int:
    """``seed`` if it is a non-negative integer (what NumPy's generators accept), else ``ValueError``."""
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"{what} must be a non-negative integer, got {seed!r}")
    return int(seed)


def check_count(value: Any, what: str, optional: bool = False) -> int | None:
    """``value`` if it is an integer >= 1 (or None when ``optional``), else ``ValueError``."""
    if optional and value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise ValueError(f"{what} must be an integer >= 1{' or None' if optional else ''}, got {value!r}")
    return int(value)


def coerce(value: Any, hint: Any, nonfinite: bool = False) -> Any:
    """``value`` checked against ``hint`` and converted as JSON needs.

    Understands ``Any``, ``bool``, ``int``, ``float``, ``str``, ``None``, unions,
    ``tuple[X, ...]``, fixed tuples, ``list[X]`` and ``dict[K, V]``; other annotations pass
    the value through unchecked. Ints are accepted (and converted) for floats and lists
    for tuples, as JSON gives them; bools are never numbers. With ``nonfinite``, floats
    may be NaN or infinite and ``None`` stands for NaN (as JSON stores NaN); otherwise
    floats must be finite.
    """
    origin, args = typing.get_origin(hint), typing.get_args(hint)
    if hint is Any or hint is object:
        return value
    if origin in (typing.Union, types.UnionType):
        if value is None and type(None) in args:
            return None  # an optional value that is absent (not a NaN stored as null)
        for option in args:
            try:
                return coerce(value, option, nonfinite)
            except TypeMismatch:
                continue
        raise TypeMismatch(" or ".join(describe(a, nonfinite) for a in args))
    if hint in _SCALARS:
        return _scalar(value, hint, nonfinite)
    if origin in (tuple, list):
        return _sequence(value, hint, nonfinite)
    if origin is dict or hint is dict:
        if not isinstance(value, dict):
            raise TypeMismatch(describe(hint, nonfinite))
        if not args:
            return value
        try:
            return {coerce(k, args[0], nonfinite): coerce(v, args[1], nonfinite) for k, v in value.items()}
        except TypeMismatch:
            raise TypeMismatch(describe(hint, nonfinite)) from None
    return value


def describe(hint: Any, nonfinite: bool = False) -> str:
    """``hint`` in words, as error messages use it ("a list of integers")."""
    if hint is float:
        return "a number" if nonfinite else "a finite number"
    if hint in _SCALARS:
        return _SCALARS[hint]
    origin, args = typing.get_origin(hint), typing.get_args(hint)
    if origin in (tuple, list) and args:
        return f"a list of {_plural(describe(args[0], nonfinite))}"
    if origin is dict or hint is dict:
        return "an object" if not args or args[1] is Any else f"an object of {_plural(describe(args[1], nonfinite))}"
    return getattr(hint, "__name__", str(hint))


_SCALARS = {bool: "true or false", int: "an integer", float: "a number", str: "a string", type(None): "null"}


def _scalar(value: Any, hint: type, nonfinite: bool) -> Any:
    number = isinstance(value, (int, float)) and not isinstance(value, bool)
    if hint is float:
        if nonfinite and value is None:
            return math.nan
        if number and (nonfinite or math.isfinite(value)):
            return float(value)
    elif hint is int:
        if number and isinstance(value, int):
            return value
    elif hint is type(None):
        if value is None:
            return None
    elif isinstance(value, hint):
        return value
    raise TypeMismatch(describe(hint, nonfinite))


def _sequence(value: Any, hint: Any, nonfinite: bool) -> Any:
    origin, args = typing.get_origin(hint), typing.get_args(hint)
    if not isinstance(value, (list, tuple)):
        raise TypeMismatch(describe(hint, nonfinite))
    try:
        if origin is tuple and len(args) == 2 and args[1] is Ellipsis:
            return tuple(coerce(v, args[0], nonfinite) for v in value)
        if origin is tuple and args:
            if len(args) != len(value):
                raise TypeMismatch(describe(hint, nonfinite))
            return tuple(coerce(v, a, nonfinite) for v, a in zip(value, args))
        return origin(coerce(v, args[0], nonfinite) for v in value) if args else origin(value)
    except TypeMismatch:
        raise TypeMismatch(describe(hint, nonfinite)) from None


def _plural(text: str) -> str:
    text = text.removeprefix("a ").removeprefix("an ")
    return text if text.endswith("s") else f"{text}s"
