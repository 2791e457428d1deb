"""Checks of values that arrive from outside: seeds, counts, JSON against type annotations.

Used where values arrive from users or files: seeds and worker counts of the Python API,
algorithm config overrides from the command line, case records read back from disk. A
bad value is a one-line ``ValueError`` saying what was expected. Values are shown in
messages by :func:`shown` (short, whatever their size) and JSON text from outside is read
by :func:`load_json` (nesting bounded, so never a ``RecursionError``).
"""

from __future__ import annotations

import dataclasses
import json
import math
import types
import typing
from collections.abc import Mapping
from typing import Any

import numpy as np

#: Deepest nesting of JSON read from outside (configs, result files, demonstration headers);
#: ours is at most a few levels deep.
MAX_JSON_DEPTH = 64
#: Largest integer a JSON value of ours may hold unless a field says otherwise: a C ``int``,
#: what IPOPT's counts take. Counts beyond it would only hang or crash deep inside.
MAX_INT = 2**31 - 1
#: Longest message (characters) of a one-line error; longer ones are cut in the middle.
MAX_MESSAGE = 400


class TypeMismatch(ValueError):
    """A value does not match its annotation; the message says what was expected."""


def shown(value: Any, limit: int = 60) -> str:
    """``repr(value)`` in about ``limit`` characters, safe for huge integers and containers: the
    one way a value from outside is shown in a message. Text keeps its start and its end
    (:func:`short_word`: a deep path keeps the names it ends with); other values are cut at
    the end."""
    if isinstance(value, str):
        return repr(short_word(value, limit))
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 4 * limit:
        return f"an integer of about {int(value.bit_length() * math.log10(2)) + 1} digits"
    if isinstance(value, (list, tuple, dict, set, frozenset)) and len(value) > limit:
        return f"a {type(value).__name__} of {len(value)} items"
    try:
        text = repr(value)
    except ValueError:  # holds an integer too long for str()
        return f"a {type(value).__name__}"
    return text if len(text) <= limit else text[: limit - 3] + "..."


#: Shortest a word of a one-line error is cut to (a path keeps this many characters of its ends).
MIN_WORD = 40


def short_word(word: str, limit: int) -> str:
    """``word`` if it has at most ``limit`` characters, else its first and last characters
    around ``...`` (a deep path keeps where it starts and the names it ends with)."""
    if len(word) <= limit:
        return word
    head = (limit - 3) * 2 // 5
    return f"{word[:head]}...{word[len(word) - (limit - 3 - head) :]}"


def one_line(text: str, limit: int = MAX_MESSAGE) -> str:
    """``text`` on one line of at most ``limit`` characters.

    A line that is too long has its longest words (deep paths, as a rule) shortened to
    their ends first, none below :data:`MIN_WORD` characters, so the sentence around them
    survives; what is still too long is cut in the middle.
    """
    words = str(text).split()
    text = " ".join(words)
    if len(text) <= limit:
        return text
    cap = _word_cap(words, limit)
    text = " ".join(short_word(word, cap) for word in words)
    if len(text) <= limit:
        return text
    head = (limit - 5) * 2 // 3
    return f"{text[:head]} ... {text[len(text) - (limit - 5 - head) :]}"


def _word_cap(words: list[str], limit: int) -> int:
    """The longest word length (at least :data:`MIN_WORD`) that makes ``words`` fit in ``limit``."""

    def length(cap: int) -> int:
        return sum(min(len(w), cap) for w in words) + len(words) - 1

    low, high = MIN_WORD, max(len(w) for w in words)
    while low < high:
        mid = (low + high + 1) // 2
        low, high = (mid, high) if length(mid) <= limit else (low, mid - 1)
    return low


def load_json(text: str | bytes, max_depth: int = MAX_JSON_DEPTH) -> Any:
    """Decode JSON from outside; ``ValueError`` (one line) for bad JSON, an object with a key
    twice, or nesting beyond ``max_depth``.

    Python's decoder recurses once per level and raises ``RecursionError`` on deep
    nesting; here that, and any nesting deeper than ``max_depth``, is a ``ValueError``.
    """
    try:
        value = json.loads(text, object_pairs_hook=_unique_keys)
    except RecursionError:
        raise ValueError(f"JSON nested deeper than {max_depth} levels") from None
    except DuplicateKey:
        raise
    except json.JSONDecodeError as exc:
        raise ValueError(f"not JSON ({one_line(str(exc), 120)})") from None
    except ValueError:  # Python refuses to convert an integer literal of over 4300 digits
        raise ValueError("JSON holding an integer of over 4300 digits") from None
    if json_depth(value) > max_depth:
        raise ValueError(f"JSON nested deeper than {max_depth} levels")
    return value


