"""Cases ported from Open3D's own registration tests, each naming the original. Open3D is
not a test dependency, so only cases whose expected values do not need Open3D itself are
ported: values the tests state (``TransformationEstimation.cpp``, ``SymmetricICP.cpp``), the
bounds of a recovery test on generated data (``test_normal_distributions_transform.py``),
and the tests' small point clouds run through Open3D's ICP loop re-derived by hand below
(``test_registration.py``: ``RegistrationICP`` in ``Registration.cpp``, Umeyama for
point-to-point, the ``[p × n, n]`` Gauss-Newton step about the origin for point-to-plane).

Not ported: every value that needs Open3D's downloaded demo clouds or bunny
(``ComputeFPFHFeature``, ``ICPColored``, ``ICPDoppler``,
``GetInformationMatrixFromPointCloud``; ``CorrespondencesFromFeatures`` is ported on
pyvista's airplane against a brute-force search instead of the legacy pipeline); the
point-to-plane ``ComputeRMSE``/``ComputeTransformation`` on given correspondences (our
``icp`` finds its own correspondences and normalises the normals, and Open3D's tensor RMSE
there sums the squared *components* of ``(p - q) * n``, not the squared dot products); the
Cauchy, GM and generalized robust kernels (ours: Huber and Tukey, whose weights are
ported).

Differences asserted as our documented behaviour: ``init`` must be a rigid transform for
``model="rigid"`` (Open3D's test matrix has singular values 0.9994 to 1.0005, so the
source is moved by it first, which is what Open3D's ``pcd.Transform(init)`` does);
point-to-plane steps linearise about the moved source's centroid, not the origin (``icp``
Notes)."""

from __future__ import annotations

import math
from typing import Literal, cast

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal
from scipy.spatial import cKDTree
from scipy.spatial.distance import cdist
from scipy.spatial.transform import Rotation

from algorithms.alignment import rigid
from algorithms.core.errors import ConvergenceWarning, InvalidInputError
from algorithms.registration import fpfh, icp, match_features
from tests.algorithms.registration._real_meshes import surface_points

# --- Open3D: python/test/t/registration/test_registration.py::get_pcds ---------------------

PCD_SOURCE = np.array([
    [1.0, 0.5, 2.0], [0.5, 0.5, 2.0], [0.5, 0.5, 2.5], [3.0, 1.0, 1.5], [3.5, 1.0, 1.0],
    [0.5, 1.0, 2.0], [1.5, 1.0, 1.5], [2.0, 1.0, 1.5], [1.0, 1.0, 2.0], [2.5, 1.0, 1.5],
    [3.0, 1.0, 1.0], [0.5, 1.0, 2.5], [1.0, 1.0, 1.0], [1.5, 1.0, 1.0], [1.0, 1.5, 1.0],
    [3.0, 1.5, 1.0], [3.5, 1.5, 1.0], [3.0, 1.5, 1.5], [0.5, 1.5, 1.5], [0.5, 1.5, 2.0],
    [1.0, 1.5, 2.0], [2.5, 1.5, 1.5], [1.5, 1.5, 1.0], [1.5, 1.5, 1.5], [2.0, 1.5, 1.5],
    [3.0, 1.5, 0.5], [2.5, 1.5, 1.0], [2.0, 1.5, 1.0], [3.0, 2.0, 0.5], [0.5, 2.0, 1.5],
    [3.0, 2.0, 1.0], [1.0, 2.0, 1.0], [2.0, 1.5, 0.5], [0.5, 2.0, 2.0], [2.5, 2.0, 1.0],
    [2.5, 2.0, 0.5], [2.0, 2.0, 0.5], [2.5, 1.5, 0.5], [3.0, 2.0, 1.5], [2.0, 2.0, 1.0],
    [1.0, 2.0, 2.0], [1.5, 2.0, 1.0], [1.5, 2.0, 1.5], [2.5, 2.0, 1.5], [2.0, 2.0, 1.5],
    [1.0, 2.0, 0.5], [0.5, 2.0, 1.0], [1.5, 2.0, 0.5], [1.0, 2.0, 1.5]])
