"""Tests for registration.multiway: generalised Procrustes against hand cases, exact copies,
its optimality conditions and scipy.spatial.procrustes; the pose graph on noisy partial views
of generated shapes, its optimiser on a graph with a wrong edge, and every error branch."""

from __future__ import annotations

import importlib
import math
import warnings

import numpy as np
import pytest
from scipy.spatial import procrustes as scipy_procrustes
from scipy.spatial.transform import Rotation

from algorithms.alignment import rigid
from algorithms.core import Cancelled, ConvergenceWarning, DegenerateInputError, InvalidInputError
from algorithms.registration import MultiwayResult, multiway

from tests.algorithms.registration._shapes import angle_deg, bent_bar, blob, random_rotation

# the module (the package attribute of the same name is the function)
mw = importlib.import_module("algorithms.registration.multiway")


def homogeneous(linear: np.ndarray, shift) -> np.ndarray:  # noqa: ANN001
    d = linear.shape[0]
    out = np.eye(d + 1)
    out[:d, :d] = linear
    out[:d, d] = shift
    return out


def apply(t: np.ndarray, pts: np.ndarray) -> np.ndarray:
    d = pts.shape[1]
    return pts @ t[:d, :d].T + t[:d, d]


def views(shape, k: int = 5, n: int = 1500, seed: int = 0, noise: float = 0.01,  # noqa: ANN001
          degrees: float = 10.0, shift: float = 0.1, keep: float = 0.7
          ) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """``k`` partial noisy views of one shape: view ``i`` keeps the ``keep`` fraction of
    points seen from direction ``2πi/k`` in the xy-plane, adds Gaussian noise and is seen
    from the pose ``T_i`` (a random turn up to ``degrees`` and shift up to ``shift``;
    ``T_0 = I``), i.e. holds ``T_i⁻¹ x``. Returns the views and the true poses."""
    rng = np.random.default_rng(seed)
    base = shape(n, seed)
    base = base - base.mean(axis=0)
    sets, poses = [], []
    for i in range(k):
        phi = 2 * np.pi * i / k
        proj = base @ [np.cos(phi), np.sin(phi), 0.0]
        pts = base[proj >= np.quantile(proj, 1 - keep)]
        pts = pts + noise * rng.standard_normal(pts.shape)
        pose = np.eye(4)
        if i:
            axis = rng.uniform(-1, 1, 3)
            pose[:3, :3] = Rotation.from_rotvec(
                np.radians(degrees) * axis / np.linalg.norm(axis)).as_matrix()
            pose[:3, 3] = rng.uniform(-shift, shift, 3)
        sets.append(apply(np.linalg.inv(pose), pts))
        poses.append(pose)
    return sets, poses


def quiet(*args, **kw) -> MultiwayResult:  # noqa: ANN002, ANN003
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        return multiway(*args, **kw)


# --- layer 1: computed by hand --------------------------------------------------------------


def test_hand_one_dimensional_sets():
    # In 1-D the only proper rotation is +1: rigid GPA is centring and averaging.
    # x0 = (0, 1, 5) has mean 2, centred (-2, -1, 3); x1 = (10, 12, 14) has mean 12, centred
    # (-2, 0, 2). Mean shape (-2, -0.5, 2.5), in set 0's frame (+2): (0, 1.5, 4.5).
    # Residuals (0, -0.5, 0.5) and (0, 0.5, -0.5): rmse sqrt(0.5 / 3) for both.
    res = multiway([[[0.0], [1.0], [5.0]], [[10.0], [12.0], [14.0]]])
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
    res = multiway([x, turned, x + 1.0])
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
    res = multiway([square, big], model="similarity")
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
    res = multiway(sets)
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
    res = multiway(sets, model="similarity")
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
    res = multiway(sets, model=model, tolerance=1e-14)
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
    res = multiway(sets, model=model)
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
    a = multiway(sets, tolerance=1e-14)
    b = multiway(sets, init=init, tolerance=1e-14)
    np.testing.assert_allclose(a.transforms, b.transforms, atol=1e-8)


def test_two_sets_rigid_agree_with_scipy_align_vectors():
    rng = np.random.default_rng(2)
    x = rng.standard_normal((15, 3))
    y = x @ random_rotation(rng).T + 0.1 * rng.standard_normal(x.shape) + 2.0
    res = multiway([x, y])
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
    res = multiway([x, y], model="similarity")
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
        multiway(sets, progress=cancel)


def test_max_iterations_is_not_convergence():
    rng = np.random.default_rng(5)
    x = rng.standard_normal((20, 3))
    sets = [apply(homogeneous(random_rotation(rng), [0, 0, 0]), x)
            + 0.3 * rng.standard_normal(x.shape) for _ in range(4)]
    with pytest.warns(ConvergenceWarning, match="did not converge"):
        res = multiway(sets, max_iterations=1, tolerance=0.0)
    assert res.converged is False and "max_iterations" in res.reason and res.iterations == 1


