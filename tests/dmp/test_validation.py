"""Bad input to vslsp.dmp: an InputError that names the demonstration (or argument) and the problem."""

import json

import numpy as np
import pytest

from vslsp.dmp import DMP
from vslsp.errors import InputError

T = np.linspace(0.0, 1.0, 20)
Y = np.column_stack([T, T**2, np.sin(T)])


def with_value(array, index, value):
    array = np.array(array, dtype=float)
    array[index] = value
    return array


# -- demonstrations ----------------------------------------------------------------------------
@pytest.mark.parametrize(
    "demos, message",
    [
        ([], "at least one demonstration"),
        ((T, Y), r"single \(t, y\) pair; pass \[\(t, y\)\]"),
        (np.zeros((2, 20, 3)), "not an array"),
        ("demo.npz", "list of demonstrations"),
        ([(T, Y), (T, Y[:, :2])], r"demonstration 1: expected t \(T,\) and y \(T, 3\), got t \(20,\) and y \(20, 2\)"),
        ([(T[:-1], Y)], r"demonstration 0: expected t .* got t \(19,\) and y \(20, 3\)"),
        ([(T[:3], Y[:3])], "demonstration 0 has 3 samples; a DMP needs at least 5"),
        ([(T, Y, Y)], r"demonstration 0 is not a pair \(t, y\)"),
        (
            [(T, Y), (T, with_value(Y, (7, 1), np.nan))],
            r"demonstration 1: y has 1 value\(s\) that are not finite \(NaN or inf\), "
            r"the first at sample 7, dimension 1",
        ),
        ([(with_value(T, 3, np.inf), Y)], "demonstration 0: t has 1 value.*not finite.*sample 3"),
        (
            [(T[::-1], Y)],
            r"demonstration 0: the time base t must increase strictly, but t\[1\] = 0.947368 does not "
            r"come after t\[0\] = 1",
        ),
        ([(with_value(T, 5, T[4]), Y)], r"demonstration 0: the time base t must increase strictly.*t\[5\]"),
        ([(T, np.ones((20, 3)))], "demonstration 0 never moves"),
        ([(T, [["a", "b", "c"]] * 20)], "demonstration 0: y is not an array of numbers"),
    ],
)
def test_fit_rejects_bad_demonstrations_saying_which_and_what(demos, message):
    dmp = DMP(3)
    with pytest.raises(InputError, match=message):
        dmp.fit(demos)
    assert dmp.n_demos == 0 and np.all(dmp.weights == 0)  # nothing learned from bad input


def test_a_nan_in_a_demonstration_never_reaches_a_file(tmp_path):
    with pytest.raises(InputError, match="not finite"):
        DMP(3).fit([(T, with_value(Y, (0, 0), np.nan))])


# -- rollouts ----------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def dmp():
    return DMP(3).fit([(T, Y)])


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"y0": np.zeros(2), "goal": np.ones(2)}, r"the start y0 must have shape \(3,\) or \(B, 3\)"),
        ({"y0": np.zeros(3), "goal": np.ones((2, 2, 3))}, r"the goal must have shape"),
        ({"y0": np.zeros((4, 3)), "goal": np.ones((3, 3))}, "4 starts and 3 goals"),
        ({"y0": np.zeros(3), "goal": with_value(np.ones(3), 2, np.nan)}, "the goal has 1 value.*not finite"),
        ({"y0": np.zeros(3), "goal": np.ones(3), "tau": 0.0}, "tau must be positive and finite, got 0.0"),
        ({"y0": np.zeros(3), "goal": np.ones(3), "tau": np.nan}, "tau must be positive and finite"),
        ({"y0": np.zeros((2, 3)), "goal": np.ones(3), "tau": [1.0, -1.0]}, "tau must be positive"),
        ({"y0": np.zeros((2, 3)), "goal": np.ones(3), "tau": [1.0, 1.0, 1.0]}, r"one per movement \(2,\)"),
        ({"y0": np.zeros(3), "goal": np.ones(3), "dt": 0.0}, "sample period dt must be positive"),
        ({"y0": np.zeros(3), "goal": np.ones(3), "duration": 0.001}, "shorter than one sample period"),
        ({"y0": np.zeros(3), "goal": np.ones(3), "duration": -1.0}, "duration must be positive"),
    ],
)
def test_rollout_rejects_bad_arguments(dmp, kwargs, message):
    with pytest.raises(InputError, match=message):
        dmp.rollout(**kwargs)


