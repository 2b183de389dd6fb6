"""The symbolic layer of VSL-SP: learned action models, goal rules, PDDL 3.0, planning, validation.

Paper: "Generalization of Learned Skills as Symbolic Action Models", "Implementation" and the
iCub experiments. Learning (:func:`learn_domain`, :func:`learn_task`) works on grounded
:class:`Step` records; :func:`make_problem` states a task in an observed scene; :func:`solve`
plans with Fast Downward (trajectory constraints compiled into the lifted domain,
:mod:`vslsp.symbolic.engines.lifted`); :func:`validate` checks a plan against preconditions, goal
and every PDDL 3.0 constraint. Split by role, as unified-planning splits itself:

- :mod:`~vslsp.symbolic.budget`: the limits of PDDL input and each phase's time budget (what every
  subpackage stands on);
- :mod:`~vslsp.symbolic.language`: the PDDL language engine (``vslsp pddl check``, the language server);
- :mod:`~vslsp.symbolic.model`: formulas, domains and problems, unified-planning's model;
- :mod:`~vslsp.symbolic.io`: reading PDDL files into the model;
- :mod:`~vslsp.symbolic.engines`: planning (constraint compilation, Fast Downward, outcomes);
- :mod:`~vslsp.symbolic.validation`: plan validation and why a problem has no plan;
- :mod:`~vslsp.symbolic.learning`: action models and goals from demonstrations.

Layers (tests/test_layers.py): budget < language < model < io, engines < validation; learning
stands on model alone. unified-planning is imported only when
called.
"""

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from vslsp.symbolic.engines.outcomes import Compilation, InternalError, NoPlan, PlanStatus, Unsolvable
    from vslsp.symbolic.engines.planner import PlanResult, check_planner, solve, solve_timed
    from vslsp.symbolic.io.pddl import parse_pddl, read_domain, read_pddl, read_problem, save
    from vslsp.symbolic.io.pddl_errors import PddlWarning
    from vslsp.symbolic.learning.learn import (
        LearnedTask,
        Rule,
        Step,
        extract_rules,
        generalise,
        learn_domain,
        learn_task,
        make_problem,
    )
    from vslsp.symbolic.model.domain import Action, Domain, Predicate, Problem, When
    from vslsp.symbolic.model.formula import (
        Always,
        And,
        AtEnd,
        AtMostOnce,
        Atom,
        Equals,
        Exists,
        Forall,
        Imply,
        Not,
        Or,
        Sometime,
        SometimeAfter,
        SometimeBefore,
        forall,
        holds,
        sometime_before,
    )
    from vslsp.symbolic.validation.validate import Validation, parse_plan, read_plan, validate

# Each name is imported on first use, so that importing one module of the layer (the language engine
# of ``vslsp pddl check``) does not import them all (the planner, unified-planning's reader).
_HOME = {
    "Always": "vslsp.symbolic.model.formula",
    "And": "vslsp.symbolic.model.formula",
    "AtEnd": "vslsp.symbolic.model.formula",
    "AtMostOnce": "vslsp.symbolic.model.formula",
    "Atom": "vslsp.symbolic.model.formula",
    "Equals": "vslsp.symbolic.model.formula",
    "Exists": "vslsp.symbolic.model.formula",
    "Forall": "vslsp.symbolic.model.formula",
    "Imply": "vslsp.symbolic.model.formula",
    "Not": "vslsp.symbolic.model.formula",
    "Or": "vslsp.symbolic.model.formula",
    "Sometime": "vslsp.symbolic.model.formula",
    "SometimeAfter": "vslsp.symbolic.model.formula",
    "SometimeBefore": "vslsp.symbolic.model.formula",
    "forall": "vslsp.symbolic.model.formula",
    "holds": "vslsp.symbolic.model.formula",
    "sometime_before": "vslsp.symbolic.model.formula",
    "LearnedTask": "vslsp.symbolic.learning.learn",
    "Rule": "vslsp.symbolic.learning.learn",
    "Step": "vslsp.symbolic.learning.learn",
    "extract_rules": "vslsp.symbolic.learning.learn",
    "generalise": "vslsp.symbolic.learning.learn",
    "learn_domain": "vslsp.symbolic.learning.learn",
    "learn_task": "vslsp.symbolic.learning.learn",
    "make_problem": "vslsp.symbolic.learning.learn",
    "Action": "vslsp.symbolic.model.domain",
    "Domain": "vslsp.symbolic.model.domain",
    "Predicate": "vslsp.symbolic.model.domain",
    "Problem": "vslsp.symbolic.model.domain",
    "When": "vslsp.symbolic.model.domain",
    "Compilation": "vslsp.symbolic.engines.outcomes",
    "InternalError": "vslsp.symbolic.engines.outcomes",
    "NoPlan": "vslsp.symbolic.engines.outcomes",
    "PlanStatus": "vslsp.symbolic.engines.outcomes",
    "Unsolvable": "vslsp.symbolic.engines.outcomes",
    "parse_pddl": "vslsp.symbolic.io.pddl",
    "read_domain": "vslsp.symbolic.io.pddl",
    "read_pddl": "vslsp.symbolic.io.pddl",
    "read_problem": "vslsp.symbolic.io.pddl",
    "save": "vslsp.symbolic.io.pddl",
    "PddlWarning": "vslsp.symbolic.io.pddl_errors",
    "PlanResult": "vslsp.symbolic.engines.planner",
    "check_planner": "vslsp.symbolic.engines.planner",
    "solve": "vslsp.symbolic.engines.planner",
    "solve_timed": "vslsp.symbolic.engines.planner",
    "Validation": "vslsp.symbolic.validation.validate",
    "parse_plan": "vslsp.symbolic.validation.validate",
    "read_plan": "vslsp.symbolic.validation.validate",
    "validate": "vslsp.symbolic.validation.validate",
}


def __getattr__(name: str) -> Any:
    if name in _HOME:
        value = getattr(importlib.import_module(_HOME[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'vslsp.symbolic' has no attribute {name!r}")


__all__ = [
    "Action",
    "Always",
    "And",
    "AtEnd",
    "AtMostOnce",
    "Atom",
    "Compilation",
    "Domain",
    "Equals",
    "Exists",
    "Forall",
    "Imply",
    "InternalError",
    "LearnedTask",
    "NoPlan",
    "Not",
    "Or",
    "PddlWarning",
    "PlanResult",
    "PlanStatus",
    "Predicate",
    "Problem",
    "Rule",
    "Sometime",
    "SometimeAfter",
    "SometimeBefore",
    "Step",
    "Unsolvable",
    "Validation",
    "When",
    "check_planner",
    "extract_rules",
    "forall",
    "generalise",
    "holds",
    "learn_domain",
    "learn_task",
    "make_problem",
    "parse_pddl",
    "parse_plan",
    "read_domain",
    "read_pddl",
    "read_plan",
    "read_problem",
    "save",
    "solve",
    "solve_timed",
    "sometime_before",
    "validate",
]
