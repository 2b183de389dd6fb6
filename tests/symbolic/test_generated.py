"""Large PDDL: generated logistics problems past 1 MB are read and checked clean; the size limit is
``--max-size MB`` on every command that reads PDDL, and a file over it is exit 2 naming the file, its
size and the option (figures of time and memory: benchmarks/bench_pddl_size.py)."""

from __future__ import annotations

import json

import pytest
from helpers.cli import vslsp

from vslsp.errors import InputError
from vslsp.symbolic.io.generated import LOGISTICS_DOMAIN, logistics_problem
from vslsp.symbolic.language import analyse, read_text


def test_a_problem_grows_linearly_with_its_objects_and_is_the_same_each_time():
    small, large = logistics_problem(10_000), logistics_problem(50_000)
    assert small == logistics_problem(10_000)
    assert 1.4e6 <= len(large) <= 1.5e6 and 5 <= len(large) / len(small) <= 5.6  # names grow by a digit
    analysis = analyse(LOGISTICS_DOMAIN, "domain.pddl", small, "problem.pddl")
    assert analysis.diagnostics == [] and len(analysis.index.of_kind("object")) == 10_000
    with pytest.raises(ValueError, match="at least 7 objects"):
        logistics_problem(6)


@pytest.fixture(scope="module")
def large(tmp_path_factory: pytest.TempPathFactory):
    folder = tmp_path_factory.mktemp("large")
    (folder / "domain.pddl").write_text(LOGISTICS_DOMAIN)
    (folder / "problem.pddl").write_text(logistics_problem(50_000))
    return folder / "domain.pddl", folder / "problem.pddl"


def test_a_problem_of_50000_objects_past_1_mb_checks_clean(capsys, large):
    domain, problem = large
    assert problem.stat().st_size > 1_400_000
    code, out, err = vslsp(capsys, "pddl", "check", "--json", domain, problem)
    report = json.loads(out)
    assert code == 0 and report["diagnostics"] == [] and err == ""
    assert len(report["problem"]["objects"]) == 50_000 and "at" in report["domain"]["predicates"]


@pytest.mark.parametrize("command", ["check", "plan", "validate", "shell"])
def test_a_file_over_max_size_is_exit_2_naming_it_its_size_and_the_option(capsys, large, command):
    domain, problem = large
    args = {
        "check": ("pddl", "check", domain, problem),
        "plan": ("plan", domain, problem),
        "validate": ("validate", domain, problem, problem),
        "shell": ("pddl", "shell", domain, problem),
    }[command]
    code, out, err = vslsp(capsys, *args, "--max-size", "1.2")
    expected = f"{problem}: the PDDL file has 1.5 MB, over the limit of 1.2 MB; raise it with --max-size MB"
    assert code == 2 and err.startswith(f"error: {expected}") and err.count("\n") == 1, err
    assert "Traceback" not in err
    if command != "shell":
        code, out, _ = vslsp(capsys, *args, "--max-size", "1.2", "--json")
        assert code == 2 and expected in json.loads(out)["error"]


def test_max_size_must_be_a_positive_number_of_mb(capsys, large):
    domain, problem = large
    for bad in ("0", "-1", "x", "nan"):
        code, _, err = vslsp(capsys, "pddl", "check", domain, problem, "--max-size", bad)
        assert code == 2 and "Invalid value for '--max-size'" in err and "Traceback" not in err


def test_a_small_file_under_a_huge_limit_takes_no_more_memory_than_itself(tmp_path):
    path = tmp_path / "domain.pddl"
    path.write_text(LOGISTICS_DOMAIN)
    # read(limit) would reserve the whole limit (a terabyte here: MemoryError) before reading
    assert read_text(path, max_bytes=10**12) == LOGISTICS_DOMAIN
    with pytest.raises(InputError, match=r"domain.pddl: the PDDL file has 0.00\d+ MB, over the limit of 0.001 MB"):
        read_text(path, max_bytes=1000)
