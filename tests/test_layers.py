"""The package's layers point down: a static import graph of ``vslsp`` (module-level and
function-level imports alike) has no cycle, between modules or between subpackages; every import
between subpackages follows the layer table of docs/architecture.md (:data:`LAYERS`,
:data:`MAY_IMPORT`), which the docs' table is drawn from; the algorithms (VSL and VSL-3D) import
no world; only the simulator imports pybullet."""

from __future__ import annotations

import ast
from pathlib import Path

import vslsp

PACKAGE = Path(vslsp.__file__).parent

#: Each subpackage's layer (docs/architecture.md, "Layers").
LAYERS = {
    **dict.fromkeys(
        (
            "vslsp.errors",
            "vslsp.outcomes",
            "vslsp.outputs",
            "vslsp.files",
            "vslsp.folders",
            "vslsp.stages",
            "vslsp.data",
            "vslsp.provenance",
            "vslsp.interrupts",
            "vslsp.parameters",
        ),
        0,
    ),
    **dict.fromkeys(("vslsp.geometry", "vslsp.dmp", "vslsp.perturbations"), 1),
    "vslsp.sim": 2,
    **dict.fromkeys(("vslsp.worlds", "vslsp.skills"), 3),
    **dict.fromkeys(("vslsp.vision", "vslsp.vsl3d"), 4),
    "vslsp.grounding": 5,
    "vslsp.vsl": 6,
    "vslsp.symbolic": 7,
    "vslsp.loop": 8,
    "vslsp.tasks": 9,
    "vslsp.experiments": 10,
    **dict.fromkeys(("vslsp.cli", "vslsp.lsp", "vslsp.shell", "vslsp.studio", "vslsp.gym", "vslsp.api"), 11),
}
BELOW = {layer: set(range(layer)) for layer in range(12)}
#: The layers (and same-layer subpackages) each layer may import; the exceptions to "all below"
#: say what a layer stands beside rather than on.
MAY_IMPORT: dict[str, set[int | str]] = {
    **{package: set(BELOW[layer]) for package, layer in LAYERS.items()},
    "vslsp.outcomes": {"vslsp.errors"},
    "vslsp.outputs": {"vslsp.errors"},
    "vslsp.files": {"vslsp.errors"},
    "vslsp.folders": {"vslsp.errors", "vslsp.files", "vslsp.outputs"},
    "vslsp.interrupts": {"vslsp.errors"},
    "vslsp.skills": {*BELOW[3], "vslsp.worlds"},  # a skill acts in a world through its protocol
    "vslsp.parameters": {"vslsp.errors"},
    "vslsp.vision": {0, 1},  # perception: no simulator, no world
    "vslsp.vsl3d": {0, 1},  # an algorithm: no simulator, no world
    "vslsp.grounding": {0, 1, 2, 4},  # the simulator only for its test kit's rendered scenes
    "vslsp.vsl": {0, 1, 4, 5},  # an algorithm: perception and grounding, no simulator, no world
    "vslsp.symbolic": {0},  # the PDDL model and planner know no perception
    "vslsp.lsp": {0, "vslsp.symbolic"},  # the language server: the PDDL language engine and the planner path
    "vslsp.shell": {0, "vslsp.symbolic"},  # the interactive shell: a user interface of the symbolic layer alone
    "vslsp.studio": {*BELOW[9], "vslsp.tasks", "vslsp.lsp"},  # beside the CLI; the tasks' registry, lsp's context
    "vslsp.cli": {*BELOW[11], "vslsp.lsp", "vslsp.shell", "vslsp.studio"},
}


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


def test_every_import_between_subpackages_follows_the_layer_table():
    packages = {subpackage(m) for m in import_graph()} - {"vslsp", "vslsp.__main__"}
    assert packages == set(LAYERS), "a subpackage is missing from the layer table (and docs/architecture.md)"
    wrong = []
    for module, targets in import_graph().items():
        source = subpackage(module)
        if source in ("vslsp", "vslsp.__main__"):  # the package's own entry points
            continue
        for target in {subpackage(t) for t in targets} - {source}:
            allowed = MAY_IMPORT[source]
            if target not in allowed and LAYERS[target] not in allowed:
                wrong.append(f"{module} (layer {LAYERS[source]}) imports {target} (layer {LAYERS[target]})")
    assert wrong == []


