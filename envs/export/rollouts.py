"""A Minari dataset of a demonstration tracked in the Gymnasium environment (the ``export`` extra).

**The rollout.** ``gymnasium.make("envs:IOCBench/PlanarWalker-v2", params=demo.params,
demonstration=demo)`` is reset (seed 0) to the demonstration's initial state and stepped
with :class:`envs.TrackingPolicy` (feed-forward torques plus PD tracking, by the step's
phase) until the episode ends: Gymnasium's time limit of 1000 steps (10 time units, 7-8
steps of the benchmark's gaits) or a fall. Environment and policy are deterministic, so one
episode is the whole dataset.

**The dataset** (Minari 0.5, HDF5 storage): observations (``n + 1`` rows of the
environment's 17, docs/environment.md), actions (``n`` rows of 4 motor torques), rewards,
terminations, truncations, and ``infos``, each key ``n + 1`` values, the first at the reset
(as Minari's ``DataCollector`` records them):

- ``phi_hip``, ``phi_knee``, ``phi_dtau``: the step's increments of the cost features, the
  environment's ``info`` (paper's units; a demonstration's feature is their sum over its
  step divided by the step's duration in seconds); 0 at the reset;
- ``reward_forward``, ``reward_hip``, ``reward_knee``, ``reward_dtau``: the reward's terms
  (the reward is their sum); 0 at the reset;
- ``x_position``: the hip's forward position, which the observation leaves out;
- ``stance_leg``: the leg in the stance role, 0 for ``a`` and 1 for ``b``;
- ``heel_strikes``: heel strikes since the reset.

Its environment spec is ``IOCBench/PlanarWalker-v2`` with the demonstration's weights, so
``dataset.recover_environment()`` rewards as the dataset does (from a standing start,
unless reset with ``options={"demonstration": ...}``); its description names the
demonstration, weights, speed and model.

**Where it goes.** Minari keeps datasets under one folder by id
(``<root>/<namespace>/<name>-v<version>``) and finds that folder by
``MINARI_DATASETS_PATH`` (default ``~/.minari/datasets``). The dataset is made in a hidden
temporary folder under ``root`` and moved to its place in one rename, so it is either
absent or whole. Minari never overwrites a dataset, and neither does this module.
"""

from __future__ import annotations

import contextlib
import dataclasses
import os
import re
import shutil
import tempfile
import warnings
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import gymnasium
import numpy as np

from envs.planar_walker import REWARD_TERMS
from envs.tracking import TrackingPolicy
from ioc_bench.demo import Demonstration
from ioc_bench.features import COST_FEATURES
from ioc_bench.fileio import TEMP_SUFFIX
from ioc_bench.model.mjcf import LEGS

#: The extra that installs Minari and its HDF5 storage.
EXTRA = "export"
#: The environment the rollouts run in (``module:id``, so that making it imports ``envs``).
ENV_ID = "envs:IOCBench/PlanarWalker-v2"
#: Namespace of the exported datasets' ids.
NAMESPACE = "ioc-bench"
#: Seed of the environment's reset (the reset from a demonstration uses no randomness).
SEED = 0
#: The ``infos`` keys that are a step's increments (0 at the reset): features, then reward terms.
STEP_KEYS: tuple[str, ...] = (*(f"phi_{f}" for f in COST_FEATURES), *REWARD_TERMS)
#: The ``infos`` keys of a dataset, in order.
INFO_KEYS: tuple[str, ...] = (*STEP_KEYS, "x_position", "stance_leg", "heel_strikes")
#: Environment variable by which Minari finds its datasets.
DATASETS_PATH_VARIABLE = "MINARI_DATASETS_PATH"


class MissingExtraError(ImportError):
    """Minari (or its HDF5 storage) is not installed."""


