"""The PDDL language engine's rules beyond typos: the type hierarchy, sections, what the planner
path refuses, constraints, a problem read without its domain, and text that is still being typed."""

from __future__ import annotations

from pathlib import Path

from helpers.symbolic import PDDL

from vslsp.symbolic.language import analyse, read_document, text_of

DOMAIN = (PDDL / "domain.pddl").read_text()
PROBLEM = (PDDL / "pull-in-order.pddl").read_text()


def messages(domain: str, problem: str | None = None) -> list[str]:
    return [d.format() for d in analyse(domain, "d.pddl", problem, "p.pddl").diagnostics]


def test_a_type_cycle_is_one_error_at_its_first_type():
    domain = DOMAIN.replace("(:types block)", "(:types block - thing thing - item item - block)")
    assert messages(domain) == [
        "d.pddl:6:11: error: the types form a cycle (block - thing - item - block); a type cannot be its own ancestor"
    ]


def test_a_type_declared_after_it_served_as_a_parent_is_fine():
    domain = DOMAIN.replace("(:types block)", "(:types block - item item)")
    assert messages(domain, PROBLEM) == []


def test_either_is_read_in_a_predicates_parameters_and_refused_elsewhere():
    domain = DOMAIN.replace("(:types block)", "(:types block cube)").replace(
        "(far ?b - block)", "(far ?b - (either block cube))"
    )
    assert messages(domain, PROBLEM) == []
    refused = domain.replace(":parameters (?b - block)", ":parameters (?b - (either block cube))", 1)
    assert "error: (either ...) types are supported only in a predicate's parameters" in messages(refused)[0]


def test_sections_in_the_wrong_file_or_misspelt_are_named():
    domain = DOMAIN.replace("(:types block)", "(:types block)\n  (:objects a - block)\n  (:constant b - block)")
    assert messages(domain) == [
        "d.pddl:7:4: error: ':objects' belongs in a problem file",
        "d.pddl:8:4: error: unknown section ':constant' (did you mean ':constants'?)",
    ]


def test_what_the_planner_refuses_is_an_error_where_written():
    derived = DOMAIN.replace("(:action push", "(:derived (near ?b - block) (not (far ?b)))\n  (:action push")
    assert "d.pddl:10:4: error: derived predicates (:derived ...) are not supported" in messages(derived)[0]
    durative = DOMAIN.replace("(:action push", "(:durative-action push")  # its :precondition is not PDDL 2.1's
    assert any(
        "unknown keyword ':precondition' in an action (did you mean ':condition'?)" in m for m in messages(durative)
    )
    paper = PROBLEM.replace("(sometime-before (not (far green))", "(somewhere-after (not (far green))")
    [message] = messages(DOMAIN, paper)
    assert message.startswith("p.pddl:16:6: error: PDDL 3.0 has no 'somewhere-after'")
    assert message.endswith("(did you mean 'sometime-before'?)")
    timed = PROBLEM.replace("(sometime-before (not (far green)) (not (far orange)))", "(within 3 (far green))")
    assert "(within ...) is not supported" in messages(DOMAIN, timed)[0]


def test_constraints_take_their_formulas_and_at_end_reads():
    problem = PROBLEM.replace("(sometime-before (not (far green)) (not (far orange)))", "(at end (far green))")
    assert messages(DOMAIN, problem) == []
    missing = PROBLEM.replace("(sometime-before (not (far green)) (not (far orange)))", "(sometime-before (far green))")
    assert messages(DOMAIN, missing) == ["p.pddl:16:5: error: (sometime-before ...) takes 2 formulas, 1 given"]
    bare = PROBLEM.replace("(sometime-before (not (far green)) (not (far orange)))", "(far green)")
    assert "is a formula, not a constraint" in messages(DOMAIN, bare)[0]
    misplaced = PROBLEM.replace("(:goal (and", "(:goal (and (always (far green))")
    assert (
        "'always' is a PDDL 3 constraint: it belongs in the problem's (:constraints ...)"
        in messages(DOMAIN, misplaced)[0]
    )


def test_a_problem_without_its_domain_is_read_for_its_outline():
    analysis = analyse(PROBLEM, "p.pddl")
    assert analysis.diagnostics == [] and analysis.problem_domain == "vsl-sp"
    assert [d.signature for d in analysis.index.in_file("p.pddl")] == [
        "problem pull-in-order",
        "orange - block",
        "green - block",
        "yellow - block",
    ]


