"""A predicate of one's own through the library API (docs/grounding.md, docs/api.md): define it,
ground an image pair with it (with the predicates of predicates.py beside it), and learn the
action model of the operation over it. Run it with

    python examples/grounding/own_predicate.py [PRE.png POST.png]
"""

from __future__ import annotations

import sys
from pathlib import Path

from vslsp import api
from vslsp.vision.image import read_image

HERE = Path(__file__).parent


@api.predicate("top-half")
def top_half(obj, scene) -> bool:
    """The object's centre is in the upper half of the image (far from the robot's camera edge)."""
    return obj.y < scene.height / 2


def main(pre_path: Path, post_path: Path) -> None:
    # far (the built-in, VSL-SP's) beside one's own: top_half and those of predicates.py
    predicates = api.with_builtins([top_half, *api.load_predicates(HERE / "predicates.py")])
    pre, post = read_image(pre_path), read_image(post_path)
    grounding = api.ground(pre, post, predicates=predicates)
    print(f"the operation: {grounding.action} {grounding.name}")
    assert grounding.atoms_pre is not None and grounding.atoms_post is not None
    print("before:", " ".join(api.true_atoms(grounding.atoms_pre)))
    print("after:", " ".join(api.true_atoms(grounding.atoms_post)))
    # The grounded operation as the symbolic layer learns from it: each object's unary literals.
    before, after = api.unary_literals(grounding.atoms_pre), api.unary_literals(grounding.atoms_post)
    domain = api.learn_domain([api.Step(grounding.action, grounding.name, before, after)])
    print(domain.to_pddl())


if __name__ == "__main__":
    pre, post = (Path(p) for p in sys.argv[1:3]) if len(sys.argv) > 2 else (HERE / "pre.png", HERE / "post.png")
    main(pre, post)
