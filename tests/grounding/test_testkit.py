"""The grounding test kit: pairs with known truth, assert_grounds, and the pytest plugin run as a
user would run it (a test file in its own folder, pytest in a subprocess)."""

import subprocess
import sys
import textwrap
from importlib import metadata

import pytest

from vslsp.grounding import load_predicates, relations
from vslsp.grounding.testkit import Square, assert_grounds, rendered_pair, synthetic_pair
from vslsp.sim import CubeSpec, LandmarkSpec, SceneSpec


def test_synthetic_pair_truth_and_a_failure_with_its_overlay(tmp_path):
    pair = synthetic_pair([Square("red", (150, 400)), Square("red", (450, 150))], move=(1, (430, 400)))
    assert list(pair.truth_pre.objects) == ["red", "red_2"]  # repeated symbols named as perception does
    assert pair.atoms([relations.LEFT_OF]) == (["(far red_2)", "(left-of red red_2)"], ["(left-of red red_2)"])
    assert_grounds(pair.pre, pair.post, atoms_pre=["(far red_2)"], atoms_post=[], predicates=[])
    with pytest.raises(AssertionError) as failure:
        assert_grounds(pair.pre, pair.post, atoms_post=["(far red_2)"], predicates=[], overlay_dir=tmp_path)
    message = str(failure.value)
    assert "post: missing (far red_2); unexpected none" in message and str(tmp_path / "grounding.png") in message
    assert (tmp_path / "grounding.png").stat().st_size > 1000
    pre, post = pair.save(tmp_path / "images")
    assert_grounds(pre, post, atoms_pre=["( far  RED_2 )"], predicates=[])  # paths, loose spelling


def test_expected_atoms_of_unknown_predicates_are_input_errors():
    pair = synthetic_pair([Square("red", (150, 400)), Square("green", (450, 150))], move=(1, (430, 400)))
    with pytest.raises(Exception, match="name no grounded predicate"):
        assert_grounds(pair.pre, pair.post, atoms_pre=["(left-of red green)"], predicates=[])
    with pytest.raises(Exception, match="is not a PDDL atom"):
        assert_grounds(pair.pre, pair.post, atoms_pre=["left-of red green"], predicates=[])


@pytest.mark.slow
def test_rendered_pair_truth_matches_what_perception_grounds():
    spec = SceneSpec(
        cubes=(
            CubeSpec("a", "red", 0.16, 0.03),
            CubeSpec("b", "green", 0.30, -0.10),
            CubeSpec("c", "blue", 0.28, -0.20),
        ),
        landmark=LandmarkSpec(x=0.22, angle=0.15),
    )
    chosen = [relations.LEFT_OF, relations.IN_FRONT_OF]
    for camera in ("head", "overhead"):
        pair = rendered_pair(spec, move=("b", (0.16, -0.08)), camera=camera)
        truth_pre, truth_post = pair.atoms(chosen)
        assert "(far green)" in truth_pre and "(far green)" not in truth_post
        # the robot's left is +y: red (y 0.03) is left of green and blue
        assert "(left-of red green)" in truth_pre and "(in-front-of red blue)" in truth_pre
        assert_grounds(pair.pre, pair.post, atoms_pre=truth_pre, atoms_post=truth_post, predicates=chosen)


