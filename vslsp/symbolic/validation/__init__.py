"""Checking plans and explaining why there is none.

- :mod:`~vslsp.symbolic.validation.validate`: a plan simulated against preconditions, the goal and
  every PDDL 3.0 constraint;
- :mod:`~vslsp.symbolic.validation.monitors`: the constraints judged state by state;
- :mod:`~vslsp.symbolic.validation.conflict`: a minimal set of goal conjuncts and constraints that
  conflict, found by real planner calls;
- :mod:`~vslsp.symbolic.validation.reachability`: why a goal atom can never hold (relaxed
  reachability).

This ``__init__`` imports nothing: import the modules.
"""
