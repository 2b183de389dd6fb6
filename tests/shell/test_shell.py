"""``vslsp shell``: a domain and a problem authored step by step from typed commands, checked as
they come, then planned, validated, saved and loaded; from piped input and from a terminal."""

import io
import shutil
import subprocess
import sys

import pytest
from helpers.cli import REPO, vslsp, vslsp_process
from helpers.events import wait_until
from helpers.symbolic import PDDL

from vslsp.shell.commands import COMMANDS
from vslsp.shell.session import Shell
from vslsp.symbolic import read_pddl

#: A whole domain from nothing: four predicates, three actions, types, objects, init, goal and
#: three constraints, one of them dropped by its number; then plan, validate and save.
KITCHEN = """\
domain kitchen
type dish
type cup - dish
predicate (on-counter ?d - dish)
predicate (holding ?d - dish)
predicate (clean ?d - dish)
predicate (hand-empty)
{actions}
problem tidy-up
objects plate bowl - dish
objects mug - cup
init (on-counter plate) (on-counter bowl) (on-counter mug) (hand-empty)
goal (and (clean plate) (clean bowl) (clean mug) (on-counter plate) (on-counter bowl) (on-counter mug))
constraint (sometime-before (clean bowl) (clean plate))
constraint (always (hand-empty))
constraint (sometime-before (clean mug) (clean bowl))
drop constraint 2
plan
validate
save {folder}/domain.pddl {folder}/problem.pddl
quit
"""
ACTIONS = (
    "action pick-up :parameters (?d - dish) :precondition (and (on-counter ?d) (hand-empty))"
    " :effect (and (holding ?d) (not (on-counter ?d)) (not (hand-empty)))\n"
    "action wash :parameters (?d - dish) :precondition (holding ?d) :effect (clean ?d)\n"
    "action put-down :parameters (?d - dish) :precondition (holding ?d)"
    " :effect (and (on-counter ?d) (hand-empty) (not (holding ?d)))"
)
KITCHEN_PLAN = "1. pick-up plate\n2. wash plate\n3. put-down plate\n4. pick-up bowl\n5. wash bowl\n"


def run(script: str, **kwargs) -> str:
    out = io.StringIO()
    shell = Shell(stdin=io.StringIO(script), stdout=out, **kwargs)
    shell.use_rawinput = False
    shell.cmdloop()
    return out.getvalue()


def check_kitchen(capsys, out: str, folder, said_after: str = "(vslsp) ") -> None:
    """The session said what each command did (on the prompt's line when piped, on the line after
    the typed command at a terminal), planned in the constrained order, and what it saved checks
    and plans with the command-line tools."""
    for said in (
        "predicate (on-counter ?d - dish)",
        "predicate (holding ?d - dish)",
        "predicate (clean ?d - dish)",
        "predicate (hand-empty)",
        "action put-down added; actions: pick-up, wash, put-down",
        "constraint (sometime-before (clean mug) (clean bowl)); 3 constraints",
        "dropped constraint 2: (always (hand-empty)); 2 constraints left",
        "valid: the plan reaches the goal in 9 steps and keeps all 2 constraints",
    ):
        assert f"{said_after}{said}\n" in out, said
    assert "error" not in out
    assert KITCHEN_PLAN in out  # plate before bowl before mug, as constrained
    code, checked, _ = vslsp(capsys, "pddl", "check", folder / "domain.pddl", folder / "problem.pddl")
    assert code == 0 and "predicates on-counter, holding, clean, hand-empty; actions pick-up, wash, put-down" in checked
    code, planned, _ = vslsp(capsys, "plan", folder / "domain.pddl", folder / "problem.pddl")
    assert code == 0 and KITCHEN_PLAN in planned


def test_a_whole_domain_from_piped_input_leaves_nothing_in_the_home_folder(tmp_path, monkeypatch, capsys):
    home = tmp_path / "home"
    home.mkdir()
    monkeypatch.setenv("HOME", str(home))
    done = vslsp_process("shell", input=KITCHEN.format(folder=tmp_path, actions=ACTIONS), timeout=300)
    assert done.returncode == 0, done.stderr
    check_kitchen(capsys, done.stdout, tmp_path)
    assert list(home.iterdir()) == []  # no history from piped input, and no temporary file


