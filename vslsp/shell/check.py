"""What is typed in ``vslsp shell``, checked against the domain and problem in the shell's words.

Paper: "Implementation" (a user extends what VSL-SP learned). Each fragment (a predicate, an
action, atoms, a goal, a constraint) is read here as an s-expression and its names are checked
before the PDDL reader sees it: an unknown type, predicate, object or variable, a wrong number
of arguments or an argument of the wrong type is told with the shell command that fixes it
(``type dish``, ``predicate (...)``, ``objects ... - TYPE``) and a "did you mean" when a declared
name is close. The reader still checks everything afterwards, so nothing is accepted that a
file would not be; this only says the common mistakes in terms of the shell.
"""

from __future__ import annotations

import difflib
import re
from collections.abc import Iterable
from dataclasses import dataclass, field

from vslsp.errors import InputError
from vslsp.symbolic.io.pddl_errors import PDDL3_OPERATORS, check_text
from vslsp.symbolic.language.vocabulary import is_reserved_name, reserved_name_message
from vslsp.symbolic.model.domain import Domain, Problem

Tree = str | list  # a word, or a parenthesised list of trees

CONNECTIVES = ("and", "or", "not", "imply", "forall", "exists")
EFFECT_WORDS = ("and", "not", "forall", "when")
#: The PDDL 3.0 trajectory constraints, as the head of a constraint (``at end`` is two words).
CONSTRAINT_OPERATORS = tuple(o for o in PDDL3_OPERATORS if o != "at end") + ("at",)
_QUANTIFIERS = ("forall", "exists")
_NAME = re.compile(r"[A-Za-z][\w-]*")
#: How many formulas each trajectory constraint takes (after its numbers, for the timed ones).
_FORMULAS = {"always": 1, "sometime": 1, "at-most-once": 1, "sometime-before": 2, "sometime-after": 2, "at": 1}
_NOT_A_PREDICATE = {*CONNECTIVES, *EFFECT_WORDS, *CONSTRAINT_OPERATORS, "=", "preference", "end"}


def tokens(text: str) -> list[str]:
    """``(on a b)`` -> ``["(", "on", "a", "b", ")"]`` (comments dropped)."""
    return re.findall(r"\(|\)|[^\s()]+", re.sub(r";[^\n]*", " ", text))


def parse(text: str) -> list[Tree]:
    """The trees of ``text`` (parentheses are balanced: the shell checks that first)."""
    stack: list[list] = [[]]
    for token in tokens(text):
        if token == "(":
            stack.append([])
        elif token == ")" and len(stack) > 1:
            done = stack.pop()
            stack[-1].append(done)
        elif token != ")":
            stack[-1].append(token)
    while len(stack) > 1:
        done = stack.pop()
        stack[-1].append(done)
    return stack[0]


def did_you_mean(name: str, known: Iterable[str]) -> str:
    """`` (did you mean 'x'?)`` for the declared name closest to ``name``, or ``""``."""
    close = difflib.get_close_matches(name, sorted(set(known)), n=1, cutoff=0.7)
    return f" (did you mean {close[0]!r}?)" if close else ""


def _listed(names: list[str], most: int = 20) -> str:
    """``a, b, c`` (the first ``most`` names, then how many more: a message stays one short line)."""
    shown = ", ".join(names[:most])
    return shown if len(names) <= most else f"{shown} and {len(names) - most} more"


def _text(tree: Tree) -> str:
    return tree if isinstance(tree, str) else "(" + " ".join(_text(t) for t in tree) + ")"


def typed_list(items: list[Tree]) -> list[tuple[str, str]]:
    """``?a ?b - block ?c`` -> ``[("?a", "block"), ("?b", "block"), ("?c", "object")]``."""
    pairs: list[tuple[str, str]] = []
    pending: list[str] = []
    words = [i for i in items if isinstance(i, str)]
    index = 0
    while index < len(words):
        if words[index] == "-" and index + 1 < len(words):
            pairs.extend((name, words[index + 1]) for name in pending)
            pending = []
            index += 2
            continue
        pending.append(words[index])
        index += 1
    return pairs + [(name, "object") for name in pending]


