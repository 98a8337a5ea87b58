"""Cases ported from scikit-learn's own tests of SMACOF and classical MDS
(sklearn/manifold/tests/test_mds.py, test_classical_mds.py; scikit-learn 1.9.1), run on
:func:`~algorithms.layout.stress` and :func:`~algorithms.layout.mds`; each test names the
original.

Conventions: scikit-learn's metric SMACOF is ``stress(..., weighting="uniform")`` (its
``smacof`` weighs every pair alike); ``init=Z`` is ``initial_positions=Z``. Its errors are
``ValueError``; ours are :class:`~algorithms.core.errors.InvalidInputError` naming the
field. ``normalized_stress`` here divides by the input's squared distances (the result's
documented definition), scikit-learn's Stress-1 by the layout's: asserted as ours."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_almost_equal
from scipy.spatial.distance import pdist, squareform
from sklearn.datasets import load_iris
from sklearn.manifold import ClassicalMDS

from algorithms.core.errors import ConvergenceWarning, InvalidInputError
from algorithms.layout import mds, stress

# scikit-learn's test data: Borg & Groenen, "Modern Multidimensional Scaling", p. 154
SIM = np.array([[0, 5, 3, 4], [5, 0, 2, 2], [3, 2, 0, 1], [4, 2, 1, 0]], float)
FOUR = np.array([[1, 1], [1, 4], [1, 5], [3, 3]], float)


# scikit-learn: test_mds.py::test_smacof (one Guttman transform from the book's start)
def test_smacof() -> None:
    z = np.array([[-0.266, -0.539], [0.451, 0.252], [0.016, -0.238], [-0.200, 0.524]])
    with pytest.warns(ConvergenceWarning, match="after 1 iterations"):
        res = stress(SIM, weighting="uniform", initial_positions=z, max_iterations=1,
                     tolerance=0)
    x_true = np.array([[-1.415, -2.471], [1.633, 1.107], [0.249, -0.067], [-0.468, 1.431]])
    assert res.iterations == 1
    assert_array_almost_equal(res.positions, x_true, decimal=3)


# scikit-learn: test_mds.py::test_smacof_error (not symmetric, not square, an init of the
# wrong shape)
def test_smacof_error() -> None:
    asym = np.array([[0, 5, 9, 4], [5, 0, 2, 2], [3, 2, 0, 1], [4, 2, 1, 0]], float)
    with pytest.raises(InvalidInputError, match="symmetric") as err:
        stress(asym, weighting="uniform")
    assert err.value.field == "distances"
    with pytest.raises(InvalidInputError) as err:
        stress(asym[:3], weighting="uniform")
    assert err.value.field == "distances"
    z = np.array([[-0.266, -0.539], [0.016, -0.238], [-0.200, 0.524]])
    with pytest.raises(InvalidInputError) as err:
        stress(SIM, weighting="uniform", initial_positions=z)
    assert err.value.field == "initial_positions"


# scikit-learn: test_mds.py::test_mds_recovers_true_data (metric: a random start, a tiny
# eps, 1000 iterations reach zero stress on four points in the plane)
def test_mds_recovers_true_data() -> None:
    res = stress(squareform(pdist(FOUR)), weighting="uniform", init="random", seed=42,
                 max_iterations=1000, tolerance=1e-15)
    assert_allclose(res.stress, 0.0, atol=1e-6)


# scikit-learn: test_mds.py::test_returned_stress (the stress reported is the final
# layout's; normalized: ours divides by the input's squared distances)
def test_returned_stress() -> None:
    d = pdist(FOUR)
    res = stress(squareform(d), weighting="uniform", init="random", seed=42)
    d_layout = pdist(res.positions)
    raw = float(np.sum((d_layout - d) ** 2))
    assert_allclose(res.stress, raw)
    assert_allclose(res.normalized_stress, np.sqrt(raw / np.sum(d ** 2)))


# scikit-learn: test_mds.py::test_convergence_does_not_depend_on_scale (the stopping rule
# is relative: the same iterations at 100 times and a hundredth of the distances)
@pytest.mark.parametrize("init", ["classical", "random"])
def test_convergence_does_not_depend_on_scale(init: str) -> None:
    d = squareform(pdist(FOUR))
    big = stress(d * 100, weighting="uniform", init=init, seed=42)
    small = stress(d / 100, weighting="uniform", init=init, seed=42)
    if init == "classical":   # the start scales with the data: the iterates do too
        assert big.iterations == small.iterations
        assert_allclose(big.positions / 100, small.positions * 100, rtol=1e-9, atol=1e-12)
    else:   # scikit-learn's random start does not scale either; both stop at zero stress
        assert big.converged and small.converged
        assert_allclose(big.normalized_stress, small.normalized_stress, atol=1e-6)


# scikit-learn: test_classical_mds.py::test_classical_mds_equivalent_on_data_and_distances
# (ClassicalMDS of the iris data equals ours of their distance matrix, up to signs)
def test_classical_mds_equivalent_on_data_and_distances() -> None:
    x, _ = load_iris(return_X_y=True)
    ref = ClassicalMDS(n_components=2, metric="euclidean").fit(x)
    ours = mds(squareform(pdist(x)), n_components=2)
    signs = np.sign(ours.positions[0]) * np.sign(ref.embedding_[0])
    assert_allclose(ours.positions, ref.embedding_ * signs, atol=1e-10)
    assert_allclose(ours.eigenvalues[:2], ref.eigenvalues_, rtol=1e-10)


# scikit-learn: test_classical_mds.py::test_classical_mds_wrong_inputs (not symmetric, not
# square)
def test_classical_mds_wrong_inputs() -> None:
    with pytest.raises(InvalidInputError, match="symmetric") as err:
        mds(np.array([[0, 1, 2], [3, 0, 5], [6, 7, 0]], float))
    assert err.value.field == "distances"
    with pytest.raises(InvalidInputError) as err:
        mds(np.array([[0, 1, 2], [3, 4, 5]], float))
    assert err.value.field == "distances"


# scikit-learn: test_mds.py::test_classical_mds_init_to_mds (SMACOF from the classical
# start equals SMACOF from ClassicalMDS's coordinates given as the start)
def test_classical_mds_init_to_mds() -> None:
    x, _ = load_iris(return_X_y=True)
    d = squareform(pdist(x))
    z = ClassicalMDS(n_components=2).fit_transform(x)
    a = stress(d, weighting="uniform", init="classical")
    b = stress(d, weighting="uniform", initial_positions=z)
    assert a.iterations == b.iterations
    assert_allclose(np.abs(a.positions), np.abs(b.positions), atol=1e-9)
