"""Reading from the language engine's tree (vslsp.symbolic.io.engine_reader) gives the model
unified-planning's reader gives, for every PDDL file of the repository; a mistake is placed and
worded by `plan` and `validate` as `pddl check` places it; and planning with Fast Downward, from
reading to the plan, never imports unified-planning (whose import alone took about 1.5 s)."""

from __future__ import annotations

import json
import re
import subprocess
import sys
import warnings
from pathlib import Path

from helpers.cli import REPO, vslsp

from vslsp.symbolic import read_pddl
from vslsp.symbolic.io import pddl

FOLDERS = sorted({p.parent for p in REPO.glob("**/*.pddl") if ".venv" not in p.parts and "out" not in p.parts})


def _pairs() -> list[tuple[Path, Path | None]]:
    pairs: list[tuple[Path, Path | None]] = []
    for folder in FOLDERS:
        files = sorted(folder.glob("*.pddl"))
        domains = [f for f in files if re.search(r"\(\s*define\s*\(\s*domain", f.read_text(), re.I)]
        for domain in domains:
            pairs += [(domain, None)] + [(domain, f) for f in files if f not in domains]
    return pairs


PAIRS = _pairs()


def test_every_file_of_the_repository_reads_to_the_same_model_both_ways(monkeypatch):
    assert len(PAIRS) > 70  # the shipped, IPC 2006 and lifted-tcore files, the examples, the test data
    read_both = 0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for domain, problem in PAIRS:
            try:
                engine = read_pddl(domain, problem)
            except Exception:  # noqa: BLE001  (a file that is meant to be broken: both refuse it, below)
                continue
            with monkeypatch.context() as patched:
                patched.setattr(pddl, "read_with_engine", lambda *args: None)  # unified-planning's reader only
                reader = read_pddl(domain, problem)
            assert engine == reader, (domain, problem)
            read_both += 1
    assert read_both > 70


def test_a_mistake_is_said_at_one_place_by_check_plan_and_validate(capsys, tmp_path):
    text = (REPO / "pddl" / "pull-in-order.pddl").read_text().replace("(far orange)", "(fra orange)", 1)
    (tmp_path / "p.pddl").write_text(text)
    (tmp_path / "plan.txt").write_text("(pull orange)\n")
    domain = REPO / "pddl" / "domain.pddl"
    code, out, _ = vslsp(capsys, "pddl", "check", domain, tmp_path / "p.pddl", "--json")
    first = json.loads(out)["diagnostics"][0]
    where = f"p.pddl:{first['line']}:{first['column']}: unknown predicate 'fra' (did you mean 'far'?)"
    for command in (["plan"], ["validate"]):
        extra = [tmp_path / "plan.txt"] if command == ["validate"] else []
        code, out, err = vslsp(capsys, *command, domain, tmp_path / "p.pddl", *extra)
        assert code == 2 and where in err, err


def test_planning_with_fast_downward_never_imports_unified_planning(tmp_path):
    program = (
        "import sys\nfrom vslsp.cli import main\n"
        "try:\n    main(sys.argv[1:])\nexcept SystemExit as end:\n"
        "    print('UP' if any(m.startswith('unified_planning') for m in sys.modules) else 'no UP', end.code)\n"
    )
    for args in (
        ["plan", "pddl/domain.pddl", "pddl/pull-in-order.pddl", "--out", str(tmp_path / "plan.txt")],
        ["validate", "pddl/domain.pddl", "pddl/pull-in-order.pddl", str(tmp_path / "plan.txt")],
    ):
        done = subprocess.run(
            [sys.executable, "-c", program, *args], cwd=REPO, capture_output=True, text=True, timeout=300
        )
        assert done.stdout.strip().endswith("no UP 0"), done.stdout + done.stderr


def test_planning_through_unified_planning_still_plans_and_prints_no_credits(capsys):
    code, out, err = vslsp(
        capsys,
        "plan",
        REPO / "pddl" / "domain.pddl",
        REPO / "pddl" / "pull-in-order.pddl",
        "--compilation",
        "ground",
        "--json",
    )
    assert code == 0 and json.loads(out)["plan"] == ["pull orange", "pull green", "pull yellow"]
    assert "Credits" not in out + err
