"""``save`` after ``load`` in ``vslsp shell``: the loaded files' text is kept (comments, layout, the
order of ``:init``) and only the sections the session changed are rewritten, in place."""

import difflib
import io
import warnings

import pytest
from helpers.cli import REPO, vslsp, vslsp_process
from helpers.symbolic import PDDL

from vslsp.shell.session import Shell
from vslsp.symbolic import read_pddl

ROVERS = REPO / "tests" / "data" / "pddl3" / "ipc2006" / "rovers-preferences-qualitative"
BLOCKSWORLD = REPO / "tests" / "data" / "pddl3" / "liftedtcore" / "blocksworld"


def session(script: str) -> tuple[Shell, str]:
    out = io.StringIO()
    shell = Shell(stdin=io.StringIO(script), stdout=out)
    shell.use_rawinput = False
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the IPC files' preferences, read leniently
        shell.cmdloop()
    return shell, out.getvalue()


def changed_lines(before: str, after: str) -> list[str]:
    """The lines removed (``-``) and added (``+``), as difflib tells them."""
    diff = difflib.unified_diff(before.splitlines(), after.splitlines(), lineterm="", n=0)
    return [line for line in diff if line[:1] in "+-" and line[:3] not in ("---", "+++")]


def read_back(domain, problem):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return read_pddl(domain, problem)


@pytest.mark.parametrize(
    ("domain", "problem"),
    [
        (PDDL / "domain.pddl", PDDL / "pull-in-order.pddl"),
        (ROVERS / "domain.pddl", ROVERS / "instance-1.pddl"),
        (BLOCKSWORLD / "domain.pddl", BLOCKSWORLD / "p1.pddl"),
    ],
)
def test_saving_what_was_loaded_unchanged_writes_the_same_bytes(tmp_path, domain, problem):
    _, out = session(f"load {domain} {problem}\nsave {tmp_path}/d.pddl {tmp_path}/p.pddl\n")
    assert f"saved {tmp_path}/d.pddl and {tmp_path}/p.pddl (the loaded text kept where unchanged)" in out
    assert (tmp_path / "d.pddl").read_bytes() == domain.read_bytes()
    assert (tmp_path / "p.pddl").read_bytes() == problem.read_bytes()


def test_an_edit_rewrites_only_its_own_parts(tmp_path, capsys):
    shell, out = session(
        f"load {PDDL / 'domain.pddl'} {PDDL / 'keep-all-near.pddl'}\n"
        "init (far orange)\ndrop action push\ngoal (not (far green))\n"
        f"save {tmp_path}/d.pddl {tmp_path}/p.pddl\n"
    )
    assert "error" not in out
    domain_text, problem_text = (tmp_path / "d.pddl").read_text(), (tmp_path / "p.pddl").read_text()
    # The dropped action's lines go; the header comment, the layout and the other action stay.
    assert changed_lines((PDDL / "domain.pddl").read_text(), domain_text) == [
        "-  (:action push",
        "-    :parameters (?b - block)",
        "-    :precondition (not (far ?b))",
        "-    :effect (far ?b))",
        "-",
    ]
    # The new atom follows the others, which keep their order; the goal is rewritten in its place.
    assert changed_lines((PDDL / "keep-all-near.pddl").read_text(), problem_text) == [
        "-    (far blue))",
        "-  (:goal (forall (?b - block) (not (far ?b)))))",
        "+    (far blue)",
        "+    (far orange))",
        "+  (:goal (not (far green))))",
    ]
    assert read_back(tmp_path / "d.pddl", tmp_path / "p.pddl") == (shell.domain, shell.problem)
    code, checked, _ = vslsp(capsys, "pddl", "check", tmp_path / "d.pddl", tmp_path / "p.pddl")
    assert code == 0, checked