@dataclass
class Checker:
    """Checks fragments against ``domain`` (and ``problem``'s objects, where a problem is meant)."""

    domain: Domain
    problem: Problem | None = None
    _objects: dict[str, str] | None = field(default=None, init=False, repr=False)

    # --- names ---
    @staticmethod
    def name(name: str, what: str) -> str:
        """``name`` when it is a PDDL name (a letter, then letters, digits, '-' or '_')."""
        article = "an" if what[0] in "aeiou" else "a"
        if not _NAME.fullmatch(name):
            raise InputError(
                f"{name!r} cannot name {article} {what}: a PDDL name is a letter, then letters, digits, - or _"
            )
        if what != "domain" and what != "problem" and is_reserved_name(name):  # the one vocabulary (`at` is a name)
            raise InputError(reserved_name_message(name, what))
        return name

    def type_(self, name: str) -> None:
        declared = [t for t, _ in self.domain.types] + ["object"]
        if name not in declared:
            raise InputError(
                f"unknown type {name!r}{did_you_mean(name, declared)}: declare it with `type {name}`"
                + (f" (types so far: {_listed(declared[:-1])})" if len(declared) > 1 else "")
            )

    def objects(self) -> dict[str, str]:
        """Object -> type (the domain's constants, and the problem's objects when checking a problem);
        made once per checker (a fragment may name many objects)."""
        if self._objects is None:
            everything = self.problem.all_objects() if self.problem is not None else self.domain.constants
            self._objects = dict(everything)
        return self._objects

    def parameters(self, items: list[Tree]) -> list[tuple[str, str]]:
        """A typed variable list, its types checked."""
        if items[-1:] == ["-"]:
            raise InputError("a '-' ends the list: name the type after it, e.g. ?d - dish")
        pairs = typed_list(items)
        names = [v for v, _ in pairs]
        for variable in names:
            if names.count(variable) > 1:
                raise InputError(f"{variable} is named twice in the parameters; give each its own name")
        for variable, type_ in pairs:
            if not variable.startswith("?"):
                raise InputError(f"{variable!r} in a parameter list: parameters are variables such as ?{variable}")
            self.type_(type_)
        return pairs

    # --- formulas ---
    def formula(self, tree: Tree, variables: dict[str, str], where: str = "formula") -> None:
        """Check a goal, precondition or effect (``where``: "formula", "effect" or "constraint")."""
        if isinstance(tree, str):
            raise InputError(f"{tree!r} on its own: write an atom in parentheses, e.g. ({tree} ...)")
        if not tree:
            return
        head, rest = tree[0], tree[1:]
        if not isinstance(head, str):
            raise InputError(f"{_text(tree)}: a formula starts with a predicate or an operator, not '('")
        if head in _QUANTIFIERS or (head == "forall" and where == "effect"):
            if not rest or isinstance(rest[0], str):
                raise InputError(f"({head} ...) needs its variables first, e.g. ({head} (?d - dish) ...)")
            bound = {**variables, **dict(self.parameters(rest[0]))}
            for part in rest[1:]:
                self.formula(part, bound, where)
            return
        if head == "at" and rest[:1] != ["end"]:  # `at` is a keyword only in (at end ...): (at d1 p1) is an atom
            self.atom(tree, variables, where)
            return
        if head == "at":
            rest = rest[1:]
        if where == "constraint" and head in _FORMULAS and len(rest) != _FORMULAS[head]:
            shown = "at end" if head == "at" else head
            raise InputError(
                f"({shown} ...) takes {_FORMULAS[head]} formula{'' if _FORMULAS[head] == 1 else 's'}, "
                f"{len(rest)} given: {_text(tree)}"
            )
        if head in _NOT_A_PREDICATE:
            # inside a trajectory operator (or a condition of `when`) come plain formulas
            nested = "formula" if head == "when" or (where == "constraint" and head != "and") else where
            for part in rest:
                if head == "=":
                    self._argument(part, variables, None, "=")
                elif not isinstance(part, str):
                    self.formula(part, variables, nested)
            return
        self.atom(tree, variables, where)

    def atom(self, tree: list, variables: dict[str, str], where: str = "formula") -> None:
        head, args = tree[0], tree[1:]
        predicates = {p.name: p for p in self.domain.predicates}
        if head not in predicates:
            operators = CONSTRAINT_OPERATORS if where == "constraint" else CONNECTIVES
            hint = did_you_mean(head, [*predicates, *operators])
            if where == "constraint" and hint and hint.split("'")[1] in operators:
                raise InputError(f"'{head}' is not a PDDL 3.0 constraint{hint}; they are: {', '.join(PDDL3_OPERATORS)}")
            shown = " ".join(a if isinstance(a, str) else "..." for a in args)
            raise InputError(
                f"unknown predicate {head!r}{hint}: declare it with `predicate ({head}{' ' if args else ''}"
                f"{'?x - TYPE' if args else ''})`" + (f" (in {_text(tree)})" if shown else "")
            )
        parameters = predicates[head].parameters
        if len(args) != len(parameters):
            signature = " ".join(f"{v} - {t}" for v, t in parameters)
            raise InputError(
                f"{_text(tree)}: {head} takes {len(parameters)} argument{'' if len(parameters) == 1 else 's'}"
                f" ({head}{' ' if signature else ''}{signature}), {len(args)} given"
            )
        for arg, (_, type_) in zip(args, parameters, strict=True):
            self._argument(arg, variables, type_, head)

    def _argument(self, arg: Tree, variables: dict[str, str], type_: str | None, head: str) -> None:
        if not isinstance(arg, str):
            raise InputError(f"{_text(arg)} inside ({head} ...): arguments are objects or variables, not formulas")
        if arg.startswith("?"):
            if arg not in variables:
                known = ", ".join(variables) or "none here"
                raise InputError(f"unknown variable {arg!r}{did_you_mean(arg, variables)} (variables: {known})")
            actual = variables[arg]
        else:
            objects = self.objects()
            if arg not in objects:
                kind = "object" if self.problem is not None else "constant"
                how = f"`objects {arg} - TYPE`" if self.problem is not None else "a variable (?x) of the action"
                raise InputError(f"unknown {kind} {arg!r}{did_you_mean(arg, objects)}: use {how}")
            actual = objects[arg]
        if type_ is not None and type_ != "object" and actual not in self.domain.subtypes(type_):
            raise InputError(f"{arg!r} is a {actual}, but {head} takes a {type_} there")

    # --- whole fragments ---
    def predicate(self, text: str) -> tuple[str, list[tuple[str, str]]]:
        trees = parse(text)
        if len(trees) != 1 or isinstance(trees[0], str) or not trees[0] or not isinstance(trees[0][0], str):
            raise InputError("write one predicate, e.g. predicate (on-counter ?d - dish)")
        name = self.name(trees[0][0], "predicate")
        return name, self.parameters(trees[0][1:])

    def action(self, text: str) -> str:
        """Check ``NAME :parameters (...) :precondition F :effect F``; the action's name."""
        check_text(text, "<input>")
        trees = parse(text)
        if not trees or not isinstance(trees[0], str) or trees[0].startswith(":"):
            raise InputError("name the action first, e.g. action pick-up :parameters (?d - dish) ...")
        name, sections = self.name(trees[0], "action"), trees[1:]
        known = (":parameters", ":precondition", ":effect")
        parts: dict[str, Tree] = {}
        for index in range(0, len(sections), 2):
            keyword = sections[index]
            if not isinstance(keyword, str) or keyword not in known:
                shown = keyword if isinstance(keyword, str) else _text(keyword)
                raise InputError(
                    f"action {name}: expected {', '.join(known)}, got {shown!r}"
                    f"{did_you_mean(shown, known) if isinstance(keyword, str) else ''}"
                )
            if index + 1 >= len(sections):
                raise InputError(f"action {name}: {keyword} has nothing after it")
            parts[keyword] = sections[index + 1]
        given = parts.get(":parameters", [])
        if isinstance(given, str):
            raise InputError(f"action {name}: :parameters takes a list, e.g. :parameters (?d - dish)")
        variables = dict(self.parameters(given))
        if ":precondition" in parts:
            self.formula(parts[":precondition"], variables)
        if ":effect" in parts:
            self.formula(parts[":effect"], variables, "effect")
        return name

    def steps(self, text: str) -> None:
        """Check plan steps ``(action object ...)``: the action, how many objects and their types."""
        actions = {a.name: a for a in self.domain.actions}
        for tree in parse(text):
            if isinstance(tree, str) or not tree or not isinstance(tree[0], str):
                raise InputError(f"{_text(tree)}: a step is (ACTION OBJECT ...), e.g. (pick-up plate)")
            head, args = tree[0], tree[1:]
            if head not in actions:
                raise InputError(
                    f"unknown action {head!r}{did_you_mean(head, actions)}; actions: {', '.join(actions) or 'none yet'}"
                )
            parameters = actions[head].parameters
            if len(args) != len(parameters):
                signature = " ".join(f"{v} - {t}" for v, t in parameters)
                raise InputError(
                    f"{_text(tree)}: {head} takes {len(parameters)} object{'' if len(parameters) == 1 else 's'}"
                    f" ({head} {signature}), {len(args)} given"
                )
            for arg, (_, type_) in zip(args, parameters, strict=True):
                self._argument(arg, {}, type_, head)

    def formulas(self, text: str, where: str = "formula") -> list[Tree]:
        """Check each formula of ``text`` (ground: init, goal, constraints, drop init)."""
        check_text(text, "<input>")  # operators that are not PDDL, constructs vslsp does not read
        trees = parse(text)
        for tree in trees:
            self.formula(tree, {}, where)
        return trees