def test_every_predicate_is_kept_after_load_too(tmp_path):
    out = run(
        f"load {PDDL / 'domain.pddl'} {PDDL / 'keep-all-near.pddl'}\n"
        "predicate (stacked ?a - block ?b - block)\npredicate (high ?b - block)\nshow domain\n"
    )
    assert "(vslsp) predicate (stacked ?a - block ?b - block)\n(vslsp) predicate (high ?b - block)\n" in out
    assert "(far ?b - block)\n    (stacked ?a - block ?b - block)\n    (high ?b - block))" in out


SESSION = """\
domain vsl-sp
type block
predicate (far ?b - block)
action push :parameters (?b - block) :precondition (not (far ?b)) :effect (far ?b)
action pull :parameters (?b - block) :precondition (far ?b) :effect (not (far ?b))
action lift :parameters (?b - block) :precondition (high ?b) :effect (far ?b)
problem pull-in-order
objects orange green yellow - block
init (far orange) (far green) (far yellow)
goal (and (not (far orange)) (not (far green)) (not (far yellow)))
constraint (sometime-before (not (far green)) (not (far orange)))
constraint (somewhere-after (not (far yellow)) (not (far green)))
constraint (sometime-before (not (far yellow)) (not (far green)))
plan
validate (pull green) (pull orange) (pull yellow)
save {folder}/domain.pddl {folder}/problem.pddl
drop constraints
validate (pull green) (pull orange) (pull yellow)
fly away
"""


def test_the_paper_task_is_built_planned_and_validated(tmp_path):
    out = run(SESSION.format(folder=tmp_path))
    assert "error: unknown predicate 'high': declare it with `predicate (high ?x - TYPE)` (in (high ?b))" in out
    assert "error: PDDL 3.0 has no 'somewhere-after'" in out
    assert "1. pull orange\n2. pull green\n3. pull yellow\n" in out
    assert "invalid: constraint (sometime-before (not (far green)) (not (far orange))) is broken" in out
    assert "valid: the plan reaches the goal in 3 steps\n" in out  # once the order is dropped
    assert "error: unknown command 'fly'; type help for the commands" in out
    for said in (
        "type block",
        "predicate (far ?b - block)",
        "action push added; actions: push",
        "true initially: (far orange) (far green) (far yellow)",
        "constraint (sometime-before (not (far green)) (not (far orange))); 1 constraint",
        "dropped 2 constraints",
    ):
        assert f"(vslsp) {said}\n" in out, said
    # What was saved is the shipped pull-in-order experiment.
    saved_domain, saved_problem = read_pddl(tmp_path / "domain.pddl", tmp_path / "problem.pddl")
    shipped_domain, shipped_problem = read_pddl(PDDL / "domain.pddl", PDDL / "pull-in-order.pddl")
    assert saved_domain == shipped_domain
    assert (saved_problem.init, saved_problem.goal, saved_problem.constraints) == (
        shipped_problem.init,
        shipped_problem.goal,
        shipped_problem.constraints,
    )


MISTAKES = """\
type dish
type cup - dsh
predicate (on-counter ?d - dish)
predicate (hand-empty)
predicate (dirty ?d - plato)
objects plate - plato
action pick-up :parameters (?d - dish) :precondition (and (on-counter ?d) (hand-emty)) :effect (not (on-counter ?d))
action pick-up :parameters (?d - dish) :precondition (and (on-counter ?d) (hand-empty)) :effect (not (on-counter ?d))
action wash :parameters (?d - dish) :precondition (on-counter ?x) :effect (clean ?d)
action wash :parametres (?d - dish)
objects plate - dish
objects mug - dish
init (on-counter cupp)
init (on-counter plate mug)
goal (on-countr plate)
constraint (sometimes-before (on-counter plate) (hand-empty))
drop action wsh
drop constraint 1
drop init (on-counter plate)
validate
predicte (x)
"""


