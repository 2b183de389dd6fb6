"""The paper's eleven experiments, each a :class:`vslsp.tasks.Task` defined here and nowhere else
(``vslsp experiment --list``), declared as any package's tasks are: in the ``vslsp.tasks``
entry-point group of vslsp's ``pyproject.toml``, ``NAME = "module:Class"``, imported on first use
(:mod:`vslsp.tasks.registry`).

One module per family, on the family's base class:

- :mod:`~vslsp.experiments.house_roof`: VSL's house-and-roof simulation (Figure 4);
- :mod:`~vslsp.experiments.tabletop` (the base: layout, demonstrate, reproduce, judge, figures)
  and :mod:`~vslsp.experiments.real_world`: the five real-world tasks with the Panda (Table 1);
- :mod:`~vslsp.experiments.vsl3d`: VSL-3D on point clouds, table cleaning and stacking (their
  trials in :mod:`~vslsp.experiments.table_cleaning` and :mod:`~vslsp.experiments.stacking`,
  imported only when a trial runs: the point-cloud method loads torch);
- :mod:`~vslsp.experiments.icub`: VSL-SP's three iCub experiments (their trials in
  :mod:`~vslsp.experiments.icub_scripts`, on the state of one trial,
  :mod:`~vslsp.experiments.icub_run`; VSL's reproduction on the iCub,
  :mod:`~vslsp.experiments.icub_vsl`; the report, :mod:`~vslsp.experiments.icub_report`).

A family module imports what it uses at its top, the simulator and OpenCV too; torch (the
skills, the point-cloud method, the VSL-SP loop) and matplotlib only inside a trial, so that
listing the experiments stays cheap (``vslsp --help`` imports none of them: the registry is lazy).

The seeds of a trial's worlds come from :mod:`~vslsp.experiments.seeds`. ``docs/tasks.md``
shows a new experiment on an existing world written as one module.
"""
