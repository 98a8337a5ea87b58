"""Tests for registration.procrustes (generalised Procrustes analysis): hand cases, exact
copies, its optimality conditions, agreement with scipy (align_vectors, procrustes),
progress and the iteration limit."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.spatial import procrustes as scipy_procrustes
from scipy.spatial.transform import Rotation

from algorithms.alignment import rigid
from algorithms.core import Cancelled, ConvergenceWarning, DegenerateInputError
from algorithms.registration import MultiwayResult, generalized_procrustes
from tests.algorithms.registration._shapes import angle_deg, bent_bar, random_rotation
from tests.algorithms.registration._views import apply, homogeneous


def quiet(*args, **kw) -> MultiwayResult:  # noqa: ANN002, ANN003
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        return generalized_procrustes(*args, **kw)


# --- layer 1: computed by hand --------------------------------------------------------------


def test_hand_one_dimensional_sets():
    # In 1-D the only proper rotation is +1: rigid GPA is centring and averaging.
    # x0 = (0, 1, 5) has mean 2, centred (-2, -1, 3); x1 = (10, 12, 14) has mean 12, centred
    # (-2, 0, 2). Mean shape (-2, -0.5, 2.5), in set 0's frame (+2): (0, 1.5, 4.5).
    # Residuals (0, -0.5, 0.5) and (0, 0.5, -0.5): rmse sqrt(0.5 / 3) for both.
    res = generalized_procrustes([[[0.0], [1.0], [5.0]], [[10.0], [12.0], [14.0]]])
    np.testing.assert_array_equal(res.transforms[0], np.eye(2))
    np.testing.assert_allclose(res.transforms[1], [[1, -10], [0, 1]], atol=1e-12)
    np.testing.assert_allclose(res.mean_shape, [[0], [1.5], [4.5]], atol=1e-12)
    np.testing.assert_allclose(res.rmse, [math.sqrt(0.5 / 3)] * 2, rtol=1e-12)
    assert res.converged and res.iterations == 2   # the second pass changes nothing
    np.testing.assert_array_equal(res.fitness, [1.0, 1.0])
    assert res.edges.shape == (0, 2) and res.edge_kept.size == 0 and res.edge_fitness.size == 0


def test_hand_quarter_turn_and_shift():
    # The second set is the first turned by +90° and shifted by (5, 0): mapping it back is
    # the turn by -90°, [[0, 1], [-1, 0]], and the translation -R(5, 0) = (0, 5).
    x = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 1.0]])
    turned = x @ np.array([[0.0, -1.0], [1.0, 0.0]]).T + [5.0, 0.0]
    res = generalized_procrustes([x, turned, x + 1.0])
    np.testing.assert_allclose(res.transforms[1], [[0, 1, 0], [-1, 0, 5], [0, 0, 1]],
                               atol=1e-12)
    np.testing.assert_allclose(res.transforms[2], [[1, 0, -1], [0, 1, -1], [0, 0, 1]],
                               atol=1e-12)
    np.testing.assert_allclose(res.mean_shape, x, atol=1e-12)
    np.testing.assert_allclose(res.rmse, 0.0, atol=1e-12)
    assert res.reason == "objective at rounding level (exact fit)"


def test_hand_similarity_halves_a_doubled_square():
    square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    big = 2.0 * square @ np.array([[0.0, -1.0], [1.0, 0.0]]).T + [3.0, 3.0]
    res = generalized_procrustes([square, big], model="similarity")
    np.testing.assert_allclose(res.scales, [1.0, 0.5], rtol=1e-12)
    np.testing.assert_allclose(apply(res.transforms[1], big), square, atol=1e-12)
    np.testing.assert_allclose(res.mean_shape, square, atol=1e-12)


# --- layer 2: invariants and recovery -------------------------------------------------------


@pytest.mark.parametrize("d", [2, 3, 5])
@pytest.mark.parametrize("seed", range(5))
def test_exact_rigid_copies_are_recovered(d, seed):
    rng = np.random.default_rng(seed)
    x = rng.standard_normal((12, d))
    truth = [homogeneous(random_rotation(rng, d), rng.uniform(-5, 5, d)) for _ in range(4)]
    sets = [apply(t, x) for t in truth]
    res = generalized_procrustes(sets)
    for i in range(4):   # set i back into set 0's frame: T_0 T_i⁻¹
        np.testing.assert_allclose(res.transforms[i], truth[0] @ np.linalg.inv(truth[i]),
                                   atol=1e-10)
    np.testing.assert_allclose(res.mean_shape, sets[0], atol=1e-10)
    np.testing.assert_allclose(res.rmse, 0.0, atol=1e-10)
    np.testing.assert_allclose(np.linalg.det(res.rotations), 1.0, atol=1e-12)
    assert res.converged and res.iterations == 1


@pytest.mark.parametrize("seed", range(3))
def test_exact_similar_copies_are_recovered(seed):
    rng = np.random.default_rng(seed)
    x = rng.standard_normal((10, 3))
    scales = rng.uniform(0.5, 2.0, 4)
    sets = [s * x @ random_rotation(rng).T + rng.uniform(-3, 3, 3) for s in scales]
    res = generalized_procrustes(sets, model="similarity")
    np.testing.assert_allclose(res.scales, scales[0] / scales, rtol=1e-10)
    for i in range(4):
        np.testing.assert_allclose(apply(res.transforms[i], sets[i]), sets[0], atol=1e-10)


@pytest.mark.parametrize("model", ["rigid", "similarity"])
def test_noisy_copies_meet_the_optimality_conditions(model):
    # At the minimum every moved set is best aligned (by the model) to the mean shape already,
    # the mean shape is the mean of the moved sets, and the objective is below that at the
    # true poses.
    rng = np.random.default_rng(4)
    x = rng.standard_normal((30, 3))
    truth = [homogeneous(random_rotation(rng) * (rng.uniform(0.7, 1.4) if model ==
                                                 "similarity" else 1.0), rng.normal(size=3))
             for _ in range(5)]
    sets = [apply(t, x) + 0.05 * rng.standard_normal(x.shape) for t in truth]
    res = generalized_procrustes(sets, model=model, tolerance=1e-14)
    moved = [apply(res.transforms[i], sets[i]) for i in range(5)]
    np.testing.assert_allclose(np.mean(moved, axis=0), res.mean_shape, atol=1e-12)
    for m in moved:
        fit = rigid(m, res.mean_shape)
        np.testing.assert_allclose(fit.rotation, np.eye(3), atol=1e-6)
    np.testing.assert_allclose(res.rmse, [np.sqrt(np.mean(np.sum((m - res.mean_shape) ** 2,
                                                                 axis=1))) for m in moved])
    if model == "rigid":  # the true poses (into set 0's frame) cost at least as much
        at_truth = [apply(truth[0] @ np.linalg.inv(truth[i]), sets[i]) for i in range(5)]
        mean = np.mean(at_truth, axis=0)
        assert np.sum((np.array(moved) - res.mean_shape) ** 2) <= \
            np.sum((np.array(at_truth) - mean) ** 2)


@pytest.mark.parametrize("model", ["rigid", "similarity"])
def test_five_noisy_views_with_correspondences_within_a_degree(model):
    rng = np.random.default_rng(7)
    x = bent_bar(400, 7)
    truth = [np.eye(4)] + [homogeneous(random_rotation(rng), rng.normal(size=3))
                           for _ in range(4)]
    sets = [apply(np.linalg.inv(t), x) + 0.02 * rng.standard_normal(x.shape) for t in truth]
    res = generalized_procrustes(sets, model=model)
    errors = [angle_deg(res.rotations[i], truth[i][:3, :3]) for i in range(5)]
    assert max(errors) < 1.0, errors
    if model == "similarity":
        np.testing.assert_allclose(res.scales, 1.0, atol=0.01)


def test_init_only_changes_the_start():
    rng = np.random.default_rng(1)
    x = rng.standard_normal((20, 3))
    sets = [apply(homogeneous(random_rotation(rng), rng.normal(size=3)), x)
            + 0.01 * rng.standard_normal(x.shape) for _ in range(3)]
    init = np.stack([homogeneous(random_rotation(rng), rng.normal(size=3)) for _ in range(3)])
    a = generalized_procrustes(sets, tolerance=1e-14)
    b = generalized_procrustes(sets, init=init, tolerance=1e-14)
    np.testing.assert_allclose(a.transforms, b.transforms, atol=1e-8)


def test_two_sets_rigid_agree_with_scipy_align_vectors():
    rng = np.random.default_rng(2)
    x = rng.standard_normal((15, 3))
    y = x @ random_rotation(rng).T + 0.1 * rng.standard_normal(x.shape) + 2.0
    res = generalized_procrustes([x, y])
    rot, _ = Rotation.align_vectors(x - x.mean(axis=0), y - y.mean(axis=0))
    np.testing.assert_allclose(res.rotations[1], rot.as_matrix(), atol=1e-10)
    np.testing.assert_allclose(res.translations[1], x.mean(axis=0) - rot.apply(y.mean(axis=0)),
                               atol=1e-10)


@pytest.mark.parametrize("seed", range(4))
def test_two_sets_similarity_agree_with_scipy_procrustes(seed):
    # scipy standardises both sets (centred, unit Frobenius norm) and fits the second onto
    # the first by rotation and Umeyama's one-sided scale s = <A, R B>. GPA's rotation is the
    # same; its relative scale is symmetric (the size ratio), so rebuild scipy's output from
    # our rotation and compare that and the disparity.
    rng = np.random.default_rng(seed)
    x = rng.standard_normal((12, 3))
    y = 1.7 * x @ random_rotation(rng).T + 0.2 * rng.standard_normal(x.shape) - 1.0
    mtx1, mtx2, disparity = scipy_procrustes(x, y)
    res = generalized_procrustes([x, y], model="similarity")
    b = y - y.mean(axis=0)
    b /= np.linalg.norm(b)
    rb = b @ res.rotations[1].T
    s = float(np.sum(mtx1 * rb))
    np.testing.assert_allclose(s * rb, mtx2, atol=1e-10)
    assert np.sum((mtx1 - s * rb) ** 2) == pytest.approx(disparity, rel=1e-9, abs=1e-14)
    size = np.linalg.norm(x - x.mean(axis=0)) / np.linalg.norm(y - y.mean(axis=0))
    assert res.scales[1] == pytest.approx(size, rel=1e-10)


def test_progress_and_cancellation_with_correspondences():
    rng = np.random.default_rng(3)
    x = rng.standard_normal((20, 3))
    sets = [apply(homogeneous(random_rotation(rng), [0, 0, 0]), x)
            + 0.05 * rng.standard_normal(x.shape) for _ in range(3)]
    calls = []
    res = quiet(sets, max_iterations=4, tolerance=0.0,
                progress=lambda done, total, msg="": calls.append((done, total)))
    assert calls == [(k, 4) for k in range(1, res.iterations + 1)]

    def cancel(done, total, msg=""):  # noqa: ANN001, ANN202
        raise Cancelled("stop")

    with pytest.raises(Cancelled):
        generalized_procrustes(sets, progress=cancel)


def test_max_iterations_is_not_convergence():
    rng = np.random.default_rng(5)
    x = rng.standard_normal((20, 3))
    sets = [apply(homogeneous(random_rotation(rng), [0, 0, 0]), x)
            + 0.3 * rng.standard_normal(x.shape) for _ in range(4)]
    with pytest.warns(ConvergenceWarning, match="did not converge"):
        res = generalized_procrustes(sets, max_iterations=1, tolerance=0.0)
    assert res.converged is False and "max_iterations" in res.reason and res.iterations == 1




# --- errors -------------------------------------------------------------------------------


def test_a_set_opposed_to_the_consensus_has_no_scale():
    # In 1-D the only rotation is +1, so a reflected set cannot be turned round: its
    # correlation with the others is -1 and no positive scale fits it.
    x = [[0.0], [1.0], [3.0]]
    with pytest.raises(DegenerateInputError, match="correlate positively") as err:
        generalized_procrustes([x, x, [[-v[0]] for v in x]], model="similarity")
    assert err.value.field == "sets[2]"