def test_bad_parameters_are_input_errors():
    for args in [(0,), (3, 1), (3, 50, -1.0), (3, 50, 25.0, 0.0), (3, 50, 25.0, 4.6, -1.0), (2.5,)]:
        with pytest.raises(InputError):
            DMP(*args)


# -- files -------------------------------------------------------------------------------------
def test_save_and_load_give_identical_rollouts(dmp, tmp_path):
    dmp.save(tmp_path / "reach.npz")
    loaded = DMP.load(tmp_path / "reach.npz")
    for name in (
        "n_dims",
        "n_basis",
        "alpha_z",
        "beta_z",
        "alpha_x",
        "regularization",
        "amplitude",
        "extent",
        "tau",
        "dt",
        "fit_rmse",
        "n_demos",
    ):
        assert getattr(loaded, name) == getattr(dmp, name)
    starts = Y[0] + np.random.default_rng(4).normal(0, 0.1, (5, 3))
    assert np.array_equal(
        loaded.rollout(starts, Y[-1], tau=[1, 2, 3, 4, 5]).y, dmp.rollout(starts, Y[-1], tau=[1, 2, 3, 4, 5]).y
    )
    with np.load(tmp_path / "reach.npz", allow_pickle=False) as data:  # no pickle needed
        assert set(data.files) == {"meta", "weights"}


def test_non_finite_weights_or_parameters_are_reported_as_not_finite(dmp, tmp_path):
    arrays = dmp.to_arrays()
    np.savez(tmp_path / "nan.npz", meta=arrays["meta"], weights=with_value(arrays["weights"], (3, 1), np.nan))
    with pytest.raises(InputError, match=r"nan.npz is not a vslsp DMP \(1 weights are not finite"):
        DMP.load(tmp_path / "nan.npz")
    meta = json.loads(str(arrays["meta"]))
    meta["tau"] = float("inf")
    np.savez(tmp_path / "inf.npz", meta=np.array(json.dumps(meta)), weights=arrays["weights"])
    with pytest.raises(InputError, match=r"tau not finite.*vslsp teach"):
        DMP.load(tmp_path / "inf.npz")


def test_a_corrupt_file_is_an_input_error(tmp_path):
    path = tmp_path / "broken.npz"
    path.write_bytes(b"PK\x03\x04 this is not a zip archive")
    with pytest.raises(InputError, match="broken.npz"):
        DMP.load(path)


def test_a_foreign_or_old_npz_is_an_input_error_that_says_what_to_do(dmp, tmp_path):
    np.savez(tmp_path / "image.npz", pixels=np.zeros((4, 4)))
    with pytest.raises(InputError, match="not a vslsp DMP.*vslsp teach"):
        DMP.load(tmp_path / "image.npz")
    arrays = dmp.to_arrays()
    np.savez(tmp_path / "other.npz", meta=np.array('{"format": "someone-else"}'), weights=arrays["weights"])
    with pytest.raises(InputError, match="format is 'someone-else'"):
        DMP.load(tmp_path / "other.npz")
    old = json.loads(str(arrays["meta"]))
    old["version"] = 1
    np.savez(tmp_path / "old.npz", meta=np.array(json.dumps(old)), weights=arrays["weights"])
    with pytest.raises(InputError, match="version 1 is not supported.*vslsp teach"):
        DMP.load(tmp_path / "old.npz")
    np.savez(tmp_path / "shape.npz", meta=arrays["meta"], weights=np.zeros((3, 3)))
    with pytest.raises(InputError, match=r"weights of shape \(3, 3\) do not fit n_basis = 50"):
        DMP.load(tmp_path / "shape.npz")
    np.savez(tmp_path / "pickled.npz", meta=np.array([{"format": "vslsp-dmp"}], dtype=object))
    with pytest.raises(InputError, match="pickled.npz"):
        DMP.load(tmp_path / "pickled.npz")


def test_a_missing_file_is_an_input_error(tmp_path):
    with pytest.raises(InputError, match="no DMP file .*missing.npz.*vslsp teach"):
        DMP.load(tmp_path / "missing.npz")


def test_a_tuple_of_two_demonstrations_is_not_mistaken_for_one():
    other = (T, Y + 1.0)
    assert DMP(3).fit(((T, Y), other)).n_demos == 2
    ragged = (np.linspace(0, 1, 30), np.column_stack([np.linspace(0, 1, 30)] * 3))
    assert DMP(3).fit(((T, Y), ragged)).n_demos == 2