def import_minari() -> Any:
    """The ``minari`` module, or :class:`MissingExtraError` naming the extra that installs it."""
    try:
        import h5py  # noqa: F401  Minari's default (HDF5) storage
        import minari
    except ImportError as exc:
        raise MissingExtraError(
            f"the minari format needs Minari and h5py ({exc.name} is not installed): pip install 'ioc-bench[{EXTRA}]'"
        ) from None
    return minari


def default_root() -> Path:
    """Minari's datasets folder: ``$MINARI_DATASETS_PATH``, else ``~/.minari/datasets`` (Minari's own rule)."""
    import_minari()
    from minari.storage.datasets_root_dir import get_dataset_path

    return Path(get_dataset_path())


def dataset_id(stem: str) -> str:
    """The id of the dataset exported from a demonstration file named ``stem``.npz:
    ``ioc-bench/<stem>-v0``, every run of characters Minari's names do not take made ``-``."""
    name = re.sub(r"[^\w-]+", "-", stem, flags=re.ASCII).strip("-") or "demonstration"
    return f"{NAMESPACE}/{name}-v0"


@dataclass(frozen=True, eq=False)
class Rollout:
    """One episode of the tracking policy in the environment.

    Attributes:
        observations: (n + 1, 17) observations, the first after the reset.
        actions: (n, 4) actions (float32, ``MOTORS`` order).
        rewards, terminations, truncations: (n,) each.
        infos: ``INFO_KEYS`` -> (n + 1,) values, the first at the reset.
        spec: the environment's spec, with the demonstration's weights as its only argument.
    """

    observations: np.ndarray
    actions: np.ndarray
    rewards: np.ndarray
    terminations: np.ndarray
    truncations: np.ndarray
    infos: dict[str, np.ndarray]
    spec: Any

    def __len__(self) -> int:
        return len(self.rewards)


def rollout(demo: Demonstration) -> Rollout:
    """Track ``demo`` from its initial state until the episode ends (time limit or fall).

    Raises:
        ValueError: if ``demo`` cannot be tracked (a gait model without a MuJoCo model, a
            hip that does not move steadily forward over the stance foot).
    """
    policy = TrackingPolicy(demo)
    env = gymnasium.make(ENV_ID, params=demo.params, demonstration=demo)
    try:
        obs, info = env.reset(seed=SEED)
        observations, actions, rewards, terminations, truncations = [obs], [], [], [], []
        infos = [_info_row(info, None)]
        terminated = truncated = False
        while not (terminated or truncated):
            action = policy(obs, info)
            obs, reward, terminated, truncated, info = env.step(action)
            for rows, value in (
                (observations, obs),
                (actions, action),
                (rewards, reward),
                (terminations, terminated),
                (truncations, truncated),
            ):
                rows.append(value)
            infos.append(_info_row(info, info))
        spec = dataclasses.replace(env.spec, kwargs={"weights": [float(w) for w in env.unwrapped.weights]})
    finally:
        env.close()
    return Rollout(
        observations=np.array(observations, dtype=np.float64),
        actions=np.array(actions, dtype=np.float32),
        rewards=np.array(rewards, dtype=np.float64),
        terminations=np.array(terminations, dtype=bool),
        truncations=np.array(truncations, dtype=bool),
        infos={k: np.array([row[k] for row in infos]) for k in INFO_KEYS},
        spec=spec,
    )


def _info_row(info: dict[str, Any], step: dict[str, Any] | None) -> dict[str, Any]:
    """The dataset's ``infos`` of one reset (``step`` None) or step."""
    row: dict[str, Any] = {k: 0.0 if step is None else float(step[k]) for k in STEP_KEYS}
    row["x_position"] = float(info["x_position"])
    row["stance_leg"] = LEGS.index(info["stance_leg"])
    row["heel_strikes"] = int(info["heel_strikes"])
    return row