def test_mistakes_are_told_in_the_shells_own_terms():
    out = run(MISTAKES)
    for told in (
        "unknown type 'dsh' (did you mean 'dish'?): declare it with `type dsh` (types so far: dish)",
        "unknown type 'plato': declare it with `type plato` (types so far: dish)",
        "unknown predicate 'hand-emty' (did you mean 'hand-empty'?): declare it with `predicate (hand-emty)`",
        "unknown variable '?x' (variables: ?d)",
        "action wash: expected :parameters, :precondition, :effect, got ':parametres' (did you mean ':parameters'?)",
        "unknown object 'cupp': use `objects cupp - TYPE`",
        "(on-counter plate mug): on-counter takes 1 argument (on-counter ?d - dish), 2 given",
        "unknown predicate 'on-countr' (did you mean 'on-counter'?)",
        "'sometimes-before' is not a PDDL 3.0 constraint (did you mean 'sometime-before'?)",
        "no action 'wsh'; actions: pick-up",
        "no constraint 1: there are 0 constraints",
        "(on-counter plate) is not true initially",
        "no plan yet: run plan first, or give the steps",
        "unknown command 'predicte' (did you mean 'predicate'?)",
    ):
        assert f"(vslsp) error: {told}" in out, told
    assert out.count("error:") == 15  # one each, and nothing else failed
    # the Python API's advice never reaches the shell
    for api_word in ("with_type", "with_predicate", "with_objects", "with_action", "Not able to handle", "fluent"):
        assert api_word not in out


ODD = """\
type
type - x
type a -
type 3x
objects 4b - object
predicate ()
predicate (and ?x)
predicate (p ?x - )
action
action a :parameters ?x
action a (x)
objects a -
init
goal ((p))
goal (forall ?x (p))
constraint (a) (b)
drop
drop constraint x
show x
validate (
load "unterminated
type block
predicate (p ?x - block)
action act :parameters (?x - block) :effect (p ?x)
objects b1 b2 - block
constraint (at end)
constraint (sometime-before (p b1))
validate (ac b1)
validate (act)
"""


def test_whatever_is_typed_gets_a_usage_or_one_error_and_the_shell_goes_on():
    out = run(ODD)
    told = [line for line in out.splitlines() if line.startswith("(vslsp) ")]
    commands = ODD.splitlines()
    answers = [t for t in told if t.startswith(("(vslsp) usage:", "(vslsp) error:"))]
    assert len(answers) == len(commands) - 4  # all but the four correct lines
    for expected in (
        "error: '3x' cannot name a type: a PDDL name is a letter, then letters, digits, - or _",
        "error: '4b' cannot name an object",
        "error: a '-' ends the list: name the type after it, e.g. ?d - dish",
        "error: (at end ...) takes 1 formula, 0 given: (at end)",
        "error: (sometime-before ...) takes 2 formulas, 1 given",
        "error: unknown action 'ac' (did you mean 'act'?); actions: act",
        "error: (act): act takes 1 object (act ?x - block), 0 given",
        "error: no closing quotation in what you typed",
    ):
        assert f"(vslsp) {expected}" in out, expected
    assert "(:types block - object)" in run(ODD + "show domain\n")  # and no type '-' or 'a -'


def test_undo_drop_and_show():
    out = run(
        "type block\npredicate (far ?b - block)\npredicate (near ?b - block)\n"
        "action push :parameters (?b - block) :precondition (near ?b) :effect (far ?b)\n"
        "action pull :parameters (?b - block) :precondition (far ?b) :effect (near ?b)\n"
        "objects a b c - block\ninit (far a) (far b) (near c)\n"
        "constraint (sometime-before (near a) (near b))\nconstraint (always (far c))\n"
        "constraint (at-most-once (near a))\nshow problem\ndrop constraint 2\nshow constraints\n"
        "drop init (far b)\ndrop action push\nshow\nundo\nundo\nundo\nshow constraints\nundo\nundo\nundo\n"
        "show domain\n"
    )
    # show numbers the constraints as drop constraint N takes them
    assert "    (always (far c))  ; 2\n" in out
    assert "(vslsp) dropped constraint 2: (always (far c)); 2 constraints left\n" in out
    assert "(vslsp) 1. (sometime-before (near a) (near b))\n2. (at-most-once (near a))\n" in out
    assert "(vslsp) no longer true initially: (far b)\n" in out
    assert "(vslsp) dropped action push; actions: pull\n" in out
    shown = out.split("(vslsp) dropped action push; actions: pull\n")[1].split("(vslsp) undone")[0]
    assert "(:action pull" in shown and "(:action push" not in shown and "(far b)" not in shown
    # undo walks back one change at a time
    for undone in ("drop action push", "drop init (far b)", "drop constraint 2"):
        assert f"(vslsp) undone: {undone}\n" in out
    assert "(vslsp) 1. (sometime-before (near a) (near b))\n2. (always (far c))\n3. (at-most-once (near a))\n" in out
    assert "(vslsp) undone: constraint (at-most-once (near a))\n(vslsp) undone: constraint (always (far c))\n" in out
    last = out.rsplit("(vslsp) ", 2)[1]
    assert "(:action push" in last and "(near ?b - block)" in last


