"""vslsp as a real package: the shipped skills and PDDL examples are package data, found through
importlib.resources, and a wheel installed in a fresh virtual environment runs from anywhere."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import venv
import zipfile
from pathlib import Path

import pytest
from helpers.cli import REPO

from vslsp.data import pddl_folder, shipped_folder, skills_folder


def test_the_shipped_data_is_found():
    assert (skills_folder() / "library.json").is_file()
    assert (pddl_folder() / "domain.pddl").is_file() and (pddl_folder() / "pull-in-order.pddl").is_file()
    with pytest.raises(ValueError, match="no shipped data 'images'"):
        shipped_folder("images")


def test_pyproject_uses_an_spdx_license_and_maps_the_data():
    text = (REPO / "pyproject.toml").read_text()
    assert 'license = "MIT"' in text and "license = {" not in text
    assert '"vslsp.data.skills" = "skills"' in text and '"vslsp.data.pddl" = "pddl"' in text


@pytest.mark.slow
def test_a_wheel_installed_in_a_fresh_venv_plans_and_loads_skills_from_elsewhere(tmp_path, monkeypatch):
    """Build the wheel, install it (with its dependencies) into a new venv, run from another folder."""
    source = tmp_path / "source"  # a copy: an in-tree build writes build/ and *.egg-info beside the sources
    shutil.copytree(
        REPO,
        source,
        ignore=shutil.ignore_patterns(
            ".git", ".venv", "out", "runs", "build", "*.egg-info", "__pycache__", ".pytest_cache", ".gl", ".whl"
        ),
    )
    # A home of this test's own for pip's cache and the build tools' settings: every pip run,
    # ensurepip's in venv.create too, asks `rustc --version` for its user agent, and rustup's
    # rustc writes ~/.rustup/settings.toml. Without PYTHONPATH, where a checkout would count as
    # installed.
    (tmp_path / "home").mkdir()
    monkeypatch.setenv("HOME", str(tmp_path / "home"))  # venv.create runs pip (ensurepip) in this environment
    home = {**os.environ}
    clean = {k: v for k, v in home.items() if k != "PYTHONPATH"}
    build = subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "-v", str(source), "--no-deps", "-w", str(tmp_path / "wheels")],
        capture_output=True,
        text=True,
        timeout=900,
        env=home,
    )
    assert build.returncode == 0, build.stderr[-3000:]
    assert "is deprecated" not in build.stdout + build.stderr  # e.g. `project.license` as a TOML table
    wheel = next((tmp_path / "wheels").glob("vslsp-*.whl"))
    shipped = zipfile.ZipFile(wheel).namelist()
    assert "vslsp/py.typed" in shipped and "vslsp/api.py" in shipped  # typed for its users (PEP 561)
    environment = tmp_path / "venv"
    venv.create(environment, with_pip=True)  # no system site-packages: only what the wheel pulls in
    python = environment / "bin" / "python"
    install = subprocess.run(
        [str(python), "-m", "pip", "install", "-q", "-c", str(REPO / "constraints.txt"), str(wheel)],
        capture_output=True,
        text=True,
        timeout=3000,
        env=clean,
    )
    assert install.returncode == 0, install.stderr[-3000:]
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    env = clean
    show = "import vslsp.data as d; print(d.skills_folder()); print(d.pddl_folder())"
    where = subprocess.run(
        [str(python), "-c", show], capture_output=True, text=True, cwd=elsewhere, env=env, timeout=600
    )
    assert where.returncode == 0, where.stderr[-3000:]
    skills, pddl = (Path(line) for line in where.stdout.split())
    assert environment in skills.parents and environment in pddl.parents  # inside the installed package
    vslsp = str(environment / "bin" / "vslsp")
    plan = subprocess.run(
        [vslsp, "plan", str(pddl / "domain.pddl"), str(pddl / "pull-in-order.pddl"), "--json"],
        capture_output=True,
        text=True,
        cwd=elsewhere,
        env=env,
        timeout=600,
    )
    assert plan.returncode == 0, plan.stderr
    assert '"plan": ["pull orange", "pull green", "pull yellow"]' in plan.stdout
    loaded = subprocess.run(
        [
            str(python),
            "-c",
            "from vslsp.skills import SkillLibrary, default_library_path; "
            "print(sorted(SkillLibrary.load(default_library_path()).skills))",
        ],
        capture_output=True,
        text=True,
        cwd=elsewhere,
        env=env,
        timeout=600,
    )
    assert loaded.stdout.strip() == "['pull', 'push']", loaded.stderr
