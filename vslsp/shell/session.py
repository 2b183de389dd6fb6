"""An interactive shell to author a PDDL 3.0 domain and problem step by step, plan and validate.

Paper: "Implementation" (a user extends or edits what VSL-SP learned: the domain's actions,
the task's goal and its ordering constraints). Every fragment typed (a predicate, an action, a
goal, a constraint) is first checked by :mod:`vslsp.shell.check`, which tells mistakes
with the shell command that fixes them, then read by the PDDL reader in the context of the
current domain and problem, so it is checked exactly like a file; after a mistake the model
stays as it was. Every change can be taken back with ``undo``. The commands are listed in
:mod:`vslsp.shell.commands`; completion is :mod:`vslsp.shell.complete`.

    vslsp shell [DOMAIN [PROBLEM]]      (the same as vslsp pddl shell)
"""

from __future__ import annotations

import cmd
import re
import shlex
import sys
import threading
from dataclasses import replace

from vslsp import interrupts
from vslsp.errors import InputError, VslspError
from vslsp.shell.check import Checker, did_you_mean, in_shell_terms, parse
from vslsp.shell.commands import NAMES, command, example, in_full, overview, usage
from vslsp.shell.complete import DELIMITERS, complete
from vslsp.shell.save import Loaded, load, saved_texts
from vslsp.shell.terminal import line_editing, read_history, write_history
from vslsp.symbolic.budget import MAX_READER_NESTING, MAX_READER_TYPE_DEPTH
from vslsp.symbolic.engines.outcomes import Unsolvable
from vslsp.symbolic.engines.planner import DEFAULT_PLANNER, PLANNERS, solve
from vslsp.symbolic.io.pddl import parse_pddl, save
from vslsp.symbolic.language.files import MAX_PDDL_BYTES
from vslsp.symbolic.model.domain import Domain, Predicate, Problem, When
from vslsp.symbolic.model.formula import Atom, atoms_of
from vslsp.symbolic.validation.conflict import explain
from vslsp.symbolic.validation.validate import parse_plan, validate

#: One fragment read at a time: the reader's first use (seconds: imports, its environment) runs in
#: the background at a terminal while the first commands are typed.
_READER = threading.Lock()


def _read(domain_text: str, problem_text: str | None = None) -> tuple[Domain, Problem | None]:
    with _READER:
        return parse_pddl(domain_text, problem_text)


def _domain_text(domain: Domain, extra_action: str = "", extra_predicate: str = "") -> str:
    """Scratch PDDL of ``domain`` (plus one more action, or one more predicate declared last) for
    the reader to check a fragment in context."""
    if extra_predicate:
        domain = replace(domain, predicates=(*domain.predicates, Predicate("vslsp-shell-placeholder")))
    text = re.sub(
        r"\(:requirements[^)]*\)", "(:requirements :strips :typing :adl :constraints)", domain.to_pddl(), count=1
    )
    text = text.replace("(vslsp-shell-placeholder)", extra_predicate, 1)
    return text.rstrip()[:-1] + f"\n{extra_action})\n"


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
    """Raise InputError, placed in what the user typed, when its parentheses do not balance or nest deeper
    than the reader takes (:data:`~vslsp.symbolic.budget.MAX_READER_NESTING`: every command's checks and
    the reader recurse per level)."""
    opened: list[int] = []
    for index, char in enumerate(typed):
        if char == "(":
            opened.append(index)
            if len(opened) > MAX_READER_NESTING:
                raise InputError(
                    f"parentheses nest {len(opened)} deep at column {index + 1} of what you typed: nested too "
                    f"deeply (limit {MAX_READER_NESTING}); flatten the formula: (and a (and b c)) is (and a b c)"
                )
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


def _plural(count: int, noun: str) -> str:
    return f"{count} {noun}{'' if count == 1 else 's'}"


def numbered_problem(problem: Problem) -> str:
    """The problem's PDDL with each constraint on its own line, numbered as ``drop constraint N`` takes them."""
    text = replace(problem, constraints=()).to_pddl().rstrip()[:-1]
    if not problem.constraints:
        return text + ")"
    lines = [f"    {c.to_pddl()}  ; {n}" for n, c in enumerate(problem.constraints, start=1)]
    return text + "\n  (:constraints (and\n" + "\n".join(lines) + "\n  )))"