PCD_TARGET = np.array([
    [1.5, 1.0, 1.5], [2.5, 1.0, 1.5], [1.5, 1.0, 1.0], [1.0, 1.0, 1.0], [2.0, 1.0, 1.5],
    [3.0, 1.0, 1.5], [1.0, 1.0, 0.5], [1.0, 1.5, 1.0], [1.0, 1.5, 0.5], [1.0, 1.0, 1.5],
    [3.0, 1.0, 2.0], [3.0, 1.5, 2.0], [3.0, 1.5, 1.5], [1.0, 1.5, 1.5], [1.5, 1.5, 1.5],
    [2.5, 1.5, 1.5], [2.0, 1.5, 1.5], [1.5, 1.5, 1.0], [2.5, 1.5, 2.0], [1.0, 2.0, 1.0],
    [1.0, 2.0, 0.5], [2.5, 1.5, 1.0], [3.0, 2.0, 1.5], [2.5, 2.0, 1.0], [2.5, 2.0, 1.5],
    [1.5, 2.0, 1.0], [2.0, 1.5, 1.0], [1.0, 2.0, 1.5], [2.0, 2.0, 1.0], [1.5, 2.0, 1.5],
    [1.5, 2.0, 0.5], [2.0, 2.0, 1.5], [2.0, 2.0, 0.5], [1.5, 2.5, 1.0], [1.0, 2.5, 1.0],
    [3.0, 2.0, 1.0], [2.0, 2.5, 1.0], [2.5, 2.5, 1.0]])
PCD_TARGET_NORMALS = np.array([
    [0.15597, -0.0463812, -0.986672], [-0.213545, 0.887963, 0.407334],
    [0.423193, -0.121977, -0.897792], [0.202251, 0.27611, -0.939605],
    [0.275452, 0.207216, -0.938716], [0.326146, 0.0385317, -0.944534],
    [0.983129, -0.174668, -0.0543011], [0.898665, -0.0602029, 0.434485],
    [0.711325, 0.193223, -0.675783], [0.346158, 0.198724, -0.916888],
    [0.302085, 0.28938, -0.908297], [0.341044, 0.414138, -0.843907],
    [0.212191, 0.213068, -0.953717], [0.239759, 0.313187, -0.918929],
    [0.302290, 0.27265, -0.913391], [0.209796, 0.402747, -0.890944],
    [0.267025, 0.218226, -0.938656], [0.00126928, -0.976587, -0.21512],
    [0.321912, 0.194736, -0.926526], [0.831227, 0.236675, -0.503037],
    [0.987006, -0.155324, 0.0411639], [0.103384, -0.808796, -0.57893],
    [0.181245, 0.66226, -0.727023], [0.235471, 0.525053, -0.817846],
    [0.231954, 0.446165, -0.864369], [-0.261931, -0.725542, -0.636381],
    [0.120953, -0.864985, -0.487003], [0.858345, -0.227847, 0.459706],
    [-0.416259, -0.367408, -0.831709], [-0.476652, 0.206048, -0.854604],
    [-0.211959, -0.523378, -0.825317], [-0.964914, 0.0541031, -0.256931],
    [-0.0653566, -0.913961, -0.400504], [-0.846868, -0.170805, -0.503628],
    [0.0366971, 0.515834, -0.855902], [-0.0714554, -0.855019, -0.513651],
    [-0.0217377, -0.957744, -0.286799], [-0.0345231, -0.947096, -0.319088]])
#: The tests' initial transform (singular values 0.99938, 1.00028, 1.00047: not a rotation).
INIT = np.array([[0.862, 0.011, -0.507, 0.5], [-0.139, 0.967, -0.215, 0.7],
                 [0.487, 0.255, 0.835, -1.4], [0.0, 0.0, 0.0, 1.0]])
MAX_DIST = 3.0