def test_a_predicate_declared_again_replaces_it_unless_an_action_needs_the_old_one():
    out = run(
        "type block\npredicate (far ?b - block)\naction push :parameters (?b - block) :effect (far ?b)\n"
        "predicate (far ?a - block ?c - block)\npredicate (far ?c - block)\npredicate (near ?b - block ?b - block)\n"
    )
    assert "error: action push uses (far ?b): change the action first (action push ...), or drop it" in out
    assert "(vslsp) predicate (far ?c - block) replaced\n" in out
    assert "error: ?b is named twice in the parameters; give each its own name" in out


def test_a_goal_of_several_formulas_is_their_conjunction():
    out = run("type block\npredicate (far ?b - block)\nobjects a b - block\ngoal (far a) (not (far b))\n")
    assert "(vslsp) goal (and (far a) (not (far b)))\n" in out


def test_undo_with_nothing_to_undo_and_errors_change_nothing():
    out = run("undo\ntype block\npredicate (far ?b - blok)\nundo\nundo\nshow domain\n")
    assert "(vslsp) nothing to undo\n" in out
    assert "(vslsp) undone: type block\n(vslsp) nothing to undo\n" in out  # the failed predicate was no change
    assert "(:types" not in out.rsplit("(vslsp) ", 2)[1]


def test_help_lists_every_command_with_an_example(capsys):
    out = run("help\nhelp drop\nhelp drp\n")
    for entry in COMMANDS:
        assert f"  {entry.name} " in out and f"e.g. {entry.example}\n" in out
    assert "drop action NAME | drop constraint N | drop constraints | drop init ATOM ...\n" in out
    assert "error: no command 'drp' (did you mean 'drop'?)" in out
    code, text, _ = vslsp(capsys, "shell", "--help")
    assert code == 0
    for entry in COMMANDS:
        assert f"  {entry.name} " in text and f"e.g. {entry.example}" in text


def test_load_plan_and_validate_the_last_plan():
    out = run(f"load {PDDL / 'domain.pddl'} {PDDL / 'keep-all-near.pddl'}\nplan\nvalidate\n")
    assert "loaded domain vsl-sp and problem keep-all-near" in out and "3 steps" in out
    assert "(vslsp) valid: the plan reaches the goal in 3 steps" in out


def test_vslsp_shell_is_the_pddl_shell_at_the_top_level(tmp_path, monkeypatch):
    monkeypatch.setenv("HOME", str(tmp_path))
    done = vslsp_process("shell", PDDL / "domain.pddl", PDDL / "pull-in-order.pddl", input="plan\nquit\n", timeout=120)
    assert done.returncode == 0, done.stderr
    assert "pull orange" in done.stdout and done.stdout.index("pull orange") < done.stdout.index("pull yellow")
    assert list(tmp_path.iterdir()) == []


def test_a_missing_parenthesis_is_placed_in_what_was_typed():
    out = run("type block\npredicate (on ?a - block ?b - block)\nobjects a b - block\ngoal (on a b\n")
    assert "error: the '(' at column 1 of what you typed is never closed: a ')' is missing\n  (on a b\n  ^\n" in out
    out = run("type block\npredicate (far ?b - block)\nobjects a - block\ninit (far a))\n")
    assert "error: unexpected ')' at column 8 of what you typed:\n  (far a))\n         ^" in out