def test_an_ipc_file_keeps_its_comments_and_layout_through_edits(tmp_path, capsys):
    shell, out = session(
        f"load {ROVERS / 'domain.pddl'} {ROVERS / 'instance-1.pddl'}\n"
        "drop action communicate_image_data\ndrop init (channel_free general)\n"
        "objects rover1 - rover\ninit (available rover1)\n"
        "goal (communicated_soil_data waypoint2)\n"
        f"save {tmp_path}/d.pddl {tmp_path}/p.pddl\n"
    )
    assert "error" not in out
    domain_text, problem_text = (tmp_path / "d.pddl").read_text(), (tmp_path / "p.pddl").read_text()
    original = (ROVERS / "domain.pddl").read_text()
    assert domain_text.startswith(original[: original.index("(:action communicate_image_data")].rstrip())
    removed = [line for line in changed_lines(original, domain_text) if line.startswith("-")]
    assert removed[0] == "-  (:action communicate_image_data" and len(removed) == 10
    assert [line for line in changed_lines(original, domain_text) if line.startswith("+")] == []
    changes = changed_lines((ROVERS / "instance-1.pddl").read_text(), problem_text)
    assert "+         objective0 - objective objective1 - objective rover1 - rover)" in changes
    assert "+         (visible_from objective1 waypoint3)" in changes and "+         (available rover1))" in changes
    assert "+        (:goal (communicated_soil_data waypoint2))" in changes
    assert "+         (at_lander general waypoint0)" in changes  # the dropped atom shared this line
    assert len([line for line in changes if line.startswith("+")]) == 5
    assert "(preference a0 (always (at_soil_sample waypoint0)))" in problem_text  # the constraints as written
    assert read_back(tmp_path / "d.pddl", tmp_path / "p.pddl") == (shell.domain, shell.problem)
    code, checked, _ = vslsp(capsys, "pddl", "check", tmp_path / "d.pddl", tmp_path / "p.pddl")
    assert code == 0, checked


def test_new_sections_and_actions_go_where_pddl_puts_them(tmp_path):
    shell, out = session(
        f"load {BLOCKSWORLD / 'domain.pddl'} {BLOCKSWORLD / 'p1.pddl'}\n"
        "type table\npredicate (wide ?t - table)\n"
        "action wipe :parameters (?t - table) :precondition (not (wide ?t)) :effect (wide ?t)\n"
        "drop constraints\n"
        f"save {tmp_path}/d.pddl {tmp_path}/p.pddl\n"
    )
    assert "error" not in out
    domain_text = (tmp_path / "d.pddl").read_text()
    assert " (:types block table)\n" in domain_text
    assert ":action-costs :negative-preconditions)" in domain_text  # newly needed, nothing declared dropped
    assert "(on ?obj1 - block ?obj2 - block) (wide ?t - table))" in domain_text
    assert domain_text.index("(:action unstack") < domain_text.index("(:action wipe") < domain_text.rindex(")")
    assert "(:constraints" not in (tmp_path / "p.pddl").read_text()
    assert read_back(tmp_path / "d.pddl", tmp_path / "p.pddl") == (shell.domain, shell.problem)


def test_a_renamed_domain_is_renamed_in_both_files(tmp_path):
    shell, _ = session(
        f"load {PDDL / 'domain.pddl'} {PDDL / 'pull-in-order.pddl'}\ndomain tabletop\nproblem in-order\n"
        f"save {tmp_path}/d.pddl {tmp_path}/p.pddl\n"
    )
    assert changed_lines((PDDL / "domain.pddl").read_text(), (tmp_path / "d.pddl").read_text()) == [
        "-(define (domain vsl-sp)",
        "+(define (domain tabletop)",
    ]
    assert changed_lines((PDDL / "pull-in-order.pddl").read_text(), (tmp_path / "p.pddl").read_text()) == [
        "-(define (problem pull-in-order)",
        "-  (:domain vsl-sp)",
        "+(define (problem in-order)",
        "+  (:domain tabletop)",
    ]
    assert read_back(tmp_path / "d.pddl", tmp_path / "p.pddl") == (shell.domain, shell.problem)


