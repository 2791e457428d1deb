"""The figure of a person's and the walker's leg segment angles."""

from __future__ import annotations

import numpy as np
import pytest

from ioc_bench.human import load_step
from ioc_bench.human.figures import plot_human_fits


def test_plot_human_fits_writes_a_png(tmp_path) -> None:
    step = load_step("WBDS01", "T05")
    panels = [{"title": "WBDS01 T05", "human": step.angles, "walkers": {"shifted": step.angles + 0.1}}]
    path = plot_human_fits(panels, tmp_path / "fits.png")
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_plot_human_fits_needs_panels(tmp_path) -> None:
    with pytest.raises(ValueError, match="no panels"):
        plot_human_fits([], tmp_path / "fits.png")
    assert not (tmp_path / "fits.png").exists()


def test_a_case_figure_shows_every_speed_even_without_a_walker_step(tmp_path, one_trial_algorithm) -> None:
    """A failed case (no scores) still draws the person's steps."""
    from ioc_bench.human.case import HumanCaseSpec
    from ioc_bench.human.figures import plot_human_case

    humans = {code: load_step("WBDS01", code).angles for code in ("T05", "T04")}
    record = HumanCaseSpec("WBDS01", "T05", ("T04",), one_trial_algorithm, also_train=("T06",)).run({})
    assert record.failed and record.scores == {}
    assert plot_human_case(record, humans, tmp_path / "case.png").read_bytes()[:4] == b"\x89PNG"


def _score(code: str, role: str, estimate, **fields):
    """A made-up score of ``code`` whose estimate's angles are ``estimate`` (None: failed)."""
    from ioc_bench.human.record import SpeedScore

    nan = float("nan")
    return SpeedScore(
        code, role, 0.3, 0.7, "Solve_Succeeded", 1.0, 5.0, 6.0, 5.0, "estimate", 0.2, True, "", nan, None,
        nan, nan, nan, 0.1, 0.2, 1.0, angles={"estimate": estimate, "nominal": None}, **fields,
    )  # fmt: skip


def _case(scores: dict):
    """A made-up converged case of WBDS01 trained at T05 with ``scores`` by speed code."""
    from ioc_bench.human.record import HumanResult

    return HumanResult(
        "WBDS01", "T05", ("T04",), "bilevel", 0, {}, 1, (), (), (), "walker", "bilevel", ("a", "b"), "converged",
        "", (0.6, 0.8), 1.0, 2, 2.0, scores,
    )  # fmt: skip


def _angles(seed: int):
    return np.random.default_rng(seed).normal(0, 0.3, (11, 4))


def test_a_continued_prediction_adds_a_row_of_the_change_of_angles(tmp_path) -> None:
    from ioc_bench.human.figures import case_panels, plot_human_case

    humans = {"T05": _angles(1), "T04": _angles(2)}
    walker = {"T05": _angles(3), "T04": _angles(4)}
    carried = {"continued_from": "T05", "change_r2": 0.42, "step_length_walker": 0.61}
    record = _case({
        "T05": _score("T05", "fit", walker["T05"].tolist()),
        "T04": _score("T04", "prediction", walker["T04"].tolist(), **carried),
    })  # fmt: skip
    panels = case_panels(record, humans)
    assert len(panels) == 3 and [p.get("ylabel") for p in panels] == [None, None, "change (deg)"]
    change = panels[-1]
    assert change["title"] == "T05->T04 change\nstep 0.61 L (person 0.70)"
    np.testing.assert_allclose(change["human"], humans["T04"] - humans["T05"])
    assert list(change["walkers"]) == ["walker's change (R^2 0.42)"]
    np.testing.assert_allclose(change["walkers"]["walker's change (R^2 0.42)"], walker["T04"] - walker["T05"])
    assert plot_human_case(record, humans, tmp_path / "case.png").read_bytes()[:4] == b"\x89PNG"

    # a failed walker step at either speed: the person's change alone
    failed = _case({**record.scores, "T05": _score("T05", "fit", None)})
    assert case_panels(failed, humans)[-1]["walkers"] == {}


def test_a_change_whose_source_speed_is_missing_is_left_out(tmp_path) -> None:
    from ioc_bench.human.figures import case_panels, plot_human_case

    record = _case({"T04": _score("T04", "prediction", _angles(4).tolist(), continued_from="T05")})
    humans = {"T04": _angles(2)}
    panels = case_panels(record, humans)
    assert len(panels) == 1 and "ylabel" not in panels[0]
    assert plot_human_case(record, humans, tmp_path / "case.png").read_bytes()[:4] == b"\x89PNG"