#: unified-planning's reader's words (as pddl_errors rewrites them) -> what to do in the shell.
_READER_TO_SHELL = (
    (re.compile(r"undefined type '([^']+)'"), "unknown type '{0}': declare it with `type {0}`"),
    (
        re.compile(r"unknown object or constant '([^']+)'"),
        "unknown name '{0}': an object (`objects {0} - TYPE`) or a 0-ary predicate (`predicate ({0})`)?",
    ),
    (
        re.compile(r"unknown predicate or operator '([^']+)'"),
        "unknown predicate '{0}': declare it with `predicate ({0} ...)`",
    ),
    (re.compile(r"undefined parameter '([^']+)'"), "unknown variable '{0}': declare it in :parameters"),
)


def in_shell_terms(message: str) -> str:
    """A reader's or the Python API's message, told with the shell's commands."""
    message = re.sub(r"^<(domain|problem|input)>(:\d+:\d+)?: ", "", message)
    for pattern, template in _READER_TO_SHELL:
        match = pattern.search(message)
        if match:
            return template.format(*match.groups())
    return (
        message.replace("add it with with_type", "declare it with `type NAME`")
        .replace("add it with with_predicate", "declare it with `predicate (NAME ...)`")
        .replace("add it with with_objects", "add it with `objects NAME - TYPE`")
    )
