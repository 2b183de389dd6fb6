"""Finding a goal conjunct or a constraint of the model in the problem file that writes it."""

from vslsp.symbolic.io.locate import as_written, find, normalised, written_parts

PROBLEM = """(define (problem p) (:domain d)
  (:objects a b - block)
  (:init (far a))
  (:goal (and (far a)
              (forall (?b - block) (and (far ?b) (far a)))))   ; one conjunct
  (:constraints (and
    (forall (?x ?y - block)   ; expanded by the reader
      (sometime-before (far ?x)
                       (far ?y)))
    (preference p1 (always (far a)))
    (at end (far b)))))
"""


def test_goal_conjuncts_and_constraints_are_listed_as_written():
    goals = written_parts(PROBLEM, ":goal")
    assert [(g.text, g.line, g.column) for g in goals] == [
        ("(far a)", 4, 15),
        ("(forall (?b - block) (and (far ?b) (far a)))", 5, 15),
    ]
    constraints = written_parts(PROBLEM, ":constraints")  # the preference is soft: not listed
    assert [(c.text, c.line, c.column) for c in constraints] == [
        ("(forall (?x ?y - block) (sometime-before (far ?x) (far ?y)))", 7, 5),
        ("(at end (far b))", 11, 5),
    ]


def test_a_ground_instance_is_found_at_its_quantified_constraint():
    constraints = written_parts(PROBLEM, ":constraints")
    assert find("(sometime-before (far a) (far b))", constraints) is constraints[0]
    assert find("(at end (far b))", constraints) is constraints[1]
    assert find("(always (far a))", constraints) is None  # a preference is no constraint
    goals = written_parts(PROBLEM, ":goal")
    assert find("(forall (?b - block) (and (far ?b) (far a)))", goals) is goals[1]
    assert find("(FAR A)", goals) is goals[0]  # PDDL names are case-insensitive


def test_an_item_not_found_keeps_the_model_text_without_position():
    item = as_written("goal", "(far b)", PROBLEM, "p.pddl")
    assert item == {
        "kind": "goal",
        "text": "(far b)",
        "instance": "(far b)",
        "file": "p.pddl",
        "line": None,
        "column": None,
    }


def test_normalised_drops_comments_and_spacing():
    assert normalised("( sometime-before  (a) ; why\n   (b) )") == "(sometime-before (a) (b))"