# --- pose graph ---------------------------------------------------------------------------


@pytest.mark.parametrize("shape, seed", [(bent_bar, 0), (blob, 1)])
def test_five_noisy_views_without_correspondences_within_a_degree(shape, seed):
    sets, poses = views(shape, seed=seed, n=1200)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConvergenceWarning)
        res = multiway(sets, correspondences=False)
    errors = [angle_deg(res.rotations[i], poses[i][:3, :3]) for i in range(5)]
    assert max(errors) < 1.0, errors
    shifts = [np.linalg.norm(res.translations[i] - poses[i][:3, 3]) for i in range(5)]
    assert max(shifts) < 0.05, shifts
    np.testing.assert_array_equal(res.transforms[0], np.eye(4))
    assert res.converged and res.mean_shape is None
    assert res.edges.tolist() == [[i, j] for i in range(5) for j in range(i + 1, 5)]
    assert res.edge_kept.sum() >= 4 and (res.fitness > 0.9).all()
    assert (res.rmse < 0.05).all()


def test_exact_copies_without_correspondences_are_assembled_exactly():
    # The same points seen from four poses (rows shuffled, so no correspondence is given
    # away): every pairwise ICP reaches an exact fit, and so does the pose graph.
    base = bent_bar(500, 3)
    rng = np.random.default_rng(3)
    truth = [np.eye(4)] + [homogeneous(Rotation.from_rotvec(rng.uniform(-0.1, 0.1, 3))
                                       .as_matrix(), rng.uniform(-0.05, 0.05, 3))
                           for _ in range(3)]
    sets = [apply(np.linalg.inv(t), base)[rng.permutation(len(base))] for t in truth]
    res = multiway(sets, correspondences=False)
    for i in range(4):
        np.testing.assert_allclose(res.transforms[i], truth[i], atol=1e-9)
    np.testing.assert_allclose(res.rmse, 0.0, atol=1e-9)
    np.testing.assert_array_equal(res.fitness, 1.0)
    assert res.edge_kept.all() and res.converged


def test_init_and_neighbours_chain():
    # Large turns (60° to 180°) are out of ICP's reach from the identity; a rough init
    # (within ~5° of the truth) brings them in. neighbors=1 registers a chain only.
    sets, poses = views(bent_bar, k=4, n=800, seed=2, degrees=0.0, shift=0.0, keep=0.8)
    rng = np.random.default_rng(2)
    big = [np.eye(4)] + [homogeneous(random_rotation(rng), rng.normal(size=3))
                         for _ in range(3)]
    moved = [apply(np.linalg.inv(big[i]), s) for i, s in enumerate(sets)]
    rough = np.stack([homogeneous(Rotation.from_rotvec(rng.uniform(-0.05, 0.05, 3))
                                  .as_matrix() @ b[:3, :3], b[:3, 3]) for b in big])
    res = multiway(moved, correspondences=False, init=rough, neighbors=1)
    assert res.edges.tolist() == [[0, 1], [1, 2], [2, 3]]
    errors = [angle_deg(res.rotations[i], big[i][:3, :3]) for i in range(4)]
    assert max(errors) < 1.0, errors


def test_the_line_process_prunes_a_wrong_loop_closure():
    # A consistent graph of five poses plus one loop closure 20° off: the optimiser turns the
    # wrong edge off (its line-process weight drops) and lands on the truth.
    rng = np.random.default_rng(0)
    poses = np.stack([np.eye(4)] + [homogeneous(random_rotation(rng), rng.normal(size=3))
                                    for _ in range(4)])
    pts = blob(200)
    info = mw._information(pts)
    edges = []
    for i, j in mw._pairs(5, None):
        z = np.linalg.inv(poses[j]) @ poses[i]
        if (i, j) == (0, 3):
            z = homogeneous(Rotation.from_rotvec([0, 0, np.radians(20.0)]).as_matrix(),
                            [0.3, 0, 0]) @ z
        edges.append(mw._Edge(i, j, z, info, 1.0, 200, odometry=False))
    mu = 0.05 ** 2 * 200
    opts = mw._GraphOptions(0.05, "point_to_plane", None, 0.3, 0.25, 1.0, 30, 100, 1e-12)
    start = poses.copy()
    for i in range(1, 5):
        start[i] = mw._exp(rng.normal(size=6) * 0.02) @ poses[i]
    out, _, converged, _ = mw._levenberg_marquardt(start, edges, mu, opts,
                                                   lambda *a: None, 0, 1)
    assert converged
    weights = {(e.i, e.j): mw._confidence(mw._residual(out, e), e.info, mu) for e in edges}
    assert weights[0, 3] < 0.25 and min(w for k, w in weights.items() if k != (0, 3)) > 0.9
    np.testing.assert_allclose(out, poses, atol=1e-3)


