"""Symbol grounding for VSL-SP (paper, VSL-SP "Implementation"; Algorithm 1 lines 7-9): from
pre- and post-action images to PDDL atoms, with predicates that are the user's.

- :func:`predicate` registers a user predicate (a function over what perception found);
  :mod:`vslsp.grounding.relations` holds the built-in ``far`` and ready relations (RCC-style on
  footprints, directions relative to the robot, near/far relative to the landmark).
- :func:`ground` grounds one operation (the moved object, the landmark, (far b) before and
  after, the action, and with ``predicates`` every atom); :func:`ground_scene` one observation.
- :func:`load_predicates` reads a user's predicates file into this process;
  :class:`UserPredicates` (``--predicates FILE.py`` of the commands) and
  :func:`ground_with_user_predicates` (the studio) run it in a child process with limits
  (:mod:`vslsp.grounding.contained`).
- :mod:`vslsp.grounding.testkit` builds image pairs whose truth is known and checks groundings
  (``assert_grounds``); :mod:`vslsp.grounding.pytest_plugin` serves it to pytest.

See docs/grounding.md ("Unit-testing symbol grounding").
"""

from vslsp.grounding.contained import Limits, UserPredicates, ground_with_user_predicates
from vslsp.grounding.loader import load_predicates, with_builtins
from vslsp.grounding.operation import Grounding, SceneGrounding, ground, ground_scene
from vslsp.grounding.overlay import draw_grounding
from vslsp.grounding.predicates import (
    Box,
    Landmark,
    Predicate,
    Scene,
    SceneObject,
    collecting,
    ground_atoms,
    predicate,
    register,
    registered,
    true_atoms,
    unary_literals,
)
from vslsp.grounding.relations import BUILTINS, FAR
from vslsp.grounding.spatial import ROBOT_SIDES, far_of, identify_action

__all__ = [
    "BUILTINS",
    "FAR",
    "ROBOT_SIDES",
    "Box",
    "Grounding",
    "Landmark",
    "Limits",
    "Predicate",
    "Scene",
    "SceneGrounding",
    "SceneObject",
    "UserPredicates",
    "collecting",
    "draw_grounding",
    "far_of",
    "ground",
    "ground_atoms",
    "ground_scene",
    "ground_with_user_predicates",
    "identify_action",
    "load_predicates",
    "predicate",
    "register",
    "registered",
    "true_atoms",
    "unary_literals",
    "with_builtins",
]