def _evaluate(tree: cKDTree, moved: np.ndarray, max_dist: float
              ) -> tuple[np.ndarray, np.ndarray, float, float]:
    # Open3D: GetRegistrationResultAndCorrespondences (nearest target within max_dist)
    dist, idx = cast(tuple[np.ndarray, np.ndarray],
                     tree.query(moved, distance_upper_bound=max_dist))
    ok = np.flatnonzero(dist <= max_dist)
    rmse = math.sqrt(float(np.mean(dist[ok] ** 2))) if ok.size else 0.0
    return ok, idx[ok], ok.size / len(moved), rmse


def _open3d_icp(source: np.ndarray, target: np.ndarray, max_dist: float, iterations: int,
                normals: np.ndarray | None = None) -> tuple[np.ndarray, float, float]:
    """Open3D's legacy ``RegistrationICP`` from the identity: match, estimate the update
    (Umeyama without scale; or point-to-plane: solve ``JᵀJ x = -Jᵀr`` with rows
    ``[p × n, n]`` and residuals ``(p - q)·n``, then ``R = Rz(x2) Ry(x1) Rx(x0)``), apply
    it, re-match; stop when fitness and RMSE both change by less than 1e-6."""
    tree = cKDTree(target)
    pcd, transform = source.copy(), np.eye(4)
    i, j, fitness, rmse = _evaluate(tree, pcd, max_dist)
    for _ in range(iterations):
        p, q = pcd[i], target[j]
        update = np.eye(4)
        if normals is None:
            pm, qm = p.mean(axis=0), q.mean(axis=0)
            u, _, vt = np.linalg.svd((q - qm).T @ (p - pm))
            r = u @ np.diag([1.0, 1.0, np.sign(np.linalg.det(u @ vt))]) @ vt
            update[:3, :3], update[:3, 3] = r, qm - r @ pm
        else:
            n = normals[j]
            jac = np.hstack([np.cross(p, n), n])
            x = np.linalg.solve(jac.T @ jac, -jac.T @ np.einsum("ij,ij->i", p - q, n))
            update[:3, :3] = (Rotation.from_rotvec([0, 0, x[2]])
                              * Rotation.from_rotvec([0, x[1], 0])
                              * Rotation.from_rotvec([x[0], 0, 0])).as_matrix()
            update[:3, 3] = x[3:]
        transform = update @ transform
        pcd = pcd @ update[:3, :3].T + update[:3, 3]
        before = (fitness, rmse)
        i, j, fitness, rmse = _evaluate(tree, pcd, max_dist)
        if abs(before[0] - fitness) < 1e-6 and abs(before[1] - rmse) < 1e-6:
            break
    return transform, fitness, rmse


def _premoved() -> np.ndarray:
    return PCD_SOURCE @ INIT[:3, :3].T + INIT[:3, 3]


# Open3D: python/test/t/registration/test_registration.py::test_icp_point_to_point
# (max_correspondence_distance 3.0, the tests' initial transform, max_iteration = 2)
def test_icp_point_to_point() -> None:
    ref_transform, ref_fitness, ref_rmse = _open3d_icp(_premoved(), PCD_TARGET, MAX_DIST, 2)
    with pytest.warns(ConvergenceWarning, match="max_iterations = 2"):
        res = icp(_premoved(), PCD_TARGET, max_correspondence_distance=MAX_DIST,
                  max_iterations=2, tolerance=0)
    assert res.iterations == 2
    assert res.fitness == ref_fitness == 1.0
    assert_allclose(res.rmse, ref_rmse, rtol=1e-12)
    assert_allclose(res.transform, ref_transform, atol=1e-12)


# Open3D: python/test/t/registration/test_registration.py::test_icp_point_to_plane (the
# tests' target normals). Ours linearises about the moved source's centroid, Open3D about
# the origin (icp Notes): after 2 iterations the fitness is the same and our RMSE is within
# 0.2 % of Open3D's, here lower.
def test_icp_point_to_plane() -> None:
    _, ref_fitness, ref_rmse = _open3d_icp(_premoved(), PCD_TARGET, MAX_DIST, 2,
                                           normals=PCD_TARGET_NORMALS)
    with pytest.warns(ConvergenceWarning, match="max_iterations = 2"):
        res = icp(_premoved(), PCD_TARGET, metric="point_to_plane",
                  target_normals=PCD_TARGET_NORMALS, max_correspondence_distance=MAX_DIST,
                  max_iterations=2, tolerance=0)
    assert res.iterations == 2
    assert res.fitness == ref_fitness == 1.0
    assert res.rmse <= ref_rmse
    assert res.rmse == pytest.approx(ref_rmse, rel=2e-3)


