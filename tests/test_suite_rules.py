"""The suite's own rules (docs/testing.md), read from its source: a test file imports no other
test file, no ``conftest`` and nothing through ``tests.`` (shared code lives in
``tests/helpers``, imported as ``helpers.*``), so that each file runs alone; and no test
watches the clock: it neither sleeps "long enough" nor asserts how long something took, it
waits on an event through ``helpers.events``."""

from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FOLDERS = (ROOT / "tests", ROOT / "examples")
HELPERS = ROOT / "tests" / "helpers"
WAITING = HELPERS / "events.py"  # the one place that reads the clock: the bounded wait

CLOCKS = {"time.time", "time.monotonic", "time.perf_counter", "time.process_time", "datetime.datetime.now"}
CLOCKS |= {f"{name}_ns" for name in CLOCKS if name.startswith("time.")}
SLEEPS = {"time.sleep", "asyncio.sleep"}
FOREVER_S = 60  # a trial that sleeps this long stands for one that runs until the test interrupts it
# A duration in a name: time_s, mean_time_s, elapsed, duration, reproduction_ms, took, wall...
DURATION = re.compile(r"(time_s|elapsed|duration|seconds|took|wall|_ms\b|_ms\W)", re.IGNORECASE)
PROGRAM_IMPORT = re.compile(r"(?:^|[\n;])\s*(?:import|from)\s+([A-Za-z_][\w.]*)")

# Files allowed a clock or a sleep, each with the reason it is no race and no speed target.
EXCUSED = {
    "tests/test_stages.py": "the stage timer's own test: it sleeps so that time passes, and asserts "
    "only lower bounds that the sleeps guarantee and parts that add up to a total it measures",
}


def sources() -> list[Path]:
    """The suite's Python files, but this one (its samples break the rules on purpose)."""
    here = Path(__file__).resolve()
    return sorted(
        p for folder in FOLDERS for p in folder.rglob("*.py") if "__pycache__" not in p.parts and p.resolve() != here
    )


def is_test_file(path: Path) -> bool:
    return path.name.startswith("test_") or path.name == "conftest.py"


def support_modules() -> dict[str, Path]:
    """Modules in a test folder that are neither tests, conftests nor helpers (e.g.
    tests/tasks/example_tasks.py): for the tests of their own folder only."""
    return {
        p.stem: p.parent
        for p in sources()
        if not is_test_file(p) and HELPERS not in p.parents and p.name != "__init__.py"
    }


def imported(tree: ast.AST) -> list[tuple[int, str]]:
    """(line, module) for each import, at any depth, and each import line of a Python program
    held in a string (``python -c "import x"``, a program run in a subprocess)."""
    found: list[tuple[int, str]] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [(node.lineno, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            found.append((node.lineno, node.module))
            found += [(node.lineno, f"{node.module}.{alias.name}") for alias in node.names]
        elif isinstance(node, ast.Constant) and isinstance(node.value, str) and "import" in node.value:
            found += [(node.lineno, name) for name in PROGRAM_IMPORT.findall(node.value)]
    return found


def import_problems(path: Path, text: str, support: dict[str, Path]) -> list[str]:
    """What ``path`` imports that a file running alone must not: a test module, a conftest,
    anything as ``tests.*``, another folder's support module."""
    problems: list[str] = []
    flagged: set[int] = set()  # one problem a line: `from tests.x import y` names tests.x and tests.x.y
    for line, module in imported(ast.parse(text, str(path))):
        if line in flagged:
            continue
        count = len(problems)
        parts = module.split(".")
        where = f"{path.relative_to(ROOT)}:{line}"
        if parts[0] == "tests":
            problems.append(f"{where}: imports {module} (shared code: tests/helpers, as helpers.*)")
        elif "conftest" in parts:
            problems.append(f"{where}: imports {module} (a conftest holds fixtures, never imported)")
        elif any(part.startswith("test_") for part in parts):
            problems.append(f"{where}: imports the test module {module} (move what it shares to tests/helpers)")
        elif parts[0] in support and support[parts[0]] != path.parent:
            problems.append(
                f"{where}: imports {module} of {support[parts[0]].relative_to(ROOT)} (shared code: tests/helpers)"
            )
        if len(problems) > count:
            flagged.add(line)
    return problems


def _aliases(tree: ast.AST) -> dict[str, str]:
    """The local name of each imported module or function -> its full name."""
    names: dict[str, str] = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                names[alias.asname or alias.name.split(".")[0]] = (
                    alias.name if alias.asname else alias.name.split(".")[0]
                )
        elif isinstance(node, ast.ImportFrom) and node.module:
            for alias in node.names:
                names[alias.asname or alias.name] = f"{node.module}.{alias.name}"
    return names


def _called(node: ast.Call, aliases: dict[str, str]) -> str:
    """The full name of the function ``node`` calls, as far as the imports tell ('' if unknown)."""
    parts: list[str] = []
    target = node.func
    while isinstance(target, ast.Attribute):
        parts.insert(0, target.attr)
        target = target.value
    if not isinstance(target, ast.Name):
        return ""
    return ".".join([aliases.get(target.id, target.id), *parts])


def _in_loop(node: ast.AST, parents: dict[ast.AST, ast.AST]) -> bool:
    while node in parents:
        node = parents[node]
        if isinstance(node, ast.While | ast.For | ast.AsyncFor):
            return True
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda):
            return False
    return False


def clock_problems(path: Path, text: str) -> list[str]:
    """Sleeps and clock reads where a test would race the clock, and assertions of an upper
    bound on a duration. A test file (or conftest) neither sleeps nor reads the clock; a helper
    or a task module sleeps only in a polling loop (or for ever: a trial waiting to be
    interrupted); only helpers/events.py reads the clock, for its hang bound."""
    tree = ast.parse(text, str(path))
    aliases = _aliases(tree)
    parents = {child: node for node in ast.walk(tree) for child in ast.iter_child_nodes(node)}
    name = str(path.relative_to(ROOT)) if path.is_relative_to(ROOT) else path.name
    problems: list[tuple[int, str]] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Assert):
            problems += [(node.lineno, f"{name}:{node.lineno}: {why}") for why in _bounded_durations(node.test, text)]
        if not isinstance(node, ast.Call) or name in EXCUSED:
            continue
        called = _called(node, aliases)
        where = f"{name}:{node.lineno}: {called}()"
        if called in CLOCKS and path != WAITING:
            problems.append((node.lineno, f"{where} reads the clock: wait on an event with helpers.events"))
        elif called in SLEEPS:
            seconds = node.args[0].value if node.args and isinstance(node.args[0], ast.Constant) else None
            if called == "asyncio.sleep" and seconds == 0:
                continue  # yields to the event loop: no clock
            if is_test_file(path):
                problems.append((node.lineno, f"{where} in a test: wait on an event with helpers.events"))
            elif not _in_loop(node, parents) and not (isinstance(seconds, int | float) and seconds >= FOREVER_S):
                problems.append((node.lineno, f"{where} sleeps a guess at how long something takes: wait on an event"))
    return [problem for _, problem in sorted(problems)]


