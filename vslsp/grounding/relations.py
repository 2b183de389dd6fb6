"""Ready relations a user's domain can use, defined with :func:`~vslsp.grounding.predicate`.

Paper, VSL-SP "Implementation": ``far`` — an object on the other side of the landmark line from
the robot — is the built-in predicate (:data:`FAR`, always grounded). "Conclusion": qualitative
spatial reasoning such as the Region Connection Calculus (RCC) gives richer constraints; here
on footprints (the bounding boxes of the objects' pixels): :data:`DISCONNECTED` (RCC DC),
:data:`OVERLAPPING` (they share area: RCC PO, TPP, NTPP, EQ) and :data:`INSIDE` (a within b:
TPP or NTPP), and :func:`inside_region` for a fixed region of the image. Directions relative
to the robot: :data:`LEFT_OF`, :data:`RIGHT_OF`, :data:`IN_FRONT_OF` (nearer to the robot),
:data:`BEHIND`; and :data:`NEAR`, the robot's side of the landmark.

None of these is registered by importing this module: register the ones a domain uses with
``register(LEFT_OF, ...)`` in a predicates file.
"""

from __future__ import annotations

from vslsp.errors import InputError
from vslsp.grounding.predicates import Box, Predicate, Scene, SceneObject, predicate


def _landmark(scene: Scene):
    if scene.landmark is None:
        raise InputError("the scene has no landmark line in view")
    return scene.landmark


@predicate("far", register=False)
def far(obj: SceneObject, scene: Scene) -> bool:
    """(far b): b lies beyond the landmark line, seen from the robot."""
    return _landmark(scene).signed_distance(obj.x, obj.y) > 0.0


FAR: Predicate = far
BUILTINS: tuple[Predicate, ...] = (FAR,)  # grounded always, with the user's predicates


@predicate("near", register=False)
def near(obj: SceneObject, scene: Scene) -> bool:
    """(near b): b lies on the robot's side of the landmark line (not far)."""
    return _landmark(scene).signed_distance(obj.x, obj.y) <= 0.0


NEAR: Predicate = near


def _along(a: SceneObject, b: SceneObject, direction: tuple[float, float]) -> float:
    return (a.x - b.x) * direction[0] + (a.y - b.y) * direction[1]


@predicate("left-of", arity=2, register=False)
def left_of(a: SceneObject, b: SceneObject, scene: Scene) -> bool:
    """(left-of a b): a's centre lies further to the robot's left than b's."""
    return _along(a, b, scene.robot_left) > 0.0


@predicate("right-of", arity=2, register=False)
def right_of(a: SceneObject, b: SceneObject, scene: Scene) -> bool:
    """(right-of a b): a's centre lies further to the robot's right than b's."""
    return _along(a, b, scene.robot_left) < 0.0


@predicate("in-front-of", arity=2, register=False)
def in_front_of(a: SceneObject, b: SceneObject, scene: Scene) -> bool:
    """(in-front-of a b): a's centre is nearer to the robot than b's."""
    return _along(a, b, scene.towards_robot) > 0.0


@predicate("behind", arity=2, register=False)
def behind(a: SceneObject, b: SceneObject, scene: Scene) -> bool:
    """(behind a b): a's centre is further from the robot than b's."""
    return _along(a, b, scene.towards_robot) < 0.0


@predicate("disconnected", arity=2, register=False)
def disconnected(a: SceneObject, b: SceneObject, scene: Scene) -> bool:
    """(disconnected a b), RCC DC: the footprints neither overlap nor touch."""
    return a.footprint.gap(b.footprint) > 0.0


@predicate("overlapping", arity=2, register=False)
def overlapping(a: SceneObject, b: SceneObject, scene: Scene) -> bool:
    """(overlapping a b): the footprints share area (RCC PO, TPP, NTPP or EQ)."""
    return a.footprint.overlap(b.footprint) > 0.0


@predicate("inside", arity=2, register=False)
def inside(a: SceneObject, b: SceneObject, scene: Scene) -> bool:
    """(inside a b), RCC TPP or NTPP: a's footprint lies within b's."""
    return b.footprint.contains(a.footprint)


LEFT_OF, RIGHT_OF, IN_FRONT_OF, BEHIND = left_of, right_of, in_front_of, behind
DISCONNECTED, OVERLAPPING, INSIDE = disconnected, overlapping, inside


def inside_region(name: str, region: tuple[float, float, float, float], *, register: bool = False) -> Predicate:
    """A unary predicate ``name``: the object's footprint lies within ``region`` (x0, y0, x1, y1)
    px of the image (RCC TPP or NTPP of a fixed region, e.g. a tray or a bin)."""
    x0, y0, x1, y1 = (float(v) for v in region)
    if not (x0 < x1 and y0 < y1):
        raise InputError(f"predicate {name}: region {region} is empty; give (x0, y0, x1, y1) with x0 < x1, y0 < y1")
    box = Box(x0, y0, x1, y1)

    def within(obj: SceneObject, scene: Scene) -> bool:
        return box.contains(obj.footprint)

    within.__qualname__ = f"inside_region[{name}]"
    return predicate(name, register=register)(within)
