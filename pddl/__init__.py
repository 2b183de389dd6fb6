"""Package data: the shipped pddl, installed as ``vslsp.data.pddl`` (see ``vslsp.data``); no code."""
