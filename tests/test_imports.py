"""The import graph of ``ioc_bench`` and ``envs``: no cycles, and no arrow from a lower layer up.

The layers, lowest first: the base utilities (``paths``, ``fileio``, ``cache``, ``validation``,
``processes``, ``plotting``); ``model`` < ``features`` < ``trajopt`` < ``ioc``; the tracks
(``synthetic``, ``human``, with ``bench``, the old name of the synthetic track's ``observe``)
and ``envs`` beside them; the list of built-in tracks (``ioc_bench.tracks``, names only);
the runner and its boards (``runner``), which imports no track: the tracks plug into it
through its protocol (``runner.protocol``, the one module of it a track may import), and it
loads them from that list; ``viz``; the command line (``cli``) on top.

Every module is parsed (never imported) and every import in it counts: at module level, in
functions (a lazy import is still an arrow: deferring it hides a cycle, it does not remove
it), under ``if TYPE_CHECKING``, ``import x``, ``from x import y`` and relative imports, and
``importlib.import_module`` of a literal name. Names looked up from a table at run time
(the registry's built-in algorithms, the executors, the packages' lazy public names) are not
followed; what they name lies in the same package or above it.
"""

from __future__ import annotations

import ast
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("ioc_bench", "envs")

#: The base utilities: they import nothing of the project but one another.
BASE = (
    "ioc_bench._version",
    "ioc_bench.cache",
    "ioc_bench.fileio",
    "ioc_bench.paths",
    "ioc_bench.plotting",
    "ioc_bench.processes",
    "ioc_bench.validation",
)
#: The tracks (and the MuJoCo environment beside them).
TRACKS = ("ioc_bench.synthetic", "ioc_bench.human", "ioc_bench.bench", "envs")
#: The list of built-in tracks, by name only: between the tracks and the runner.
TRACK_LIST = "=ioc_bench.tracks"
#: The runner's protocol: the one module of the runner a track imports.
PROTOCOL = "=ioc_bench.runner.protocol"
_ABOVE_IOC = (*TRACKS, TRACK_LIST, "ioc_bench.runner", "ioc_bench.cli", "ioc_bench.viz")


@dataclass(frozen=True)
class Rule:
    """``importers`` (but those in ``exempt``) may not import ``forbidden`` (but those in
    ``spared``). A name covers the module and everything under it, ``=name`` the module
    alone, ``*`` every module."""

    what: str
    importers: tuple[str, ...]
    forbidden: tuple[str, ...]
    exempt: tuple[str, ...] = ()
    spared: tuple[str, ...] = ()


#: Every module file directly under ioc_bench/ that is not a base utility (demo, optimize,
#: task, weights, ...): between the optimizer and IOC.
_BASE_LEVEL = tuple(
    f"=ioc_bench.{path.stem}"
    for path in sorted((ROOT / "ioc_bench").glob("*.py"))
    if path.name != "__init__.py"
    and f"ioc_bench.{path.stem}" not in BASE
    and f"={'ioc_bench.' + path.stem}" != TRACK_LIST
)

RULES = [
    Rule(
        "the model is the lowest layer",
        ("ioc_bench.model",),
        ("ioc_bench.features", "ioc_bench.trajopt", "ioc_bench.ioc", *_ABOVE_IOC),
    ),
    Rule(
        "features sit below the optimizer", ("ioc_bench.features",), ("ioc_bench.trajopt", "ioc_bench.ioc", *_ABOVE_IOC)
    ),
    Rule("the optimizer sits below IOC", ("ioc_bench.trajopt",), ("ioc_bench.ioc", *_ABOVE_IOC)),
    Rule("IOC sits below the tracks", ("ioc_bench.ioc",), _ABOVE_IOC),
    Rule("the package's modules at its base sit below IOC", _BASE_LEVEL, ("ioc_bench.ioc", *_ABOVE_IOC)),
    Rule("the base utilities import only one another", BASE, ("ioc_bench", "envs"), spared=BASE),
    Rule(
        "the human track stands beside the synthetic one",
        ("ioc_bench.human",),
        ("ioc_bench.synthetic", "ioc_bench.bench"),
    ),
    Rule(
        "the synthetic track stands beside the human one",
        ("ioc_bench.synthetic", "ioc_bench.bench"),
        ("ioc_bench.human",),
    ),
    Rule("the MuJoCo environment stands beside the tracks", ("envs",), TRACKS[:-1]),
    Rule(
        "the tracks sit below the runner (but for its protocol, which they implement)",
        TRACKS,
        (TRACK_LIST, "ioc_bench.runner"),
        spared=(PROTOCOL,),
    ),
    Rule("the runner's protocol imports nothing of the project", (PROTOCOL,), ("ioc_bench", "envs")),
    Rule("the list of built-in tracks is names only", (TRACK_LIST,), ("ioc_bench", "envs")),
    Rule("the runner imports no track (it loads them from their list)", ("ioc_bench.runner",), TRACKS),
    Rule("only the command line imports the MuJoCo environment", ("*",), ("envs",), exempt=("envs", "ioc_bench.cli")),
    Rule(
        "only the command line imports the benchmark's figures",
        ("*",),
        ("ioc_bench.viz",),
        exempt=("ioc_bench.viz", "ioc_bench.cli"),
    ),
    Rule("only the command line imports the command line", ("*",), ("ioc_bench.cli",), exempt=("ioc_bench.cli",)),
    Rule(
        "no module imports a package's lazy facade (its names import from every layer)", ("*",), ("=ioc_bench", "=envs")
    ),
]

