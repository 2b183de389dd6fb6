"""Planning: trajectory constraints compiled away, Fast Downward run as vslsp's own subprocess.

- :mod:`~vslsp.symbolic.engines.planner`: :func:`solve`, the planner names, the bounds of a run (the
  only module that imports unified-planning's engines: its planners' kinds and its compilers);
- :mod:`~vslsp.symbolic.engines.lifted`: PDDL 3.0 constraints compiled into the lifted domain;
- :mod:`~vslsp.symbolic.engines.fast_downward`: Fast Downward's driver run on PDDL text, bounded in
  time and memory, its processes ended with this one;
- :mod:`~vslsp.symbolic.engines.outcomes`: how a run ended (:class:`PlanStatus`) and its failures.

This ``__init__`` imports nothing: import the modules.
"""
