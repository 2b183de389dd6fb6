"""The symbolic layer of VSL-SP: learned action models, goal rules, PDDL 3.0, planning, validation.

Paper: "Generalization of Learned Skills as Symbolic Action Models", "Implementation" and the
iCub experiments. Learning (:func:`learn_domain`, :func:`learn_task`) works on grounded
:class:`Step` records; :func:`make_problem` states a task in an observed scene; :func:`solve`
plans with unified-planning + Fast Downward (trajectory constraints compiled into the lifted
domain, :mod:`vslsp.symbolic.lifted`); :func:`validate` checks a plan against preconditions,
goal and every PDDL 3.0 constraint. Layers: formula < model < lifted, validate < up_model <
pddl (reader), planner (engines) < shell. unified-planning is imported only when called.
"""

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
from vslsp.symbolic.learning import Rule, Step, Task, extract_rules, generalise, learn_domain, learn_task, make_problem
from vslsp.symbolic.model import Action, Domain, Predicate, Problem, When
from vslsp.symbolic.outcomes import Compilation, InternalError
from vslsp.symbolic.pddl import parse_pddl, read_domain, read_pddl, read_problem, save
from vslsp.symbolic.pddl_errors import PddlWarning
from vslsp.symbolic.planner import PlanResult, check_planner, solve, solve_timed
from vslsp.symbolic.validate import Validation, parse_plan, read_plan, validate

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
    "Not",
    "Or",
    "PddlWarning",
    "PlanResult",
    "Predicate",
    "Problem",
    "Rule",
    "Sometime",
    "SometimeAfter",
    "SometimeBefore",
    "Step",
    "Task",
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
