"""Shared pieces of the CLI: argument validation, error exits and report printing.

Every path a command takes goes through :func:`path_arg` when parsed and through
:func:`output_file`, :func:`output_dir`, :func:`input_dir` (the policy of
:mod:`ioc_bench.fileio`) before any work; commands that solve demonstrations check the
cache with :func:`check_cache` first.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import math
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any, NoReturn

from ioc_bench.fileio import to_jsonable
from ioc_bench.model.catalogue import DEFAULT_MODEL
from ioc_bench.paths import check_path_text
from ioc_bench.validation import load_json, one_line


class UsageError(Exception):
    """Bad command-line input: reported as one line, exit code 2."""


def fail(message: str) -> NoReturn:
    """Print ``message`` as one line (cut to a readable length) on stderr; exit with code 2."""
    print(one_line(message), file=sys.stderr)
    raise SystemExit(2)


def is_run_fault(exc: BaseException) -> bool:
    """Whether ``exc`` is a fault of the run's surroundings, reported in one line (exit 2):
    a file system error (full disk, a folder replaced by a file, no permission), a results
    folder or file the run cannot use, a demonstration file that does not read, a worker
    process that died. Anything else is a bug and keeps its traceback."""
    from ioc_bench.demo import DemonstrationFileError
    from ioc_bench.paths import PathError
    from ioc_bench.runner.results import ResultFileError
    from ioc_bench.trajopt.multistart import WorkerDied

    return isinstance(exc, (OSError, ResultFileError, DemonstrationFileError, PathError, WorkerDied))


def path_arg(text: str) -> Path:
    """An argparse type: a path that is usable text (not empty, no NUL, names not too long)."""
    try:
        return check_path_text(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(value) or value <= 0:
        raise argparse.ArgumentTypeError(f"must be a positive number, got {text!r}")
    return value


def positive_int(text: str) -> int:
    """An argparse type: an integer >= 1 (counts: workers, starts, repeats)."""
    return _int_at_least(text, 1)


def seed_int(text: str) -> int:
    """An argparse type: a seed, a non-negative integer (what NumPy's generators accept)."""
    return _int_at_least(text, 0)


def _int_at_least(text: str, minimum: int) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
    if value < minimum:
        raise argparse.ArgumentTypeError(f"must be >= {minimum}, got {text!r}")
    return value


@contextlib.contextmanager
def usage_errors(prefix: str = "") -> Iterator[None]:
    """Turn a ``ValueError`` (the library's bad-input error) into a one-line :class:`UsageError`."""
    try:
        yield
    except ValueError as exc:
        raise UsageError(one_line(prefix + str(exc))) from None


def output_file(path: Path, what: str = "--out") -> Path:
    """``path`` if a file can be written there, else :class:`UsageError` (checked before the work)."""
    from ioc_bench.paths import check_output_file

    with usage_errors(f"{what}: "):
        return check_output_file(path)


def output_dir(path: Path, what: str = "--out") -> Path:
    """``path`` if it is or can be made a writable directory, else :class:`UsageError`."""
    from ioc_bench.paths import check_output_dir

    with usage_errors(f"{what}: "):
        return check_output_dir(path)


def input_dir(path: Path, what: str = "results directory") -> Path:
    """``path`` if it is a folder to read (not under /proc, no link loop), else :class:`UsageError`."""
    from ioc_bench.paths import check_input_dir

    with usage_errors():
        return check_input_dir(path, what)


def check_cache() -> Path:
    """The demonstration cache folder if usable (:func:`ioc_bench.cache.cache_dir`), else
    :class:`UsageError`: checked before the work, not when the first demonstration is saved."""
    from ioc_bench.cache import check_cache as check

    with usage_errors():
        return check()


def json_object(text: str) -> dict:
    """An argparse type: a JSON object (e.g. algorithm config overrides); nesting bounded."""
    try:
        value = load_json(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    if not isinstance(value, dict):
        raise argparse.ArgumentTypeError(f"must be a JSON object, got {one_line(repr(text), 80)}")
    return value


def mujoco_log_to_stderr() -> None:
    """Send MuJoCo's warnings to stderr: by default it also appends them to ``MUJOCO_LOG.TXT``
    in the current folder, a file written outside --out."""
    import mujoco

    mujoco.set_mju_user_warning(lambda message: print(f"MuJoCo warning: {message}", file=sys.stderr))


def add_json_flag(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--json", action="store_true", help="print the report as one JSON object on stdout")


def print_json(data: Any) -> None:
    print(json.dumps(to_jsonable(data), sort_keys=True))


def progress_bar(total: int, desc: str, enabled: bool = True):
    """A tqdm bar on stderr (disabled under ``--json`` or when stderr is not a terminal)."""
    from tqdm import tqdm

    disable = not enabled or not sys.stderr.isatty()
    return tqdm(total=total, desc=desc, file=sys.stderr, disable=disable, leave=False, dynamic_ncols=True)


def weights_arg(text: str) -> str:
    """Validate a ``--weights`` value (a set name or comma-separated numbers) early: it must
    name weights of some model (:func:`model_weights` checks them against the chosen one)."""
    from ioc_bench.features import cost_features
    from ioc_bench.model.catalogue import MODELS
    from ioc_bench.weights import parse_weights

    errors = []
    for model in MODELS.values():
        try:
            parse_weights(text, cost_features(model))
            return text
        except ValueError as exc:
            errors.append(str(exc))
    raise argparse.ArgumentTypeError(errors[0])


def add_model_arg(parser: argparse.ArgumentParser, default: str | None = DEFAULT_MODEL) -> None:
    """--model: a gait model by name."""
    from ioc_bench.model.catalogue import MODELS

    where = f"default {default}" if default else "default: the suite's"
    parser.add_argument("--model", choices=tuple(MODELS), default=default, help=f"gait model ({where})")


def model_weights(text: str, model: Any) -> Any:
    """The unit weights ``--weights`` names over the chosen model's cost features (``model``
    the resolved :class:`~ioc_bench.model.gait_model.GaitModel`); :class:`UsageError` if it
    names none of that model's."""
    from ioc_bench.features import cost_features
    from ioc_bench.weights import parse_weights

    try:
        return parse_weights(text, cost_features(model))
    except ValueError as exc:
        raise UsageError(f"--weights {text}: {exc} (model {model.name})") from None


def solver_dict(report: Any) -> dict[str, Any]:
    """The solver fields every JSON report carries."""
    return {
        "status": report.status,
        "success": report.success,
        "max_violation": report.max_violation,
        "iterations": report.iterations,
        "wall_time": report.wall_time,
        "objective": report.objective,
    }


def add_multistart_args(parser: argparse.ArgumentParser, speed_default: float) -> None:
    """--speed, --starts, --seed and --workers, as every gait-solving command takes them."""
    speed_help = f"average forward speed (default {speed_default:g})"
    parser.add_argument("--speed", type=positive_float, default=speed_default, help=speed_help)
    parser.add_argument("--starts", type=positive_int, default=15, help="multi-start size (default 15)")
    parser.add_argument("--seed", type=seed_int, default=0, help="seed of the start perturbations (>= 0)")
    parser.add_argument("--workers", type=positive_int, default=None, help="worker processes (default: all cores)")
