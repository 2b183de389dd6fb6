"""``vslsp learn-domain`` on picture files, as a user with a camera over a line on a table runs
VSL-SP: the pull-in-order trial's own exploration and tutor demonstration rendered on its seed
and saved as ``NN-pre.png`` / ``NN-post.png`` with ``names.json``; the learned domain and problem
plan the demonstrated order with ``vslsp plan``, as the experiment's own learning on that seed
does; bad folders are refused with exit 2 and one line naming the file."""

import json
import shutil
from pathlib import Path

import pytest
from helpers.cli import vslsp

from vslsp.experiments.icub_pictures import write_pull_in_order
from vslsp.experiments.icub_scripts import ORDERED_COLOURS
from vslsp.symbolic import read_domain, read_problem, solve

pytestmark = pytest.mark.slow

SEED = 0
REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def rendered(tmp_path_factory, library):
    """The folder of pictures of seed 0 and what the experiment learned from the same observations."""
    folder = tmp_path_factory.mktemp("pull-in-order") / "pictures"
    return folder, write_pull_in_order(SEED, folder, library)


@pytest.fixture
def pictures(rendered, tmp_path):
    """A copy of the rendered folder that a test may spoil."""
    return shutil.copytree(rendered[0], tmp_path / "pictures")


def _plan(capsys, folder):
    code, out, err = vslsp(capsys, "plan", folder / "domain.pddl", folder / "problem.pddl", "--json")
    assert code == 0, err
    return json.loads(out)["plan"]


def test_the_learned_domain_plans_the_demonstrated_order_as_the_experiment_learns_it(rendered, tmp_path, capsys):
    folder, experiment = rendered
    code, out, err = vslsp(capsys, "learn-domain", folder, "--out", tmp_path / "out", "--json")
    assert code == 0, err
    summary = json.loads(out)
    assert summary["order"] == list(ORDERED_COLOURS) and summary["actions"] == ["push", "pull"]
    assert _plan(capsys, tmp_path / "out") == [f"pull {c}" for c in ORDERED_COLOURS]
    # The same action models as the experiment's (learned from the same exploration), and the same plan.
    domain = read_domain(tmp_path / "out" / "domain.pddl")
    assert domain.to_pddl() == experiment.domain.to_pddl()
    assert (
        solve(experiment.domain, experiment.problem).lines()
        == solve(domain, read_problem(tmp_path / "out" / "domain.pddl", tmp_path / "out" / "problem.pddl")).lines()
    )
    assert "(sometime-before" in (tmp_path / "out" / "problem.pddl").read_text()
    # Per pair: the moved object, far before and after, what changed, and its overlay.
    first = summary["operations"][0]
    assert first["object"] == "orange" and first["action"] == "pull" and first["far"] == {"pre": True, "post": False}
    assert first["changed"] == {"far": False}
    assert [op["action"] for op in summary["explorations"]] == ["push", "pull"]
    for op in summary["operations"] + summary["explorations"]:
        assert (tmp_path / "out" / op["overlay"]).stat().st_size > 1000
    assert json.loads((tmp_path / "out" / "learned.json").read_text()) == summary


def test_without_explorations_the_demonstration_teaches_the_pull_alone(pictures, tmp_path, capsys):
    shutil.rmtree(pictures / "explore")
    code, out, err = vslsp(capsys, "learn-domain", pictures, "--out", tmp_path / "out")
    assert code == 0, err
    assert "learned pull; order orange < green < yellow" in out
    assert _plan(capsys, tmp_path / "out") == [f"pull {c}" for c in ORDERED_COLOURS]


def _refused(capsys, pictures, tmp_path):
    code, out, err = vslsp(capsys, "learn-domain", pictures, "--out", tmp_path / "out")
    assert code == 2 and out == "" and len(err.strip().splitlines()) == 1, err
    assert not (tmp_path / "out" / "domain.pddl").exists()
    return err


def test_a_missing_post_picture_is_named(pictures, tmp_path, capsys):
    (pictures / "02-post.png").unlink()
    assert "02-post.png is missing" in _refused(capsys, pictures, tmp_path)
    assert not (tmp_path / "out").exists()  # refused before any work


def test_names_json_naming_an_unknown_action_is_named(pictures, tmp_path, capsys):
    (pictures / "names.json").write_text(json.dumps({"01": "slide orange", "02": "pull green", "03": "pull yellow"}))
    err = _refused(capsys, pictures, tmp_path)
    assert "names.json" in err and "'slide'" in err
    assert not (tmp_path / "out").exists()


def test_names_json_naming_another_object_or_action_than_moved_is_named(pictures, tmp_path, capsys):
    (pictures / "names.json").write_text(json.dumps({"01": "push orange", "02": "pull green", "03": "pull yellow"}))
    err = _refused(capsys, pictures, tmp_path)
    assert "01-pre.png -> " in err and "(a pull)" in err and "'push orange'" in err


def test_a_pair_where_nothing_moved_is_named(pictures, tmp_path, capsys):
    shutil.copy(pictures / "03-pre.png", pictures / "03-post.png")
    err = _refused(capsys, pictures, tmp_path)
    assert "03-pre.png -> " in err and "03-post.png" in err


def test_json_errors_are_json(pictures, tmp_path, capsys):
    (pictures / "names.json").unlink()
    code, out, _ = vslsp(capsys, "learn-domain", pictures, "--out", tmp_path / "out", "--json")
    assert code == 2 and "names.json is missing" in json.loads(out)["error"]


def test_the_users_predicates_enter_the_models_and_each_pairs_atoms(rendered, tmp_path, capsys):
    predicates = REPO / "examples" / "grounding" / "predicates.py"
    code, out, err = vslsp(
        capsys, "learn-domain", rendered[0], "--out", tmp_path / "out", "--predicates", predicates, "--json"
    )
    assert code == 0, err
    first = json.loads(out)["operations"][0]
    assert "(on-robot-side orange)" in first["atoms"]["post"] and "(far orange)" in first["atoms"]["pre"]
    pull = next(a for a in read_domain(tmp_path / "out" / "domain.pddl").actions if a.name == "pull")
    assert "(on-robot-side ?b)" in pull.to_pddl()  # an effect the skill makes in every execution
    assert _plan(capsys, tmp_path / "out") == [f"pull {c}" for c in ORDERED_COLOURS]
