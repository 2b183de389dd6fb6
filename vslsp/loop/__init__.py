"""The VSL-SP loop: watch the tutor, perceive, learn, plan, execute and monitor (paper, VSL-SP).

- :mod:`~vslsp.loop.perception`: one camera image grounded into the objects to act on;
- :mod:`~vslsp.loop.monitor`: one plan step executed by its skill, its effect checked, faults;
- :mod:`~vslsp.loop.pipeline`: exploration of the skills, model learning, plan-execute-replan.

The tutor's operations are the iCub world's (:func:`vslsp.worlds.icub.tutor_operation`); the
paper's three iCub experiments built on the loop are in :mod:`vslsp.experiments.icub`.
"""