# The figures the icp Notes state for Open3D's test clouds: RMSE relative to Open3D's after
# 1, 2 and 5 point-to-plane iterations (the loop above equals Open3D 0.20's registration_icp
# on these clouds to 4e-15 in the transform, measured when the Notes were written)
@pytest.mark.filterwarnings("ignore::algorithms.core.errors.ConvergenceWarning")
@pytest.mark.parametrize(("iterations", "relative"), [(1, -0.0094), (2, -0.0015), (5, -0.0055)])
def test_icp_point_to_plane_figures_of_the_notes(iterations: int, relative: float) -> None:
    _, _, ref_rmse = _open3d_icp(_premoved(), PCD_TARGET, MAX_DIST, iterations,
                                 normals=PCD_TARGET_NORMALS)
    res = icp(_premoved(), PCD_TARGET, metric="point_to_plane",
              target_normals=PCD_TARGET_NORMALS, max_correspondence_distance=MAX_DIST,
              max_iterations=iterations, tolerance=0)
    assert res.rmse / ref_rmse - 1 == pytest.approx(relative, abs=5e-5)


# Open3D's SearchHybrid keeps pairs strictly closer than max_correspondence_distance; ours
# keeps a pair at exactly the bound (icp Notes, "The distance bound"): a documented
# difference, asserted as our behaviour. Four points each exactly 0.5 from their partner
# (0.5 is exact in binary), bound 0.5: Open3D 0.20 pairs none (fitness 0, identity kept),
# ours pairs all four and finds the translation in one step.
def test_pair_at_exactly_the_bound_is_kept() -> None:
    source = np.array([[0, 0, 0], [10, 0, 0], [0, 10, 0], [0, 0, 10]], float)
    target = source + [0.5, 0.0, 0.0]
    _, _, fitness, _ = _evaluate(cKDTree(target), source, 0.5)   # Open3D's rule
    assert fitness == 0.0
    res = icp(source, target, max_correspondence_distance=0.5)
    assert res.fitness == 1.0 and res.converged
    assert_allclose(res.translation, [0.5, 0.0, 0.0], atol=1e-12)


# Open3D: the same tests pass INIT as ``init``: Open3D applies any 4×4 matrix; ours checks
# that a rigid model's init is a rotation and a translation (documented under ``init``).
def test_icp_rejects_a_non_rigid_init() -> None:
    with pytest.raises(InvalidInputError, match=r"linear part of `init` to be a rotation") as e:
        icp(PCD_SOURCE, PCD_TARGET, init=INIT, max_correspondence_distance=MAX_DIST)
    assert e.value.field == "init"


# Open3D: python/test/t/registration/test_registration.py::test_evaluate_registration and
# ::test_icp_point_to_point: ``fitness`` counts source points with a target point within the
# distance, ``inlier_rmse`` the RMS distance of those, after the final transform
@pytest.mark.filterwarnings("ignore::algorithms.core.errors.ConvergenceWarning")
@pytest.mark.parametrize("max_dist", [0.3, 0.5, 3.0])
def test_fitness_and_inlier_rmse(max_dist: float) -> None:
    res = icp(_premoved(), PCD_TARGET, max_correspondence_distance=max_dist,
              max_iterations=5, tolerance=0)
    moved = _premoved() @ res.linear.T + res.translation
    _, _, fitness, rmse = _evaluate(cKDTree(PCD_TARGET), moved, max_dist)
    assert res.fitness == fitness
    assert_allclose(res.rmse, rmse, rtol=1e-12)


# --- Open3D: cpp/tests/t/pipelines/registration/TransformationEstimation.cpp and
# python/test/t/registration/test_transformation_estimation.py::get_pcds_and_correspondences

