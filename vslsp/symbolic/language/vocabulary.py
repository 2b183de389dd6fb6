"""The fixed words of PDDL 3.0 the engine knows: requirements, sections, operators (Gerevini & Long
2005, "Plan constraints and preferences in PDDL3"; Fox & Long 2003 for PDDL 2.1)."""

from __future__ import annotations

REQUIREMENTS = (
    ":strips",
    ":typing",
    ":negative-preconditions",
    ":disjunctive-preconditions",
    ":equality",
    ":existential-preconditions",
    ":universal-preconditions",
    ":quantified-preconditions",
    ":conditional-effects",
    ":fluents",
    ":numeric-fluents",
    ":object-fluents",
    ":adl",
    ":durative-actions",
    ":duration-inequalities",
    ":continuous-effects",
    ":derived-predicates",
    ":timed-initial-literals",
    ":preferences",
    ":constraints",
    ":action-costs",
    ":domain-axioms",
    ":safety-constraints",
    ":expression-evaluation",
    ":open-world",
    ":true-negation",
    ":ucpop",
)

#: What declaring a requirement also declares.
IMPLIED = {
    ":adl": (
        ":strips",
        ":typing",
        ":negative-preconditions",
        ":disjunctive-preconditions",
        ":equality",
        ":existential-preconditions",
        ":universal-preconditions",
        ":quantified-preconditions",
        ":conditional-effects",
    ),
    ":quantified-preconditions": (":existential-preconditions", ":universal-preconditions"),
    ":fluents": (":numeric-fluents", ":object-fluents"),
    ":ucpop": (":adl", ":domain-axioms", ":safety-constraints"),
}

DOMAIN_SECTIONS = (
    ":requirements",
    ":types",
    ":constants",
    ":predicates",
    ":functions",
    ":constraints",
    ":action",
    ":durative-action",
    ":derived",
)
PROBLEM_SECTIONS = (":domain", ":requirements", ":objects", ":init", ":goal", ":constraints", ":metric")
ACTION_KEYWORDS = (":parameters", ":precondition", ":effect")

#: Operators of goal descriptions (preconditions, goals, the formulas inside constraints).
GOAL_OPERATORS = ("and", "or", "not", "imply", "exists", "forall", "=", "preference")
COMPARISONS = ("<", ">", "<=", ">=")
EFFECT_OPERATORS = ("and", "not", "forall", "when", "increase", "decrease", "assign", "scale-up", "scale-down")
NUMERIC_EFFECTS = ("increase", "decrease", "assign", "scale-up", "scale-down")
ARITHMETIC = ("+", "-", "*", "/")
#: PDDL 3.0 trajectory constraints with the number of formulas (and numbers) each takes.
PDDL3_OPERATORS = {
    "at": ("", 1),  # (at end φ): "end" is read apart
    "always": ("", 1),
    "sometime": ("", 1),
    "within": ("n", 1),
    "at-most-once": ("", 1),
    "sometime-after": ("", 2),
    "sometime-before": ("", 2),
    "always-within": ("n", 2),
    "hold-during": ("nn", 1),
    "hold-after": ("n", 1),
}
PDDL3_NAMES = ("at end", *(name for name in PDDL3_OPERATORS if name != "at"))
#: Trajectory constraints a temporal planner needs; vslsp's planners refuse them.
TIMED_OPERATORS = ("within", "always-within", "hold-during", "hold-after")
#: The paper's spelling of the demonstrated order, which is not PDDL (docs/planning.md).
NOT_PDDL = {
    "somewhere-after": "PDDL 3.0 has no 'somewhere-after'; for \"p only after q\" (the demonstrated order) "
    "write (sometime-before p q)",
    "somewhere-before": "PDDL 3.0 has no 'somewhere-before'; for \"p only after q\" write (sometime-before p q)",
}
BUILT_IN_TYPES = ("object",)

#: Words PDDL reads as syntax wherever a name may stand: the operators of formulas and effects, the
#: PDDL 3.0 constraints, ``either`` and ``define``, and the built-in types. ``at`` is no reserved word:
#: it is the usual predicate ``(at ?x ?place)``; ``(at end φ)`` is read by its second word.
RESERVED_NAMES = frozenset(
    name
    for name in (
        *GOAL_OPERATORS,
        *EFFECT_OPERATORS,
        *PDDL3_OPERATORS,
        "either",
        "define",
        *BUILT_IN_TYPES,
    )
    if name not in ("at", "=")
)


def is_reserved_name(name: str) -> bool:
    """Whether ``name`` is a word of PDDL's syntax that no predicate, type, object or action may take
    (PDDL is case-insensitive: ``AND`` is ``and``; a variable's ``?`` is not part of the word)."""
    return name.removeprefix("?").lower() in RESERVED_NAMES


def reserved_name_message(name: str, what: str) -> str:
    """Why ``name`` cannot name a ``what`` (object, predicate ...), and what to do."""
    article = "an" if what[:1] in "aeiou" else "a"
    return (
        f"'{name}' is a word of PDDL ({name.lower()} ...), so it cannot name {article} {what}; "
        f"choose another name (e.g. '{name}-1')"
    )
