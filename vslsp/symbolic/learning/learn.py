"""Learning action models, goal rules and the demonstrated order from grounded observations.

Paper: "Generalization of Learned Skills as Symbolic Action Models" (Table 3: preconditions
and effects of push and pull from pre-/post-action observations) and the iCub experiments:
"Keeping All Objects Near" (rules r_i^j = <object -> effect> IF <context>; contexts that
disagree across demonstrations eliminate each other and the colour is lifted, so the rule
holds for any block) and "Pull All Objects in a Given Order" (one demonstration; the order
becomes PDDL 3.0 ``(sometime-before p q)`` constraints, the paper's "somewhere-after").

Everything here is a pure function of recorded data (:class:`Step`), never of the simulator.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, replace

from vslsp.errors import InputError
from vslsp.symbolic.model.domain import Action, Domain, Predicate, Problem, When
from vslsp.symbolic.model.formula import (
    Constraint,
    Formula,
    SometimeBefore,
    atoms_of,
    conjunction,
    forall,
    formula_from_list,
    formula_to_list,
    holds,
    literal,
)

BLOCK = "block"
Literals = Mapping[str, Mapping[str, bool]]  # object -> {predicate: value}


@dataclass(frozen=True)
class Step:
    """One demonstrated or executed operation, grounded: the acted object's colour, the action
    (``"push"``, ``"pull"`` or None when no action was recognised) and every seen object's
    predicates before and after, e.g. ``{"green": {"far": True}, "red": {"far": False}}``."""

    action: str | None
    obj: str
    before: Literals
    after: Literals

    def changed(self) -> dict[str, bool]:
        """The acted object's predicates whose value changed: ``{predicate: value after}``."""
        if self.obj not in self.before or self.obj not in self.after:
            raise InputError(
                f"step on {self.obj!r}: the object is missing from the before/after observations "
                f"(seen: {', '.join(sorted(self.before))})"
            )
        before, after = self.before[self.obj], self.after[self.obj]
        return {p: bool(v) for p, v in after.items() if p in before and bool(before[p]) != bool(v)}

    def to_dict(self) -> dict:
        return {
            "action": self.action,
            "obj": self.obj,
            "before": {o: dict(v) for o, v in self.before.items()},
            "after": {o: dict(v) for o, v in self.after.items()},
        }

    @classmethod
    def from_dict(cls, data: dict) -> Step:
        return cls(data["action"], data["obj"], data["before"], data["after"])


def learn_domain(steps: Iterable[Step], name: str = "vsl-sp") -> Domain:
    """Lifted action schemas over ``?b - block`` learned from executions (Table 3), over every
    grounded predicate (``far`` and the user's).

    Effects: the acted object's literals that changed, intersected over the executions of the
    action. Preconditions: its literals before, intersected likewise, of the predicates that some
    action changes (fluents): a predicate no skill ever changes is static here, and successful
    executions alone give no evidence that a skill needs it, so it stays out of the models (it
    still is declared, and goals and rules may speak of it). An execution in which the acted
    object did not change failed and is no evidence; steps without an action are skipped.
    """
    steps = list(steps)
    predicates = sorted({p for s in steps for side in (s.before, s.after) for values in side.values() for p in values})
    preconditions: dict[str, set] = {}
    effects: dict[str, set] = {}
    for step in steps:
        if step.action is None:
            continue
        changed = step.changed()
        if not changed:
            continue
        before = {(p, bool(v)) for p, v in step.before[step.obj].items()}
        preconditions[step.action] = preconditions.get(step.action, before) & before
        effects[step.action] = effects.get(step.action, set(changed.items())) & set(changed.items())
    if not preconditions:
        raise InputError(
            "no action to learn from: no step names an action whose object changed "
            "(check the grounding of the demonstrations)"
        )
    fluents = {p for effect in effects.values() for p, _ in effect}
    actions = []
    for action_name in preconditions:  # in the order first seen
        if not effects[action_name]:
            raise InputError(
                f"{action_name}: its executions changed different predicates, so no effect is common "
                "to all of them; check the grounding"
            )
        needed = sorted((p, v) for p, v in preconditions[action_name] if p in fluents)
        actions.append(
            Action(
                action_name,
                (("?b", BLOCK),),
                conjunction(literal(p, ("?b",), v) for p, v in needed),
                tuple(literal(p, ("?b",), v) for p, v in sorted(effects[action_name])),
            )
        )
    return Domain(name, ((BLOCK, None),), tuple(Predicate(p, (("?b", BLOCK),)) for p in predicates), tuple(actions))


