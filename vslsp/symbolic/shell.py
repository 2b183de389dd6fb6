"""An interactive shell to author a PDDL 3.0 domain and problem step by step, plan and validate.

Paper: "Implementation" (a user extends or edits what VSL-SP learned: the domain's actions,
the task's goal and its ordering constraints). Every fragment typed (an action, a goal, a
constraint) is read by unified-planning's PDDL reader in the context of the current domain
and problem, so it is checked exactly like a file; mistakes are reported and the model stays
as it was. Standard ``cmd`` shell: tab completion of commands and names, readline history.

    vslsp pddl shell [DOMAIN [PROBLEM]]
"""

from __future__ import annotations

import cmd
import re
import shlex
from dataclasses import replace
from pathlib import Path

from vslsp.errors import InputError, VslspError
from vslsp.symbolic.formula import Formula, atoms_of
from vslsp.symbolic.model import Domain, Problem
from vslsp.symbolic.pddl import parse_pddl, read_pddl, save
from vslsp.symbolic.planner import DEFAULT_PLANNER, solve
from vslsp.symbolic.validate import parse_plan, validate

HISTORY = Path.home() / ".vslsp_history"


def _domain_text(domain: Domain, extra_action: str = "", extra_predicate: str = "") -> str:
    """Scratch PDDL of ``domain`` (plus one more action or predicate) for the reader to check a
    fragment in context."""
    text = re.sub(
        r"\(:requirements[^)]*\)", "(:requirements :strips :typing :adl :constraints)", domain.to_pddl(), count=1
    )
    if extra_predicate:
        text = text.replace("(:predicates", f"(:predicates {extra_predicate}", 1)
    return text.rstrip()[:-1] + f"\n{extra_action})\n"


def _predicate_text(predicate) -> str:
    return f"({predicate.name} {_typed(predicate.parameters)})"


def _typed(parameters) -> str:
    return " ".join(f"{v} - {t}" for v, t in parameters)


def _problem_text(problem: Problem, goal: str | None = None, constraints: list[str] | None = None) -> str:
    objects = " ".join(f"{o} - {t}" for o, t in problem.objects)
    init = " ".join(a.to_pddl() for a in sorted(problem.init, key=lambda a: (a.predicate, a.args)))
    goal = goal if goal is not None else problem.goal.to_pddl()
    parts = constraints if constraints is not None else [c.to_pddl() for c in problem.constraints]
    section = f"(:constraints (and {' '.join(parts)}))" if parts else ""
    return (
        f"(define (problem {problem.name}) (:domain {problem.domain.name}) (:objects {objects})\n"
        f"(:init {init}) (:goal {goal}) {section})"
    )


def _balanced(typed: str) -> None:
    """Raise InputError, placed in what the user typed, when its parentheses do not balance."""
    opened: list[int] = []
    for index, char in enumerate(typed):
        if char == "(":
            opened.append(index)
        elif char == ")":
            if not opened:
                raise InputError(
                    f"unexpected ')' at column {index + 1} of what you typed:\n  {typed}\n  {' ' * index}^"
                )
            opened.pop()
    if opened:
        raise InputError(
            f"the '(' at column {opened[-1] + 1} of what you typed is never closed: a ')' is missing"
            f"\n  {typed}\n  {' ' * opened[-1]}^"
        )


