"""A user's predicates for a tabletop domain (docs/grounding.md, "Unit-testing symbol grounding").

Ground them with ``vslsp ground PRE POST --predicates examples/grounding/predicates.py``, learn
with them with ``vslsp experiment keep-all-near --predicates examples/grounding/predicates.py``.
"""

from vslsp.grounding import predicate, register
from vslsp.grounding.relations import IN_FRONT_OF


@predicate("right-half")
def right_half(obj, scene):
    """The object's centre is in the right half of the image."""
    return obj.x > scene.width / 2


@predicate("on-robot-side")
def on_robot_side(obj, scene):
    """The object lies on the robot's side of the landmark line (the user's name for "not far")."""
    return scene.landmark.signed_distance(obj.x, obj.y) < 0


@predicate("warm")
def warm(obj, scene):
    """A red, orange or yellow object (by its colour symbol: red, red_2, ...). No skill changes it,
    so it stays out of the learned action models."""
    return obj.name.split("_")[0] in ("red", "orange", "yellow")


@predicate("left-of", arity=2)
def left_of(a, b, scene):
    """a's centre is left of b's in the image."""
    return a.x < b.x


register(IN_FRONT_OF)  # a ready relation: a is nearer to the robot than b