def test_undoing_a_load_saves_what_was_there_before(tmp_path):
    _, out = session(
        f"type block\nload {PDDL / 'domain.pddl'}\nundo\nsave {tmp_path}/d.pddl\n"
        f"load {PDDL / 'domain.pddl'}\nsave {tmp_path}/again.pddl\n"
    )
    assert f"undone: load {PDDL / 'domain.pddl'}" in out
    assert f"saved {tmp_path}/d.pddl\n" in out  # built in the shell: written as to_pddl writes it
    assert (
        "(:types block - object)" in (tmp_path / "d.pddl").read_text() and "; " not in (tmp_path / "d.pddl").read_text()
    )
    assert (tmp_path / "again.pddl").read_bytes() == (PDDL / "domain.pddl").read_bytes()


def test_crlf_files_keep_their_line_ends(tmp_path):
    (tmp_path / "in.pddl").write_bytes((PDDL / "keep-all-near.pddl").read_bytes().replace(b"\n", b"\r\n"))
    _, out = session(
        f"load {PDDL / 'domain.pddl'} {tmp_path}/in.pddl\ninit (far orange)\nsave {tmp_path}/d.pddl {tmp_path}/p.pddl\n"
    )
    saved = (tmp_path / "p.pddl").read_bytes()
    assert b"    (far blue)\r\n    (far orange))\r\n" in saved and b"\n" not in saved.replace(b"\r\n", b"")


def test_every_accepted_command_says_what_it_did(tmp_path):
    commands = [
        f"load {PDDL / 'domain.pddl'} {PDDL / 'pull-in-order.pddl'}",
        "drop init (far orange)",
        "undo",
        "show constraints",
        "drop constraint 1",
        f"save {tmp_path}/d.pddl {tmp_path}/p.pddl",
        "validate (pull orange) (pull green) (pull yellow)",
        "domain",
        "problem in-order",
        "type heavy - block",
        "predicate (high ?b - block)",
        "action lift :parameters (?b - heavy) :effect (high ?b)",
        "objects red - heavy",
        "init (far red)",
        "goal (high red)",
        "constraint (sometime (far red))",
        "drop constraints",
        "drop action lift",
        "show",
        "help undo",
    ]
    _, out = session("\n".join(commands) + "\n")
    said = out.split("(vslsp) ")[1:]  # what followed each prompt; the last prompt met the end of input
    assert len(said) == len(commands) + 1 and all(text.strip() for text in said[:-1]), said
    assert said[2] == "undone: drop init (far orange)\n" and said[5].startswith("saved ")


#: A hand-written domain: a comment per action, one inside :predicates, a trailing one.
KITCHEN = """\
; A kitchen, written by hand.
(define (domain kitchen)
  (:requirements :strips :typing)
  (:types dish)
  (:predicates
    (clean ?d - dish)   ; washed
    (holding ?d - dish))

  ; Picking a dish up.
  (:action pick-up
    :parameters (?d - dish)
    :effect (holding ?d))

  ; Washing what is held.
  (:action wash
    :parameters (?d - dish)
    :precondition (holding ?d)
    :effect (clean ?d)))
; the end
"""


def test_a_replaced_action_is_rewritten_in_its_place_and_a_dropped_one_goes_with_its_comment(tmp_path):
    (tmp_path / "kitchen.pddl").write_text(KITCHEN)
    shell, out = session(
        f"load {tmp_path}/kitchen.pddl\n"
        "action wash :parameters (?d - dish) :precondition (and (holding ?d) (not (clean ?d))) :effect (clean ?d)\n"
        "drop action pick-up\npredicate (dirty ?d - dish)\n"
        f"save {tmp_path}/saved.pddl\n"
    )
    assert "error" not in out
    saved = (tmp_path / "saved.pddl").read_text()
    # Only the action, the predicates' end and the requirements differ; every comment left stays.
    assert saved == (
        KITCHEN.replace(":typing)", ":typing :negative-preconditions)")
        .replace("(holding ?d - dish))", "(holding ?d - dish)\n    (dirty ?d - dish))")
        .replace(KITCHEN[KITCHEN.index("  ; Picking") : KITCHEN.index("  ; Washing")], "")
        .replace(
            "    :precondition (holding ?d)\n    :effect (clean ?d)))",
            "    :precondition (and (holding ?d) (not (clean ?d)))\n    :effect (and (clean ?d))))",
        )
    )
    assert read_back(tmp_path / "saved.pddl", None)[0] == shell.domain