#: Arrows that break a rule and stay for now, each with its reason. A new arrow that breaks
#: a rule fails the test; so does an entry here once its arrow is gone (remove it then).
ALLOWED: dict[tuple[str, str], str] = {}


def _modules() -> dict[str, tuple[Path, bool]]:
    """Every module of the packages: dotted name -> (file, is a package's ``__init__``)."""
    modules = {}
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            parts = list(path.relative_to(ROOT).with_suffix("").parts)
            is_package = parts[-1] == "__init__"
            modules[".".join(parts[:-1] if is_package else parts)] = (path, is_package)
    return modules


MODULES = _modules()


def _owner(name: str, modules: Mapping[str, object] = MODULES) -> str | None:
    """The project module ``name`` is, or is in (``a.b.c`` -> ``a.b`` if ``c`` is a name in it)."""
    while name:
        if name in modules:
            return name
        name = name.rpartition(".")[0]
    return None


def _imported_names(
    node: ast.AST, module: str, is_package: bool, modules: Mapping[str, object] = MODULES
) -> Iterable[str]:
    """The dotted names an import statement (or an ``import_module`` call) brings in."""
    if isinstance(node, ast.Import):
        yield from (alias.name for alias in node.names)
    elif isinstance(node, ast.ImportFrom):
        base = node.module or ""
        if node.level:
            package = module.split(".") if is_package else module.split(".")[:-1]
            anchor = ".".join(package[: len(package) - (node.level - 1)])
            base = f"{anchor}.{base}" if base else anchor
        for alias in node.names:
            name = f"{base}.{alias.name}"
            yield name if name in modules else base  # a submodule, or a name in ``base``
    elif (
        isinstance(node, ast.Call)
        and getattr(node.func, "attr", getattr(node.func, "id", None)) == "import_module"
        and node.args
        and isinstance(node.args[0], ast.Constant)
        and isinstance(node.args[0].value, str)
    ):
        yield node.args[0].value


def _graph() -> dict[str, dict[str, int]]:
    """Module -> {imported project module -> line of its first import}."""
    graph: dict[str, dict[str, int]] = {}
    for module, (path, is_package) in MODULES.items():
        arrows = graph[module] = {}
        for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
            for name in _imported_names(node, module, is_package):
                target = _owner(name)
                if target is not None:
                    arrows.setdefault(target, node.lineno)
    return graph


GRAPH = _graph()