TE_SOURCE = np.array([
    [1.15495, 2.40671, 1.15061], [1.81481, 2.06281, 1.71927], [0.888322, 2.05068, 2.04879],
    [3.78842, 1.70788, 1.30246], [1.8437, 2.22894, 0.986237], [2.95706, 2.20180, 0.987878],
    [1.72644, 1.24356, 1.93486], [0.922024, 1.14872, 2.34317], [3.70293, 1.85134, 1.15357],
    [3.06505, 1.30386, 1.55279], [0.634826, 1.04995, 2.47046], [1.40107, 1.37469, 1.09687],
    [2.93002, 1.96242, 1.48532], [3.74384, 1.30258, 1.30244]])
TE_TARGET = np.array([
    [2.41766, 2.05397, 1.74994], [1.37848, 2.19793, 1.66553], [2.24325, 2.27183, 1.33708],
    [3.09898, 1.98482, 1.77401], [1.81615, 1.48337, 1.49697], [3.01758, 2.20312, 1.51502],
    [2.38836, 1.39096, 1.74914], [1.30911, 1.4252, 1.37429], [3.16847, 1.39194, 1.90959],
    [1.59412, 1.53304, 1.58040], [1.34342, 2.19027, 1.30075]])
TE_CORRES = np.array([10, 1, 1, 3, 2, 5, 9, 7, 5, 8, 7, 7, 5, 8])


# Open3D: TransformationEstimation.cpp ComputeRMSEPointToPoint (0.706437, the pairs as
# given) and ComputeTransformationPointToPoint (0.578255 after the fitted transform);
# test_transformation_estimation.py::test_compute_rmse_point_to_point and
# ::test_compute_transformation_point_to_point
def test_compute_transformation_point_to_point() -> None:
    target = TE_TARGET[TE_CORRES]
    before = math.sqrt(float(np.mean(np.sum((TE_SOURCE - target) ** 2, axis=1))))
    assert before == pytest.approx(0.706437, abs=1e-4)          # the input as transcribed
    res = rigid(TE_SOURCE, target)
    assert res.rmse == pytest.approx(0.578255, abs=1e-4)
    moved = TE_SOURCE @ res.rotation.T + res.translation
    after = math.sqrt(float(np.mean(np.sum((moved - target) ** 2, axis=1))))
    assert after == pytest.approx(0.578255, abs=1e-4)


# --- Open3D: cpp/tests/pipelines/registration/SymmetricICP.cpp and
# cpp/tests/t/pipelines/registration/TransformationEstimation.cpp (ComputeTransformationSymmetric)

SYM_POINTS = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 0], [1, 0, 1]], float)
SYM_NORMALS = np.array([[1, 2, 3], [2, -1, 1], [-1, 3, 2], [3, 1, -2], [-2, -1, 3], [1, -3, 2]],
                       float)
SYM_NORMALS /= np.linalg.norm(SYM_NORMALS, axis=1, keepdims=True)


def _sym_expected() -> np.ndarray:
    t = np.eye(4)
    t[:3, :3] = Rotation.from_rotvec(0.3 * np.array([1.0, 2.0, -1.0]) / math.sqrt(6)).as_matrix()
    t[:3, 3] = [0.2, -0.1, 0.15]
    return t