class Shell(cmd.Cmd):
    """``vslsp pddl shell``: type ``help`` for the commands."""

    intro = "vslsp PDDL shell: build a domain and a problem, plan, validate. Type help or ? to list commands."
    prompt = "(vslsp) "

    def __init__(self, domain: Domain | None = None, problem: Problem | None = None, **kwargs):
        super().__init__(**kwargs)
        self.domain = domain or Domain("vsl-sp")
        self.problem = problem or Problem("task", self.domain)
        self.last_plan: list[tuple[str, tuple[str, ...]]] = []

    # --- plumbing ---
    def say(self, text: str) -> None:
        self.stdout.write(text + "\n")

    def onecmd(self, line: str) -> bool:
        try:
            _balanced(line.partition(" ")[2])
            return super().onecmd(line)
        except VslspError as error:
            # Places in the scratch text the reader saw mean nothing to the person typing.
            self.say("error: " + re.sub(r"^<(domain|problem|input)>:\d+:\d+: ", "", str(error)))
        except ValueError as error:  # shlex on unbalanced quotes
            self.say(f"error: {error}")
        return False

    def emptyline(self) -> bool:
        return False

    def default(self, line: str) -> None:
        self.say(f"error: unknown command {line.split()[0]!r}; type help")

    def completedefault(self, text, line, begidx, endidx):
        names = (
            [p.name for p in self.domain.predicates]
            + [a.name for a in self.domain.actions]
            + [o for o, _ in self.problem.objects]
            + [t for t, _ in self.domain.types]
            + [
                "not",
                "and",
                "or",
                "forall",
                "exists",
                "imply",
                "sometime-before",
                "sometime-after",
                "always",
                "sometime",
                "at-most-once",
            ]
        )
        return sorted(n for n in set(names) if n.startswith(text.lstrip("(")))

    def _set(self, domain: Domain | None = None, problem: Problem | None = None) -> None:
        """Adopt an edited domain (the problem follows it) or problem."""
        if domain is not None:
            self.domain = domain
            self.problem = replace(self.problem, domain=domain)
        if problem is not None:
            self.problem = replace(problem, domain=self.domain)

    def _reparse(self, problem_text: str) -> Problem:
        _, problem = parse_pddl(_domain_text(self.domain), problem_text)
        assert problem is not None
        return problem

    # --- domain ---
    def do_domain(self, arg: str) -> None:
        """domain NAME: name the domain (a fresh one when nothing is in it yet)."""
        self._set(domain=replace(self.domain, name=arg.strip() or self.domain.name))
        self.say(f"domain {self.domain.name}")

    def do_type(self, arg: str) -> None:
        """type NAME [- PARENT]: declare a type, e.g. type block."""
        words = arg.replace("-", " - ").split()
        if not words:
            self.say("usage: type NAME [- PARENT]")
            return
        self._set(domain=self.domain.with_type(words[0], words[2] if len(words) > 2 else None))
        self.say(f"type {words[0]}" + (f" - {words[2]}" if len(words) > 2 else ""))

    def do_predicate(self, arg: str) -> None:
        """predicate (NAME ?x - TYPE ...): declare a predicate, e.g. predicate (far ?b - block)."""
        text = arg.strip() if arg.strip().startswith("(") else f"({arg.strip()})"
        domain, _ = parse_pddl(_domain_text(self.domain, extra_predicate=text))
        self._set(domain=self.domain.with_predicate(domain.predicates[-1]))
        self.say(f"predicate {_predicate_text(domain.predicates[-1])}")

    def do_action(self, arg: str) -> None:
        """action NAME :parameters (...) :precondition F :effect F -- as in a domain file, without (:action )."""
        name = arg.split()[0] if arg.split() else ""
        domain, _ = parse_pddl(_domain_text(self.domain.without_action(name), f"(:action {arg})"))
        replaced = any(a.name == name for a in self.domain.actions)
        self._set(domain=self.domain.with_action(domain.action(name)))
        self.say(
            f"action {name} {'replaced' if replaced else 'added'}; actions: "
            f"{', '.join(a.name for a in self.domain.actions)}"
        )

    def do_drop(self, arg: str) -> None:
        """drop action NAME | drop constraints | drop init ATOM: remove something."""
        kind, _, rest = arg.partition(" ")
        if kind == "action":
            self._set(domain=self.domain.without_action(rest.strip()))
            self.say(f"dropped action {rest.strip()}")
        elif kind == "constraints":
            count = len(self.problem.constraints)
            self._set(problem=self.problem.without_constraints())
            self.say(f"dropped {count} constraint{'' if count == 1 else 's'}")
        elif kind == "init":
            atoms = list(atoms_of(self._parse_formula(f"(and {rest})")))
            self._set(problem=self.problem.without_init(*atoms))
            self.say("no longer true initially: " + " ".join(a.to_pddl() for a in atoms))
        else:
            self.say("usage: drop action NAME | drop constraints | drop init ATOM ...")

    # --- problem ---
    def do_problem(self, arg: str) -> None:
        """problem NAME: name the problem."""
        self._set(problem=replace(self.problem, name=arg.strip() or self.problem.name))
        self.say(f"problem {self.problem.name}")

    def do_objects(self, arg: str) -> None:
        """objects NAME ... - TYPE: add objects, e.g. objects red green blue - block."""
        names, _, type_ = arg.partition(" - ")
        if not names.split() or not type_.strip():
            self.say("usage: objects NAME ... - TYPE")
            return
        self._set(problem=self.problem.with_objects(type_.strip(), *names.split()))
        self.say(f"objects {' '.join(names.split())} - {type_.strip()}; {len(self.problem.objects)} in all")

    def do_init(self, arg: str) -> None:
        """init ATOM ...: make atoms true initially, e.g. init (far red) (far green)."""
        formula = self._parse_formula(f"(and {arg})")
        atoms = list(atoms_of(formula))
        self._set(problem=self.problem.with_init(*atoms))
        self.say("true initially: " + " ".join(a.to_pddl() for a in atoms))

    def do_goal(self, arg: str) -> None:
        """goal FORMULA: the goal, e.g. goal (forall (?b - block) (not (far ?b)))."""
        self._set(problem=self._reparse(_problem_text(self.problem, goal=arg.strip())))
        self.say(f"goal {self.problem.goal.to_pddl()}")

    def do_constraint(self, arg: str) -> None:
        """constraint C: add a PDDL 3.0 constraint,
        e.g. constraint (sometime-before (not (far green)) (not (far red)))."""
        parts = [c.to_pddl() for c in self.problem.constraints] + [arg.strip()]
        self._set(problem=self._reparse(_problem_text(self.problem, constraints=parts)))
        count = len(self.problem.constraints)
        self.say(
            f"constraint {self.problem.constraints[-1].to_pddl() if count else arg.strip()}; "
            f"{count} constraint{'' if count == 1 else 's'}"
        )

    def _parse_formula(self, text: str) -> Formula:
        return self._reparse(_problem_text(self.problem, goal=text)).goal

    # --- look, plan, validate, files ---
    def do_show(self, arg: str) -> None:
        """show [domain|problem]: print the PDDL (both by default)."""
        if arg.strip() in ("", "domain"):
            self.say(self.domain.to_pddl())
        if arg.strip() in ("", "problem"):
            self.say(self.problem.to_pddl())

    def do_plan(self, arg: str) -> None:
        """plan [PLANNER]: plan for the problem (fast-downward by default)."""
        result = solve(self.domain, self.problem, planner=(arg.split() or [DEFAULT_PLANNER])[0])
        self.last_plan = list(result.steps)
        for number, line in enumerate(result.lines(), start=1):
            self.say(f"{number}. {line}")
        steps = len(result.steps)
        self.say(f"{steps} step{'' if steps == 1 else 's'}, {result.planner}, {result.time_s:.2f} s")

    def do_validate(self, arg: str) -> None:
        """validate [(action arg ...) ...]: check the given steps, or the last plan."""
        steps = (
            parse_plan(arg.replace(")", ")\n"), self.domain, self.problem, "<input>") if arg.strip() else self.last_plan
        )
        verdict = validate(self.domain, self.problem, steps)
        self.say(f"{'valid' if verdict.valid else 'invalid'}: {verdict.reason}")

    def do_load(self, arg: str) -> None:
        """load DOMAIN [PROBLEM]: read PDDL files."""
        paths = shlex.split(arg)
        if not paths:
            self.say("usage: load DOMAIN [PROBLEM]")
            return
        domain, problem = read_pddl(*paths[:2])
        self.domain, self.problem = domain, problem or Problem("task", domain)
        self.say(f"loaded domain {domain.name}" + (f" and problem {problem.name}" if problem else ""))

    def do_save(self, arg: str) -> None:
        """save DOMAIN [PROBLEM]: write PDDL files."""
        paths = shlex.split(arg)
        if not paths:
            self.say("usage: save DOMAIN [PROBLEM]")
            return
        save(self.domain.to_pddl(), paths[0])
        if len(paths) > 1:
            save(self.problem.to_pddl(), paths[1])
        self.say(f"saved {' and '.join(paths[:2])}")

    def do_quit(self, arg: str) -> bool:
        """quit: leave the shell (also Ctrl-D)."""
        return True

    do_EOF = do_quit

    def preloop(self) -> None:
        if not self.use_rawinput:  # scripted input: no history
            return
        try:
            import readline

            if HISTORY.exists():
                readline.read_history_file(HISTORY)
        except (ImportError, OSError):
            pass

    def postloop(self) -> None:
        if not self.use_rawinput:
            return
        try:
            import readline

            readline.write_history_file(HISTORY)
        except (ImportError, OSError):
            pass