@dataclass(frozen=True)
class Rule:
    """``<obj -> effect> IF <context>``: r_i^j of the paper (``sources`` lists (i, j), 1-based).

    ``obj`` is a colour, or ``"?"`` once lifted to any block; ``effect`` is ``((predicate,
    value), ...)``; ``context`` is ``((object, predicate, value), ...)`` before the action.
    """

    obj: str
    effect: tuple[tuple[str, bool], ...]
    context: tuple[tuple[str, str, bool], ...]
    sources: tuple[tuple[int, int], ...]

    def __str__(self) -> str:
        def words(pairs):
            return ", ".join(f"{'' if v else 'not '}{p}" for p, v in pairs)

        context = "; ".join(f"B_{o} is {'' if v else 'not '}{p}" for o, p, v in self.context)
        names = ", ".join(f"r_{i}^{j}" for i, j in self.sources)
        return f"{names}: <B_{self.obj} -> {words(self.effect)}> IF <{context}>"

    def to_dict(self) -> dict:
        return {
            "obj": self.obj,
            "effect": [list(e) for e in self.effect],
            "context": [list(c) for c in self.context],
            "sources": [list(s) for s in self.sources],
        }

    @classmethod
    def from_dict(cls, data: dict) -> Rule:
        return cls(
            data["obj"],
            tuple((p, bool(v)) for p, v in data["effect"]),
            tuple((o, p, bool(v)) for o, p, v in data["context"]),
            tuple((i, j) for i, j in data["sources"]),
        )


@dataclass(frozen=True)
class LearnedTask:
    """What the demonstrations ask for: a goal, the demonstrated order as trajectory
    constraints, and the generalised rules they came from."""

    goal: Formula
    constraints: tuple[Constraint, ...] = ()
    rules: tuple[Rule, ...] = ()

    def without_order(self) -> LearnedTask:
        """The same goal with no ordering: the planner is free to choose the sequence."""
        return replace(self, constraints=())

    @property
    def ordered(self) -> bool:
        return bool(self.constraints)

    def to_dict(self) -> dict:
        return {
            "goal": formula_to_list(self.goal),
            "constraints": [formula_to_list(c) for c in self.constraints],
            "rules": [r.to_dict() for r in self.rules],
        }

    @classmethod
    def from_dict(cls, data: dict) -> LearnedTask:
        return cls(
            formula_from_list(data["goal"]),  # type: ignore[arg-type]
            tuple(formula_from_list(c) for c in data.get("constraints", ())),  # type: ignore[misc]
            tuple(Rule.from_dict(r) for r in data.get("rules", ())),
        )


def changed_by(domain: Domain) -> dict[str, set[str]]:
    """Action name -> the predicates its learned effects change."""
    return {
        action.name: {
            atom.predicate
            for effect in action.effects
            for literal in (effect.effects if isinstance(effect, When) else (effect,))
            for atom in atoms_of(literal)
        }
        for action in domain.actions
    }


