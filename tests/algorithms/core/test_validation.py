"""Tests for algorithms.core.validation: every check, every message."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from algorithms.core import (
    DegenerateInputError,
    InvalidInputError,
    as_bool,
    as_choice,
    as_float,
    as_indices,
    as_int,
    as_points,
    as_weights,
    check_min_points,
    same_dim,
    same_shape,
)
from algorithms.core.validation import MAX_COORDINATE

# --- as_points ---------------------------------------------------------------------------


def test_as_points_converts_lists_and_dtypes():
    out = as_points([[1, 2], [3, 4]], name="source")
    assert out.dtype == np.float64 and out.flags.c_contiguous
    np.testing.assert_array_equal(out, [[1.0, 2.0], [3.0, 4.0]])
    for dtype in (np.float32, np.int32, np.int64, np.uint8, np.float16):
        arr = np.arange(6, dtype=dtype).reshape(3, 2)
        got = as_points(arr, name="source")
        assert got.dtype == np.float64
        np.testing.assert_array_equal(got, arr.astype(np.float64))


def test_as_points_fortran_order_becomes_c_contiguous():
    arr = np.asfortranarray(np.arange(12.0).reshape(4, 3))
    out = as_points(arr, name="source")
    assert out.flags.c_contiguous
    np.testing.assert_array_equal(out, arr)


def test_as_points_misaligned_view_becomes_aligned():
    """A view at an odd byte offset (as unpickled from a network frame) is copied."""
    arr = np.arange(12.0).reshape(4, 3)
    raw = bytearray(1 + arr.nbytes)
    view = np.frombuffer(raw, dtype=np.float64, count=12, offset=1).reshape(4, 3)
    view[...] = arr
    assert not view.flags.aligned
    out = as_points(view, name="source")
    assert out.flags.aligned and out.flags.c_contiguous
    assert out.tobytes() == arr.tobytes()


def test_as_points_no_copy_when_already_right():
    arr = np.zeros((4, 3))
    assert as_points(arr, name="source") is arr


def test_as_points_magnitudes_up_to_the_limit_pass():
    arr = np.full((3, 2), -MAX_COORDINATE)
    assert as_points(arr, name="source") is arr
    big = np.full((300, 300), MAX_COORDINATE)  # the large-array (one sum) finite check
    assert as_points(big, name="source") is big


def test_as_points_refuses_magnitudes_whose_squares_overflow():
    arr = np.zeros((4, 3))
    arr[2, 1] = -1e300  # finite, but every distance through it overflows
    with pytest.raises(InvalidInputError, match=r"magnitude at most 1e\+100 .* got "
                       r"-1e\+300 at row 2\.") as info:
        as_points(arr, name="target")
    assert info.value.field == "target"


def test_as_points_rejects_1d():
    with pytest.raises(
        InvalidInputError,
        match=r"Expected `source` to be an \(n, d\) array of finite numbers, got shape \(5,\)\.",
    ) as info:
        as_points(np.zeros(5), name="source")
    assert info.value.field == "source"


def test_as_points_rejects_3d_and_scalar():
    with pytest.raises(InvalidInputError, match=r"got shape \(2, 2, 2\)"):
        as_points(np.zeros((2, 2, 2)), name="points")
    with pytest.raises(InvalidInputError, match=r"got shape \(\)"):
        as_points(3.0, name="points")


def test_as_points_wrong_dim_message():
    with pytest.raises(
        InvalidInputError,
        match=r"^Expected `source` to be an \(n, 3\) array of finite numbers, "
        r"got shape \(5, 2\)\.$",
    ):
        as_points(np.zeros((5, 2)), name="source", dim=3)


def test_as_points_zero_columns_and_min_dim():
    with pytest.raises(InvalidInputError, match=r"d >= 1 coordinates per point, got shape \(5, 0\)"):
        as_points(np.zeros((5, 0)), name="source")
    with pytest.raises(InvalidInputError, match=r"d >= 2 coordinates per point, got shape \(5, 1\)"):
        as_points(np.zeros((5, 1)), name="source", min_dim=2)


def test_as_points_counts():
    with pytest.raises(InvalidInputError, match=r"Expected `source` to hold at least 1 point, got 0\."):
        as_points(np.zeros((0, 3)), name="source")
    with pytest.raises(InvalidInputError, match=r"at least 4 points, got 3\."):
        as_points(np.zeros((3, 3)), name="source", min_points=4)
    with pytest.raises(InvalidInputError, match=r"Expected `source` to hold at most 2 points, got 3\."):
        as_points(np.zeros((3, 3)), name="source", max_points=2)
    assert as_points(np.zeros((0, 3)), name="source", min_points=0).shape == (0, 3)


@pytest.mark.parametrize(
    ("bad", "text"), [(np.nan, "nan"), (np.inf, "inf"), (-np.inf, "-inf")]
)
def test_as_points_nonfinite_names_first_bad_row(bad, text):
    arr = np.zeros((30, 3))
    arr[17, 1] = bad
    arr[20, 0] = np.nan
    with pytest.raises(
        InvalidInputError,
        match=rf"^Expected `source` to hold finite numbers, got {text} at row 17\.$",
    ) as info:
        as_points(arr, name="source")
    assert info.value.field == "source"


def test_as_points_nonfinite_float32():
    arr = np.zeros((4, 2), dtype=np.float32)
    arr[2, 0] = np.nan
    with pytest.raises(InvalidInputError, match=r"got nan at row 2"):
        as_points(arr, name="target")


def test_as_points_ragged():
    with pytest.raises(InvalidInputError, match=r"Expected `source` to be .* got a ragged"):
        as_points([[1.0, 2.0], [3.0]], name="source")


@pytest.mark.parametrize(
    ("value", "dtype"),
    [
        ([["a", "b"], ["c", "d"]], "<U1"),
        ([[True, False]], "bool"),
        ([[1 + 2j, 0j]], "complex128"),
        ([[None, 1.0]], "object"),
    ],
)
def test_as_points_non_numeric(value, dtype):
    with pytest.raises(InvalidInputError, match=rf"got an array of dtype {dtype}\."):
        as_points(value, name="source")


def test_as_points_numeric_strings_are_not_parsed():
    with pytest.raises(InvalidInputError, match="dtype <U3"):
        as_points([["1.5", "2.0"]], name="source")


# --- check_min_points, same_shape, same_dim ------------------------------------------------


def test_check_min_points():
    pts = np.zeros((2, 3))
    check_min_points(pts, 2, name="source")
    with pytest.raises(
        InvalidInputError,
        match=r"^Expected `source` to hold at least 3 points \(one per dimension\), got 2\.$",
    ) as info:
        check_min_points(pts, 3, name="source", reason="one per dimension")
    assert info.value.field == "source"


def test_same_shape():
    a = np.zeros((5, 3))
    same_shape(a, np.ones((5, 3)), names=("source", "target"))
    with pytest.raises(
        InvalidInputError,
        match=r"Expected `target` to hold as many points as `source` \(5, paired row by row\), got 4\.",
    ) as info:
        same_shape(a, np.zeros((4, 3)), names=("source", "target"))
    assert info.value.field == "target"
    with pytest.raises(
        InvalidInputError,
        match=r"Expected `target` to have the same dimension as `source` \(3\), got shape \(5, 2\)\.",
    ):
        same_shape(a, np.zeros((5, 2)), names=("source", "target"))
    with pytest.raises(
        InvalidInputError, match=r"same shape as `a`, \(5, 3\), got \(5,\)\."
    ):
        same_shape(a, np.zeros(5), names=("a", "b"))


def test_same_dim():
    same_dim(np.zeros((5, 3)), np.zeros((7, 3)), names=("source", "target"))
    with pytest.raises(
        InvalidInputError,
        match=r"Expected `target` to have the same dimension as `source` \(3\), got shape \(7, 2\)\.",
    ) as info:
        same_dim(np.zeros((5, 3)), np.zeros((7, 2)), names=("source", "target"))
    assert info.value.field == "target"


# --- as_weights ----------------------------------------------------------------------------


def test_as_weights_ok_and_none():
    assert as_weights(None, 3, name="weights") is None
    out = as_weights([1, 0, 2], 3, name="weights")
    assert out.dtype == np.float64
    np.testing.assert_array_equal(out, [1.0, 0.0, 2.0])
    assert as_weights(np.full(3, 1e308), 3, name="weights") is not None


def test_as_weights_errors():
    with pytest.raises(
        InvalidInputError,
        match=r"Expected `weights` to be an \(3,\) array of finite non-negative numbers, "
        r"got shape \(4,\)\.",
    ) as info:
        as_weights(np.ones(4), 3, name="weights")
    assert info.value.field == "weights"
    with pytest.raises(InvalidInputError, match=r"got shape \(3, 1\)"):
        as_weights(np.ones((3, 1)), 3, name="weights")
    with pytest.raises(InvalidInputError, match=r"to hold finite numbers, got nan at position 1\."):
        as_weights([1.0, np.nan, 1.0], 3, name="weights")
    with pytest.raises(InvalidInputError, match=r"to be non-negative, got -0.5 at position 2\."):
        as_weights([1.0, 1.0, -0.5], 3, name="weights")
    with pytest.raises(InvalidInputError, match=r"to have a positive sum, got all zeros\."):
        as_weights([0, 0, 0], 3, name="weights")
    with pytest.raises(InvalidInputError, match=r"dtype <U1"):
        as_weights(["a", "b", "c"], 3, name="weights")


# --- scalars -------------------------------------------------------------------------------


def test_as_int_accepts():
    assert as_int(3, name="k") == 3
    assert as_int(np.int32(3), name="k") == 3
    assert as_int(3.0, name="k") == 3
    assert type(as_int(np.int64(3), name="k")) is int
    assert as_int(5, name="k", minimum=5, maximum=5) == 5


@pytest.mark.parametrize("value", [True, np.bool_(False), 2.5, "3", None, float("nan"), float("inf")])
def test_as_int_rejects_type(value):
    with pytest.raises(InvalidInputError, match=r"^Expected `k` to be an integer, got .*\.$") as info:
        as_int(value, name="k")
    assert info.value.field == "k"


def test_as_int_bounds():
    with pytest.raises(InvalidInputError, match=r"^Expected `k` to be an integer >= 1, got 0\.$"):
        as_int(0, name="k", minimum=1)
    with pytest.raises(
        InvalidInputError,
        match=r"^Expected `k` to be an integer >= 1 and <= 4 \(the number of `target` points\), got 5\.$",
    ):
        as_int(5, name="k", minimum=1, maximum=4, reason="the number of `target` points")
    with pytest.raises(InvalidInputError, match=r"integer <= 2, got 3"):
        as_int(3, name="k", maximum=2)


def test_as_float():
    assert as_float(2, name="r") == 2.0 and type(as_float(np.float32(0.5), name="r")) is float
    assert as_float(0.0, name="r", minimum=0.0) == 0.0
    with pytest.raises(InvalidInputError, match=r"^Expected `r` to be a number > 0.0, got 0.0\.$"):
        as_float(0.0, name="r", minimum=0.0, inclusive=False)
    with pytest.raises(InvalidInputError, match=r"number >= 0 and < 1, got 1.0"):
        as_float(1.0, name="r", minimum=0, maximum=1, inclusive=(True, False))
    with pytest.raises(InvalidInputError, match=r"number <= 1, got 1.5"):
        as_float(1.5, name="r", maximum=1)
    with pytest.raises(InvalidInputError, match=r"^Expected `r` to be a finite number, got nan\.$"):
        as_float(float("nan"), name="r")
    with pytest.raises(InvalidInputError, match=r"finite number, got -inf"):
        as_float(-np.inf, name="r")
    for bad in (True, "1.0", None, [1.0]):
        with pytest.raises(InvalidInputError, match=r"^Expected `r` to be a number, got") as info:
            as_float(bad, name="r")
        assert info.value.field == "r"


def test_as_bool():
    assert as_bool(True, name="flag") is True and as_bool(np.bool_(False), name="flag") is False
    for bad in ("false", 0, 1, None):
        with pytest.raises(InvalidInputError, match=r"^Expected `flag` to be true or false, got"):
            as_bool(bad, name="flag")


def test_as_choice():
    assert as_choice("union", ("forward", "union"), name="direction") == "union"
    with pytest.raises(
        InvalidInputError,
        match=r"^Expected `direction` to be one of 'forward', 'union', got 'Union'\.$",
    ) as info:
        as_choice("Union", ["forward", "union"], name="direction")
    assert info.value.field == "direction"
    with pytest.raises(InvalidInputError, match=r"got 1\.$"):
        as_choice(1, ["forward"], name="direction")


# --- as_indices ----------------------------------------------------------------------------


def test_as_indices_ok():
    faces = as_indices([[0, 1, 2], [2, 3, 0]], 4, name="faces")
    assert faces.dtype == np.int64 and faces.shape == (2, 3)
    np.testing.assert_array_equal(as_indices(np.array([3.0, 1.0]), 4, name="idx"), [3, 1])
    np.testing.assert_array_equal(as_indices(np.array([3], dtype=np.uint64), 4, name="idx"), [3])
    assert as_indices([], 0, name="idx").shape == (0,)


def test_as_indices_out_of_range_names_row():
    faces = np.zeros((30, 3), dtype=np.int32)
    faces[17, 2] = 1031
    faces[25, 0] = 2000
    with pytest.raises(
        InvalidInputError,
        match=r"^Expected `faces` to hold vertex indices below 1024, got 1031 at row 17\.$",
    ) as info:
        as_indices(faces, 1024, name="faces", what="vertex indices")
    assert info.value.field == "faces"


def test_as_indices_negative_and_1d():
    with pytest.raises(
        InvalidInputError,
        match=r"^Expected `indices` to hold non-negative indices, got -1 at position 2\.$",
    ):
        as_indices([0, 1, -1], 5, name="indices")
    with pytest.raises(InvalidInputError, match=r"indices below 5, got 5 at position 0\."):
        as_indices([5], 5, name="indices")
    with pytest.raises(InvalidInputError, match=r"indices below 5, got \d+ at position 0\."):
        as_indices(np.array([2**63 + 5], dtype=np.uint64), 5, name="indices")


def test_as_indices_non_integer():
    with pytest.raises(InvalidInputError, match=r"to hold integer indices, got 1.5 at row 1\."):
        as_indices([[0.0, 1.0], [1.5, 2.0]], 5, name="edges")
    with pytest.raises(InvalidInputError, match=r"got nan at position 0"):
        as_indices([np.nan], 5, name="indices")
    with pytest.raises(InvalidInputError, match=r"dtype bool"):
        as_indices([True, False], 5, name="indices")


# --- errors --------------------------------------------------------------------------------


def test_errors_are_value_errors_and_pickle_with_field():
    err = DegenerateInputError("Expected x, got y.", field="source")
    assert isinstance(err, InvalidInputError) and isinstance(err, ValueError)
    back = pickle.loads(pickle.dumps(err))
    assert type(back) is DegenerateInputError and back.field == "source"
    assert str(back) == "Expected x, got y."


def test_check_keys_names_what_is_missing_or_unknown():
    from algorithms.core.validation import check_keys

    expected = "an object with keys 'a' and 'b'"
    check_keys({"a": 1, "b": 2, "c": 3}, ("a", "b"), ("c",), name="x", expected=expected)
    with pytest.raises(InvalidInputError, match=r"^Expected `x` to be an object with keys 'a' "
                       r"and 'b', got missing 'b'\.$") as info:
        check_keys({"a": 1, "z": 0}, ("a", "b"), name="x", expected=expected)
    assert info.value.field == "x"  # missing keys first, before unknown ones
    with pytest.raises(InvalidInputError, match=r"got unknown key 'z'\.$"):
        check_keys({"a": 1, "b": 2, "z": 0}, ("a", "b"), name="x", expected=expected)
    with pytest.raises(InvalidInputError, match=r"got unknown keys 'y', 'z'\.$"):
        check_keys({"a": 1, "b": 2, "z": 0, "y": 0}, ("a", "b"), name="x", expected=expected)
