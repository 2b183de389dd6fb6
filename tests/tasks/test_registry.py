"""The registry (vslsp.tasks.registry): the paper's experiments are lazy ``module:Class`` entries
of the ``vslsp.tasks`` entry-point group, declared in pyproject.toml as another package's tasks
are, each imported only when it is looked up; another package's entries join them."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tomllib
from importlib.metadata import entry_points
from pathlib import Path

from helpers.cli import REPO
from helpers.paper_experiments import PAPER

from vslsp.tasks import list_tasks
from vslsp.tasks.registry import GROUP


def _python(code: str, *path: Path) -> str:
    """``code`` run by a fresh interpreter with ``path`` and this checkout first on its path; its stdout."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([*map(str, path), str(REPO), os.environ.get("PYTHONPATH", "")])}
    done = subprocess.run(
        [sys.executable, "-c", code],
        env=env,
        cwd=path[0] if path else REPO,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_the_papers_experiments_are_declared_as_entry_points_and_installed_so():
    declared = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]["entry-points"][GROUP]
    assert list(declared) == PAPER
    assert all(value.startswith("vslsp.experiments.") and ":" in value for value in declared.values())
    installed = {e.name: e.value for e in entry_points(group=GROUP) if e.value.startswith("vslsp.")}
    assert installed == declared, "the installed metadata is older than pyproject.toml: pip install -e ."


def test_the_list_is_by_system_in_the_papers_order():
    names = [cls.name for cls in list_tasks()]
    assert [n for n in names if n in PAPER] == PAPER


def test_looking_up_one_experiment_imports_its_module_alone_and_help_imports_none():
    families = ["house_roof", "real_world", "vsl3d", "icub"]
    code = (
        "import sys; from vslsp.tasks import task_class; cls = task_class('house-roof'); "
        f"print(cls.__name__, [f for f in {families} if 'vslsp.experiments.' + f in sys.modules])"
    )
    assert _python(code) == "HouseRoof ['house_roof']\n"
    code = (
        "import sys; from vslsp.cli import main\ntry: main(['--help'])\nexcept SystemExit: pass\n"
        "print('EXPERIMENTS', sorted(m for m in sys.modules if m.startswith('vslsp.experiments')))"
    )
    assert _python(code).splitlines()[-1] == "EXPERIMENTS []"


def _package(folder: Path, entries: str) -> Path:
    """An installed package ``other`` of ``folder`` whose ``vslsp.tasks`` entries are ``entries``."""
    (folder / "other_tasks.py").write_text(
        "from vslsp.tasks import System, Task, TrialResult\n\n\n"
        "class Coin(Task):\n"
        "    name = 'coin'\n    system = System.VSL_SP\n    paper_section = 'another package'\n\n"
        "    def run_trial(self, seed, keep=False):\n        return TrialResult(self.name, seed, seed % 2 == 0)\n"
    )
    info = folder / "other-1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: other\nVersion: 1.0\n")
    (info / "entry_points.txt").write_text(f"[{GROUP}]\n{entries}\n")
    return folder


def test_another_packages_entry_is_listed_after_the_papers_and_runs(tmp_path):
    folder = _package(tmp_path, "coin = other_tasks:Coin")
    code = (
        "import json; from vslsp.tasks import list_tasks, get_task\n"
        "print(json.dumps([[c.name for c in list_tasks()], get_task('coin').run_trial(4).to_dict()['status']]))"
    )
    names, status = json.loads(_python(code, folder))
    assert names[-1] == "coin" and names[:-1] == PAPER and status == "solved"


def test_an_entry_whose_class_has_another_name_is_refused(tmp_path):
    folder = _package(tmp_path, "heads = other_tasks:Coin")
    code = "from vslsp.tasks import task_class\ntry: task_class('heads')\nexcept TypeError as e: print(e)"
    assert "entry point 'heads' names <class 'other_tasks.Coin'>, not a Task subclass named 'heads'" in _python(
        code, folder
    )


def test_an_install_older_than_the_entry_points_is_told_to_install_again(tmp_path):
    info = tmp_path / "vslsp-0.1.0.dist-info"  # first on the path: vslsp's metadata without its tasks
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: vslsp\nVersion: 0.1.0\n")
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(tmp_path), str(REPO), os.environ.get("PYTHONPATH", "")])}
    done = subprocess.run(
        [sys.executable, "-m", "vslsp", "experiment", "--list"],
        env=env,
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert "declares none of the paper's experiments" in done.stderr and "pip install -e ." in done.stderr
