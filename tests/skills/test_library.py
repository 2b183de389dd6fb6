"""The skill library of vslsp.skills.library: the shipped push/pull, its files, and hand paths."""

import json
import re
import shutil

import numpy as np
import pytest

from vslsp.dmp import DMP
from vslsp.errors import InputError
from vslsp.skills import SKILL_NAMES, Skill, SkillLibrary, default_library_path
from vslsp.skills.library import from_object_frame


@pytest.fixture
def copy(tmp_path):
    """A copy of the shipped library folder to damage."""
    folder = tmp_path / "skills"
    shutil.copytree(default_library_path(), folder)
    return folder


def rotation_z(angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


# -- the shipped library -------------------------------------------------------------------------
def test_the_shipped_library_has_push_and_pull(library):
    assert SKILL_NAMES == ("push", "pull")
    assert all(name in library for name in SKILL_NAMES)
    assert "stack" not in library
    with pytest.raises(InputError, match="no skill 'stack'.*vslsp teach stack"):
        library["stack"]


@pytest.mark.parametrize("name", SKILL_NAMES)
def test_each_shipped_skill_comes_with_its_demonstrations_and_metadata(library, name):
    skill = library[name]
    index = json.loads((default_library_path() / "library.json").read_text())["skills"][name]
    assert skill.reach.n_demos >= 5
    assert len(skill.demos) == skill.reach.n_demos == index["demonstrations"]
    for t, y in skill.demos:
        assert t.ndim == 1 and y.shape == (len(t), 3) and np.all(np.diff(t) > 0)
    assert index["reach_fit_rmse_mm"] == pytest.approx(skill.reach.fit_rmse * 1000, abs=1e-3)
    assert (index["n_basis"], index["alpha_z"], index["alpha_x"]) == (
        skill.reach.n_basis,
        skill.reach.alpha_z,
        skill.reach.alpha_x,
    )
    assert index["goal"] == pytest.approx(skill.goal) and index["move"] == pytest.approx(skill.move)


@pytest.mark.parametrize("name", SKILL_NAMES)
def test_the_shipped_dmp_is_the_one_its_demonstrations_give(library, name):
    skill = library[name]
    refit = DMP(3, n_basis=skill.reach.n_basis, alpha_z=skill.reach.alpha_z, alpha_x=skill.reach.alpha_x)
    refit.fit(skill.demos)
    # The same fit, up to the rounding of the least-squares solve, which differs between numpy/BLAS
    # builds (4.9e-8 on weights of about 10 with numpy 2.4.6 against the shipped fit): 1e-6 relative is far below
    # any change of demonstrations or DMP parameters.
    assert refit.weights == pytest.approx(skill.reach.weights, rel=1e-6, abs=1e-9)
    assert refit.fit_rmse == pytest.approx(skill.reach.fit_rmse, rel=1e-6)
    # The reach goal is where the demonstrated reaches ended, in the object frame.
    assert skill.goal == pytest.approx(np.mean([y[-1] for _, y in skill.demos], axis=0), abs=1e-9)


@pytest.mark.parametrize("name", SKILL_NAMES)
def test_each_shipped_reach_settles_on_its_goal_from_every_demonstrated_start(library, name):
    skill = library[name]
    starts = np.array([y[0] for _, y in skill.demos])
    ends = skill.reach.rollout(starts, skill.goal, duration=1.5 * skill.reach.tau).y[:, -1]
    assert np.linalg.norm(ends - skill.goal, axis=1).max() < 1e-3


def test_push_moves_away_from_the_robot_and_pull_toward_it(library):
    push, pull = library["push"], library["pull"]
    assert push.move[0] > 0.05 and pull.move[0] < -0.05  # along the landmark's normal n
    assert abs(push.move[1]) < 0.01 and abs(pull.move[1]) < 0.01
    assert push.goal[0] < 0 < pull.goal[0]  # reach-before the cube, reach-after it


# -- files ---------------------------------------------------------------------------------------
def test_save_and_load_round_trip(library, tmp_path):
    library.save(tmp_path / "out")
    loaded = SkillLibrary.load(tmp_path / "out")
    start, object_xy, normal = np.array([0.1, -0.25, 0.7]), np.array([0.25, -0.1]), np.array([0.9, 0.3])
    for name in SKILL_NAMES:
        before, after = library[name], loaded[name]
        assert np.array_equal(after.reach.weights, before.reach.weights)
        assert np.array_equal(after.goal, before.goal) and np.array_equal(after.move, before.move)
        assert len(after.demos) == len(before.demos)
        for (t0, y0), (t1, y1) in zip(before.demos, after.demos, strict=True):
            assert np.array_equal(t0, t1) and np.array_equal(y0, y1)
        assert after.summary() == before.summary()
        assert np.array_equal(after.hand_path(start, object_xy, normal), before.hand_path(start, object_xy, normal))


def test_a_missing_library_is_an_input_error(tmp_path):
    with pytest.raises(InputError, match="no skill library.*vslsp teach push"):
        SkillLibrary.load(tmp_path / "nowhere")


def test_a_corrupt_library_json_is_an_input_error(copy):
    (copy / "library.json").write_text('{"format": "vslsp-skill-library", "skills": {')
    with pytest.raises(InputError, match="library.json is corrupt"):
        SkillLibrary.load(copy)


def test_a_foreign_json_is_an_input_error(copy):
    (copy / "library.json").write_text(json.dumps({"format": "something-else"}))
    with pytest.raises(InputError, match="not a vslsp skill library"):
        SkillLibrary.load(copy)
    (copy / "library.json").write_text("[1, 2, 3]")
    with pytest.raises(InputError, match="not a vslsp skill library"):
        SkillLibrary.load(copy)


def test_an_entry_without_a_goal_is_an_input_error_naming_the_skill(copy):
    index = json.loads((copy / "library.json").read_text())
    del index["skills"]["pull"]["goal"]
    (copy / "library.json").write_text(json.dumps(index))
    with pytest.raises(InputError, match="skill 'pull'.*vslsp teach pull"):
        SkillLibrary.load(copy)


def test_a_corrupt_reach_npz_is_an_input_error(copy):
    data = (copy / "push_reach.npz").read_bytes()
    (copy / "push_reach.npz").write_bytes(data[: len(data) // 2])
    with pytest.raises(InputError, match="push_reach.npz"):
        SkillLibrary.load(copy)


def test_a_foreign_reach_npz_is_an_input_error(copy):
    np.savez(copy / "pull_reach.npz", weights=np.zeros((50, 3)))
    with pytest.raises(InputError, match="pull_reach.npz is not a vslsp DMP"):
        SkillLibrary.load(copy)


def test_demonstrations_that_are_not_arrays_are_an_input_error(copy):
    (copy / "push_demos.npz").write_bytes(b"not an npz at all")
    with pytest.raises(InputError, match="skill 'push'"):
        SkillLibrary.load(copy)


def test_truncated_demonstrations_are_an_input_error(copy):
    data = (copy / "push_demos.npz").read_bytes()
    (copy / "push_demos.npz").write_bytes(data[:500])
    with pytest.raises(InputError, match="skill 'push'"):
        SkillLibrary.load(copy)


# -- hand paths: the goal is relative to the object ----------------------------------------------
@pytest.mark.parametrize("name", SKILL_NAMES)
def test_a_hand_path_reaches_the_goal_beside_the_object_then_moves_it(library, name):
    skill = library[name]
    start, object_xy, normal = np.array([0.12, -0.28, 0.72]), np.array([0.26, -0.12]), np.array([1.0, 0.2])
    path = skill.hand_path(start, object_xy, normal)
    steps = np.linalg.norm(np.diff(path, axis=0), axis=1)
    # 5 mm Cartesian steps; the move starts on the goal, where the reach ends within 2 mm.
    assert np.median(steps) == pytest.approx(0.005, abs=3e-4)
    assert steps.max() < 0.007 and steps.min() > 1e-4
    assert path[0] == pytest.approx(start, abs=1e-9)
    goal = from_object_frame(skill.goal[None], object_xy, normal)[0]
    end = from_object_frame((skill.goal + skill.move)[None], object_xy, normal)[0]
    assert path[-1] == pytest.approx(end, abs=1e-9)
    assert np.linalg.norm(path - goal, axis=1).min() < 2e-3  # the reach ends on the goal
    # The move is straight along the normal, away from the robot for push, toward it for pull.
    n = np.array([*normal, 0.0]) / np.linalg.norm(normal)
    assert np.dot(end - goal, n) == pytest.approx(skill.move[0], abs=1e-9)


@pytest.mark.parametrize("name", SKILL_NAMES)
def test_moving_the_object_translates_the_hand_path(library, name):
    skill = library[name]
    start, object_xy, normal = np.array([0.1, -0.25, 0.7]), np.array([0.25, -0.1]), np.array([1.0, 0.0])
    shift = np.array([0.04, -0.07])
    path = skill.hand_path(start, object_xy, normal)
    moved = skill.hand_path(start + [*shift, 0.0], object_xy + shift, normal)
    assert moved == pytest.approx(path + [*shift, 0.0], abs=1e-9)


@pytest.mark.parametrize("angle", [0.3, -0.5])
def test_rotating_the_line_normal_rotates_the_hand_path_about_the_object(library, angle):
    skill = library["push"]
    start, object_xy, normal = np.array([0.1, -0.25, 0.7]), np.array([0.25, -0.1]), np.array([1.0, 0.0])
    pivot = np.array([*object_xy, 0.0])
    turn = rotation_z(angle)
    path = skill.hand_path(start, object_xy, normal)
    turned = skill.hand_path(pivot + turn @ (start - pivot), object_xy, turn[:2, :2] @ normal)
    assert turned == pytest.approx(pivot + (path - pivot) @ turn.T, abs=1e-9)
    # Not a mere translation: the same start with a turned normal gives another path.
    other = skill.hand_path(start, object_xy, turn[:2, :2] @ normal)
    assert len(other) != len(path) or np.abs(other - path).max() > 0.01


# -- every value is checked on load (issue 17) ---------------------------------------------------
def edit_index(change):
    def edit(folder):
        index = json.loads((folder / "library.json").read_text())
        change(index)
        (folder / "library.json").write_text(json.dumps(index))

    return edit


def edit_npz(change, file="push_reach.npz"):
    def edit(folder):
        arrays = dict(np.load(folder / file))
        change(arrays)
        np.savez(folder / file, **arrays)

    return edit


def dmp_meta(key, value):
    def change(arrays):
        arrays["meta"] = np.array(json.dumps({**json.loads(str(arrays["meta"])), key: value}))

    return change


def write_pickle(folder):
    import pickle

    (folder / "push_reach.npz").write_bytes(pickle.dumps({"weights": [1.0, 2.0]}))


BAD_LIBRARIES = {
    "nan goal": (
        edit_index(lambda i: i["skills"]["push"].update(goal=[float("nan"), 0.0, 0.6])),
        r"skill 'push'.*goal\[0\] is nan: not finite",
    ),
    "goal of 2 values": (
        edit_index(lambda i: i["skills"]["pull"].update(goal=[0.1, 0.2])),
        r"skill 'pull'.*goal is \[0\.1, 0\.2\], not a list of 3 numbers",
    ),
    "huge move": (
        edit_index(lambda i: i["skills"]["push"].update(move=[1e9, 0.0, 0.0])),
        r"move\[0\] is 1e\+09, outside \[-10, 10\]",
    ),
    "skills as a list": (
        edit_index(lambda i: i.update(skills=[{"name": "push"}])),
        r'not a vslsp skill library \("skills" is a JSON list',
    ),
    "entry as a string": (
        edit_index(lambda i: i["skills"].update(push="push.npz")),
        r"the entry of skill 'push' is a JSON str",
    ),
    "travel model as a string": (
        edit_index(lambda i: i["skills"]["pull"].update(travel_model="linear")),
        r"skill 'pull'.*travel_model is 'linear', not an object",
    ),
    "travel model without a slope": (
        edit_index(lambda i: i["skills"]["pull"].update(travel_model={"offset": 0})),
        r"travel_model is .*, not an object with \"slope\" and \"offset\"",
    ),
    "nan slope": (
        edit_index(lambda i: i["skills"]["pull"]["travel_model"].update(slope=float("nan"))),
        r"travel_model\.slope is nan: not finite",
    ),
    "reach file outside the folder": (
        edit_index(lambda i: i["skills"]["push"].update(reach_file="../../x.npz")),
        r"reach_file is '\.\./\.\./x\.npz', not the name of a file",
    ),
    "unsupported version": (edit_index(lambda i: i.update(version=2)), r"version 2 is not supported"),
    "weights x1e12": (
        edit_npz(lambda a: a.update(weights=a["weights"] * 1e12)),
        r"push_reach\.npz: weights reach [0-9.]+e\+1[0-9], beyond any plausible value",
    ),
    "nan weights": (
        edit_npz(lambda a: a.update(weights=a["weights"] * np.nan)),
        r"push_reach\.npz: weights are not finite \(150 NaN or infinite",
    ),
    "weights of another shape": (
        edit_npz(lambda a: a.update(weights=a["weights"][:10]), "pull_reach.npz"),
        r"pull_reach\.npz is not a vslsp DMP",
    ),
    "text weights": (edit_npz(lambda a: a.update(weights=np.array(["a", "b"]))), r"weights are of type <U1"),
    "tau 0": (edit_npz(dmp_meta("tau", 0.0)), r"push_reach\.npz: tau is 0, outside \(0, 60\]"),
    "tau nan": (edit_npz(dmp_meta("tau", float("nan"))), r"tau is nan: not finite"),
    "tau 1e12": (edit_npz(dmp_meta("tau", 1e12)), r"tau is 1e\+12, outside"),
    "dt 0": (edit_npz(dmp_meta("dt", 0.0)), r"dt is 0, outside"),
    "n_basis 1e12": (edit_npz(dmp_meta("n_basis", 10**12)), r"n_basis is 1e\+12, outside \[2, 1000\]"),
    "n_basis as text": (edit_npz(dmp_meta("n_basis", "50")), r"n_basis is '50', not an integer"),
    "nan demonstration": (
        edit_npz(lambda a: a.update(y_0=a["y_0"] * np.nan), "push_demos.npz"),
        r"push_demos\.npz: y_0 are not finite",
    ),
    "demonstration of 2 dimensions": (
        edit_npz(lambda a: a.update(y_1=a["y_1"][:, :2]), "push_demos.npz"),
        r"demonstration 1 has t of shape \(\d+,\) and y of shape \(\d+, 2\)",
    ),
    "time going back": (
        edit_npz(lambda a: a.update(t_0=a["t_0"][::-1].copy()), "push_demos.npz"),
        r"t_0, the sample times of demonstration 0, do not increase",
    ),
    "a pickle as the reach": (write_pickle, r"push_reach\.npz holds pickled Python objects"),
    "object arrays in the demonstrations": (
        lambda f: np.savez(f / "pull_demos.npz", t_0=np.array([{"a": 1}], dtype=object)),
        r"pull_demos\.npz holds pickled Python objects",
    ),
}


@pytest.mark.parametrize("case", BAD_LIBRARIES, ids=str)
def test_every_value_of_a_library_is_checked_and_named(copy, case):
    edit, expected = BAD_LIBRARIES[case]
    edit(copy)
    with pytest.raises(InputError) as error:
        SkillLibrary.load(copy)
    message = str(error.value)
    assert re.search(expected, message), message
    assert "allow_pickle" not in message and "unsafe" not in message  # never advise loading a pickle
    assert f"--out {copy} --force`" in message  # a command that re-creates it (tests/cli runs one)


def test_salvage_keeps_the_skills_that_load(copy):
    (copy / "push_reach.npz").write_bytes(b"garbage")
    library, problems = SkillLibrary.salvage(copy)
    assert sorted(library.skills) == ["pull"] and len(problems) == 1 and "skill 'push'" in problems[0]
    (copy / "library.json").write_text("{")
    library, problems = SkillLibrary.salvage(copy)
    assert library.skills == {} and "library.json is corrupt" in problems[0]
    library, problems = SkillLibrary.salvage(copy / "none")  # no library yet: an empty one, nothing wrong
    assert library.skills == {} and problems == []


def test_require_names_the_missing_skills(library):
    library.require(SKILL_NAMES)
    with pytest.raises(InputError, match=r"skills has no 'stack' and no 'slide' skill.*vslsp teach stack --out skills"):
        library.require(["stack", "slide", "push"], "skills")


def test_a_hand_path_of_implausible_length_is_refused_before_resampling(library):
    skill = library["push"]
    huge = Skill("push", skill.reach, skill.goal, np.array([1e12, 0.0, 0.0]), [], {})
    with pytest.raises(InputError, match=r"skill 'push' gives a hand path of 1e\+12 m"):
        huge.hand_path(np.array([0.1, -0.25, 0.7]), np.array([0.25, -0.1]), np.array([1.0, 0.0]))
