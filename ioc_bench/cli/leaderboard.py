"""``ioc-bench leaderboard``: regenerate the leaderboard (Markdown, JSON, per-case CSV, HTML page)
from results directories and boards; a case in more than one source is taken from the last."""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from ioc_bench.cli.common import add_json_flag, path_arg, print_json, usage_errors


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("leaderboard", help="write the leaderboard from result files", description=__doc__)
    p.add_argument(
        "results",
        type=path_arg,
        nargs="+",
        help="results directories (as written by `ioc-bench run`) or boards' leaderboard.json files; "
        "a case in more than one is taken from the last",
    )
    out_help = "output directory (default: the first results directory; a board already there is replaced)"
    p.add_argument("--out", type=path_arg, default=None, help=out_help)
    add_json_flag(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from ioc_bench.runner.leaderboard import board_files, plan_leaderboard, summary
    from ioc_bench.runner.results import select_sources

    with usage_errors():  # every result and the output checked here, so that errors while writing stay real errors
        results = select_sources(args.results)
        out = _default_out(args.results) if args.out is None else args.out
        source = " ".join(_folder_name(path) for path in args.results)
        board = plan_leaderboard(results, out, source=source, out_name="--out")
    replaced = [str(board.out / name) for name in board_files() if (board.out / name).is_file()]
    paths = board.write()
    if args.json:
        print_json({"files": [str(p) for p in paths], "replaced": replaced} | summary(results))
    else:
        print(paths[0].read_text())
        print(f"wrote {', '.join(str(p) for p in paths)}" + (f" (replacing {', '.join(replaced)})" if replaced else ""))
    return 0


def _default_out(sources: list[Path]) -> Path:
    """The first source's folder (a board file's own folder)."""
    return sources[0].parent if sources[0].is_file() else sources[0]


def _folder_name(path: str | os.PathLike) -> str:
    """The results folder as the board names it: its last part, never where it lies on this
    machine (a committed board carries no machine's path)."""
    return Path(path).resolve().name or str(path)