def description(demo: Demonstration, source: str | os.PathLike | None = None) -> str:
    """The dataset's description: what it holds and of which demonstration."""
    weights = ", ".join(f"{k} {v:.4g}" for k, v in demo.weights.items() if v)
    name = "" if source is None else f" {Path(source).name}"
    return (
        f"ioc-bench demonstration{name} (model {demo.model}, unit weights {weights}, speed {demo.task.speed:g}) "
        "tracked in IOCBench/PlanarWalker-v2 by envs.TrackingPolicy (feed-forward torques plus PD by the "
        "step's phase) from the demonstration's initial state until the episode ended. infos: the cost "
        "features' increments (phi_*), the reward terms, x_position, stance_leg (0 = a, 1 = b), heel_strikes. "
        f"Walker parameters: {demo.params.to_dict()}."
    )


def write_minari(
    demo: Demonstration,
    root: str | os.PathLike,
    dataset: str,
    source: str | os.PathLike | None = None,
) -> tuple[Path, Rollout]:
    """Write the rollout of ``demo`` as the Minari dataset ``dataset`` under ``root``.

    Load it with ``minari.load_dataset(dataset)`` when ``MINARI_DATASETS_PATH`` is ``root``.
    Returns the dataset's folder and the rollout.

    Raises:
        MissingExtraError: without Minari or h5py.
        ValueError: if the dataset exists already, ``dataset`` is not a Minari id, or as
            :func:`rollout`.
    """
    minari = import_minari()
    from minari.data_collector import EpisodeBuffer

    root = Path(root).absolute()  # Minari joins its paths in ways a relative root breaks
    target = check_dataset_free(root, dataset)
    data = rollout(demo)
    root.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=".ioc-bench-export.", suffix=TEMP_SUFFIX, dir=root))
    try:
        with _datasets_path(staging):
            buffer = EpisodeBuffer(
                id=0,
                seed=SEED,
                observations=data.observations,
                actions=data.actions,
                rewards=data.rewards,
                terminations=data.terminations,
                truncations=data.truncations,
                infos=dict(data.infos),
            )
            with warnings.catch_warnings():  # Minari asks for a code link and an e-mail address
                warnings.filterwarnings("ignore", category=UserWarning, module=r"minari\.")
                minari.create_dataset_from_buffers(
                    dataset,
                    [buffer],
                    env=data.spec,
                    eval_env=data.spec,
                    algorithm_name="ioc-bench TrackingPolicy",
                    author="ioc-bench export",
                    description=description(demo, source),
                )
        namespace = dataset.rpartition("/")[0]
        if namespace:
            (root / namespace).mkdir(parents=True, exist_ok=True)
            made = staging / namespace / "namespace_metadata.json"
            kept = root / namespace / "namespace_metadata.json"
            if made.is_file() and not kept.exists():
                os.replace(made, kept)
        os.rename(staging / dataset, target)  # refuses a folder that appeared meanwhile (unless empty)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return target, data


def check_dataset_free(root: Path, dataset: str) -> Path:
    """The folder the dataset ``dataset`` would take under ``root``; ``ValueError`` if the id is
    not Minari's form or the folder exists (Minari never overwrites a dataset)."""
    import_minari()
    from minari.dataset.minari_dataset import parse_dataset_id

    parse_dataset_id(dataset)  # ValueError for a malformed id
    target = Path(root) / dataset
    if os.path.lexists(target):
        raise ValueError(f"the Minari dataset {dataset} exists already in {root}: Minari datasets are not overwritten")
    return target


@contextlib.contextmanager
def _datasets_path(path: Path) -> Iterator[None]:
    """Point Minari at ``path`` for the duration (it reads the variable on every call)."""
    old = os.environ.get(DATASETS_PATH_VARIABLE)
    os.environ[DATASETS_PATH_VARIABLE] = str(path)
    try:
        yield
    finally:
        if old is None:
            os.environ.pop(DATASETS_PATH_VARIABLE, None)
        else:
            os.environ[DATASETS_PATH_VARIABLE] = old
