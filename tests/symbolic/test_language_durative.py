"""The language engine on PDDL 2.1 (vslsp.symbolic.language.durative and the numeric checks):
the numeric and temporal domains of tests/data/pddl21 check clean, and 21 broken variants each
report their error on its line, with what was meant where a declared name is close."""

from __future__ import annotations

from pathlib import Path

import pytest

from vslsp.symbolic.language import check_files

DATA = Path(__file__).resolve().parents[1] / "data" / "pddl21"
PAIRS = [
    ("rover-numeric-domain.pddl", "rover-numeric-problem.pddl"),
    ("counters-domain.pddl", "counters-problem.pddl"),
    ("rover-temporal-domain.pddl", "rover-temporal-problem.pddl"),
    ("rover-temporal-domain.pddl", "rover-timed-problem.pddl"),
]
TEMPORAL = "rover-temporal-domain.pddl"
#: Blocks of four lines: FILE LINE, what is written, the broken variant, what the error says.
BROKEN_TEXT = """
rover-numeric-domain.pddl 22
(decrease (battery ?r) 1)
(decrease (batery ?r) 1)
unknown function 'batery' (did you mean 'battery'?)

rover-numeric-domain.pddl 11
(distance ?from ?to))
(distance ?from))
'distance' takes 2 arguments, 1 given

rover-numeric-domain.pddl 18
(assign (battery ?r) 10)
(asign (battery ?r) 10)
unknown operator 'asign' (did you mean 'assign'?)

rover-numeric-domain.pddl 17
(< (battery ?r) 10)
(< (battery ?x) 10)
undefined parameter '?x'

rover-numeric-domain.pddl 14
(increase (energy-used)
(increase (energy-use)
unknown function 'energy-use' (did you mean 'energy-used'?)

rover-numeric-domain.pddl 22
(decrease (battery ?r) 1)
(decrease (battery ?r) one)
expected a number or a numeric expression, found 'one'

rover-temporal-domain.pddl 11
:duration (= ?duration 4)
:duraton (= ?duration 4)
unknown keyword ':duraton' in an action (did you mean ':duration'?)

rover-temporal-domain.pddl 12
(at start (at ?r ?from))
(at begin (at ?r ?from))
a durative action's condition is (at start ...), (over all ...), (at end ...)

rover-temporal-domain.pddl 12
(over all (road ?from ?to))
(over all (rode ?from ?to))
unknown predicate 'rode'

rover-temporal-domain.pddl 14
(at end (at ?r ?to))
(at end (at ?r ?too))
undefined parameter '?too' (did you mean '?to'?)

rover-temporal-domain.pddl 14
(at ?r ?to)) (at end (free ?r))))
(at ?r ?to)) (over all (free ?r))))
a durative action's effect is (at start ...), (at end ...); found (over all ...)

rover-temporal-domain.pddl 17
:duration (= ?duration 2)
:duration (= ?time 2)
a duration constraint is (= ?duration N)

rover-temporal-domain.pddl 19
(at end (sampled ?w))
(at end (sampled ?w ?r))
'sampled' takes 1 argument, 2 given

rover-temporal-domain.pddl 18
(over all (at ?r ?w)) (at start (free ?r)))
(over all (at ?r ?w)) (free ?r))
found (free ...)

rover-temporal-domain.pddl 15
(:durative-action sample
(:durative-acton sample
unknown section ':durative-acton' (did you mean ':durative-action'?)

rover-numeric-problem.pddl 5
(= (battery curiosity) 6)
(= (batery curiosity) 6)
unknown function 'batery' (did you mean 'battery'?)

rover-numeric-problem.pddl 11
(:metric minimize (energy-used))
(:metric minimize (energy-usd))
unknown function 'energy-usd' (did you mean 'energy-used'?)

rover-numeric-problem.pddl 5
(= (energy-used) 0)
(= (energy-used) zero)
found 'zero'

rover-numeric-problem.pddl 6
(= (distance base hill) 4)
(= (distance base hil) 4)
unknown object or constant 'hil' (did you mean 'hill'?)

counters-problem.pddl 5
(value c0) 1) (value c1))
(value c0) 1) (valu c1))
unknown function 'valu' (did you mean 'value'?)

rover-timed-problem.pddl 5
(at 3 (road base crater))
(at 3 (rod base crater))
unknown predicate 'rod' (did you mean 'road'?)
"""
BROKEN = [
    (head.split()[0], written, broken, int(head.split()[1]), message)
    for head, written, broken, message in (block.splitlines() for block in BROKEN_TEXT.strip().split("\n\n"))
]


@pytest.mark.parametrize(("domain", "problem"), PAIRS)
def test_numeric_and_temporal_files_check_clean(domain, problem):
    analysis = check_files(str(DATA / domain), str(DATA / problem))
    assert [d.format() for d in analysis.diagnostics] == []


@pytest.mark.parametrize(("file", "written", "broken", "line", "message"), BROKEN)
def test_a_broken_variant_reports_its_line_and_what_was_meant(tmp_path, file, written, broken, line, message):
    text = (DATA / file).read_text()
    assert written in text
    path = tmp_path / file
    path.write_text(text.replace(written, broken, 1))
    if "problem" in file:
        domain = TEMPORAL if "timed" in file else file.replace("problem", "domain")
        analysis = check_files(str(DATA / domain), str(path))
    else:
        analysis = check_files(str(path), None)
    first = analysis.errors[0].format()
    assert first.startswith(f"{path}:{line}:") and message in first


def test_a_durative_action_is_an_action_of_the_outline():
    analysis = check_files(str(DATA / TEMPORAL), None)
    assert [d.key for d in analysis.index.of_kind("action")] == ["drive", "sample"]
    assert [d.key for d in analysis.index.of_kind("function")] == []
