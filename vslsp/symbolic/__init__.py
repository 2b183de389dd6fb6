"""The symbolic layer of VSL-SP: learned action models, goal rules, PDDL 3.0, planning, validation.

Paper: "Generalization of Learned Skills as Symbolic Action Models", "Implementation" and the
iCub experiments. Learning (:func:`learn_domain`, :func:`learn_task`) works on grounded
:class:`Step` records; :func:`make_problem` states a task in an observed scene; :func:`solve`
plans with unified-planning + Fast Downward (trajectory constraints compiled into the lifted
domain, :mod:`vslsp.symbolic.lifted`); :func:`validate` checks a plan against preconditions,
goal and every PDDL 3.0 constraint. Layers: budget (the limits of PDDL input) < formula < model <
lifted, monitors < validate < up_model, flat_problem < pddl (reader), planner (engines) < shell.
unified-planning is imported only when called.
"""

import importlib
import sys
import types
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from vslsp.symbolic.formula import (
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
    from vslsp.symbolic.learning import (
        Rule,
        Step,
        Task,
        extract_rules,
        generalise,
        learn_domain,
        learn_task,
        make_problem,
    )
    from vslsp.symbolic.model import Action, Domain, Predicate, Problem, When
    from vslsp.symbolic.outcomes import Compilation, InternalError, NoPlan, PlanStatus, Unsolvable
    from vslsp.symbolic.pddl import parse_pddl, read_domain, read_pddl, read_problem, save
    from vslsp.symbolic.pddl_errors import PddlWarning
    from vslsp.symbolic.planner import PlanResult, check_planner, solve, solve_timed
    from vslsp.symbolic.validate import Validation, parse_plan, read_plan, validate

# Each name is imported on first use, so that importing one module of the layer (the language engine
# of ``vslsp pddl check``) does not import them all (the planner, unified-planning's reader).
_HOME = {
    "Always": "vslsp.symbolic.formula",
    "And": "vslsp.symbolic.formula",
    "AtEnd": "vslsp.symbolic.formula",
    "AtMostOnce": "vslsp.symbolic.formula",
    "Atom": "vslsp.symbolic.formula",
    "Equals": "vslsp.symbolic.formula",
    "Exists": "vslsp.symbolic.formula",
    "Forall": "vslsp.symbolic.formula",
    "Imply": "vslsp.symbolic.formula",
    "Not": "vslsp.symbolic.formula",
    "Or": "vslsp.symbolic.formula",
    "Sometime": "vslsp.symbolic.formula",
    "SometimeAfter": "vslsp.symbolic.formula",
    "SometimeBefore": "vslsp.symbolic.formula",
    "forall": "vslsp.symbolic.formula",
    "holds": "vslsp.symbolic.formula",
    "sometime_before": "vslsp.symbolic.formula",
    "Rule": "vslsp.symbolic.learning",
    "Step": "vslsp.symbolic.learning",
    "Task": "vslsp.symbolic.learning",
    "extract_rules": "vslsp.symbolic.learning",
    "generalise": "vslsp.symbolic.learning",
    "learn_domain": "vslsp.symbolic.learning",
    "learn_task": "vslsp.symbolic.learning",
    "make_problem": "vslsp.symbolic.learning",
    "Action": "vslsp.symbolic.model",
    "Domain": "vslsp.symbolic.model",
    "Predicate": "vslsp.symbolic.model",
    "Problem": "vslsp.symbolic.model",
    "When": "vslsp.symbolic.model",
    "Compilation": "vslsp.symbolic.outcomes",
    "InternalError": "vslsp.symbolic.outcomes",
    "NoPlan": "vslsp.symbolic.outcomes",
    "PlanStatus": "vslsp.symbolic.outcomes",
    "Unsolvable": "vslsp.symbolic.outcomes",
    "parse_pddl": "vslsp.symbolic.pddl",
    "read_domain": "vslsp.symbolic.pddl",
    "read_pddl": "vslsp.symbolic.pddl",
    "read_problem": "vslsp.symbolic.pddl",
    "save": "vslsp.symbolic.pddl",
    "PddlWarning": "vslsp.symbolic.pddl_errors",
    "PlanResult": "vslsp.symbolic.planner",
    "check_planner": "vslsp.symbolic.planner",
    "solve": "vslsp.symbolic.planner",
    "solve_timed": "vslsp.symbolic.planner",
    "Validation": "vslsp.symbolic.validate",
    "parse_plan": "vslsp.symbolic.validate",
    "read_plan": "vslsp.symbolic.validate",
    "validate": "vslsp.symbolic.validate",
}


def __getattr__(name: str) -> Any:
    if name in _HOME:
        value = getattr(importlib.import_module(_HOME[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'vslsp.symbolic' has no attribute {name!r}")


class _Layer(types.ModuleType):
    """The package as a module whose exported names win over its submodules of the same name: importing
    ``vslsp.symbolic.validate`` (the module) leaves ``vslsp.symbolic.validate`` the function, as an eager
    ``from vslsp.symbolic.validate import validate`` here would."""

    def __setattr__(self, name: str, value: Any) -> None:
        if isinstance(value, types.ModuleType) and _HOME.get(name) == value.__name__ and hasattr(value, name):
            value = getattr(value, name)
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Layer

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
    "Task",
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
