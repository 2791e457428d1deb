"""``ioc-bench algorithms``: the registered IOC algorithms, grouped by family, one line each."""

from __future__ import annotations

import argparse
import warnings

from ioc_bench.cli.common import add_json_flag, print_json


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("algorithms", help="list the registered IOC algorithms", description=__doc__)
    add_json_flag(p)
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from ioc_bench.ioc.registry import PluginWarning, describe_algorithms, get_algorithm

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", PluginWarning)
        described = describe_algorithms()
    problems = [str(w.message) for w in caught if issubclass(w.category, PluginWarning)]
    families = {name: get_algorithm(name).family for name in described}
    if args.json:
        print_json({"algorithms": described, "families": families, "skipped_plugins": problems})
        return 0
    width = max((len(n) for n in described), default=0)
    for family in sorted(set(families.values())):
        print(f"{family}:")
        for name, text in described.items():
            if families[name] == family:
                print(f"  {name:<{width}}  {text}")
    for message in problems:
        print(f"warning: {message}")
    return 0
