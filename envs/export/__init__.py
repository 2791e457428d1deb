"""A demonstration in the formats other tools read (``ioc-bench export``; docs/exports.md).

- :mod:`~envs.export.joints`: one full stride (the step, then its mirror image built by the
  gait model's leg swap) as MuJoCo joint trajectories at a uniform rate in SI units, and
  the LocoMuJoCo-style ``qpos``/``qvel`` arrays written from it.
- :mod:`~envs.export.opensim`: the same stride as an OpenSim storage file (``.sto``) with
  the coordinate names of OpenSim's planar gait models.
- :mod:`~envs.export.rollouts`: a Minari dataset of the tracking policy's rollout in the
  Gymnasium environment, each step's cost-feature increments in its ``infos`` (needs the
  ``export`` extra).

The MuJoCo states come from the environment's own mapping of a demonstration
(:func:`envs.coordinates.to_generalized`, as :class:`envs.reference.DemoReference` uses it),
interpolated as the optimizer's Hermite-Simpson collocation assumes the motion between knots.
"""
