"""Trustworthiness against scikit-learn's, on hand-checked and random cases; the sign rule."""

from __future__ import annotations

import numpy as np
import pytest
from sklearn.manifold import trustworthiness as sk_trustworthiness

from algorithms.core.errors import InvalidInputError
from algorithms.embedding import trustworthiness
from algorithms.embedding._quality import fix_signs


def test_hand_case_one_swapped_neighbour() -> None:
    # 1-D input 0,1,2,3,10 ; the embedding moves point 4 next to point 0.
    x = np.array([[0.0], [1.0], [2.0], [3.0], [10.0]])
    y = np.array([[0.0], [1.0], [2.0], [3.0], [-0.5]])
    # k = 1: point 0's embedded neighbour is 4 (input rank 4): penalty 4 - 1 = 3; point 4's
    # embedded neighbour is 0 (input rank 4): penalty 3. T = 1 - 2/(5·1·(10-3-1))·6 = 0.6
    assert trustworthiness(x, y, n_neighbors=1) == pytest.approx(0.6)
    assert sk_trustworthiness(x, y, n_neighbors=1) == pytest.approx(0.6)


def test_identity_and_tiny_sets() -> None:
    x = np.random.default_rng(0).normal(size=(30, 4))
    assert trustworthiness(x, x) == pytest.approx(1.0)
    assert trustworthiness(x[:2], x[:2, :1]) == 1.0


@pytest.mark.parametrize("seed", range(5))
@pytest.mark.parametrize("k", [1, 5, 12])
def test_equals_scikit_learn(seed: int, k: int) -> None:
    rng = np.random.default_rng(seed)
    x = rng.normal(size=(120, 6))
    for y in (x[:, :2], rng.normal(size=(120, 2)), x[:, :1] + 0.3 * rng.normal(size=(120, 1))):
        assert trustworthiness(x, y, n_neighbors=k) == pytest.approx(
            sk_trustworthiness(x, y, n_neighbors=k), abs=1e-12)


def test_too_many_neighbours_are_clipped_where_scikit_learn_refuses() -> None:
    # the documented difference: k >= n / 2 is clipped to (n - 1) // 2 = 4 for 10 points
    rng = np.random.default_rng(3)
    x, y = rng.normal(size=(10, 3)), rng.normal(size=(10, 2))
    with pytest.raises(ValueError, match="should be less than"):
        sk_trustworthiness(x, y, n_neighbors=7)
    assert trustworthiness(x, y, n_neighbors=7) == trustworthiness(x, y, n_neighbors=4)
    assert trustworthiness(x, y, n_neighbors=4) == pytest.approx(
        sk_trustworthiness(x, y, n_neighbors=4), abs=1e-12)


def test_errors_name_the_input() -> None:
    x = np.zeros((5, 2))
    with pytest.raises(InvalidInputError, match="embedding") as e:
        trustworthiness(x, np.zeros((4, 2)))
    assert e.value.field == "embedding"
    with pytest.raises(InvalidInputError, match="n_neighbors"):
        trustworthiness(x, x, n_neighbors=0)


def test_fix_signs_makes_largest_entry_positive() -> None:
    v = np.array([[1.0, -3.0], [-2.0, 1.0]])
    np.testing.assert_array_equal(fix_signs(v), [[-1.0, 3.0], [2.0, -1.0]])
    np.testing.assert_array_equal(fix_signs(-v), fix_signs(v))


def test_neighbour_lists_of_the_wrong_shape_are_refused() -> None:
    x = np.random.default_rng(0).normal(size=(20, 3))
    with pytest.raises(InvalidInputError, match="input_neighbours") as err:
        trustworthiness(x, x[:, :2], input_neighbours=(np.zeros((20, 6)), np.zeros((19, 6))))
    assert err.value.field == "input_neighbours"
    # lists narrower than k: the value without them
    d2 = np.zeros((20, 2))
    nbr = np.zeros((20, 2), dtype=int)
    assert trustworthiness(x, x[:, :2], n_neighbors=5, input_neighbours=(d2, nbr)) == \
        trustworthiness(x, x[:, :2], n_neighbors=5)
