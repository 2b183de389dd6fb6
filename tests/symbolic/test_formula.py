"""Formulas and PDDL 3.0 constraints: printing, JSON, substitution and truth in a state."""

from helpers.symbolic import far

from vslsp.symbolic import Forall, Not, SometimeBefore, forall, holds
from vslsp.symbolic.model.formula import Exists, Imply, formula_from_list, formula_to_list, substitute

UNIVERSE = {"block": ("red", "green")}


def test_formulas_print_as_pddl():
    assert (~far("?b")).to_pddl() == "(not (far ?b))"
    assert forall(("?b", "block"), ~far("?b")).to_pddl() == "(forall (?b - block) (not (far ?b)))"
    assert (
        SometimeBefore(~far("green"), ~far("orange")).to_pddl()
        == "(sometime-before (not (far green)) (not (far orange)))"
    )


def test_quantifiers_range_over_the_objects_of_the_type():
    nobody_far = forall(("?b", "block"), ~far("?b"))
    assert holds(nobody_far, frozenset(), UNIVERSE)
    assert not holds(nobody_far, frozenset({far("green")}), UNIVERSE)
    assert holds(Exists((("?b", "block"),), far("?b")), frozenset({far("green")}), UNIVERSE)
    assert holds(Imply(far("red"), far("green")), frozenset({far("green")}), UNIVERSE)


def test_substitution_respects_bound_variables():
    formula = far("?b") & Forall((("?b", "block"),), far("?b"))
    assert substitute(formula, {"?b": "red"}) == far("red") & Forall((("?b", "block"),), far("?b"))


def test_json_lists_round_trip():
    for formula in (forall(("?b", "block"), ~far("?b") | far("red")), SometimeBefore(far("a"), Not(far("b")))):
        data = formula_to_list(formula)
        assert formula_from_list(data) == formula
    assert formula_to_list(~far("?b")) == ["not", ["far", "?b"]]