def test_the_algorithms_import_no_world():
    """VSL and VSL-3D (Algorithm 1, the point-cloud method) see observations only: no module
    under them imports the simulator, a world, the skills, the loop or an experiment."""
    worldly = ("vslsp.sim", "vslsp.worlds", "vslsp.skills", "vslsp.loop", "vslsp.experiments", "vslsp.tasks")
    for module, targets in import_graph().items():
        if module.startswith(("vslsp.vsl.", "vslsp.vsl3d.")) or module in ("vslsp.vsl", "vslsp.vsl3d"):
            assert not [t for t in targets if t.startswith(worldly)], module


def test_only_the_simulator_imports_pybullet():
    importers = set()
    for path in PACKAGE.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            names = [a.name for a in node.names] if isinstance(node, ast.Import) else []
            names += [node.module or ""] if isinstance(node, ast.ImportFrom) else []
            if any(name.split(".")[0] in ("pybullet", "pybullet_data", "pybullet_utils") for name in names):
                importers.add(subpackage(_module_name(path)))
    assert importers == {"vslsp.sim"}


def test_the_simulator_imports_no_perception_planning_or_task_code():
    for module, targets in import_graph().items():
        if module.startswith("vslsp.sim"):
            below = ("vslsp.sim", "vslsp.errors", "vslsp.outcomes", "vslsp.files", "vslsp.geometry")
            upward = [t for t in targets if not t.startswith(below)]
            assert upward == [], f"{module} imports {upward}"


def test_the_language_server_imports_only_the_symbolic_layer():
    """vslsp.lsp (layer 9, beside the CLI) stands on the PDDL language engine and the planner path alone."""
    allowed = ("vslsp.lsp", "vslsp.symbolic", "vslsp.errors")
    for module, targets in import_graph().items():
        if module.startswith("vslsp.lsp"):
            upward = [t for t in targets if not t.startswith(allowed)]
            assert upward == [], f"{module} imports {upward}"


#: The subpackages of vslsp.symbolic (docs/architecture.md, "Inside the symbolic layer"), each with the
#: ones it may import: split by role as unified-planning splits itself (model, io, engines).
SYMBOLIC_MAY_IMPORT: dict[str, set[str]] = {
    "vslsp.symbolic.budget": set(),
    "vslsp.symbolic.language": {"vslsp.symbolic.budget"},
    "vslsp.symbolic.model": {"vslsp.symbolic.budget"},
    "vslsp.symbolic.io": {"vslsp.symbolic.budget", "vslsp.symbolic.language", "vslsp.symbolic.model"},
    # engines.pddl21 reads numeric and temporal files itself (unified-planning's reader, with the
    # language's size limit and io's located errors)
    "vslsp.symbolic.engines": {
        "vslsp.symbolic.budget",
        "vslsp.symbolic.model",
        "vslsp.symbolic.language",
        "vslsp.symbolic.io",
    },
    "vslsp.symbolic.validation": {
        "vslsp.symbolic.budget",
        "vslsp.symbolic.model",
        "vslsp.symbolic.io",
        "vslsp.symbolic.engines",
    },
    "vslsp.symbolic.learning": {"vslsp.symbolic.model"},
}


def test_the_symbolic_layer_s_subpackages_follow_their_table():
    """The model never imports its reader, the engines never validation (only the numeric and temporal
    engine reads its own files), and the
    language engine nothing but the budget; the layer's ``__init__`` (its lazy names) stands above all."""
    wrong = []
    for module, targets in import_graph().items():
        if not module.startswith("vslsp.symbolic."):
            continue
        source = ".".join(module.split(".")[:3])
        assert source in SYMBOLIC_MAY_IMPORT, f"{source} is missing from SYMBOLIC_MAY_IMPORT"
        for target in targets:
            inner = ".".join(target.split(".")[:3])
            if target.startswith("vslsp.symbolic.") and inner != source and inner not in SYMBOLIC_MAY_IMPORT[source]:
                wrong.append(f"{module} imports {target}")
    assert wrong == []


def test_the_studio_stands_beside_the_cli():
    """vslsp.studio (layer 9, beside the CLI) imports the layers below and the language server's cursor
    context, never the CLI; only vslsp.cli.studio imports it, and the web stack only inside it."""
    for module, targets in import_graph().items():
        if module.startswith("vslsp.studio"):
            upward = [t for t in targets if t.startswith("vslsp.cli")]
            assert upward == [], f"{module} imports {upward}"
        elif not module.startswith("vslsp.cli.studio"):
            assert not [t for t in targets if t.startswith("vslsp.studio")], module
