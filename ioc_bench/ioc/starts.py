"""Where a fit of the weights starts, shared by the methods that fit an optimum to the data.

``bilevel`` and ``single-level`` both start at the better (by tracking error) of the uniform
weights and the inverse-KKT weights. When neither start's optimum explains the observation
within its noise (the misfit test, :mod:`ioc_bench.ioc.misfit`), :func:`further_starts` are
ranked with them: a forward solve that fails at the inverse-KKT weights (one weight near
zero) left the fit at the uniform start, where it stuck (measured under
``noise-kinematics``, ``docs/ioc.md``). The design is over the features, not over the
benchmark's weight sets (which are 10:1).
"""

from __future__ import annotations

import numpy as np

#: The lowest weight (relative to the largest, before normalising) of the floored
#: inverse-KKT start.
MORE_STARTS = 0.05
#: How much larger the dominant feature's weight is in its start.
DOMINANT = 3.0


def unit(u: np.ndarray) -> np.ndarray:
    """``u`` scaled to unit norm."""
    return u / np.linalg.norm(u)


def further_starts(raw: np.ndarray) -> list[np.ndarray]:
    """The unit-norm starts tried when the first two do not fit: the inverse-KKT weights
    ``raw`` floored at :data:`MORE_STARTS` of their largest, and one start per feature with
    that feature's weight :data:`DOMINANT` times the others'."""
    raw = np.asarray(raw, dtype=float)
    more = [unit(np.maximum(raw / max(raw.max(), 1e-300), MORE_STARTS))]
    more += [unit(np.where(np.arange(raw.size) == i, DOMINANT, 1.0)) for i in range(raw.size)]
    return more