def extract_rules(demonstrations: Sequence[Sequence[Step]], models: Domain | None = None) -> list[Rule]:
    """One rule per demonstrated step that changed its object: r_i^j with its full context.

    With the robot's action ``models``, a rule's effect keeps what the demonstrated action's
    model changes: a predicate the tutor's pull happened to change too (an object pulled across
    the image's middle) but the skill does not is no part of what was taught.
    """
    kept = changed_by(models) if models is not None else None
    rules = []
    for i, demonstration in enumerate(demonstrations, start=1):
        j = 0
        for step in demonstration:
            if step.action is None:
                continue
            changed = {p: v for p, v in step.changed().items() if kept is None or p in kept.get(step.action, {p})}
            if not changed:
                continue
            j += 1
            context = tuple(
                sorted((o, p, bool(v)) for o, values in step.before.items() if o != step.obj for p, v in values.items())
            )
            rules.append(Rule(step.obj, tuple(sorted(changed.items())), context, ((i, j),)))
    if not rules:
        raise InputError("the demonstrations contain no step that changed an object; nothing to learn")
    return rules


def generalise(rules: Sequence[Rule]) -> list[Rule]:
    """Merge rules whose effects share literals: the merged effect is what they all share (with
    ``far`` alone: rules with the same effect), contexts that disagree are dropped, and the
    colour is lifted to ``"?"`` when several colours share the effect (unless another rule
    demands the opposite literal of one object, which a rule for every block would contradict)."""
    groups: dict[tuple, list[Rule]] = {}
    for rule in rules:  # a rule joins the first group whose effect shares a literal with its own
        effect = next((e for e in groups if set(e) & set(rule.effect)), None)
        if effect is None:
            groups[rule.effect] = [rule]
        elif set(rule.effect) >= set(effect):
            groups[effect].append(rule)
        else:
            members = [*groups.pop(effect), rule]
            groups.setdefault(tuple(sorted(set(effect) & set(rule.effect))), []).extend(members)
    opposite = {(p, not v) for effect in groups for p, v in effect}
    merged = []
    for effect, group in groups.items():
        context = set(group[0].context).intersection(*(r.context for r in group[1:]))
        colours = sorted({r.obj for r in group})
        sources = tuple(s for r in group for s in r.sources)
        if len(colours) > 1 and not opposite & set(effect):
            merged.append(Rule("?", effect, tuple(sorted(c for c in context if c[0] not in colours)), sources))
        else:
            merged.extend(
                Rule(c, effect, tuple(sorted(context)), tuple(s for r in group if r.obj == c for s in r.sources))
                for c in colours
            )
    return merged


def learn_task(
    demonstrations: Sequence[Sequence[Step]], ordered: bool | None = None, models: Domain | None = None
) -> LearnedTask:
    """The goal (and order) that ``demonstrations`` teach, over every grounded predicate.

    ``ordered=None`` follows the paper: one demonstration teaches a sequence (the colours stay,
    the order becomes ``sometime-before`` constraints); several demonstrations teach a rule
    (disagreeing contexts dropped, colours lifted: "no block is far"). ``ordered`` forces either.
    ``models``: the robot's learned action models; a demonstrated step's effect keeps what its
    action's model changes (see :func:`extract_rules`). Rules whose effects share literals are
    merged with the literals they all share, as their contexts are.
    """
    demonstrations = [list(d) for d in demonstrations]
    if not demonstrations:
        raise InputError("no demonstration given")
    rules = extract_rules(demonstrations, models)
    if ordered is None:
        ordered = len(demonstrations) == 1
    if ordered:
        final = _final_literals(rules)
        goal = conjunction(literal(p, (o,), v) for o, effect in final.items() for p, v in effect)
        constraints = tuple(
            SometimeBefore(_effect_formula(b, final[b]), _effect_formula(a, final[a]))
            for a, b in _demonstrated_order(demonstrations, rules)
        )
        return LearnedTask(goal, constraints, tuple(rules))
    general = generalise(rules)
    parts: list[Formula] = []
    for rule in general:
        if rule.obj == "?":
            parts.append(forall(("?b", BLOCK), conjunction(literal(p, ("?b",), v) for p, v in rule.effect)))
    _final_literals([r for r in general if r.obj != "?"])  # raises when demonstrations disagree on an object
    parts.extend(literal(p, (r.obj,), v) for r in general if r.obj != "?" for p, v in r.effect)
    return LearnedTask(conjunction(parts), (), tuple(general))


