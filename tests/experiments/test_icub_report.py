"""The iCub report's pieces: Table 3 compared, what was learned grouped, step labels apart."""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from vslsp.experiments.icub_report import _label_ends, learned_lines, matches_table_3, observed_grounding
from vslsp.tasks.drawing import caption
from vslsp.vision.image import read_image

ICUB = Path(__file__).resolve().parents[1] / "data" / "icub"

PAPER = [
    {"action": "push", "parameters": "?x - block", "precondition": "(not (far ?x))", "effects": ["(far ?x)"]},
    {"action": "pull", "parameters": "?x - block", "precondition": "(far ?x)", "effects": ["(not (far ?x))"]},
]


def test_table_3_is_recognised_up_to_the_variable_name_and_a_different_model_is_not():
    assert matches_table_3({"action_models": PAPER})
    wrong = [PAPER[0], {**PAPER[1], "effects": ["(not (far ?x))", "(near ?x)"]}]
    assert not matches_table_3({"action_models": wrong})
    assert not matches_table_3({"action_models": PAPER[:1]})


def test_what_was_learned_is_shown_once_per_distinct_content_with_its_trials():
    same = {"action_models": PAPER, "domain_pddl": "(define (domain d))", "goal": "(not (far orange))"}
    records = [
        {"seed": 3, "learned": {**same, "constraints": ["(sometime-before a b)"], "rules": []}},
        {"seed": 4, "learned": {**same, "constraints": [], "rules": []}},
    ]
    text = "\n".join(learned_lines(records))
    assert text.count("### Action models, trials 3, 4") == 1 and text.count("(define (domain d))") == 1
    assert "### Goal and order, trials 3" in text and "### Goal and order, trials 4" in text
    assert "- `(sometime-before a b)`" in text and "No ordering constraints" in text
    assert "| push ?x - block | `(not (far ?x))` | `(far ?x)` | `(not (far ?b))` | `(far ?b)` |" in text


def test_step_labels_at_one_point_never_overlap():
    figure, axes = plt.subplots()
    axes.set(xlim=(0, 1), ylim=(0, 1))
    figure.canvas.draw()
    # Six paths ending within a few millimetres of each other (a cube acted on again and again).
    _label_ends(axes, [(k, np.array([0.5 + 0.001 * k, 0.5, 0.0])) for k in range(1, 7)])
    figure.canvas.draw()
    renderer = figure.canvas.get_renderer()
    boxes = [text.get_bbox_patch().get_window_extent(renderer) for text in axes.texts]
    assert len(boxes) == 6
    assert not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1 :])
    plt.close(figure)


def test_a_caption_wraps_to_the_picture_and_covers_none_of_it():
    picture = np.full((100, 300, 3), 200, np.uint8)
    captioned = caption(picture, ["a long line of words " * 4, "short"])
    assert captioned.shape[1] == 300 and captioned.shape[0] > 100 + 3 * 16
    assert (captioned[-100:] == picture).all()


def test_an_executed_step_is_pictured_as_vslsp_ground_grounds_its_raw_images():
    # the robot pulled orange and its hand moved yellow 2.9 px: the picture shows orange's
    # grounding (it once said "no object changed side" beside the caption "observed ... ok")
    pre, post = read_image(ICUB / "nudged_pre.png"), read_image(ICUB / "nudged_post.png")
    grounding, why = observed_grounding(pre, post)
    assert grounding is not None and grounding.name == "orange" and grounding.action == "pull" and not why
    assert grounding.to_dict()["nudged"] == [{"name": "yellow", "moved_px": 2.9}]
    nothing, why = observed_grounding(pre, pre)
    assert nothing is None and why.startswith("nothing moved between the pre- and the post-action image")
