"""ICP's nearest-point search keeps the previous partners it can prove unchanged: every
answer must equal a plain query of a kd-tree of the target (scipy's cKDTree: distances bit
for bit; the index its own, and among equally near points the smallest), and the skipping
must really happen. Split over threads (the source in parts), the answers and the whole
result are the same bits."""

from __future__ import annotations

import importlib
import warnings

import numpy as np
import pytest
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation

icp_mod = importlib.import_module("algorithms.registration.icp")


def _blob(n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    u = rng.standard_normal((n, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    r = 1.0 + 0.3 * u[:, 0] + 0.15 * u[:, 1] * u[:, 2] + 0.1 * u[:, 2] ** 3
    return u * r[:, None] * [1.3, 1.0, 0.8]


def _reference(dst: np.ndarray, x: np.ndarray, bound: float) -> tuple[np.ndarray, np.ndarray]:
    """Each row's nearest point of ``dst`` strictly within ``bound`` by cKDTree: the distance
    and its index, the smallest index when several are equally near (their distances
    summed over the coordinates in order, as the tree sums them); inf and ``len(dst)``
    where none is."""
    tree = cKDTree(dst)
    two, which = tree.query(x, k=2, distance_upper_bound=bound)
    d1, idx = two[:, 0], which[:, 0].astype(np.int64)
    for row in np.flatnonzero((d1 == two[:, 1]) & np.isfinite(d1)):
        near = np.array(tree.query_ball_point(x[row], d1[row] * (1 + 1e-9)))
        diff = x[row] - dst[near]
        sq = diff[:, 0] ** 2 + diff[:, 1] ** 2 + diff[:, 2] ** 2
        idx[row] = near[np.sqrt(sq) == d1[row]].min()
    return d1, idx


def _run(monkeypatch, src, dst, **kw):
    """Run ICP, comparing every answer of ``nearest`` with :func:`_reference`; the points
    queried in each call."""
    queried = []
    original = icp_mod._Problem.nearest

    def checked(self, moved, transform):
        dist, idx = original(self, moved, transform)
        bound = np.inf if self.max_dist is None else self.max_dist * (1 + 1e-9)
        ref_d, ref_i = _reference(self.dst, moved, bound)
        np.testing.assert_array_equal(dist, ref_d)
        np.testing.assert_array_equal(idx, ref_i)
        queried.append(self.queried)
        return dist, idx

    monkeypatch.setattr(icp_mod._Problem, "nearest", checked)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        icp_mod.icp(src, dst, **kw)
    return queried


def _queried_fewer(monkeypatch, src, dst, **kw):
    return min(_run(monkeypatch, src, dst, **kw)) < len(src)


ROT = Rotation.from_rotvec([0.05, 0.1, -0.08]).as_matrix()


def _split(monkeypatch, parts: int, spread: bool = False) -> None:
    """Make runs of a few hundred points split over ``parts`` threads (1: no split); with
    ``spread``, into parts of 256 points that the threads take in turn (the split of large
    runs)."""
    monkeypatch.setattr(icp_mod, "PART_MIN", 200)
    monkeypatch.setattr(icp_mod, "usable_cores", lambda: parts)
    if spread:
        monkeypatch.setattr(icp_mod, "SPREAD_FROM", 1000)
        monkeypatch.setattr(icp_mod, "SPREAD_PART", 256)


@pytest.mark.parametrize(("parts", "spread"), [(1, False), (3, False), (3, True)])
@pytest.mark.parametrize("metric", ["point_to_point", "point_to_plane", "symmetric"])
@pytest.mark.parametrize("max_dist", [None, 0.15])
def test_answers_equal_a_plain_query(monkeypatch, metric, max_dist, parts, spread):
    _split(monkeypatch, parts, spread)
    rng = np.random.default_rng(3)
    src = _blob(3000, 1)
    dst = _blob(2500, 2) @ ROT.T + [0.03, -0.02, 0.01] + rng.normal(0, 0.002, (2500, 3))
    queried = _run(monkeypatch, src, dst, metric=metric, max_correspondence_distance=max_dist,
                   max_iterations=25, tolerance=0.0)
    assert len(queried) >= 2 and queried[0] == len(src)   # the first call queries them all


def test_partial_overlap_and_far_coordinates(monkeypatch):
    # half the source has no partner within the bound; coordinates far from the origin
    rng = np.random.default_rng(4)
    src = _blob(2000, 3) + 1e5
    dst = (_blob(2000, 4) @ ROT.T)[:1000] + 1e5 + rng.normal(0, 0.001, (1000, 3))
    _run(monkeypatch, src, dst, metric="point_to_plane", max_correspondence_distance=0.1,
         max_iterations=20, tolerance=0.0)


@pytest.mark.parametrize("parts", [1, 2])
def test_ties_on_a_lattice_go_to_the_smallest_index(monkeypatch, parts):
    _split(monkeypatch, parts)
    # a grid against the same grid shifted by half a cell along x: every source point is
    # equidistant from two target points
    g = np.arange(12, dtype=float)
    x, y, z = np.meshgrid(g, g, g[:6], indexing="ij")
    dst = np.column_stack([x.ravel(), y.ravel(), z.ravel()])
    src = dst + [0.5, 0.0, 0.0]
    _run(monkeypatch, src, dst, max_iterations=5, tolerance=0.0)


def test_partners_are_kept_once_the_steps_are_small(monkeypatch):
    rng = np.random.default_rng(5)
    src = _blob(3000, 1)
    dst = _blob(3000, 2) @ ROT.T + rng.normal(0, 0.002, (3000, 3))
    assert _queried_fewer(monkeypatch, src, dst, metric="point_to_plane", max_iterations=30,
                          tolerance=0.0)


@pytest.mark.parametrize("kw", [
    {"max_correspondence_distance": 0.15},
    {"metric": "point_to_plane"},
    {"metric": "symmetric", "max_correspondence_distance": 0.1},
    {"overlap": 0.8, "kernel": "huber", "init": "pca"},
])
def test_the_result_does_not_depend_on_the_threads(monkeypatch, kw):
    rng = np.random.default_rng(6)
    src = _blob(3000, 7)
    dst = _blob(2800, 8) @ ROT.T + [0.02, 0.0, -0.03] + rng.normal(0, 0.002, (2800, 3))
    results = []
    # threads, spread, then the parts expected: one per thread, or from SPREAD_FROM points
    # at least PARTS_PER_THREAD per thread and parts of at most about SPREAD_PART points
    for parts, spread, expected in ((1, False, 1), (2, False, 2), (5, False, 5),
                                    (2, True, 11), (3, True, 12)):
        _split(monkeypatch, parts, spread)
        threads = []
        original = icp_mod._Problem.threads

        def spy(self, _original=original, _threads=threads):
            _threads.append((self.threads_used, len(self.parts) - 1))
            return _original(self)

        monkeypatch.setattr(icp_mod._Problem, "threads", spy)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = icp_mod.icp(src, dst, max_iterations=20, tolerance=0.0, **kw)
        assert threads == [(parts, expected)]  # the split really happened
        results.append(res)
    for other in results[1:]:
        np.testing.assert_array_equal(other.transform, results[0].transform)
        np.testing.assert_array_equal(other.rmse_history, results[0].rmse_history)
        assert other.fitness == results[0].fitness
