"""The synthetic track: IOC on steps the trajectory optimizer made for known weights.

``conditions`` (what an IOC is shown: noise, wrong model, distractors), ``suites`` (the case
grids as data), ``demos`` (demonstrations, solved once and cached), ``observe``, ``case``
(one case: run, scored), ``scoring`` and ``transfer``, ``results`` (a record read back and
checked), ``board`` (the track's leaderboard section) with ``ranking``, ``robustness`` and
``statistics``, ``compare`` (two runs, cell by cell) and ``track`` (the track as the runner
registers it).
"""
