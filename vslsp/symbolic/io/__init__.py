"""Reading PDDL files into the model, and where their parts are written.

- :mod:`~vslsp.symbolic.io.pddl`: :func:`read_pddl`, :func:`parse_pddl`, :func:`save` (the reading
  phase within its budget; unified-planning's reader where our own readers cannot);
- :mod:`~vslsp.symbolic.io.engine_reader` and :mod:`~vslsp.symbolic.io.flat_problem`: a domain and a
  problem built straight from the language engine's tree (no unified-planning);
- :mod:`~vslsp.symbolic.io.pddl_errors`: ``FILE:LINE:COL`` errors for malformed PDDL;
- :mod:`~vslsp.symbolic.io.locate`: where a goal conjunct or a constraint is written in its file;
- :mod:`~vslsp.symbolic.io.generated`: logistics problems of any size (the size tests and benchmarks).

Writing is the model's own ``to_pddl``. This ``__init__`` imports nothing: import the modules.
"""
