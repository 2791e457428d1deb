"""Registration by string entry point: ``ioc_bench`` imports neither ``envs`` nor MuJoCo."""

from __future__ import annotations

import subprocess
import sys

import gymnasium as gym


def test_make_with_module_prefix_registers_and_builds():
    env = gym.make("envs:IOCBench/PlanarWalker-v2")
    assert env.spec is not None
    assert env.spec.id == "IOCBench/PlanarWalker-v2"
    assert env.spec.max_episode_steps == 1000
    assert env.spec.entry_point == "envs.planar_walker:PlanarWalkerEnv"
    env.close()


def test_register_envs_form():
    import envs

    gym.register_envs(envs)
    assert envs.PLANAR_WALKER_ID in gym.registry


def _modules_after(code: str) -> set[str]:
    out = subprocess.run(
        [sys.executable, "-c", code + "; import sys; print(' '.join(sys.modules))"],
        check=True,
        capture_output=True,
        text=True,
    )
    return set(out.stdout.split())


def test_ioc_bench_and_its_cli_import_neither_envs_nor_mujoco():
    loaded = _modules_after("import ioc_bench, ioc_bench.cli; ioc_bench.cli.build_parser()")
    assert "envs" not in loaded
    assert "mujoco" not in loaded


def test_importing_envs_does_not_import_mujoco():
    loaded = _modules_after("import envs")
    assert "mujoco" not in loaded
    assert "envs.planar_walker" not in loaded