def test_typed_lists_get_new_names_appended_in_the_order_given(tmp_path):
    shell, out = session(
        f"load {PDDL / 'domain.pddl'} {PDDL / 'pull-in-order.pddl'}\n"
        "type heavy - block\ntype table\nobjects red - block\nobjects t1 - table\n"
        f"save {tmp_path}/d.pddl {tmp_path}/p.pddl\n"
    )
    assert "error" not in out
    # The untyped 'block' says '- object' once a typed name follows it; 'red' joins its type's group.
    assert changed_lines((PDDL / "domain.pddl").read_text(), (tmp_path / "d.pddl").read_text()) == [
        "-  (:types block)",
        "+  (:types block - object heavy - block table)",
    ]
    assert changed_lines((PDDL / "pull-in-order.pddl").read_text(), (tmp_path / "p.pddl").read_text()) == [
        "-  (:objects orange green yellow - block)",
        "+  (:objects orange green yellow red - block t1 - table)",
    ]
    assert read_back(tmp_path / "d.pddl", tmp_path / "p.pddl") == (shell.domain, shell.problem)


def test_the_files_given_to_vslsp_shell_are_edited_in_place_too(tmp_path):
    done = vslsp_process(
        "shell",
        PDDL / "domain.pddl",
        PDDL / "pull-in-order.pddl",
        input=f"save {tmp_path}/same.pddl {tmp_path}/same-problem.pddl\ndrop init (far green)\n"
        f"save {tmp_path}/d.pddl {tmp_path}/p.pddl\n",
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "same.pddl").read_bytes() == (PDDL / "domain.pddl").read_bytes()
    assert (tmp_path / "same-problem.pddl").read_bytes() == (PDDL / "pull-in-order.pddl").read_bytes()
    assert changed_lines((PDDL / "pull-in-order.pddl").read_text(), (tmp_path / "p.pddl").read_text()) == [
        "-    (far green)"
    ]


def test_a_dropped_constraint_takes_only_its_line_and_a_new_one_follows_the_rest(tmp_path):
    shell, out = session(
        f"load {PDDL / 'domain.pddl'} {PDDL / 'pull-in-order.pddl'}\n"
        "drop constraint 1\nconstraint (sometime (far green))\n"
        f"save {tmp_path}/d.pddl {tmp_path}/p.pddl\n"
    )
    assert "error" not in out
    assert changed_lines((PDDL / "pull-in-order.pddl").read_text(), (tmp_path / "p.pddl").read_text()) == [
        "-    (sometime-before (not (far green)) (not (far orange)))",
        "-    (sometime-before (not (far yellow)) (not (far green))))))",
        "+    (sometime-before (not (far yellow)) (not (far green)))",
        "+    (sometime (far green)))))",
    ]
    assert read_back(tmp_path / "d.pddl", tmp_path / "p.pddl") == (shell.domain, shell.problem)


def test_loading_the_same_model_with_other_text_is_a_change_undo_takes_back(tmp_path):
    (tmp_path / "commented.pddl").write_text("; my own comment\n" + (PDDL / "domain.pddl").read_text())
    _, out = session(f"load {PDDL / 'domain.pddl'}\nload {tmp_path}/commented.pddl\nundo\nsave {tmp_path}/d.pddl\n")
    assert f"undone: load {tmp_path}/commented.pddl" in out
    assert (tmp_path / "d.pddl").read_bytes() == (PDDL / "domain.pddl").read_bytes()
