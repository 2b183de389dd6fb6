"""Visuospatial Skill Learning (paper, Algorithm 1): the demonstration recorder (part I) with
its observation dictionaries O^Pre, O^Post, match finding and reproduction (part II), on
observations only: no simulator, no world (the paper's worlds are :mod:`vslsp.worlds`, its VSL
experiments :mod:`vslsp.experiments`). Grounding symbols from observations lives in
:mod:`vslsp.grounding`.
"""
