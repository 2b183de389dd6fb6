"""``vslsp pddl check`` on the language engine: one line per diagnostic
``FILE:LINE:COL: error|warning: message (did you mean 'x'?)``, ``--json`` with every diagnostic,
exit 2 with any error and 0 with warnings only; the check imports neither unified-planning nor the
planner."""

from __future__ import annotations

import json

from helpers.cli import vslsp, vslsp_process
from helpers.symbolic import PDDL

DOMAIN = PDDL / "domain.pddl"
PROBLEM = PDDL / "pull-in-order.pddl"


def write_mistakes(tmp_path):
    domain = tmp_path / "domain.pddl"
    domain.write_text(
        DOMAIN.read_text()
        .replace("(:types block)", "(:types block - item)")
        .replace(":precondition (far ?b)", ":precondition (fra ?b)")
    )
    problem = tmp_path / "problem.pddl"
    problem.write_text(
        PROBLEM.read_text()
        .replace("(far green)\n", "(far gren)\n", 1)
        .replace("(sometime-before (not (far green))", "(sometimes-before (not (far green))")
    )
    return domain, problem


def test_every_diagnostic_is_one_line_file_line_column_and_the_exit_code_is_2(capsys, tmp_path):
    domain, problem = write_mistakes(tmp_path)
    code, out, err = vslsp(capsys, "pddl", "check", domain, problem)
    assert code == 2 and err == "3 errors, 1 warning\n"
    assert out.splitlines() == [
        f"{domain}:6:19: warning: type 'item' is used as a parent but not declared; declare it in (:types ...)",
        f"{domain}:17:20: error: unknown predicate 'fra' (did you mean 'far'?)",
        f"{problem}:9:10: error: unknown object or constant 'gren' (did you mean 'green'?)",
        f"{problem}:16:6: error: unknown PDDL 3 operator 'sometimes-before' (did you mean 'sometime-before'?)",
    ]


def test_json_lists_every_diagnostic_with_its_range_and_suggestion(capsys, tmp_path):
    domain, problem = write_mistakes(tmp_path)
    code, out, _ = vslsp(capsys, "pddl", "check", domain, problem, "--json")
    data = json.loads(out)
    assert code == 2 and data["exit_code"] == 2 and data["error"].startswith("3 errors; the first: ")
    first = data["diagnostics"][1]
    assert {
        k: first[k] for k in ("file", "line", "column", "end_line", "end_column", "severity", "message", "suggestion")
    } == {
        "file": str(domain),
        "line": 17,
        "column": 20,
        "end_line": 17,
        "end_column": 23,
        "severity": "error",
        "message": "unknown predicate 'fra'",
        "suggestion": "far",
    }
    assert [d["severity"] for d in data["diagnostics"]] == ["warning", "error", "error", "error"]
    assert data["diagnostics"][0]["suggestion"] is None


def test_warnings_only_exit_0_and_print_the_summary(capsys, tmp_path):
    domain = tmp_path / "domain.pddl"
    domain.write_text(DOMAIN.read_text().replace(":negative-preconditions ", ""))
    code, out, _ = vslsp(capsys, "pddl", "check", domain, PROBLEM)
    lines = out.splitlines()
    assert (
        code == 0 and lines[0].startswith(f"{domain}:") and ": warning: this needs :negative-preconditions" in lines[0]
    )
    assert lines[-1] == "ok"
    code, out, _ = vslsp(capsys, "pddl", "check", domain, PROBLEM, "--json")
    data = json.loads(out)
    assert code == 0 and data["exit_code"] == 0 and "error" not in data
    assert [d["severity"] for d in data["diagnostics"]] == ["warning"]  # at the first place that needs it
    assert data["domain"]["actions"] == ["push", "pull"] and data["warnings"] == [lines[0]]


def test_a_clean_pair_is_exit_0_with_no_diagnostics(capsys):
    code, out, _ = vslsp(capsys, "pddl", "check", DOMAIN, PROBLEM, "--json")
    data = json.loads(out)
    assert code == 0 and data["diagnostics"] == [] and data["exit_code"] == 0


def test_an_unreadable_file_is_one_message_and_json_with_no_diagnostics(capsys, tmp_path):
    code, out, err = vslsp(capsys, "pddl", "check", DOMAIN, tmp_path / "missing.pddl", "--json")
    data = json.loads(out)
    assert code == 2 and data["diagnostics"] == [] and "missing.pddl: cannot read the file" in data["error"]
    too_big = tmp_path / "big.pddl"
    too_big.write_text(";" * 1_000_001)
    code, _, err = vslsp(capsys, "pddl", "check", DOMAIN, too_big, "--max-size", "1")
    assert code == 2 and "over the limit of 1.0 MB; raise it with --max-size MB" in err and "Traceback" not in err


def test_the_check_imports_neither_unified_planning_nor_the_planner():
    script = (
        "import sys\n"
        "from vslsp.cli import main\n"
        "try:\n"
        f"    main(['pddl', 'check', {str(DOMAIN)!r}, {str(PROBLEM)!r}])\n"
        "except SystemExit:\n"
        "    pass\n"
        "heavy = sorted(m for m in sys.modules if m.split('.')[0] in ('unified_planning', 'numpy')"
        " or m in ('vslsp.symbolic.io.pddl', 'vslsp.symbolic.engines.planner', 'vslsp.symbolic.model.up_model'))\n"
        "print('imported:', heavy)\n"
    )
    import subprocess
    import sys

    from helpers.cli import REPO

    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, cwd=REPO, timeout=120)
    assert result.stdout.splitlines()[-1] == "imported: []", result.stderr


def test_the_program_prints_the_diagnostics(tmp_path):
    domain, problem = write_mistakes(tmp_path)
    result = vslsp_process("pddl", "check", domain, problem, timeout=120)
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert f"{domain}:17:20: error: unknown predicate 'fra' (did you mean 'far'?)" in result.stdout.splitlines()