def test_se3_exp_and_log_are_inverse():
    rng = np.random.default_rng(0)
    for angle in (0.0, 1e-9, 1e-4, 0.05, 1.0, 3.0):
        axis = rng.normal(size=3)
        xi = np.r_[angle * axis / np.linalg.norm(axis), rng.normal(size=3)]
        t = mw._exp(xi)
        np.testing.assert_allclose(t[:3, :3], Rotation.from_rotvec(xi[:3]).as_matrix(),
                                   atol=1e-15)
        np.testing.assert_allclose(mw._log(t), xi, atol=1e-13)


def test_disconnected_sets_are_an_error():
    a = blob(200, 0)
    with pytest.raises(DegenerateInputError, match="sets 2 not connected") as err:
        multiway([a, a + 0.01, a + 100.0], correspondences=False,
                 max_correspondence_distance=0.2)
    assert err.value.field == "max_correspondence_distance"


def test_progress_and_cancellation_without_correspondences():
    sets, _ = views(blob, k=3, n=300, seed=4)
    calls = []
    quiet(sets, correspondences=False,
          progress=lambda done, total, msg="": calls.append((done, total)))
    done = [c[0] for c in calls]
    assert done == sorted(done) and len({c[1] for c in calls}) == 1
    assert 0 < done[-1] <= calls[0][1]

    def cancel(done, total, msg=""):  # noqa: ANN001, ANN202
        raise Cancelled("stop")

    with pytest.raises(Cancelled):
        multiway(sets, correspondences=False, progress=cancel)


# --- errors -------------------------------------------------------------------------------

SQ = [[0, 0], [1, 0], [0, 1], [1, 1]]
CUBE = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 0], [1, 0, 1], [0, 1, 1]]


@pytest.mark.parametrize("kw, field, fragment", [
    ({"sets": [SQ]}, "sets", "at least 2 point sets, got 1"),
    ({"sets": "abc"}, "sets", "list of (n, d) point arrays"),
    ({"sets": [SQ, SQ, SQ[:3]]}, "sets[2]", "as many points as `sets[0]` (4"),
    ({"sets": [SQ, [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]]}, "sets[1]",
     "dimension of `sets[0]` (2)"),
    ({"sets": [SQ, SQ, [[0, 0], [1, float("nan")], [0, 1], [1, 1]]]}, "sets[2]",
     "nan at row 1"),
    ({"sets": [SQ, SQ, [[1, 1]] * 4, SQ], "model": "similarity"}, "sets[2]", "coincident"),
    ({"sets": [SQ, SQ], "correspondences": False}, "sets", "3-D"),
    ({"sets": [CUBE, CUBE], "correspondences": False, "model": "similarity"}, "model",
     "rigid"),
    ({"sets": [CUBE, CUBE[:4]], "correspondences": False}, "sets[1]", "at least 6"),
    ({"sets": [SQ, SQ], "model": "affine"}, "model", None),
    ({"sets": [SQ, SQ], "init": np.eye(3)}, "init", "(2, 3, 3)"),
    ({"sets": [SQ, SQ], "init": [np.eye(3), 2 * np.eye(3)]}, "init", "init[1]"),
    ({"sets": [CUBE, CUBE], "correspondences": False, "neighbors": 2}, "neighbors", "<= 1"),
    ({"sets": [CUBE, CUBE], "correspondences": False, "min_fitness": 1.5}, "min_fitness",
     None),
    ({"sets": [CUBE, CUBE], "correspondences": False, "max_correspondence_distance": 0},
     "max_correspondence_distance", None),
    ({"sets": [SQ, SQ], "correspondences": "no"}, "correspondences", None),
])
def test_invalid_inputs_name_the_field(kw, field, fragment):
    sets = kw.pop("sets")
    with pytest.raises(InvalidInputError) as err:
        multiway(sets, **kw)
    assert err.value.field == field
    if fragment:
        assert fragment in str(err.value)


def test_flat_sets_are_degenerate():
    line3 = [[0, 0, 0], [1, 1, 1], [2, 2, 2], [3, 3, 3]]
    with pytest.raises(DegenerateInputError, match="collinear") as err:
        multiway([CUBE[:4], CUBE[:4], line3])
    assert err.value.field == "sets[2]"
    with pytest.raises(DegenerateInputError, match="collinear") as err:
        multiway([CUBE, line3 * 2], correspondences=False)
    assert err.value.field == "sets[1]"
    # collinear in 2-D still fixes the rotation (rank d - 1 = 1): fine
    line2 = np.array([[0.0, 0.0], [1.0, 0.0], [3.0, 0.0]])
    res = multiway([line2, line2 @ np.array([[0.0, -1.0], [1.0, 0.0]]).T])
    np.testing.assert_allclose(res.rotations[1], [[0, 1], [-1, 0]], atol=1e-12)