def test_the_pytest_plugin_serves_its_fixtures(tmp_path):
    (tmp_path / "predicates.py").write_text(
        textwrap.dedent("""
        from vslsp.grounding import predicate

        @predicate("right-half")
        def right_half(obj, scene):
            return obj.x > scene.width / 2
    """)
    )
    (tmp_path / "test_mine.py").write_text(
        textwrap.dedent("""
        from pathlib import Path
        from vslsp.grounding import load_predicates
        from vslsp.grounding.testkit import Square

        MINE = load_predicates(Path(__file__).with_name("predicates.py"))

        def test_passes(synthetic_pair, assert_grounds):
            pair = synthetic_pair([Square("red", (150, 400)), Square("green", (450, 150))], move=(1, (430, 400)))
            assert_grounds(pair.pre, pair.post, predicates=MINE,
                           atoms_pre=["(far green)", "(right-half green)"], atoms_post=["(right-half green)"])

        def test_fails(synthetic_pair, assert_grounds):
            pair = synthetic_pair([Square("red", (150, 400)), Square("green", (450, 150))], move=(1, (430, 400)))
            assert_grounds(pair.pre, pair.post, predicates=MINE, atoms_post=["(right-half red)"])
    """)
    )
    installed = any(ep.value == "vslsp.grounding.pytest_plugin" for ep in metadata.entry_points(group="pytest11"))
    plugin = [] if installed else ["-p", "vslsp.grounding.pytest_plugin"]  # a source checkout not reinstalled
    result = subprocess.run(
        [sys.executable, "-m", "pytest", *plugin, "-q", "-p", "no:cacheprovider", "-W", "ignore", str(tmp_path)],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=120,
    )
    assert "1 failed, 1 passed" in result.stdout, result.stdout + result.stderr
    assert "missing (right-half red); unexpected (right-half green)" in result.stdout
    assert "overlay: " in result.stdout and "grounding.png" in result.stdout


def test_example_predicates_file_loads():
    from pathlib import Path

    names = [p.name for p in load_predicates(Path(__file__).parents[2] / "examples/grounding/predicates.py")]
    assert names == ["right-half", "on-robot-side", "warm", "left-of", "in-front-of"]


def _run_pytest(folder, *args):
    installed = any(ep.value == "vslsp.grounding.pytest_plugin" for ep in metadata.entry_points(group="pytest11"))
    plugin = [] if installed else ["-p", "vslsp.grounding.pytest_plugin"]
    return subprocess.run(
        [sys.executable, "-m", "pytest", *plugin, "-p", "no:cacheprovider", "-p", "no:randomly", *map(str, args)],
        capture_output=True,
        text=True,
        cwd=folder,
        timeout=300,
    )


def test_a_users_kit_tests_never_depend_on_order_hide_the_kits_frames_and_know_slow(tmp_path):
    # Module a registers right-half and never names it; module b's test would see (right-half ...) atoms
    # as unexpected if the kit grounded everything registered so far (issue 27, item 11).
    (tmp_path / "test_a.py").write_text(
        textwrap.dedent("""
        from vslsp.grounding import predicate

        @predicate("right-half")
        def right_half(obj, scene):
            return obj.x > scene.width / 2

        def test_a():
            pass
    """)
    )
    (tmp_path / "test_b.py").write_text(
        textwrap.dedent("""
        import pytest
        from vslsp.grounding.testkit import Square

        @pytest.mark.slow
        def test_far_only(synthetic_pair, assert_grounds):
            pair = synthetic_pair([Square("red", (150, 400)), Square("green", (450, 150))], move=(1, (430, 400)))
            assert_grounds(pair.pre, pair.post, atoms_pre=["(far green)"], atoms_post=[])

        def test_wrong(synthetic_pair, assert_grounds):
            pair = synthetic_pair([Square("red", (150, 400)), Square("green", (450, 150))], move=(1, (430, 400)))
            assert_grounds(pair.pre, pair.post, atoms_pre=[], atoms_post=[])
    """)
    )
    strict = ("-W", "error::pytest.PytestUnknownMarkWarning")
    for order in (("test_a.py", "test_b.py"), ("test_b.py", "test_a.py")):
        result = _run_pytest(tmp_path, *strict, *order)
        assert "1 failed, 2 passed" in result.stdout, result.stdout + result.stderr
        assert "test_b.py::test_wrong" in result.stdout and "test_far_only" not in result.stdout.split("FAILED")[-1]
    failure = result.stdout
    assert "pre: missing none; unexpected (far green)" in failure
    assert "grounded pre: (far green)" in failure and "overlay: " in failure and "grounding.png" in failure
    assert "def assert_grounds" not in failure and "__tracebackhide__" not in failure  # the kit's source stays hidden
