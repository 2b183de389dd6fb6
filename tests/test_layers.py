"""The package's layers point down: a static import graph of ``vslsp`` (module-level and
function-level imports alike) has no cycle, between modules or between subpackages, and the
simulator imports no perception, planning or task code."""

from __future__ import annotations

import ast
from pathlib import Path

import vslsp

PACKAGE = Path(vslsp.__file__).parent


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def import_graph() -> dict[str, set[str]]:
    """Module -> the vslsp modules it imports anywhere in its text."""
    modules = {_module_name(p): p for p in PACKAGE.rglob("*.py")}
    graph: dict[str, set[str]] = {name: set() for name in modules}
    for name, path in modules.items():
        package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            targets: list[str] = []
            if isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    base = ".".join(
                        package.split(".")[: len(package.split(".")) - node.level + 1] + ([base] if base else [])
                    )
                targets = [
                    f"{base}.{alias.name}" if f"{base}.{alias.name}" in modules else base for alias in node.names
                ]
            for target in targets:
                while target and target not in modules:
                    target = target.rpartition(".")[0]
                if target.startswith("vslsp") and target != name and target != "vslsp":
                    graph[name].add(target)
    return graph


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one node (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []

    def visit(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for other in graph.get(node, ()):
            if other not in index:
                visit(other)
                low[node] = min(low[node], low[other])
            elif other in on_stack:
                low[node] = min(low[node], index[other])
        if low[node] == index[node]:
            component = []
            while True:
                member = stack.pop()
                on_stack.discard(member)
                component.append(member)
                if member == node:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return found


def subpackage(module: str) -> str:
    parts = module.split(".")
    return ".".join(parts[:2])


def test_no_module_import_cycle():
    assert cycles(import_graph()) == []


def test_no_subpackage_import_cycle():
    graph: dict[str, set[str]] = {}
    for module, targets in import_graph().items():
        graph.setdefault(subpackage(module), set()).update(
            subpackage(t) for t in targets if subpackage(t) != subpackage(module)
        )
    assert cycles(graph) == []


def test_the_simulator_imports_no_perception_planning_or_task_code():
    for module, targets in import_graph().items():
        if module.startswith("vslsp.sim"):
            below = ("vslsp.sim", "vslsp.errors", "vslsp.outcomes", "vslsp.files", "vslsp.geometry")
            upward = [t for t in targets if not t.startswith(below)]
            assert upward == [], f"{module} imports {upward}"


def test_no_module_is_over_500_lines():
    long = {
        str(p.relative_to(PACKAGE)): n for p in PACKAGE.rglob("*.py") if (n := len(p.read_text().splitlines())) > 500
    }
    assert long == {}


def test_the_language_server_imports_only_the_symbolic_layer():
    """vslsp.lsp (layer 9, beside the CLI) stands on the PDDL language engine and the planner path alone."""
    allowed = ("vslsp.lsp", "vslsp.symbolic", "vslsp.errors")
    for module, targets in import_graph().items():
        if module.startswith("vslsp.lsp"):
            upward = [t for t in targets if not t.startswith(allowed)]
            assert upward == [], f"{module} imports {upward}"


def test_the_studio_stands_beside_the_cli():
    """vslsp.studio (layer 9, beside the CLI) imports the layers below and the language server's cursor
    context, never the CLI; only vslsp.cli.studio imports it, and the web stack only inside it."""
    for module, targets in import_graph().items():
        if module.startswith("vslsp.studio"):
            upward = [t for t in targets if t.startswith("vslsp.cli")]
            assert upward == [], f"{module} imports {upward}"
        elif not module.startswith("vslsp.cli.studio"):
            assert not [t for t in targets if t.startswith("vslsp.studio")], module