def test_text_being_typed_never_breaks_the_engine():
    # every prefix of the shipped pair, as an editor sends it keystroke by keystroke
    for end in range(0, len(PROBLEM) + 1, 7):
        analysis = analyse(DOMAIN, "d.pddl", PROBLEM[:end], "p.pddl")
        assert all(d.file in ("d.pddl", "p.pddl") and d.line >= 1 and d.column >= 1 for d in analysis.diagnostics)
    for end in range(0, len(DOMAIN) + 1, 7):
        analyse(DOMAIN[:end], "d.pddl", PROBLEM, "p.pddl")


def test_tokens_carry_their_places_and_lists_their_text():
    document = read_document("(define (domain d)\n  ; note\n  (:predicates (On-Top ?x)))", "d.pddl")
    names = [(t.text, t.key, t.line, t.column, t.end_column) for t in document.tokens if t.kind == "name"]
    assert names[-2:] == [("On-Top", "on-top", 3, 17, 23), ("?x", "?x", 3, 24, 26)]
    assert document.comment_above(3) == "note"
    assert text_of(document.groups[0]) == "(define (domain d) (:predicates (On-Top ?x)))"


def test_a_plan_is_checked_step_by_step_with_the_names_meant():
    from vslsp.symbolic.language import analyse_plan

    analysis = analyse(DOMAIN, "d.pddl", PROBLEM, "p.pddl")
    plan = "(pull orange)\n0: (pul green) ; VAL's format\n1. pull gren\n(push)\nnonsense\n"
    checked = analyse_plan(analysis, plan, "plan.txt")
    assert [d.format() for d in checked.diagnostics] == [
        "plan.txt:2:5: error: unknown action 'pul' (did you mean 'pull'?)",
        "plan.txt:3:9: error: unknown object or constant 'gren' (did you mean 'green'?)",
        "plan.txt:4:2: error: 'push' takes 1 argument, 0 given",
        "plan.txt:5:1: error: expected one step like (pull green) or 1. pull green, got 'nonsense'",
    ]
    assert checked.steps == [("pull", ("orange",))]
    orange = analysis.index.find("object", "orange")
    assert [r.declaration for r in checked.references if r.name == "orange"] == [orange]


def test_a_parenthesis_too_many_or_too_few_is_found_where_the_lists_go_wrong():
    extra = DOMAIN.replace(":effect (far ?b))", ":effect (far ?b)))")
    assert messages(extra) == [
        "d.pddl:13:22: error: unexpected ')': it closes (define ...) before its sections end; remove it"
    ]
    missing = DOMAIN.replace(":effect (far ?b))", ":effect (far ?b)")
    assert messages(missing) == ["d.pddl:10:3: error: '(:action' is never closed: a ')' is missing"]
    storage = (
        Path(__file__).parents[1] / "data" / "pddl3" / "ipc2006" / "storage-preferences-qualitative" / "domain.pddl"
    )
    flat = storage.read_text().replace("(not (in ?c ?p))))", "(not (in ?c ?p)))", 1)  # sections at column 1
    errors = [d.format() for d in analyse(flat, "d.pddl").errors]
    assert errors == ["d.pddl:20:1: error: '(:action' is never closed: a ')' is missing"]


def test_every_name_declared_twice_is_an_error_at_the_second():
    domain = DOMAIN.replace("(far ?b - block))", "(far ?b - block)\n    (far ?c - block))").replace(
        ":parameters (?b - block)", ":parameters (?b - block ?b - block)", 1
    )
    assert messages(domain) == [
        "d.pddl:9:6: error: predicate 'far' is declared twice (first at line 8)",
        "d.pddl:12:29: error: parameter '?b' is declared twice",
    ]
    problem = PROBLEM.replace("(:objects orange green yellow - block)", "(:objects orange green orange - block)")
    assert messages(DOMAIN, problem)[0] == "p.pddl:6:26: error: object 'orange' is declared twice (first at line 6)"


def test_names_in_an_action_are_its_parameters_or_the_domains_constants():
    domain = DOMAIN.replace(":effect (far ?b))", ":effect (far green))", 1)
    assert messages(domain) == ["d.pddl:13:18: error: unknown constant 'green'"]
    constant = domain.replace("(:types block)", "(:types block)\n  (:constants green - block)")
    assert messages(constant, PROBLEM) == ["p.pddl:6:20: warning: 'green' is a constant of the domain already"]