def _sym_target(flip: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    t = _sym_expected()
    return SYM_POINTS @ t[:3, :3].T + t[:3, 3], (SYM_NORMALS @ t[:3, :3].T) * flip[:, None]


FLIPS = {"as_given": np.ones(6), "every_other_flipped": np.array([-1, 1, -1, 1, -1, 1.0])}


# Open3D: SymmetricICP.cpp::ComputeTransformationRecoversFullRankRigidMotion (and its flipped
# normals); t/.../TransformationEstimation.cpp::ComputeTransformationSymmetric (alternating
# signs). Our icp pairs the points itself (here: row i with row i) and reaches the motion to
# rounding: the fit is exact, so it stops there.
@pytest.mark.parametrize("flip", FLIPS.values(), ids=FLIPS.keys())
def test_symmetric_recovers_rigid_motion(flip: np.ndarray) -> None:
    target, normals = _sym_target(flip)
    assert_array_equal(cKDTree(target).query(SYM_POINTS)[1], np.arange(6))
    res = icp(SYM_POINTS, target, metric="symmetric", source_normals=SYM_NORMALS,
              target_normals=normals, max_iterations=30)
    assert res.converged
    assert_allclose(res.transform, _sym_expected(), atol=1e-10)


# The same cases, one estimation: Open3D's single ComputeTransformation is exact to 1e-10
# because it centres source and target each at their own centroid; ours does too.
@pytest.mark.parametrize("flip", FLIPS.values(), ids=FLIPS.keys())
def test_symmetric_one_estimation_is_exact(flip: np.ndarray) -> None:
    target, normals = _sym_target(flip)
    res = icp(SYM_POINTS, target, metric="symmetric", source_normals=SYM_NORMALS,
              target_normals=normals, max_iterations=1)
    assert_allclose(res.transform, _sym_expected(), atol=1e-10)
    assert res.iterations == 1 and res.rmse < 1e-10


# Open3D: SymmetricICP.cpp::InputContracts and t/.../ComputeTransformationSymmetric (no
# correspondences: the identity). Ours: no pair within the distance leaves the initial
# transform, with fitness 0, converged False and a ConvergenceWarning.
def test_symmetric_without_correspondences_is_identity() -> None:
    target, normals = _sym_target(FLIPS["as_given"])
    with pytest.warns(ConvergenceWarning, match="do not overlap"):
        res = icp(SYM_POINTS, target + 10.0, metric="symmetric", source_normals=SYM_NORMALS,
                  target_normals=normals, max_correspondence_distance=0.01)
    assert_array_equal(res.transform, np.eye(4))
    assert res.fitness == 0.0 and res.rmse == 0.0 and not res.converged


# Open3D: SymmetricICP.cpp::InputContracts (malformed normals throw). Ours: a typed error
# naming the field. (Missing normals differ by design: Open3D throws, ours estimates them.)
@pytest.mark.parametrize("which", ["source_normals", "target_normals"])
def test_symmetric_malformed_normals(which: str) -> None:
    target, normals = _sym_target(FLIPS["as_given"])
    src_n, tgt_n = SYM_NORMALS, normals
    if which == "source_normals":
        src_n = src_n[:, :2]
    else:
        tgt_n = tgt_n[:, :2]
    with pytest.raises(InvalidInputError, match=which) as e:
        icp(SYM_POINTS, target, metric="symmetric", source_normals=src_n, target_normals=tgt_n)
    assert e.value.field == which


# --- Open3D: cpp/tests/t/pipelines/registration/Registration.cpp::RobustKernel ----------
# The weight at residual 0.98 with scale 1: Huber scale / max(|r|, scale) = 1.0, Tukey
# (1 - min(1, |r| / scale)²)² = 0.00156816 (the kernels ours shares). Observed through one
# point-to-point iteration: every pair exact but one, 0.98 off, so the fit is the weighted
# Kabsch solution with that pair weighted by the kernel.


def _weighted_kabsch(x: np.ndarray, y: np.ndarray, w: np.ndarray) -> np.ndarray:
    xm, ym = w @ x / w.sum(), w @ y / w.sum()
    u, _, vt = np.linalg.svd(((y - ym) * w[:, None]).T @ (x - xm))
    r = u @ np.diag([1.0, 1.0, np.sign(np.linalg.det(u @ vt))]) @ vt
    t = np.eye(4)
    t[:3, :3], t[:3, 3] = r, ym - r @ xm
    return t


@pytest.mark.parametrize(("kernel", "weight"), [("huber", 1.0), ("tukey", 0.00156816)])
def test_robust_kernel_weight(kernel: str, weight: float) -> None:
    grid = np.stack(np.meshgrid(*[np.arange(3.0)] * 3, indexing="ij"), -1).reshape(-1, 3)
    source = 10.0 * grid
    target = source.copy()
    target[5] += 0.98 * np.array([0.6, 0.0, 0.8])             # one pair 0.98 apart
    w = np.ones(len(source))
    w[5] = weight
    with pytest.warns(ConvergenceWarning):
        res = icp(source, target, kernel=cast(Literal["huber", "tukey"], kernel),
                  kernel_scale=1.0, max_iterations=1, tolerance=0)
    assert_allclose(res.transform, _weighted_kabsch(source, target, w), atol=1e-9)
    # and the weight matters: the fit with that pair weighted 0.5 instead differs
    other = w.copy()
    other[5] = 0.5
    assert np.abs(_weighted_kabsch(source, target, other) - res.transform).max() > 1e-6


# --- Open3D: python/test/pipelines/test_normal_distributions_transform.py ----------------


def _structured_cloud() -> np.ndarray:
    # Open3D: test_normal_distributions_transform.py::make_structured_point_cloud
    centres = np.array([[-1.2, -0.8, -0.4], [-0.2, 0.7, 0.3], [0.9, -0.1, 0.8],
                        [1.5, 1.0, -0.2], [-1.5, 1.1, 0.9]])
    points = []
    for cluster, centre in enumerate(centres):
        c, s = math.cos(0.35 * cluster), math.sin(0.35 * cluster)
        rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        for i in range(160):
            a = ((i % 16) - 7.5) / 7.5
            b = (((i // 16) % 10) - 4.5) / 4.5
            h = math.sin(0.37 * i + cluster)
            offset = np.array([0.20 * a + 0.04 * b, 0.13 * b + 0.03 * h,
                               0.08 * h + 0.025 * a * b])
            points.append(centre + rot @ offset)
    return np.asarray(points)


def _ndt_transform() -> np.ndarray:
    # Open3D: test_normal_distributions_transform.py::make_transformation
    t = np.eye(4)
    c, s = math.cos(0.08), math.sin(0.08)
    t[:3, :3] = [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
    t[:3, 3] = [0.24, -0.17, 0.11]
    return t


# Open3D: test_normal_distributions_transform.py::test_registration_ndt_recovers_known_transform
# (we have no NDT: the same data, distance 0.35 and acceptance bounds, with each ICP metric)
@pytest.mark.parametrize("metric", ["point_to_point", "point_to_plane", "symmetric"])
def test_recovers_known_transform(
        metric: Literal["point_to_point", "point_to_plane", "symmetric"]) -> None:
    source = _structured_cloud()
    expected = _ndt_transform()
    target = source @ expected[:3, :3].T + expected[:3, 3]
    tree = cKDTree(target)
    _, _, fit0, rmse0 = _evaluate(tree, source, 0.35)
    res = icp(source, target, metric=metric, max_correspondence_distance=0.35,
              max_iterations=40)
    moved = source @ res.linear.T + res.translation
    _, _, fit1, rmse1 = _evaluate(tree, moved, 0.35)
    assert fit1 > fit0 and rmse1 < rmse0
    assert res.fitness > 0.80
    assert res.rmse < 0.16
    assert_allclose(res.transform, expected, atol=5e-2)
    # inlier_rmse is the RMS distance of the correspondences after the final transform
    assert res.fitness == fit1
    assert_allclose(res.rmse, rmse1, rtol=1e-12)


# --- Open3D: cpp/tests/t/pipelines/registration/Feature.cpp::CorrespondencesFromFeatures ---
# (there on the demo clouds, against the legacy pipeline: valid ratio 1.0 with and without
# the mutual filter; here on points of pyvista's airplane, against a brute-force search)
@pytest.mark.parametrize("mutual", [True, False])
def test_correspondences_from_features(mutual: bool) -> None:
    a = surface_points("airplane.ply", 600, seed=1)
    b = surface_points("airplane.ply", 600, seed=2)
    fa, fb = fpfh(a, radius=0.08), fpfh(b, radius=0.08)
    src, tgt = match_features(fa, fb, mutual=mutual)
    d = cdist(fa, fb)
    forward, backward = d.argmin(axis=1), d.argmin(axis=0)
    rows = np.arange(len(a))
    if mutual:
        rows = rows[backward[forward] == rows]
    assert_array_equal(src, rows)
    assert_array_equal(tgt, forward[rows])