def _final_literals(rules: Sequence[Rule]) -> dict[str, tuple[tuple[str, bool], ...]]:
    """Each acted object's final literals; raises when demonstrations disagree."""
    final: dict[str, dict[str, tuple[bool, int]]] = {}
    for rule in rules:
        demo = rule.sources[0][0]
        values = final.setdefault(rule.obj, {})
        for predicate, value in rule.effect:
            if predicate in values and values[predicate][1] != demo and values[predicate][0] != value:
                raise InputError(
                    f"the demonstrations disagree about {rule.obj}: {predicate} is "
                    f"{values[predicate][0]} in demonstration {values[predicate][1]} and {value} in "
                    f"demonstration {demo}"
                )
            values[predicate] = (value, demo)  # a later step of the same demonstration overrides
    return {o: tuple(sorted((p, v) for p, (v, _) in values.items())) for o, values in final.items()}


def _effect_formula(obj: str, effect: tuple[tuple[str, bool], ...]) -> Formula:
    return conjunction(literal(p, (obj,), v) for p, v in effect)


def _demonstrated_order(demonstrations: Sequence[Sequence[Step]], rules: Sequence[Rule]) -> list[tuple[str, str]]:
    """Consecutive pairs (a, b): a was done before b in every demonstration showing both.

    Each object counts at its last operation (the one that left its final literals).
    """
    sequences = []
    for i in range(1, len(demonstrations) + 1):
        last = {r.obj: j for r in rules for d, j in r.sources if d == i}
        sequences.append(sorted(last, key=last.__getitem__))
    objects = list(dict.fromkeys(o for s in sequences for o in s))
    before = {
        (a, b)
        for a in objects
        for b in objects
        if a != b
        and any(a in s and b in s and s.index(a) < s.index(b) for s in sequences)
        and not any(a in s and b in s and s.index(a) > s.index(b) for s in sequences)
    }
    # Transitive reduction: keep a < b only when no c sits between them.
    return [
        (a, b)
        for a in objects
        for b in objects
        if (a, b) in before and not any((a, c) in before and (c, b) in before for c in objects)
    ]


def make_problem(domain: Domain, task: LearnedTask, state: Literals, name: str = "vsl-sp-task") -> Problem:
    """The planning problem for ``task`` in an observed ``state`` (object -> {predicate: value}).

    Objects are the keys of ``state`` (blocks); the initial state is its true literals. A
    ``sometime-before`` whose later literal already holds in ``state`` is left out: that part of
    the order is behind us (e.g. when replanning halfway). A task that names an object not in
    the scene raises InputError.
    """
    block = BLOCK if any(t == BLOCK for t, _ in domain.types) else (domain.types[0][0] if domain.types else "object")
    known = {p.name for p in domain.predicates}
    init = set()
    for obj, values in state.items():
        for predicate, value in values.items():
            if predicate not in known:
                raise InputError(
                    f"the state says {predicate} of {obj}, but the domain {domain.name} has only: "
                    f"{', '.join(sorted(known))}"
                )
            if value:
                init.add(literal(predicate, (obj,), True))
    named = {
        a
        for part in (task.goal, *task.constraints)
        for atom in atoms_of(part)
        for a in atom.args
        if not a.startswith("?")
    }
    missing = sorted(named - set(state))
    if missing:
        raise InputError(
            f"the task names {', '.join(missing)}, not in the scene (objects: {', '.join(state)}); "
            "use a scene with these objects or a lifted task"
        )
    problem = Problem(name, domain, tuple((o, block) for o in state), frozenset(init), task.goal)
    # An ordering whose later literal already holds in this scene is done with: the order can only
    # speak of what is still to be done (this is what lets the robot replan halfway through).
    universe, now = problem.universe(), frozenset(init)
    pending = tuple(
        c for c in task.constraints if not (isinstance(c, SometimeBefore) and holds(c.formula, now, universe))
    )
    return replace(problem, constraints=pending)
