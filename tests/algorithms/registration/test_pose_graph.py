"""Tests for registration.pose_graph (pairwise ICP and pose-graph optimisation on SE(3)):
noisy partial views of generated shapes, exact copies, a start and a chain of neighbours,
the line process on a graph with a wrong loop closure, progress, and its errors."""

from __future__ import annotations

import importlib
import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from algorithms.core import (
    Cancelled,
    ConvergenceWarning,
    DegenerateInputError,
    InvalidInputError,
    se3,
)
from algorithms.registration import MultiwayResult, pose_graph
from tests.algorithms.registration._real_meshes import surface_points
from tests.algorithms.registration._shapes import angle_deg, bent_bar, blob, random_rotation
from tests.algorithms.registration._views import apply, homogeneous, views

# the module (the package attribute of the same name is the function)
pg = importlib.import_module("algorithms.registration.pose_graph")


def quiet(*args, **kw) -> MultiwayResult:  # noqa: ANN002, ANN003
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        return pose_graph(*args, **kw)


@pytest.mark.parametrize("shape, seed", [(bent_bar, 0), (blob, 1)])
def test_five_noisy_views_without_correspondences_within_a_degree(shape, seed):
    sets, poses = views(shape, seed=seed, n=1200)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConvergenceWarning)
        res = pose_graph(sets)
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
    res = pose_graph(sets)
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
    res = pose_graph(moved, init=rough, neighbors=1)
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
    info = pg._information(pts)
    edges = []
    for i, j in pg._pairs(5, None):
        z = np.linalg.inv(poses[j]) @ poses[i]
        if (i, j) == (0, 3):
            z = homogeneous(Rotation.from_rotvec([0, 0, np.radians(20.0)]).as_matrix(),
                            [0.3, 0, 0]) @ z
        edges.append(pg._Edge(i, j, z, info, 1.0, 200, odometry=False))
    mu = 0.05 ** 2 * 200
    opts = pg._GraphOptions(0.05, "point_to_plane", None, 0.3, 0.25, 1.0, 30, 100, 1e-12)
    start = poses.copy()
    for i in range(1, 5):
        start[i] = se3.exp(rng.normal(size=6) * 0.02) @ poses[i]
    out, _, converged, _ = pg._levenberg_marquardt(start, edges, mu, opts,
                                                   lambda *a: None, 0, 1)
    assert converged
    weights = {(e.i, e.j): pg._confidence(pg._residual(out, e), e.info, mu) for e in edges}
    assert weights[0, 3] < 0.25 and min(w for k, w in weights.items() if k != (0, 3)) > 0.9
    np.testing.assert_allclose(out, poses, atol=1e-3)


def test_disconnected_sets_are_an_error():
    a = blob(200, 0)
    with pytest.raises(DegenerateInputError, match="sets 2 not connected") as err:
        pose_graph([a, a + 0.01, a + 100.0],
                 max_correspondence_distance=0.2)
    assert err.value.field == "max_correspondence_distance"


def test_progress_and_cancellation_without_correspondences():
    sets, _ = views(blob, k=3, n=300, seed=4)
    calls = []
    quiet(sets,
          progress=lambda done, total, msg="": calls.append((done, total)))
    done = [c[0] for c in calls]
    assert done == sorted(done) and len({c[1] for c in calls}) == 1
    assert 0 < done[-1] <= calls[0][1]

    def cancel(done, total, msg=""):  # noqa: ANN001, ANN202
        raise Cancelled("stop")

    with pytest.raises(Cancelled):
        pose_graph(sets, progress=cancel)




def test_neighbors_may_be_every_other_set():
    # neighbors = k - 1 registers every pair, as the default does, but as odometry in order.
    sets, _ = views(blob, k=3, n=300, seed=4)
    res = quiet(sets, neighbors=2)
    assert res.edges.tolist() == [[0, 1], [0, 2], [1, 2]]


# --- errors -------------------------------------------------------------------------------

CUBE = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 0], [1, 0, 1], [0, 1, 1]]


@pytest.mark.parametrize("kw, field, fragment", [
    ({"sets": [[[0, 0], [1, 0], [0, 1]]] * 2}, "sets", "3-D"),
    ({"sets": [CUBE, CUBE[:5]]}, "sets[1]", "at least 6 points (pairwise symmetric ICP)"),
    ({"sets": [CUBE, CUBE[:2]], "metric": "point_to_point"}, "sets[1]", "at least 3"),
    ({"sets": [CUBE] * 3, "neighbors": 3}, "neighbors",
     "an integer >= 1 and <= 2 (the number of other sets), got 3"),
    ({"sets": [CUBE] * 2, "init": np.eye(4)}, "init", "(2, 4, 4)"),
    ({"sets": [CUBE] * 2, "init": [np.eye(4), np.diag([2.0, 2, 2, 1])]}, "init",
     "init[1]: Expected the linear part of `init` to be a rotation"),
    ({"sets": [CUBE] * 2, "min_fitness": -0.1}, "min_fitness", ">= 0"),
    ({"sets": [CUBE] * 2, "edge_prune_threshold": 1.0}, "edge_prune_threshold", "< 1"),
    ({"sets": [CUBE] * 2, "preference_loop_closure": 0.0}, "preference_loop_closure",
     "> 0"),
    ({"sets": [CUBE] * 2, "icp_max_iterations": 0}, "icp_max_iterations", ">= 1"),
    ({"sets": [CUBE] * 2, "metric": "plane"}, "metric", "one of 'symmetric'"),
])
def test_invalid_inputs_name_the_field(kw, field, fragment):
    sets = kw.pop("sets")
    with pytest.raises(InvalidInputError) as err:
        pose_graph(sets, **kw)
    assert err.value.field == field
    assert fragment in str(err.value), str(err.value)


def test_coincident_sets_give_no_default_distance():
    # every point repeated: the median spacing is 0, so no default bound exists
    pts = np.repeat(np.asarray(CUBE, float), 2, axis=0)
    with pytest.raises(DegenerateInputError, match="median spacing of 0") as err:
        pose_graph([pts, pts])
    assert err.value.field == "max_correspondence_distance"


# --- real meshes (pyvista's PLY files) ------------------------------------------------------


def test_three_views_of_the_airplane_are_put_together() -> None:
    points = surface_points("airplane.ply", 3000, 2)
    rng = np.random.default_rng(2)
    truths = [Rotation.identity()] + [Rotation.from_rotvec(np.radians(8) * rng.normal(size=3))
                                     for _ in range(2)]
    parts = [truths[i].apply(points[i * 300:i * 300 + 2400]) + 0.02 * rng.normal(size=3)
             for i in range(3)]
    res = pose_graph(parts)
    for i in range(1, 3):
        # transforms[i] maps view i into view 0's frame: the inverse of its turn
        assert angle_deg(res.rotations[i], truths[i].inv().as_matrix()) < 1.0
