"""The figure of a person's and the walker's leg segment angles."""

from __future__ import annotations

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
