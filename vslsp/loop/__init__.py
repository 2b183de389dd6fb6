"""The VSL-SP loop: watch the tutor, perceive, learn, plan, execute and monitor (paper, VSL-SP).

- :mod:`~vslsp.loop.perception`: one camera image grounded into the objects to act on;
- :mod:`~vslsp.loop.monitor`: one plan step executed by its skill, the effect its learned model
  expects checked (how a step is acted out is a hook: the experiments inject faults through it);
- :mod:`~vslsp.loop.pipeline`: exploration of the skills, model learning, plan-execute-replan.

The tutor's operations are the iCub world's (:func:`vslsp.worlds.icub.tutor_operation`); the
paper's three iCub experiments built on the loop are in :mod:`vslsp.experiments.icub`.
"""
