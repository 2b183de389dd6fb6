"""The predicate API and the ready relations, decided on drawn scenes whose truth is known."""

import numpy as np
import pytest

from vslsp.errors import InputError
from vslsp.grounding import (
    Box,
    collecting,
    ground,
    ground_atoms,
    predicate,
    register,
    registered,
    true_atoms,
    with_builtins,
)
from vslsp.grounding import relations as r
from vslsp.grounding.synthetic import Square, tabletop_image
from vslsp.grounding.testkit import synthetic_pair


def test_the_decorator_registers_and_the_function_stays_callable():
    with collecting() as registry:

        @predicate("right-half")
        def right_half(obj, scene):
            return obj.x > scene.width / 2

        @predicate("left-of", arity=2)
        def left_of(a, b, scene):
            return a.x < b.x

        assert registered() == (right_half, left_of) == registry.predicates()
        assert right_half.signature == "(right-half ?b)" and left_of.signature == "(left-of ?a ?b)"
    assert right_half not in registered()  # the registry of the with block is gone


@pytest.mark.parametrize(
    "name, arity, function, message",
    [
        ("Left Of", 1, lambda o, s: True, "not a PDDL name"),
        ("far-away", 3, lambda a, b, c, s: True, "arity 3"),
        ("odd", 2, lambda o, s: True, "must take (a, b, scene)"),
        ("odd", 1, lambda s: True, "must take (obj, scene)"),
    ],
)
def test_bad_declarations_are_input_errors(name, arity, function, message):
    with collecting(), pytest.raises(InputError, match=message.replace("(", r"\(").replace(")", r"\)")):
        predicate(name, arity)(function)


def test_two_functions_under_one_name_are_an_input_error():
    def one(obj, scene):
        return True

    def other(obj, scene):
        return False

    with collecting(), pytest.raises(InputError, match="defined twice"):
        predicate("twice")(one)
        predicate("twice")(other)


def _pair():
    # red near the robot on the left, green far on the right, blue far in the middle; green is pulled.
    squares = [Square("red", (120, 400)), Square("green", (500, 120)), Square("blue", (300, 150))]
    return synthetic_pair(squares, move=(1, (520, 410)), noise=3.0)


def test_built_in_far_and_near_match_the_landmark():
    pair = _pair()
    grounding = ground(pair.pre, pair.post, predicates=with_builtins([r.NEAR]))
    assert true_atoms(grounding.atoms_pre) == ["(far blue)", "(far green)", "(near red)"]
    assert true_atoms(grounding.atoms_post) == ["(far blue)", "(near green)", "(near red)"]
    assert grounding.far_pre and not grounding.far_post  # the same decision as the operation's (far b)


def test_directions_relative_to_the_robot_on_every_side():
    pair = _pair()
    chosen = [r.LEFT_OF, r.RIGHT_OF, r.IN_FRONT_OF, r.BEHIND]
    atoms = set(true_atoms(ground(pair.pre, pair.post, predicates=chosen).atoms_pre))
    assert {"(left-of red blue)", "(left-of blue green)", "(right-of green red)"} <= atoms
    assert {"(in-front-of red blue)", "(in-front-of blue green)", "(behind green red)"} <= atoms
    assert "(left-of green red)" not in atoms and "(behind red blue)" not in atoms
    # Seen with the robot at the top edge, its left is the image's right and its front is up.
    rotated = [np.ascontiguousarray(np.rot90(image, 2)) for image in (pair.pre, pair.post)]
    atoms = set(true_atoms(ground(*rotated, robot_side="top", predicates=chosen).atoms_pre))
    assert {"(left-of red blue)", "(in-front-of red blue)", "(behind green red)"} <= atoms


def test_rcc_relations_on_footprints_and_a_region():
    # A small yellow square on a large blue one (inside), a red one touching nothing.
    image_pre = tabletop_image(
        [
            Square("blue", (200, 380), 120),
            Square("yellow", (200, 380), 40),
            Square("red", (500, 400)),
            Square("green", (450, 120)),
        ]
    )
    image_post = tabletop_image(
        [
            Square("blue", (200, 380), 120),
            Square("yellow", (200, 380), 40),
            Square("red", (500, 400)),
            Square("green", (250, 400)),
        ]
    )
    tray = r.inside_region("in-tray", (100, 300, 330, 470))
    chosen = [r.DISCONNECTED, r.OVERLAPPING, r.INSIDE, tray]
    grounding = ground(image_pre, image_post, predicates=chosen)
    pre, post = set(true_atoms(grounding.atoms_pre)), set(true_atoms(grounding.atoms_post))
    assert {
        "(inside yellow blue)",
        "(overlapping yellow blue)",
        "(overlapping blue yellow)",
        "(disconnected red blue)",
        "(in-tray blue)",
        "(in-tray yellow)",
    } <= pre
    assert "(inside blue yellow)" not in pre and "(disconnected yellow blue)" not in pre
    assert "(in-tray green)" not in pre and "(in-tray green)" in post and "(overlapping green blue)" in post


def test_box_geometry():
    a, b = Box(0, 0, 10, 10), Box(12, 0, 20, 10)
    assert a.gap(b) == 2 and a.overlap(b) == 0 and Box(0, 0, 30, 30).contains(b) and not b.contains(a)
    assert Box(5, 5, 15, 15).overlap(a) == 25


def test_a_predicate_that_raises_or_returns_a_non_bool_is_named():
    pair = _pair()
    scene = pair.truth_pre
    with collecting():
        broken = predicate("broken")(lambda obj, scene: obj.colour)
        counting = predicate("counting")(lambda obj, scene: len(scene.objects))
        numpy_bool = predicate("numpy-bool")(lambda obj, scene: np.float64(obj.x) > 1.0)
    with pytest.raises(InputError, match=r"predicate broken raised AttributeError.*while grounding \(broken"):
        ground_atoms(scene, [broken])
    with pytest.raises(InputError, match="predicate counting returned int 3 for"):
        ground_atoms(scene, [counting])
    assert all(ground_atoms(scene, [numpy_bool]).values())


def test_registering_ready_relations_and_truth_of_a_pair():
    with collecting():
        register(r.LEFT_OF)
        pair = _pair()
        truth_pre, _ = pair.atoms(registered())  # atoms() alone: far only (never test order)
    assert "(left-of red blue)" in truth_pre and "(far green)" in truth_pre
