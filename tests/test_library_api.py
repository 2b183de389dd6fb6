"""The library API (docs/api.md): every name of ``vslsp.api.__all__`` resolves, has a docstring
and is listed in docs/api.md; ``vslsp`` re-exports them without importing them; the API's own
compositions plan and validate a shipped problem (that the wheel ships ``py.typed``, PEP 561:
tests/cli/test_cli_packaging.py)."""

import re
import subprocess
import sys
from pathlib import Path

import pytest

import vslsp
from vslsp import api

ROOT = Path(__file__).resolve().parents[1]
REFERENCE = ROOT / "docs" / "api.md"


def test_every_name_has_a_docstring():
    undocumented = [name for name in api.__all__ if not (getattr(api, name).__doc__ or "").strip()]
    assert undocumented == []


def test_every_name_is_in_the_reference():
    listed = set(re.findall(r"^- \*\*`(\w+)`\*\*", REFERENCE.read_text(), re.MULTILINE))
    assert sorted(set(api.__all__) - listed) == []
    assert sorted(listed - set(api.__all__)) == []  # and the page lists nothing that is not there


def test_vslsp_reexports_the_api_names():
    assert vslsp.Recorder is api.Recorder and vslsp.plan is api.plan and vslsp.ground is api.ground
    with pytest.raises(AttributeError, match="no attribute 'recorder'"):
        vslsp.recorder  # noqa: B018


def test_import_vslsp_imports_no_part_of_the_api():
    code = "import sys, vslsp; print(sorted(m for m in sys.modules if m.startswith(('vslsp.', 'cv2', 'pybullet'))))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "['vslsp.errors']"


def test_a_shipped_problem_is_planned_and_its_plan_validated():
    domain = api.read_domain(ROOT / "pddl" / "domain.pddl")
    problem = api.read_problem(ROOT / "pddl" / "domain.pddl", ROOT / "pddl" / "pull-in-order.pddl")
    result = api.plan(domain, problem, timeout=60.0)
    assert result.lines() and api.validate(domain, problem, result.steps).valid
