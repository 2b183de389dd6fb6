"""The PDDL model: formulas and trajectory constraints, domains and problems as frozen values, and
their translation to and from unified-planning's model.

- :mod:`~vslsp.symbolic.model.formula`: logical formulas and PDDL 3.0 trajectory constraints;
- :mod:`~vslsp.symbolic.model.domain`: :class:`Domain`, :class:`Problem`, :class:`Action`,
  :class:`Predicate`, :class:`When` (each prints itself as PDDL, ``to_pddl``);
- :mod:`~vslsp.symbolic.model.up_model`: our model to and from ``unified_planning.model`` (imported
  lazily; never its engines nor its reader).

The model never imports its reader (:mod:`vslsp.symbolic.io`), as unified-planning keeps ``model/``
apart from ``io/``. This ``__init__`` imports nothing: import the modules.
"""
