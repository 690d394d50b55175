"""The house's shape, read from every module's imports (TYPE_CHECKING and function-level
imports included): no import circle anywhere in maxk/, nothing imports a layer above its
own, controllers never import each other's personality, language or controller room
(the shared modules beside the rooms, such as the registry, excepted), and a module over
~500 lines says at its top why it is that long."""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "maxk"

# Lowest first. A module may import its own layer or any layer below.
LAYERS = [
    ("support", ("maxk.plotting",)),  # leaf helpers every layer may use
    ("world", ("maxk.firmware_model.world", "maxk.firmware_model.motor")),
    ("shared machine", ("maxk.firmware_model",)),
    ("personalities", ("maxk.personalities",)),
    ("languages", ("maxk.commands",)),
    ("controllers", ("maxk.controllers",)),
    ("doors", ("maxk",)),
]
SIBLING_PACKAGES = ("maxk.personalities.", "maxk.commands.", "maxk.controllers.")
MAX_LINES = 520


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _modules() -> dict[str, Path]:
    return {_module_name(p): p for p in PACKAGE.rglob("*.py")}


def _imports(name: str, path: Path, known: set[str]) -> set[str]:
    """Every maxk module this one imports, at any place in the file."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found: set[str] = set()
    for node in ast.walk(tree):
        targets: list[str] = []
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                parent = package.split(".")
                parent = parent[: len(parent) - (node.level - 1)]
                base = ".".join(parent + ([base] if base else []))
            targets = [base] + [f"{base}.{alias.name}" for alias in node.names]
        for target in targets:
            # the longest known module the import names (a name inside it is not a module)
            while target and target not in known:
                target = target.rpartition(".")[0]
            if target and target.startswith("maxk") and target != name:
                found.add(target)
    return found


def _graph() -> dict[str, set[str]]:
    modules = _modules()
    known = set(modules)
    return {name: _imports(name, path, known) for name, path in modules.items()}


def _layer(name: str) -> int:
    for rank, (_title, prefixes) in enumerate(LAYERS):
        if any(name == p or name.startswith(p + ".") for p in prefixes):
            return rank
    raise AssertionError(f"{name} is in no layer")


def _is_package_init(name: str) -> bool:
    return (PACKAGE.parent / name.replace(".", "/") / "__init__.py").exists()


def test_no_import_circle_anywhere():
    graph = _graph()
    # a package's __init__ re-exporting its own modules is not a circle of code
    edges = {m: {t for t in targets if not (_is_package_init(m) and t.startswith(m + "."))}
             for m, targets in graph.items()}
    state: dict[str, int] = {}
    stack: list[str] = []
    circles: list[list[str]] = []

    def visit(node: str) -> None:
        state[node] = 1
        stack.append(node)
        for nxt in sorted(edges.get(node, ())):
            if state.get(nxt) == 1:
                circles.append(stack[stack.index(nxt):] + [nxt])
            elif nxt not in state:
                visit(nxt)
        stack.pop()
        state[node] = 2

    for node in sorted(edges):
        if node not in state:
            visit(node)
    assert not circles, "import circles:\n" + "\n".join(" -> ".join(c) for c in circles)


def test_imports_run_one_way_down_the_layers():
    upward = []
    for name, targets in _graph().items():
        for target in targets:
            if target == "maxk":  # the package itself (version, pyserial hook)
                continue
            if _layer(target) > _layer(name):
                upward.append(f"{name} ({LAYERS[_layer(name)][0]}) imports {target} "
                              f"({LAYERS[_layer(target)][0]})")
    assert not upward, "\n".join(upward)


def test_controllers_do_not_share_personalities_or_languages():
    crossing = []
    for name, targets in _graph().items():
        for prefix in SIBLING_PACKAGES:
            if not name.startswith(prefix):
                continue
            own = name[len(prefix):].split(".")[0]
            if (PACKAGE / prefix.strip(".").replace("maxk.", "", 1).replace(".", "/")
                    / f"{own}.py").is_file():
                continue  # a shared module beside the rooms (the registry) knows them all
            for target in targets:
                for other in SIBLING_PACKAGES:
                    if target.startswith(other):
                        theirs = target[len(other):].split(".")[0]
                        shared = (PACKAGE / other.strip(".").replace("maxk.", "", 1).replace(
                            ".", "/") / f"{theirs}.py").is_file()  # a module every one shares
                        if other == prefix and theirs != own and not shared:
                            crossing.append(f"{name} imports {target}")
    assert not crossing, "\n".join(crossing)


def test_the_shared_machine_knows_no_controller():
    for name, targets in _graph().items():
        if _layer(name) <= 1:
            assert all(_layer(t) <= 1 for t in targets), (name, targets)


def test_long_modules_say_why():
    long = []
    for name, path in _modules().items():
        text = path.read_text(encoding="utf-8")
        if text.count("\n") > MAX_LINES:
            head = ast.get_docstring(ast.parse(text)) or ""
            if "Long module:" not in head:
                long.append(f"{name}: {text.count(chr(10))} lines")
    assert not long, "modules over ~500 lines without 'Long module:' in their docstring: " \
        + ", ".join(long)


GENERIC_DOORS = ("maxk.cli", "maxk.repl", "maxk.script", "maxk.script_directives",
                 "maxk.pytest_plugin", "maxk.trace", "maxk.pathplot", "maxk.host.server",
                 "maxk.host.client", "maxk.host.serve", "maxk.host.pacing",
                 "maxk.host.traffic", "maxk.host.control", "maxk.host.control_board",
                 "maxk.control", "maxk.testing")
"""Doors written once for every controller. (The MAXk's own doors, its PCI map, its
`maxk://` URL and its servo tuning assistant, name it by nature.)"""
CONTRACTS = ("maxk.controllers.contract", "maxk.controllers.registry",
             "maxk.controllers.world_view", "maxk.controllers.world_settings",
             "maxk.firmware_model.engine",  # (the engine is the contract's clock)
             "maxk.controllers.panel")  # (each kind's own picture for a front panel)
KIND_NAMES = ("MAXk", "MM4005", "MC405", "PoKeys")


def test_the_doors_name_no_controller():
    """A door speaks to controllers through the contracts and the registry only: it
    imports no controller, personality or language, and no string in its code (its
    docstrings and comments aside) names a kind of controller."""
    graph = _graph()
    for door in GENERIC_DOORS:
        for target in graph[door]:
            below = (_layer(target) < _layer("maxk.controllers") and target not in CONTRACTS
                     and _layer(target) > _layer("maxk.plotting"))  # (support: any may)
            controller = target.startswith("maxk.controllers.") and target not in CONTRACTS
            assert not (below or controller), f"{door} imports {target}"
        tree = ast.parse(_modules()[door].read_text(encoding="utf-8"))
        docstrings = {id(node.body[0].value) for node in ast.walk(tree)
                      if isinstance(node, ast.Module | ast.FunctionDef | ast.ClassDef
                                    | ast.AsyncFunctionDef)
                      and node.body and isinstance(node.body[0], ast.Expr)}
        for node in ast.walk(tree):
            if (isinstance(node, ast.Constant) and isinstance(node.value, str)
                    and id(node) not in docstrings):
                named = [k for k in KIND_NAMES if k in node.value]
                assert not named or _context(tree, node) in ("help", "description"), (
                    door, node.value)


def _context(tree: ast.AST, target: ast.AST) -> str:
    """The keyword a string is passed as (`help=`, `description=`), if any: a door's help
    text may name models as examples."""
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            for keyword in node.keywords:
                if any(sub is target for sub in ast.walk(keyword.value)):
                    return keyword.arg or ""
    return ""
