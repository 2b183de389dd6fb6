"""Visuospatial Skill Learning (paper, Algorithm 1): the demonstration recorder (part I) with
its observation dictionaries O^Pre, O^Post, match finding and reproduction (part II), and the
paper's VSL tasks. Grounding symbols from observations lives in :mod:`vslsp.grounding`.
"""