class DuplicateKey(ValueError):
    """A JSON object names one key twice (which value was meant is unknowable)."""


def _unique_keys(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    value = dict(pairs)
    if len(value) != len(pairs):
        seen: set[str] = set()
        twice = next(k for k, _ in pairs if k in seen or seen.add(k))
        raise DuplicateKey(f"JSON object with the key {shown(twice)} twice")
    return value


def json_depth(value: Any) -> int:
    """Nesting depth of a decoded JSON value (a scalar is 0), without recursion."""
    deepest, stack = 0, [(value, 0)]
    while stack:
        item, depth = stack.pop()
        if isinstance(item, dict):
            item = list(item.values())
        if isinstance(item, (list, tuple)):
            deepest = max(deepest, depth + 1)
            stack.extend((v, depth + 1) for v in item if isinstance(v, (list, tuple, dict)))
    return deepest


def check_seed(seed: Any, what: str = "seed") -> int:
    """``seed`` if it is a non-negative integer (what NumPy's generators accept), else ``ValueError``."""
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"{what} must be a non-negative integer, got {shown(seed)}")
    return int(seed)


def check_non_negative(value: Any, what: str) -> float:
    """``value`` if it is a finite real number >= 0 (not a bool), else ``ValueError``."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise ValueError(f"{what} must be a finite number >= 0, got {shown(value)}")
    if not (math.isfinite(value) and value >= 0):
        raise ValueError(f"{what} must be a finite number >= 0, got {shown(value)}")
    return float(value)


def check_count(value: Any, what: str, optional: bool = False, maximum: int | None = None) -> int | None:
    """``value`` if it is an integer >= 1 (and <= ``maximum``; or None when ``optional``), else ``ValueError``."""
    if optional and value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise ValueError(f"{what} must be an integer >= 1{' or None' if optional else ''}, got {shown(value)}")
    if maximum is not None and value > maximum:
        raise ValueError(f"{what} must be at most {maximum}, got {shown(int(value))}")
    return int(value)


def coerce(value: Any, hint: Any, nonfinite: bool = False, max_int: int | None = MAX_INT) -> Any:
    """``value`` checked against ``hint`` and converted as JSON needs.

    Understands ``Any``, ``bool``, ``int``, ``float``, ``str``, ``None``, unions,
    ``tuple[X, ...]``, fixed tuples, ``list[X]`` and ``dict[K, V]``; other annotations pass
    the value through unchecked. Ints are accepted (and converted) for floats and lists
    for tuples, as JSON gives them; bools are never numbers. With ``nonfinite``, floats
    may be NaN or infinite and ``None`` stands for NaN (as JSON stores NaN); otherwise
    floats must be finite. Integers must lie within ``±max_int`` (None: any size).
    """
    return _coerce(value, hint, _Mode(nonfinite, max_int))


class _Mode(typing.NamedTuple):
    nonfinite: bool
    max_int: int | None


def _coerce(value: Any, hint: Any, mode: _Mode) -> Any:
    nonfinite = mode.nonfinite
    origin, args = typing.get_origin(hint), typing.get_args(hint)
    if hint is Any or hint is object:
        return value
    if origin in (typing.Union, types.UnionType):
        if value is None and type(None) in args:
            return None  # an optional value that is absent (not a NaN stored as null)
        for option in args:
            try:
                return _coerce(value, option, mode)
            except TypeMismatch:
                continue
        raise TypeMismatch(" or ".join(describe(a, nonfinite) for a in args))
    if hint in _SCALARS:
        return _scalar(value, hint, mode)
    if origin in (tuple, list):
        return _sequence(value, hint, mode)
    if origin is dict or hint is dict:
        if not isinstance(value, dict):
            raise TypeMismatch(describe(hint, nonfinite))
        if not args:
            return value
        try:
            return {_coerce(k, args[0], mode): _coerce(v, args[1], mode) for k, v in value.items()}
        except TypeMismatch:
            raise TypeMismatch(describe(hint, nonfinite)) from None
    return value


def json_fields(
    cls: type,
    data: Any,
    where: str = "",
    extra: Mapping[str, Any] | None = None,
    hints: Mapping[str, Any] | None = None,
    max_int: int | None = None,
) -> dict[str, Any]:
    """The fields of the dataclass ``cls`` in the decoded JSON object ``data``, each checked
    against its annotation (or its entry in ``hints``) by :func:`coerce`, NaN stored as null.

    ``extra`` maps the keys a file may hold beside the fields to their annotations: checked,
    then left out. Integers must lie within ``±max_int`` (None: any size). ``ValueError``
    naming the first problem (a field missing, a key unknown, a value of the wrong type),
    prefixed by ``where`` (the part of the file it is in).
    """
    at = f"{where}: " if where else ""
    if not isinstance(data, dict):
        raise ValueError(f"{at}expected a JSON object, got {json_kind(data)}")
    annotations = typing.get_type_hints(cls) | dict(hints or {})
    extra = dict(extra or {})
    required = [
        f.name
        for f in dataclasses.fields(cls)
        if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING
    ]
    missing = [k for k in required if k not in data]
    if missing:
        raise ValueError(f"{at}missing field(s) {', '.join(missing)}")
    unknown = [k for k in data if k not in annotations and k not in extra]
    if unknown:
        raise ValueError(f"{at}unknown field(s) {', '.join(one_line(str(k), 40) for k in unknown[:5])}")
    values = {}
    for key, value in data.items():
        hint = annotations[key] if key in annotations else extra[key]
        try:
            checked = coerce(value, hint, nonfinite=True, max_int=max_int)
        except TypeMismatch as exc:
            raise ValueError(f"{where + '.' if where else ''}{key} must be {exc}, got {json_kind(value)}") from None
        if key in annotations:
            values[key] = checked
    return values


def json_kind(value: Any) -> str:
    """What a JSON value is, as a message shows it: ``null``, a short literal, or its type."""
    if value is None:
        return "null"
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 128:
        return shown(value)
    text = json.dumps(value) if isinstance(value, (bool, int, float, str)) else type(value).__name__
    return text if len(text) <= 40 else text[:37] + "..."


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


def _scalar(value: Any, hint: type, mode: _Mode) -> Any:
    nonfinite = mode.nonfinite
    number = isinstance(value, (int, float)) and not isinstance(value, bool)
    if hint is float:
        if nonfinite and value is None:
            return math.nan
        try:
            converted = float(value) if number else None
        except OverflowError:  # an integer beyond any float
            converted = None
        if converted is not None and (nonfinite or math.isfinite(converted)):
            return converted
    elif hint is int:
        if number and isinstance(value, int):
            if mode.max_int is not None and abs(value) > mode.max_int:
                raise TypeMismatch(f"an integer within ±{mode.max_int}")
            return value
    elif hint is type(None):
        if value is None:
            return None
    elif isinstance(value, hint):
        return value
    raise TypeMismatch(describe(hint, nonfinite))


def _sequence(value: Any, hint: Any, mode: _Mode) -> Any:
    nonfinite = mode.nonfinite
    origin, args = typing.get_origin(hint), typing.get_args(hint)
    if not isinstance(value, (list, tuple)):
        raise TypeMismatch(describe(hint, nonfinite))
    try:
        if origin is tuple and len(args) == 2 and args[1] is Ellipsis:
            return tuple(_coerce(v, args[0], mode) for v in value)
        if origin is tuple and args:
            if len(args) != len(value):
                raise TypeMismatch(describe(hint, nonfinite))
            return tuple(_coerce(v, a, mode) for v, a in zip(value, args))
        return origin(_coerce(v, args[0], mode) for v in value) if args else origin(value)
    except TypeMismatch:
        raise TypeMismatch(describe(hint, nonfinite)) from None


def _plural(text: str) -> str:
    text = text.removeprefix("a ").removeprefix("an ")
    return text if text.endswith("s") else f"{text}s"