def _bounded_durations(test: ast.expr, text: str) -> list[str]:
    """An upper bound on a duration in an assertion: ``elapsed < 5``, ``3.0 > result.time_s``."""
    found = []
    for compare in (n for n in ast.walk(test) if isinstance(n, ast.Compare)):
        operands = [compare.left, *compare.comparators]
        for op, smaller_first in ((ast.Lt, True), (ast.LtE, True), (ast.Gt, False), (ast.GtE, False)):
            for index, operator in enumerate(compare.ops):
                if not isinstance(operator, op):
                    continue
                smaller = operands[index] if smaller_first else operands[index + 1]
                if isinstance(smaller, ast.Constant | ast.Set | ast.List | ast.Tuple | ast.Dict):
                    continue  # a literal: a set of field names holds "time_s", no duration
                segment = ast.get_source_segment(text, smaller) or ""
                if DURATION.search(segment) and "timeout" not in segment.lower():
                    found.append(f"asserts an upper bound on a duration ({segment}): speed goes in benchmarks/")
    return found


def test_no_test_file_imports_another_test_file_a_conftest_or_tests_as_a_package():
    support = support_modules()
    problems = [problem for path in sources() for problem in import_problems(path, path.read_text(), support)]
    assert not problems, "\n".join(problems)


def test_no_test_sleeps_reads_the_clock_or_asserts_how_long_something_took():
    problems = [problem for path in sources() for problem in clock_problems(path, path.read_text())]
    assert not problems, "\n".join(problems)


def test_the_rules_catch_what_they_are_for():
    """Each rule fails on the code it is written against (issue 31's findings) and passes
    the way the suite does it instead."""
    test_file = ROOT / "tests" / "vsl3d" / "test_example.py"
    support = {"example_tasks": ROOT / "tests" / "tasks"}
    bad_imports = (
        "from tests.vsl3d.conftest import scene\n"
        "import conftest\n"
        "from test_vsl import helper\n"
        "from example_tasks import DiceBelowFive\n"
        "PROGRAM = 'import sys\\nimport test_ray_backend\\nmain()'\n"
    )
    found = import_problems(test_file, bad_imports, support)
    assert [problem.split(":")[1] for problem in found] == ["1", "2", "3", "4", "5"], found
    good = "from helpers.events import wait_until\nimport numpy as np\nPROGRAM = 'import helpers.interrupt_tasks'\n"
    assert import_problems(test_file, good, support) == []
    assert import_problems(ROOT / "tests" / "tasks" / "test_x.py", "import example_tasks\n", support) == []

    clocks = (
        "import time\nfrom time import sleep as nap\nimport asyncio\n"
        "def test_a():\n"
        "    time.sleep(12)\n"  # 5: sleeps 'long enough' for a trial to finish
        "    start = time.monotonic()\n"  # 6
        "    nap(1)\n"  # 7
        "    assert run.elapsed < 15\n"  # 8
        "    assert 3.0 >= result.time_s and result.duration_s > 1.0\n"  # 9: only the upper bound
        "async def test_b():\n"
        "    await asyncio.sleep(0)\n"  # 11: no clock
        "    await asyncio.sleep(0.5)\n"  # 12
        "    assert process.wait(timeout=5) == 0\n"  # 13: a hang bound, no measure
    )
    found = clock_problems(test_file, clocks)
    assert [problem.split(":")[1] for problem in found] == ["5", "6", "7", "8", "9", "12"], found
    task = (
        "import time\ndef run_trial(seed):\n"
        "    time.sleep(1.0)\n"  # 3: a guess
        "    time.sleep(600)\n"  # 4: until interrupted
        "    while not done():\n        time.sleep(0.05)\n"  # 6: polling
    )
    found = clock_problems(ROOT / "tests" / "tasks" / "example_tasks.py", task)
    assert [problem.split(":")[1] for problem in found] == ["3"], found


def test_no_two_test_files_share_a_name():
    """The test folders are no packages (pytest's rootdir import mode): two files of one name in
    different folders make the second an import error when both are collected in one run."""
    names: dict[str, list[str]] = {}
    for path in sorted((ROOT / "tests").rglob("test_*.py")):
        names.setdefault(path.name, []).append(str(path.relative_to(ROOT)))
    assert {name: paths for name, paths in names.items() if len(paths) > 1} == {}
