"""The track registry: the tracks whose cases the runner runs and whose records it reads.

A track plugs in as a :class:`~ioc_bench.runner.protocol.Track` (its record parser, its
suites, its board section), registered with :func:`register_track`, or named in the
entry-point group ``ioc_bench.tracks`` (``name = "package.module:TRACK"``) of an installed
package. The built-in tracks are named as data (:data:`ioc_bench.tracks.BUILTIN_TRACKS`)
and loaded on first use: this package imports no track. The order of registration is the
board's order of sections; a suite name belongs to one track.
"""

from __future__ import annotations

import importlib
import importlib.metadata
import warnings
from typing import Any

from ioc_bench.runner.protocol import Record, Suite, Track
from ioc_bench.tracks import BUILTIN_TRACKS
from ioc_bench.validation import shown

ENTRY_POINT_GROUP = "ioc_bench.tracks"

_REGISTRY: dict[str, Track] = {}
_LOADED: list[bool] = []


class TrackError(ValueError):
    """An unknown or clashing track or suite."""


class TrackPluginWarning(UserWarning):
    """A track plugin could not be loaded and was skipped."""


def register_track(track: Track) -> Track:
    """Add ``track`` (``TrackError`` for a name, a suite name or an unnamed-records track already taken)."""
    if not isinstance(track, Track):
        raise TrackError(f"a track must be a Track, got {type(track).__name__}")
    existing = _REGISTRY.get(track.name)
    if existing is track:
        return track
    if existing is not None:
        raise TrackError(f"track {track.name!r} is already registered")
    for other in _REGISTRY.values():
        if not (track.names_itself or other.names_itself):
            raise TrackError(f"track {track.name!r}: the records of track {other.name!r} already name no track")
        clash = sorted(set(track.suites) & set(other.suites))
        if clash:
            raise TrackError(f"track {track.name!r}: suite {clash[0]!r} is already one of track {other.name!r}")
    _REGISTRY[track.name] = track
    return track


def unregister_track(name: str) -> None:
    """Remove the track ``name`` (a test's own track, once done with)."""
    _REGISTRY.pop(name, None)


def tracks() -> list[Track]:
    """Every track: the built-in ones, installed plugins, then those registered since."""
    _load()
    return list(_REGISTRY.values())


def get_track(name: str) -> Track:
    """The track called ``name`` (``TrackError`` listing the valid ones)."""
    known = {track.name: track for track in tracks()}
    if name not in known:
        raise TrackError(f"track must be one of {', '.join(known)}, got {shown(name)}")
    return known[name]


def track_of(data: Any) -> Track:
    """The track whose record ``data`` (decoded JSON) is: by its ``track``, else the track whose records name none."""
    name = data.get("track") if isinstance(data, dict) else None
    return get_track(name) if name is not None else _unnamed()


def track_of_record(record: Record) -> Track:
    """The track a parsed record is of (by its ``track`` attribute, else the one whose records name none)."""
    name = getattr(record, "track", None)
    return get_track(name) if name is not None else _unnamed()


def _unnamed() -> Track:
    for track in tracks():
        if not track.names_itself:
            return track
    raise TrackError(f"a record must name its track, one of {', '.join(t.name for t in tracks())}")


def suites() -> dict[str, Suite]:
    """Every track's suites by name, track by track."""
    return {name: suite for track in tracks() for name, suite in track.suites.items()}


def get_suite(name: str) -> Suite:
    """The suite called ``name``, of whichever track (``TrackError`` listing the valid ones)."""
    known = suites()
    if name not in known:
        raise TrackError(f"unknown suite {name!r}; valid: {', '.join(known)}")
    return known[name]


def _load() -> None:
    """Register the built-in tracks and installed track plugins, once per process."""
    if _LOADED:
        return
    _LOADED.append(True)
    added = dict(_REGISTRY)  # tracks registered before the first use come after the built-in ones
    _REGISTRY.clear()
    for target in BUILTIN_TRACKS.values():
        module, attr = target.split(":")
        register_track(getattr(importlib.import_module(module), attr))
    for ep in importlib.metadata.entry_points(group=ENTRY_POINT_GROUP):
        _load_plugin(ep)
    for track in added.values():
        register_track(track)


def _load_plugin(ep: importlib.metadata.EntryPoint) -> None:
    try:
        register_track(ep.load())
    except Exception as exc:  # a plugin's import may fail in any way
        warnings.warn(f"track plugin {ep.name!r} ({ep.value}) skipped: {exc}", TrackPluginWarning, stacklevel=3)
