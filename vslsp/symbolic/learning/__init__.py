"""Learning action models, goal rules and the demonstrated order from grounded observations.

- :mod:`~vslsp.symbolic.learning.learn`: :class:`Step` records in, :func:`learn_domain`,
  :func:`learn_task` and :func:`make_problem` out (pure functions of recorded data, never of the
  simulator).

This ``__init__`` imports nothing: import the module.
"""