def _components(graph: dict[str, dict[str, int]]) -> list[list[str]]:
    """The strongly connected components (Tarjan's algorithm, without recursion)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    components = []
    for start in graph:
        if start in index:
            continue
        work = [(start, iter(graph[start]))]
        index[start] = low[start] = len(index)
        stack.append(start)
        on_stack.add(start)
        while work:
            node, successors = work[-1]
            for succ in successors:
                if succ not in index:
                    index[succ] = low[succ] = len(index)
                    stack.append(succ)
                    on_stack.add(succ)
                    work.append((succ, iter(graph[succ])))
                    break
                if succ in on_stack:
                    low[node] = min(low[node], index[succ])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[node])
                if low[node] == index[node]:
                    component = []
                    while True:
                        member = stack.pop()
                        on_stack.discard(member)
                        component.append(member)
                        if member == node:
                            break
                    components.append(sorted(component))
    return components


def _cycle(graph: dict[str, dict[str, int]], component: list[str]) -> str:
    """The component's modules, a shortest cycle through the first, and every arrow among them."""
    members = set(component)
    first = component[0]
    paths = {first: [first]}
    queue = [first]
    cycle: list[str] = []
    while queue and not cycle:  # breadth first: the shortest way back to ``first``
        node = queue.pop(0)
        for succ in graph[node]:
            if succ == first:
                cycle = [*paths[node], first]
                break
            if succ in members and succ not in paths:
                paths[succ] = [*paths[node], succ]
                queue.append(succ)
    arrows = [f"    {a} -> {b} (line {graph[a][b]})" for a in component for b in graph[a] if b in members]
    return "\n".join([f"{', '.join(component)}: {' -> '.join(cycle)}", *arrows])


def _covers(names: tuple[str, ...], module: str) -> bool:
    return any(
        name == "*" or module == name.lstrip("=") or (not name.startswith("=") and module.startswith(f"{name}."))
        for name in names
    )


def _violations() -> dict[tuple[str, str], str]:
    """(importer, imported) -> the rule it breaks, for every arrow that breaks one."""
    found = {}
    for rule in RULES:
        for module, arrows in GRAPH.items():
            if not _covers(rule.importers, module) or _covers(rule.exempt, module):
                continue
            for target in arrows:
                if _covers(rule.forbidden, target) and not _covers(rule.spared, target):
                    found.setdefault((module, target), f"{rule.what} (line {arrows[target]})")
    return found


def test_the_graph_sees_the_packages() -> None:
    """The parse finds modules and arrows of every kind (so an empty graph cannot pass)."""
    assert {"ioc_bench.model.walker", "ioc_bench.cli", "envs.plots", "ioc_bench.plotting"} <= set(MODULES)
    assert "ioc_bench.model.walker" in GRAPH["envs.plots"]  # from x import y, module level
    assert "envs.drawing" in GRAPH["envs.plots"]  # inside a function
    assert "ioc_bench.human.step" in GRAPH["ioc_bench.human.baselines"]  # under TYPE_CHECKING
    assert sum(map(len, GRAPH.values())) > 300


def test_no_import_cycles() -> None:
    cycles = [
        _cycle(GRAPH, component)
        for component in _components(GRAPH)
        if len(component) > 1 or component[0] in GRAPH[component[0]]
    ]
    assert not cycles, "import cycles (lazy imports count):\n" + "\n".join(cycles)


def test_no_import_goes_up_a_layer() -> None:
    new = {arrow: rule for arrow, rule in _violations().items() if arrow not in ALLOWED}
    lines = [f"{a} -> {b}: {rule}" for (a, b), rule in sorted(new.items())]
    assert not new, "imports against the layering:\n" + "\n".join(lines)


def test_every_allowed_violation_still_exists() -> None:
    """An allowed arrow that is gone leaves the list, so that it cannot come back unseen."""
    gone = sorted(set(ALLOWED) - set(_violations()))
    assert not gone, f"no longer imported (remove them from ALLOWED): {gone}"


@pytest.mark.parametrize(
    ("source", "expected"),
    [
        ("from . import b\nfrom .b import c\nfrom .. import x", {"p.q.b", "p.q.b.c", "p.x"}),
        ("import p.q.b.c\nfrom p.q.b import name\n", {"p.q.b.c", "p.q.b"}),
        ("def f():\n    from ..x import thing\n", {"p.x"}),
        ("import importlib\nimportlib.import_module('p.x')\n", {"p.x"}),
    ],
)
def test_relative_and_lazy_imports_resolve(source: str, expected: set[str]) -> None:
    """``p/q/a.py`` importing in every way (a made-up tree, through the same resolution)."""
    tree = {"p": True, "p.q": True, "p.q.a": False, "p.q.b": True, "p.q.b.c": False, "p.x": False}
    names = {n for node in ast.walk(ast.parse(source)) for n in _imported_names(node, "p.q.a", False, tree)}
    assert {_owner(n, tree) for n in names} - {None} == expected  # importlib: not of the tree
