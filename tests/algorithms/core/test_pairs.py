"""Tests for core.pairs: the checked, centred pairs every alignment and ICP fit from. Hand
cases (a quarter turn about z, weights that favour one pair), the identity of the checked
and the trusted paths, the weighted figures against their formulas, and the refusals of a
rotation the pairs do not determine."""

from __future__ import annotations

import math

import numpy as np
import pytest

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.core.pairs import (
    Pairs,
    flat_error,
    one_per_dimension,
    prepare,
    rotation_fit,
    trusted_pairs,
)

QUARTER_TURN = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
"""A quarter turn about z: x -> y, y -> -x."""

TETRAHEDRON = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 3.0]])


def _pairs(src: np.ndarray, dst: np.ndarray, weights: object = None) -> Pairs:
    return prepare(src, dst, weights, min_dim=2, minimum=one_per_dimension)


def _fields(p: Pairs) -> dict[str, object]:
    return {name: getattr(p, name) for name in Pairs.__dataclass_fields__}


def test_trusted_pairs_are_what_prepare_builds_without_weights() -> None:
    rng = np.random.default_rng(0)
    src, dst = rng.normal(size=(7, 3)), rng.normal(size=(7, 3))
    checked, trusted = _pairs(src, dst), trusted_pairs(src, dst)
    assert checked.p is None and trusted.p is None and trusted.total == 7.0
    for name, value in _fields(checked).items():
        if isinstance(value, np.ndarray):
            np.testing.assert_allclose(getattr(trusted, name), value, rtol=0, atol=1e-15)
        else:
            assert getattr(trusted, name) == value, name


def test_hand_centring_and_figures() -> None:
    """Two pairs in 2-D: the centroids, the cross-covariance (1/n) Σ ỹ x̃ᵀ and the rmse."""
    p = _pairs(np.array([[0.0, 0.0], [2.0, 0.0]]), np.array([[0.0, 1.0], [0.0, 3.0]]))
    np.testing.assert_array_equal(p.x_mean, [1.0, 0.0])
    np.testing.assert_array_equal(p.y_mean, [0.0, 2.0])
    np.testing.assert_array_equal(p.cross_covariance(), [[0.0, 0.0], [1.0, 0.0]])
    assert (p.n, p.d, p.weighted) == (2, 2, False)
    resid = np.array([[3.0, 4.0], [0.0, 0.0]])
    assert p.mean_square(resid) == 12.5
    assert p.rmse(resid) == math.sqrt(12.5)
    assert p.rmse(resid, np.zeros((2, 2))) == math.sqrt(12.5 / 2)


def test_weights_normalised_and_total_kept() -> None:
    """p sums to 1 whatever the scale of the weights; total is their raw sum; the weighted
    mean square is Σ pᵢ‖rᵢ‖²."""
    src = np.array([[0.0, 0.0], [4.0, 0.0], [0.0, 4.0]])
    a = _pairs(src, src, [1.0, 1.0, 2.0])
    b = _pairs(src, src, [1e300, 1e300, 2e300])  # no overflow on the way to p
    for p, total in ((a, 4.0), (b, 4e300)):
        assert p.p is not None
        np.testing.assert_allclose(p.p, [0.25, 0.25, 0.5], rtol=1e-15)
        np.testing.assert_allclose(p.x_mean, [1.0, 2.0], rtol=1e-15)
        assert p.weighted and p.total == pytest.approx(total, rel=1e-15)
    resid = np.array([[2.0, 0.0], [0.0, 0.0], [0.0, 1.0]])
    assert a.mean_square(resid) == pytest.approx(0.25 * 4.0 + 0.5 * 1.0, rel=1e-15)
    assert a.p is not None
    np.testing.assert_allclose(a.sqrt_p() ** 2, a.p, rtol=1e-15)
    np.testing.assert_allclose(_pairs(src, src).sqrt_p() ** 2, np.full(3, 1 / 3), rtol=1e-15)


def test_linear_rmse_of_an_exact_map_is_zero_both_ways() -> None:
    linear = np.array([[2.0, 1.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 3.0]])
    p = _pairs(TETRAHEDRON, TETRAHEDRON @ linear.T + [1.0, -2.0, 0.5])
    assert p.linear_rmse(linear) == pytest.approx(0.0, abs=1e-14)
    assert p.linear_rmse(linear, symmetric=True) == pytest.approx(0.0, abs=1e-14)
    assert p.linear_rmse(np.eye(3)) > 1.0


def test_rotation_fit_recovers_a_quarter_turn() -> None:
    p = _pairs(TETRAHEDRON, TETRAHEDRON @ QUARTER_TURN.T + [5.0, 0.0, -1.0])
    fit = rotation_fit(p, reflect_ok=False)
    np.testing.assert_allclose(fit.rotation, QUARTER_TURN, atol=1e-14)


def test_rotation_fit_of_coplanar_pairs() -> None:
    """Coplanar pairs in 3-D fix a rotation (rank d - 1 suffices), but not a reflection nor
    an invertible map; the message names the flat set and says why."""
    flat = TETRAHEDRON[:3]
    p = _pairs(flat, flat @ QUARTER_TURN.T)
    np.testing.assert_allclose(rotation_fit(p, reflect_ok=False).rotation, QUARTER_TURN,
                               atol=1e-14)
    with pytest.raises(DegenerateInputError, match="`source` .* coplanar and a reflection"):
        rotation_fit(p, reflect_ok=True)
    with pytest.raises(DegenerateInputError, match="coplanar and the map has no inverse"):
        rotation_fit(p, reflect_ok=False, invertible=True)


def test_rotation_fit_of_collinear_target_names_it() -> None:
    line = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [3.0, 0.0, 0.0]])
    p = _pairs(TETRAHEDRON, line)
    with pytest.raises(DegenerateInputError, match="`target` .* collinear and the rotation "
                       "is undetermined") as info:
        rotation_fit(p, reflect_ok=False)
    assert info.value.field == "target"


def test_prepare_refusals() -> None:
    with pytest.raises(InvalidInputError, match="`target`"):
        _pairs(TETRAHEDRON, TETRAHEDRON[:3])
    with pytest.raises(InvalidInputError, match="`weights`"):
        _pairs(TETRAHEDRON, TETRAHEDRON, [1.0, 1.0])
    with pytest.raises(InvalidInputError, match="at least one per dimension in 3-D"):
        _pairs(TETRAHEDRON[:2], TETRAHEDRON[:2])


def test_flat_error_text() -> None:
    err = flat_error("source", 2, 3, "the map is undetermined", weighted=True)
    assert str(err) == ("Expected `source` to span at least 3 dimensions after centring, got "
                        "2: the points are coplanar (counting only points with positive "
                        "weight) and the map is undetermined.")
    assert err.field == "source"
