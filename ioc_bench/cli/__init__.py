"""The ``ioc-bench`` command line: one module per subcommand, each with ``register``.

Every command validates its arguments up front; bad input exits with code 2 and a
one-line message, never a traceback. So does a fault the run meets on its way (a full
disk, its results folder moved or taken by another run, a worker killed: see
:func:`~ioc_bench.cli.common.is_run_fault`), after everything finished so far is kept.
Commands that print a report take ``--json``.

A command prints its own progress and report; what the library logs (the ``ioc_bench``
logger) is shown only when asked for, with ``ioc-bench --log-level LEVEL COMMAND``.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import logging
import sys
from collections.abc import Iterator, Sequence

from ioc_bench._version import __version__
from ioc_bench.cli.common import UsageError, fail, is_run_fault

#: Levels ``--log-level`` takes.
LOG_LEVELS: tuple[str, ...] = ("debug", "info", "warning", "error")
#: How a log record is printed on stderr under ``--log-level``.
LOG_FORMAT = "%(levelname)s %(name)s: %(message)s"

#: Subcommand modules, in the order ``--help`` lists them.
COMMANDS: tuple[str, ...] = (
    "gait",
    "table1",
    "solver_timing",
    "replay",
    "export",
    "algorithms",
    "ioc",
    "run",
    "leaderboard",
    "figures",
    "compare",
    "human",
)


class _Parser(argparse.ArgumentParser):
    """An argparse parser whose errors are one line on stderr and exit code 2."""

    def error(self, message: str) -> None:  # type: ignore[override]
        fail(f"{self.prog}: error: {message}")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="ioc-bench", description="Inverse optimal control benchmark for bipedal walking.")
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    parser.add_argument(
        "--log-level",
        type=str.lower,
        choices=LOG_LEVELS,
        default=None,
        help="also print what the library logs at this level and above on stderr (default: nothing)",
    )
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser, metavar="COMMAND")
    for name in COMMANDS:  # a missing or broken command module is a bug: let it raise
        importlib.import_module(f"ioc_bench.cli.{name}").register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    command = "ioc-bench"
    try:
        args = build_parser().parse_args(argv)  # imports every command: Ctrl-C is honoured here too
        command = f"ioc-bench {args.command}"
        with _log_to_stderr(args.log_level):
            return int(args.run(args) or 0)
    except UsageError as exc:
        fail(f"{command}: error: {exc}")
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except Exception as exc:
        if not is_run_fault(exc):
            raise  # a bug: its traceback is what a report needs
        fail(f"{command}: error: {exc}")
    return 0


@contextlib.contextmanager
def _log_to_stderr(level: str | None) -> Iterator[None]:
    """While the command runs, the ``ioc_bench`` logger's records at ``level`` and above on
    stderr (nothing when ``level`` is None); the logger is left as it was found."""
    if level is None:
        yield
        return
    logger = logging.getLogger("ioc_bench")
    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(logging.Formatter(LOG_FORMAT))
    old_level = logger.level
    logger.addHandler(handler)
    logger.setLevel(level.upper())
    try:
        yield
    finally:
        logger.removeHandler(handler)
        logger.setLevel(old_level)


if __name__ == "__main__":
    raise SystemExit(main())