def test_a_domain_with_constants_is_edited_in_the_shell():
    folder = REPO / "tests" / "data" / "pddl3" / "ipc2006" / "tpp-preferences-qualitative"
    out = run(
        f"load {folder / 'domain.pddl'} {folder / 'instance-1.pddl'}\ngoal (forall (?g - goods) (stored ?g level1))\n"
    )
    assert "(vslsp) goal (forall (?g - goods) (stored ?g level1))\n" in out, out


# --- from a terminal -------------------------------------------------------------------------

TMUX = shutil.which("tmux")


class Terminal:
    """``vslsp shell`` in a tmux pane of its own server: keys in, the screen out."""

    def __init__(self, folder, home):
        self.socket = str(folder / "tmux.sock")
        command = f"env HOME={home} PYTHONPATH={REPO} {sys.executable} -m vslsp shell"
        self.tmux("new-session", "-d", "-x", "250", "-y", "80", command)
        self.tmux("set-option", "-g", "remain-on-exit", "on")
        self.tmux("set-option", "-g", "history-limit", "10000")

    def tmux(self, *args: str) -> str:
        return subprocess.run(["tmux", "-S", self.socket, *args], capture_output=True, text=True, check=True).stdout

    def screen(self) -> str:
        return self.tmux("capture-pane", "-p", "-J", "-S", "-")

    def wait_for(self, text: str, count: int = 1) -> str:
        """The screen once ``text`` shows ``count`` times."""
        wait_until(lambda: self.screen().count(text) >= count, lambda: f"{text!r} to show:\n{self.screen()}")
        return self.screen()

    def wait_for_exit(self) -> str:
        """The screen once the shell has ended (the pane stays, dead, to be read)."""
        dead = lambda: self.tmux("display-message", "-p", "-t", "0", "#{pane_dead}").strip() == "1"
        wait_until(dead, lambda: f"the shell to end:\n{self.screen()}")
        return self.screen()

    def type(self, *keys: str) -> None:
        self.tmux("send-keys", "-t", "0", *keys)

    def close(self) -> None:
        subprocess.run(["tmux", "-S", self.socket, "kill-server"], capture_output=True)


@pytest.mark.skipif(TMUX is None, reason="tmux is not installed (apt-get install tmux)")
def test_a_whole_domain_from_a_terminal_with_completion(tmp_path, capsys):
    home = tmp_path / "home"
    home.mkdir()
    terminal = Terminal(tmp_path, home)
    try:
        terminal.wait_for("(vslsp) ")
        lines = KITCHEN.format(folder=tmp_path, actions=ACTIONS).splitlines()
        for number, line in enumerate(lines, start=1):
            if line.startswith("init "):
                # TAB completes the hyphenated predicate and, after it, the one cup
                terminal.type("init (on-c", "Tab")
                terminal.wait_for("init (on-counter ")
                terminal.type("plate) (on-counter bowl) (on-counter m", "Tab")
                terminal.wait_for("(on-counter mug ")
                terminal.type("BSpace", ") (hand-empty)", "Enter")
            elif line == "quit":
                terminal.type("drop act", "C-c")  # Ctrl-C drops the line, not the session
                terminal.wait_for("^C (quit or Ctrl-D to leave)")
                terminal.wait_for("(vslsp) ", number + 1)
                terminal.type(line, "Enter")
            else:
                terminal.type(line, "Enter")
            if line != "quit":
                terminal.wait_for("(vslsp) ", number + 1)
        screen = terminal.wait_for_exit()
    finally:
        terminal.close()
    assert "(vslsp) init (on-counter plate) (on-counter bowl) (on-counter mug) (hand-empty)\n" in screen
    check_kitchen(capsys, screen, tmp_path, said_after="\n")
    # the history is all the shell leaves in the home folder
    assert [p.name for p in home.iterdir()] == [".vslsp_history"]
    assert (home / ".vslsp_history").stat().st_mode & 0o777 == 0o600  # private, as readline keeps it
    history = (home / ".vslsp_history").read_text().splitlines()
    assert history[0] == "domain kitchen" and history[-1] == "quit" and len(history) == len(lines)


