"""The own-predicate example (examples/grounding/own_predicate.py) runs as a user runs it: its
predicate is grounded beside far and predicates.py's, and the learned pull model is over it."""

from pathlib import Path

from helpers.examples import run_example

EXAMPLE = Path(__file__).with_name("own_predicate.py")


def test_the_example_grounds_its_own_predicate_and_learns_over_it(capsys, monkeypatch):
    printed = run_example(EXAMPLE, [], capsys, monkeypatch)
    assert "the operation: pull green" in printed
    before = next(line for line in printed.splitlines() if line.startswith("before:"))
    assert "(top-half green)" in before and "(far green)" in before
    assert ":precondition (and (far ?b) (not (on-robot-side ?b)) (top-half ?b))" in printed
