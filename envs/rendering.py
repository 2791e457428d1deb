"""Choosing the environment's renderer: MuJoCo's OpenGL renderer or the stick figure.

``"mujoco"`` means MuJoCo's renderer or an error, never anything else; ``"stick"`` is the
matplotlib stick figure (no OpenGL); ``"auto"`` tries MuJoCo and falls back to the stick
figure. A failed attempt is remembered for the process, so later ``"auto"`` environments
skip straight to the stick figure (making a context that cannot be made is slow and
noisy), while an explicit ``"mujoco"`` always tries again and raises if it fails.
"""

from __future__ import annotations

import warnings
from typing import Any

import mujoco

from ioc_bench.model.params import WalkerParams

#: The renderer choices of the environment's ``renderer`` argument.
RENDERER_CHOICES: tuple[str, ...] = ("auto", "mujoco", "stick")
#: Why MuJoCo's renderer could not be made in this process (None: not failed so far).
_GL_FAILURE: str | None = None


class RendererUnavailableError(RuntimeError):
    """``renderer="mujoco"`` was asked for and no OpenGL context can be made."""


def make_renderer(choice: str, model: mujoco.MjModel, params: WalkerParams, width: int, height: int) -> tuple[Any, str]:
    """A renderer for ``choice`` and the name of the one made (``"mujoco"`` or ``"stick"``).

    Raises:
        RendererUnavailableError: ``choice == "mujoco"`` and MuJoCo cannot render here.
    """
    global _GL_FAILURE
    if choice not in RENDERER_CHOICES:
        raise ValueError(f"renderer must be one of {RENDERER_CHOICES}, got {choice!r}")
    if choice == "mujoco" or (choice == "auto" and _GL_FAILURE is None):
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # GLFW warns before failing without a display
                return mujoco.Renderer(model, height, width), "mujoco"
        except Exception as exc:
            _GL_FAILURE = " ".join(f"{type(exc).__name__}: {exc}".split())
            if choice == "mujoco":
                raise RendererUnavailableError(
                    f"renderer='mujoco' cannot make an OpenGL context here ({_GL_FAILURE}); set MUJOCO_GL=egl or "
                    "osmesa before MuJoCo is imported, or use renderer='stick'"
                ) from exc
    from envs.drawing import StickRenderer

    return StickRenderer(params, width, height), "stick"