def test_why_names_the_conflict_and_dropping_one_constraint_makes_it_solvable(tmp_path):
    out = run(
        f"load {PDDL / 'domain.pddl'} {PDDL / 'pull-in-order.pddl'}\nwhy\n"
        "constraint (sometime-before (not (far orange)) (not (far yellow)))\nplan\nwhy\n"
        "drop constraint 2\nplan\nvalidate (pull green) (pull orange) (pull yellow)\n"
    )
    assert "(vslsp) the problem has a plan: nothing conflicts\n" in out
    assert "type why to see which goal conjuncts and constraints conflict\n" in out
    # orange after yellow after green after orange: a cycle; any block's goal conjunct needs it broken
    assert (
        "(vslsp) why: a minimal conflict: these cannot all hold together; removing any one makes the rest solvable\n"
        "  goal: (not (far yellow))\n"
        "  constraint 1: (sometime-before (not (far green)) (not (far orange)))\n"
        "  constraint 2: (sometime-before (not (far yellow)) (not (far green)))\n"
        "  constraint 3: (sometime-before (not (far orange)) (not (far yellow)))\n"
        "to take one out: drop constraint N (e.g. drop constraint 1), or change the goal\n"
    ) in out
    assert "(vslsp) 1. pull yellow\n2. pull orange\n3. pull green\n" in out  # without the middle order
    # the wrong order breaks two constraints: both are listed
    assert "(vslsp) invalid: constraint (sometime-before (not (far green)) (not (far orange))) is broken" in out
    assert "  also: constraint (sometime-before (not (far orange)) (not (far yellow))) is broken" in out


def test_a_piped_session_with_refused_commands_exits_1_unless_keep_going(tmp_path):
    session = "type block\npredicate (on ?a - block)\nbogus\nobjects a b - nope\naction\nquit\n"
    done = vslsp_process("shell", input=session, timeout=120)
    assert done.returncode == 1 and "Traceback" not in done.stderr
    assert "3 commands were refused (errors above); --keep-going exits 0 regardless" in done.stderr
    assert "(vslsp) type block\n" in done.stdout and "error: unknown command 'bogus'" in done.stdout
    assert vslsp_process("shell", "--keep-going", input=session, timeout=120).returncode == 0
    clean = vslsp_process("shell", input="type block\npredicate (on ?a - block)\nquit\n", timeout=120)
    assert clean.returncode == 0 and clean.stderr == ""


def test_at_is_a_predicate_name_and_pddl_words_name_nothing():
    # one vocabulary (the language engine's is_reserved_name): `at` is a keyword only in (at end ...)
    out = run(
        "type dish place\npredicate (at ?d - dish ?p - place)\nobjects d1 - dish\nobjects sink - place\n"
        "init (at d1 sink)\ngoal (not (at d1 sink))\nconstraint (at end (not (at d1 sink)))\n"
        "predicate (and ?d - dish)\nobjects or - dish\ntype not\nshow problem\n"
    )
    assert "(vslsp) predicate (at ?d - dish ?p - place)\n" in out and "true initially: (at d1 sink)" in out
    assert "constraint (at end (not (at d1 sink))); 1 constraint" in out
    assert "error: 'and' is a word of PDDL (and ...), so it cannot name a predicate; choose another name" in out
    assert "error: 'or' is a word of PDDL (or ...), so it cannot name an object" in out
    assert "error: 'not' is a word of PDDL (not ...), so it cannot name a type" in out


@pytest.mark.parametrize("word", ["and", "or", "not", "imply", "forall", "exists", "when", "either", "define", "at"])
def test_the_checker_and_the_shell_agree_on_what_may_name_a_predicate(tmp_path, word):
    # one vocabulary (vslsp.symbolic.language.vocabulary): both accept `at`, both refuse the others alike
    from vslsp.symbolic.language import check_files, reserved_name_message

    domain = tmp_path / "d.pddl"
    domain.write_text(
        f"(define (domain d) (:requirements :strips :typing) (:types dish place)\n"
        f" (:predicates ({word} ?d - dish ?p - place))\n"
        f" (:action put :parameters (?d - dish ?p - place) :precondition (and) :effect ({word} ?d ?p)))\n"
    )
    checked = [d.message for d in check_files(domain).errors]
    out = run(f"type dish place\npredicate ({word} ?d - dish ?p - place)\n")
    if word == "at":
        assert checked == [] and "error" not in out
    else:
        message = reserved_name_message(word, "predicate")
        assert message in checked and f"error: {message}" in out
