"""``vslsp studio``: a local web app over the files under one root folder (docs/studio.md).

Pages (NiceGUI: Vue, Quasar and a CodeMirror editor shipped in its wheel, so it works offline):
``/author`` (PDDL with live diagnostics from :mod:`vslsp.symbolic.language`, plan, timeline,
validate), ``/ground`` (an image pair grounded by :mod:`vslsp.grounding`), ``/experiments`` (runs of
the registered experiments in the background), ``/reports/REL`` (a report folder). The pages use
the JSON API under ``/api`` (:mod:`vslsp.studio.api`); files are served under ``/files/REL``.

Safety (:mod:`vslsp.studio.files`): nothing outside the root is read or written, a token guards
every request when bound beyond the loopback address, predicates run only from files under the root.
Layer: beside the command line (it imports 0-8, never ``vslsp.cli``).
"""
