"""Named blocks of a flat NLP vector, and named groups of constraints.

CasADi's NLP interface takes one flat decision vector and one flat constraint vector; these
two small classes keep an index map so that every block and constraint group is addressed
by name (packing a warm start, unpacking a solution, reporting which group is violated).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np


@dataclass
class Layout:
    """Named, shaped blocks laid end to end in one flat vector."""

    blocks: dict[str, tuple[int, tuple[int, ...]]] = field(default_factory=dict)
    size: int = 0

    def add(self, name: str, shape: tuple[int, ...]) -> None:
        if name in self.blocks:
            raise ValueError(f"duplicate block {name!r}")
        self.blocks[name] = (self.size, shape)
        self.size += int(np.prod(shape, dtype=int))

    def slice(self, name: str) -> slice:
        start, shape = self.blocks[name]
        return slice(start, start + int(np.prod(shape, dtype=int)))

    def views(self, flat: ca.SX) -> dict[str, np.ndarray]:
        """Object arrays of scalar symbols, one per block, in the block's shape."""
        elems = ca.vertsplit(flat)
        out = {}
        for name, (start, shape) in self.blocks.items():
            n = int(np.prod(shape, dtype=int))
            arr = np.empty(n, dtype=object)
            arr[:] = elems[start : start + n]
            out[name] = arr.reshape(shape)
        return out

    def unpack(self, flat: Any) -> dict[str, np.ndarray]:
        flat = np.asarray(flat, dtype=float).ravel()
        return {name: flat[self.slice(name)].reshape(shape) for name, (_, shape) in self.blocks.items()}

    def pack(self, values: Mapping[str, Any], default: float = 0.0) -> np.ndarray:
        flat = np.full(self.size, default, dtype=float)
        for name, value in values.items():
            _, shape = self.blocks[name]
            flat[self.slice(name)] = np.broadcast_to(np.asarray(value, dtype=float), shape).ravel()
        return flat


@dataclass
class Constraints:
    """Named groups of constraints ``lb <= g <= ub`` built up one group at a time."""

    exprs: list[Any] = field(default_factory=list)
    lb: list[float] = field(default_factory=list)
    ub: list[float] = field(default_factory=list)
    groups: dict[str, slice] = field(default_factory=dict)

    def add(self, name: str, exprs: Iterable[Any], lb: float = 0.0, ub: float = 0.0) -> None:
        items = list(np.asarray(list(exprs), dtype=object).ravel())
        start = len(self.exprs)
        self.exprs += items
        self.lb += [lb] * len(items)
        self.ub += [ub] * len(items)
        previous = self.groups.get(name)
        if previous is not None and previous.stop != start:
            raise ValueError(f"constraint group {name!r} must be added contiguously")
        self.groups[name] = slice(previous.start if previous else start, start + len(items))

    def vector(self) -> ca.SX:
        return ca.vertcat(*self.exprs)

    def violation(self, g: Any) -> dict[str, float]:
        """Largest bound violation of each group at constraint values ``g``."""
        g = np.asarray(g, dtype=float).ravel()
        excess = np.maximum(np.maximum(np.asarray(self.lb) - g, g - np.asarray(self.ub)), 0.0)
        return {name: float(excess[s].max(initial=0.0)) for name, s in self.groups.items()}