class Shell(cmd.Cmd):
    """``vslsp shell``: type ``help`` for the commands."""

    intro = "vslsp PDDL shell: build a domain and a problem, plan, validate. Type help for the commands."
    prompt = "(vslsp) "
    identchars = cmd.Cmd.identchars + "-"
    max_bytes = MAX_PDDL_BYTES  # the largest PDDL file ``load`` reads (the session's --max-size)

    def __init__(
        self, domain: Domain | None = None, problem: Problem | None = None, loaded: Loaded | None = None, **kwargs
    ):
        super().__init__(**kwargs)
        self.domain = domain or Domain("vsl-sp")
        self.problem = problem or Problem("task", self.domain)
        self.loaded = loaded  # the files read, which save edits in place (vslsp.shell.save)
        self.last_plan: list[tuple[str, tuple[str, ...]]] = []
        # (command, domain, problem and files loaded before it), for undo
        self.changes: list[tuple[str, Domain, Problem, Loaded | None]] = []
        self.errors = 0  # commands refused (an error or their usage shown): a piped session's exit code
        self.unsaved: list[VslspError] = []  # the saves that failed (a script's exit code tells of them)

    # --- plumbing ---
    def say(self, text: str) -> None:
        self.stdout.write(text + "\n")

    def onecmd(self, line: str) -> bool:
        before, loaded = (self.domain, self.problem), self.loaded
        try:
            _balanced(line.partition(" ")[2])
            return super().onecmd(line)
        except VslspError as error:
            self.errors += 1
            self.say("error: " + in_shell_terms(str(error)))
        except ValueError as error:  # shlex on unbalanced quotes
            self.errors += 1
            self.say(f"error: {str(error).lower()} in what you typed")
        except RecursionError:  # a check that recursed past Python's limit: the shell goes on
            self.say("error: what you typed nests too deeply for vslsp; flatten it: (and a (and b c)) is (and a b c)")
        finally:
            changed = (self.domain, self.problem) != before or self.loaded is not loaded
            if changed and line.split()[:1] != ["undo"]:
                self.changes.append((" ".join(line.split()), *before, loaded))
        return False

    def _usage(self, name: str) -> None:
        """A command typed without what it needs: its usage, counted as an error."""
        self.errors += 1
        self.say(usage(name))

    def emptyline(self) -> bool:
        return False

    def default(self, line: str) -> None:
        word = line.split()[0]
        self.errors += 1
        self.say(f"error: unknown command {word!r}{did_you_mean(word, NAMES)}; type help for the commands")

    def _checker(self, problem: bool = True) -> Checker:
        return Checker(self.domain, self.problem if problem else None)

    def _set(self, domain: Domain | None = None, problem: Problem | None = None) -> None:
        """Adopt an edited domain (the problem follows it) or problem."""
        if domain is not None:
            self.domain = domain
            self.problem = replace(self.problem, domain=domain)
        if problem is not None:
            self.problem = replace(problem, domain=self.domain)

    def _reparse(self, problem_text: str) -> Problem:
        _, problem = _read(_domain_text(self.domain), problem_text)
        assert problem is not None
        return problem

    # --- completion (readline splits words at DELIMITERS only, set in cmdloop) ---
    def completenames(self, text: str, *ignored) -> list[str]:
        return [name + " " for name in NAMES if name.startswith(text)]

    def completedefault(self, text: str, line: str, begidx: int, endidx: int) -> list[str]:
        return complete(line, begidx, text, self.domain, self.problem, list(PLANNERS))

    complete_help = completedefault

    # --- the domain ---
    def do_domain(self, arg: str) -> None:
        if arg.strip():
            self._checker().name(arg.strip(), "domain")
        self._set(domain=replace(self.domain, name=arg.strip() or self.domain.name))
        self.say(f"domain {self.domain.name}")

    def do_type(self, arg: str) -> None:
        words = arg.split()
        names, parents = (words[: words.index("-")], words[words.index("-") + 1 :]) if "-" in words else (words, [])
        if not names or ("-" in words and len(parents) != 1):
            self._usage("type")
            return
        parent = parents[0] if parents else None
        above = _ancestors(self.domain, parent) if parent else set()
        if parent:
            self._checker().type_(parent)
            if len(above) + 1 > MAX_READER_TYPE_DEPTH:
                raise InputError(
                    f"type {names[0]} under {parent} would be {len(above) + 1} types deep: nested too deeply "
                    f"(limit {MAX_READER_TYPE_DEPTH}); put it under a type nearer to object"
                )
        for name in names:
            self._checker().name(name, "type")
            if name in above:
                raise InputError(f"type {name} cannot be under {parent}: the types would form a cycle")
        self._set(domain=self.domain.with_types(parent, *names))
        self.say(f"type {' '.join(names)}" + (f" - {parent}" if parent else ""))

    def do_predicate(self, arg: str) -> None:
        text = arg.strip() if arg.strip().startswith("(") else f"({arg.strip()})"
        name, parameters = self._checker().predicate(text)
        replaced = any(p.name == name for p in self.domain.predicates)
        predicate = Predicate(name, tuple(parameters))
        for action in self.domain.actions if replaced else ():
            conditions = [action.precondition, *(e.condition for e in action.effects if isinstance(e, When))]
            for atom in (*(a for c in conditions for a in atoms_of(c)), *action.effect_atoms()):
                if atom.predicate == name and len(atom.args) != len(parameters):
                    raise InputError(
                        f"action {action.name} uses {atom.to_pddl()}: change the action first "
                        f"(action {action.name} ...), or drop it (drop action {action.name})"
                    )
        if replaced:  # the actions that use it are read again with the new declaration
            others = replace(self.domain, predicates=tuple(p for p in self.domain.predicates if p.name != name))
            predicate = _read(_domain_text(others, extra_predicate=text))[0].predicate(name)
        self._set(domain=self.domain.with_predicate(predicate))
        signature = " ".join(f"{v} - {t}" for v, t in predicate.parameters)
        self.say(f"predicate ({name}{' ' if signature else ''}{signature})" + (" replaced" if replaced else ""))

    def do_action(self, arg: str) -> None:
        if not arg.strip():
            self._usage("action")
            return
        name = self._checker(problem=False).action(arg)
        domain, _ = _read(_domain_text(self.domain.without_action(name), f"(:action {arg})"))
        replaced = any(a.name == name for a in self.domain.actions)
        self._set(domain=self.domain.with_action(domain.action(name)))
        self.say(
            f"action {name} {'replaced' if replaced else 'added'}; actions: "
            f"{', '.join(a.name for a in self.domain.actions)}"
        )

    def do_drop(self, arg: str) -> None:
        kind, _, rest = arg.strip().partition(" ")
        rest = rest.strip()
        if kind == "action" and rest:
            actions = [a.name for a in self.domain.actions]
            if rest not in actions:
                raise InputError(
                    f"no action {rest!r}{did_you_mean(rest, actions)}; actions: {', '.join(actions) or 'none yet'}"
                )
            self._set(domain=self.domain.without_action(rest))
            self.say(f"dropped action {rest}; actions: {', '.join(a.name for a in self.domain.actions) or 'none'}")
        elif kind == "constraints" and not rest:
            count = len(self.problem.constraints)
            self._set(problem=self.problem.without_constraints())
            self.say(f"dropped {_plural(count, 'constraint')}")
        elif kind == "constraint" and rest:
            self._drop_constraint(rest)
        elif kind == "init" and rest:
            atoms = self._atoms(rest)
            missing = [a.to_pddl() for a in atoms if a not in self.problem.init]
            if missing:
                raise InputError(f"{' '.join(missing)} {'is' if len(missing) == 1 else 'are'} not true initially")
            self._set(problem=self.problem.without_init(*atoms))
            self.say("no longer true initially: " + " ".join(a.to_pddl() for a in atoms))
        else:
            self._usage("drop")

    def _drop_constraint(self, number: str) -> None:
        count = len(self.problem.constraints)
        if not number.isdigit() or not 1 <= int(number) <= count:
            raise InputError(
                f"no constraint {number}: there {'is' if count == 1 else 'are'} {_plural(count, 'constraint')}"
                + ("; `show constraints` numbers them" if count else "")
            )
        index = int(number) - 1
        dropped = self.problem.constraints[index]
        kept = self.problem.constraints[:index] + self.problem.constraints[index + 1 :]
        self._set(problem=replace(self.problem, constraints=kept))
        self.say(f"dropped constraint {number}: {dropped.to_pddl()}; {_plural(len(kept), 'constraint')} left")

    def do_undo(self, arg: str) -> None:
        if not self.changes:
            self.say("nothing to undo")
            return
        line, self.domain, self.problem, self.loaded = self.changes.pop()
        self.say(f"undone: {line}")

    # --- the problem ---
    def do_problem(self, arg: str) -> None:
        if arg.strip():
            self._checker().name(arg.strip(), "problem")
        self._set(problem=replace(self.problem, name=arg.strip() or self.problem.name))
        self.say(f"problem {self.problem.name}")

    def do_objects(self, arg: str) -> None:
        words = arg.split()
        if "-" not in words or not words[: words.index("-")] or len(words[words.index("-") :]) != 2:
            self._usage("objects")
            return
        names, type_ = words[: words.index("-")], words[-1]
        for name in names:
            self._checker().name(name, "object")
        self._checker().type_(type_)
        self._set(problem=self.problem.with_objects(type_, *names))
        self.say(f"objects {' '.join(names)} - {type_}; {len(self.problem.objects)} in all")

    def do_init(self, arg: str) -> None:
        if not arg.strip():
            self._usage("init")
            return
        atoms = self._atoms(arg)
        self._set(problem=self.problem.with_init(*atoms))
        self.say("true initially: " + " ".join(a.to_pddl() for a in atoms))

    def do_goal(self, arg: str) -> None:
        if not arg.strip():
            self._usage("goal")
            return
        trees = self._checker().formulas(arg)
        text = arg.strip() if len(trees) == 1 else f"(and {arg.strip()})"
        self._set(problem=self._reparse(_problem_text(self.problem, goal=text)))
        self.say(f"goal {self.problem.goal.to_pddl()}")

    def do_constraint(self, arg: str) -> None:
        if len(parse(arg)) != 1:
            self.errors += 1
            self.say(usage("constraint") + " (one at a time)")
            return
        self._checker().formulas(arg, "constraint")
        parts = [c.to_pddl() for c in self.problem.constraints] + [arg.strip()]
        self._set(problem=self._reparse(_problem_text(self.problem, constraints=parts)))
        count = len(self.problem.constraints)
        self.say(
            f"constraint {self.problem.constraints[-1].to_pddl() if count else arg.strip()}; "
            f"{_plural(count, 'constraint')}"
        )

    def _atoms(self, text: str) -> list[Atom]:
        """The ground atoms listed in ``text``, each checked (no reader needed for atoms)."""
        predicates = {p.name for p in self.domain.predicates}
        trees = self._checker().formulas(text)
        for tree in trees:
            if not isinstance(tree, list) or not tree or tree[0] not in predicates:
                raise InputError("list atoms such as (on-counter plate) here; an atom not listed is false initially")
        return [Atom(tree[0], tuple(tree[1:])) for tree in trees]

    # --- look, plan, validate, files ---
    def do_show(self, arg: str) -> None:
        what = arg.strip()
        if what not in ("", "domain", "problem", "constraints"):
            self._usage("show")
        if what in ("", "domain"):
            self.say(self.domain.to_pddl())
        if what in ("", "problem"):
            self.say(numbered_problem(self.problem))
        if what == "constraints":
            for number, constraint in enumerate(self.problem.constraints, start=1):
                self.say(f"{number}. {constraint.to_pddl()}")
            if not self.problem.constraints:
                self.say("no constraints")

    def do_plan(self, arg: str) -> None:
        try:
            result = solve(self.domain, self.problem, planner=(arg.split() or [DEFAULT_PLANNER])[0])
        except Unsolvable as error:
            raise Unsolvable(f"{error.reason}; type why to see which goal conjuncts and constraints conflict") from None
        self.last_plan = list(result.steps)
        for number, line in enumerate(result.lines(), start=1):
            self.say(f"{number}. {line}")
        self.say(f"{_plural(len(result.steps), 'step')}, {result.planner}, {result.time_s:.2f} s")

    def do_validate(self, arg: str) -> None:
        if arg.strip():
            self._checker().steps(arg)
            steps = parse_plan(arg.replace(")", ")\n"), self.domain, self.problem, "<input>")
        elif self.last_plan:
            steps = self.last_plan
        else:
            raise InputError(f"no plan yet: run plan first, or give the steps, e.g. {example('validate')}")
        verdict = validate(self.domain, self.problem, steps)
        self.say(f"{'valid' if verdict.valid else 'invalid'}: {verdict.reason}")
        for violation in verdict.violations[1:]:
            self.say(f"  also: {violation.message}")

    def do_why(self, arg: str) -> None:
        if arg.strip():
            self._usage("why")
            return
        conflict = explain(self.domain, self.problem)
        if conflict is None:
            self.say("the problem has a plan: nothing conflicts")
            return
        self.say(f"why: {conflict.summary()}")
        for part in conflict.parts:
            label = "goal" if part.kind == "goal" else f"constraint {part.index + 1}"
            self.say(f"  {label}: {part.to_pddl()}")
        for reason in conflict.reasons(self.domain, self.problem):
            self.say(f"  because: {reason}")
        numbers = [part.index + 1 for part in conflict.parts if part.kind == "constraint"]
        if numbers:
            self.say(f"to take one out: drop constraint N (e.g. drop constraint {numbers[0]}), or change the goal")

    def do_load(self, arg: str) -> None:
        paths = shlex.split(arg)
        if not paths or len(paths) > 2:
            self._usage("load")
            return
        self.loaded = load(paths[0], paths[1] if len(paths) > 1 else None, self.max_bytes)
        domain, problem = self.loaded.domain, self.loaded.problem
        self.domain, self.problem = domain, problem or Problem("task", domain)
        self.last_plan = []
        self.say(f"loaded domain {domain.name}" + (f" and problem {problem.name}" if problem else ""))

    def do_save(self, arg: str) -> None:
        paths = shlex.split(arg)
        if not paths or len(paths) > 2:
            self._usage("save")
            return
        texts = saved_texts(self.loaded, self.domain, self.problem)
        try:
            for path, text in zip(paths, texts, strict=False):
                save(text, path)
        except VslspError as error:
            self.unsaved.append(error)
            raise
        kept = " (the loaded text kept where unchanged)" if self.loaded else ""
        self.say(f"saved {' and '.join(paths)}{kept}")

    def do_help(self, arg: str) -> None:
        name = arg.strip()
        if not name:
            self.say("commands (help COMMAND for one):\n" + overview())
            return
        entry = command(name)
        if entry is None:
            raise InputError(f"no command {name!r}{did_you_mean(name, NAMES)}; type help for the commands")
        self.say(in_full(entry))

    def do_quit(self, arg: str) -> bool:
        return True

    def do_EOF(self, arg: str) -> bool:
        if self._interactive():
            self.say("")  # the prompt's line ends before the terminal's next prompt
        return True

    # --- the terminal: history, word delimiters, Ctrl-C ---
    def _interactive(self) -> bool:
        return bool(self.use_rawinput and self.stdin is sys.stdin and sys.stdin.isatty())

    def cmdloop(self, intro: str | None = None) -> None:
        """Read commands until ``quit`` or end of input; at a terminal Ctrl-C clears the line (or
        stops a running plan) instead of leaving, and the history is kept in ``~/.vslsp_history``."""
        readline = line_editing() if self._interactive() else None
        delimiters = readline.get_completer_delims() if readline else ""
        if self._interactive():
            threading.Thread(target=_read, args=(_domain_text(Domain("warm-up")),), daemon=True).start()
        if readline:
            readline.set_completer_delims(DELIMITERS)
            read_history(readline)
        try:
            while True:
                try:
                    super().cmdloop(intro)
                    return
                except KeyboardInterrupt:
                    interrupts.resume()  # handled: the next Ctrl-C is a first one again
                    self.say("^C (quit or Ctrl-D to leave)")
                    intro = ""
        finally:
            if readline:
                readline.set_completer_delims(delimiters)
                write_history(readline)


def _ancestors(domain: Domain, type_: str) -> set[str]:
    parents = dict(domain.types)
    found = {type_}
    while parents.get(type_):
        type_ = parents[type_]  # type: ignore[assignment]
        if type_ in found:
            break
        found.add(type_)
    return found
