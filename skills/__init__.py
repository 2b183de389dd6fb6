"""Package data: the shipped skills, installed as ``vslsp.data.skills`` (see ``vslsp.data``); no code."""
