"""Bijective parameterization (symmetric Dirichlet + boundary barrier, SLIM steps): hand
cases of its energy and step bounds, its gradient against finite differences, no flips on
a disk where LSCM flips, and libigl's SLIM energy matched or beaten after the same
iterations from the same start."""

from __future__ import annotations

import warnings

import igl
import numpy as np
import pytest

from algorithms.core.errors import ConvergenceWarning, DegenerateInputError, InvalidInputError
from algorithms.parameterization import NotADiskError, bijective, conformal
from algorithms.parameterization._disk import read_disk
from algorithms.parameterization.bijective import (
    BijectiveSolver,
    boundary_crossings,
    max_flip_free_step,
    symmetric_dirichlet,
    tutte_start,
)
from tests.algorithms.parameterization.param_meshes import bumpy, grid


def ruffle(nx: int = 11, amplitude: float = 3.0, waves: int = 3) -> tuple[np.ndarray,
                                                                         np.ndarray]:
    """A square grid lifted to a ruffled (saddle-like, negatively curved) disk,
    z = a r²/c sin(kθ): LSCM flips triangles on it."""
    v, f = grid(nx, nx)
    c = (nx - 1) / 2
    x, y = v[:, 0] - c, v[:, 1] - c
    z = amplitude * (x * x + y * y) / c * np.sin(waves * np.arctan2(y, x))
    return np.column_stack([v, z]), f


def _slim(v: np.ndarray, f: np.ndarray, uv0: np.ndarray, iterations: int) -> np.ndarray:
    v3 = v if v.shape[1] == 3 else np.column_stack([v, np.zeros(len(v))])
    data = igl.slim_precompute(np.asfortranarray(v3), np.asfortranarray(f.astype(np.int32)),
                               np.asfortranarray(uv0), igl.SYMMETRIC_DIRICHLET,
                               np.zeros(0, dtype=np.int32), np.zeros((0, 2)), 0.0)
    return igl.slim_solve(data, iterations)


def test_symmetric_dirichlet_by_hand() -> None:
    tri = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    f = np.array([[0, 1, 2]])
    # J = diag(2, 1): 2² + 1² + 2⁻² + 1⁻² = 6.25
    assert symmetric_dirichlet(tri, f, tri * [2.0, 1.0]) == pytest.approx(6.25, rel=1e-14)
    t = 0.4
    rot = np.array([[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]])
    assert symmetric_dirichlet(tri, f, tri @ rot.T + 3.0) == pytest.approx(4.0, rel=1e-14)
    assert symmetric_dirichlet(tri, f, tri * [1.0, 0.0]) == np.inf        # collapsed


def test_max_flip_free_step_by_hand() -> None:
    uv = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    f = np.array([[0, 1, 2]])
    d = np.zeros((3, 2))
    d[2] = [0.0, -2.0]                           # vertex 2 reaches edge 01 at t = 1/2
    assert max_flip_free_step(uv, f, d) == pytest.approx(0.5, rel=1e-14)
    d = np.zeros((3, 2))
    d[1], d[2] = [-1.0, 1.0], [1.0, -1.0]        # det(t) = (1 - t)² - t², zero at t = 1/2
    assert max_flip_free_step(uv, f, d) == pytest.approx(0.5, rel=1e-14)
    assert max_flip_free_step(uv, f, uv) == np.inf          # a pure scaling never flips


def test_crossing_free_step_by_hand() -> None:
    v, f = grid(3, 3)
    disk = read_disk((v, f))
    solver = BijectiveSolver(disk)
    d = np.zeros_like(v)
    d[0] = [1.0, 0.75]            # corner (0, 0) runs into the edge (2, 1)-(2, 2) at t = 2
    assert solver._max_crossing_free_step(v, d, 3.0) == pytest.approx(2.0, rel=1e-12)
    assert solver._max_crossing_free_step(v, d, 1.5) == np.inf
    assert boundary_crossings(v, disk.loop) == 0
    moved = v + 2.5 * d
    assert boundary_crossings(moved, disk.loop) > 0


def test_gradient_matches_finite_differences() -> None:
    v, f = bumpy(8, 7, seed=3)
    disk = read_disk((v, f))
    uv = tutte_start(disk)
    solver = BijectiveSolver(disk, uv)
    solver.eps *= 12.0                        # make the barrier act on many pairs
    assert solver._barrier(uv)[1].size > 0
    _, grad = solver._system(uv)
    rng = np.random.default_rng(0)
    n = len(v)
    for _ in range(3):
        d = rng.standard_normal((n, 2))
        h = 1e-6
        fd = (solver.energy(uv + h * d) - solver.energy(uv - h * d)) / (2 * h)
        an = float(grad @ np.concatenate([d[:, 0], d[:, 1]]))
        assert an == pytest.approx(fd, rel=1e-5)


def test_no_flips_where_lscm_flips_and_slim_energy_matched() -> None:
    v, f = ruffle()
    assert conformal((v, f)).flipped_faces > 0          # LSCM flips here
    disk = read_disk((v, f))
    uv0 = tutte_start(disk)
    iterations = 15
    ours = BijectiveSolver(disk, uv0).solve(uv0, max_iterations=iterations, tolerance=0)
    peer = _slim(v, f, uv0, iterations)
    assert ours.iterations == iterations
    assert ours.flipped_faces == 0 and ours.degenerate_faces == 0
    assert ours.boundary_crossings == 0
    assert np.all(np.diff(ours.energy) < 0)
    # libigl's SLIM after the same iterations from the same start: the same steps while
    # the barrier is idle, so the same map and energy up to rounding
    assert ours.symmetric_dirichlet <= symmetric_dirichlet(v, f, peer) * (1 + 1e-9)
    np.testing.assert_allclose(ours.uv, peer, atol=1e-7 * np.ptp(peer))
    assert ours.symmetric_dirichlet == pytest.approx(symmetric_dirichlet(v, f, ours.uv))


def ramp(turns: float = 1.5, pitch: float = 0.05) -> tuple[np.ndarray, np.ndarray]:
    """A strip wound ``turns`` times around an axis and lifted by ``pitch`` per radian (a
    nearly flat spiral ramp): unrolled with little distortion it covers more than a full
    turn, so a free-boundary map that only minimises distortion overlaps itself."""
    v, f = grid(3, 30)
    r = 0.5 + v[:, 0] / 2
    t = 2 * np.pi * turns * v[:, 1] / 29
    return np.column_stack([r * np.cos(t), r * np.sin(t), pitch * t]), f


def _side(a: np.ndarray, c: np.ndarray, x: np.ndarray) -> float:
    return float(np.sign((c[0] - a[0]) * (x[1] - a[1]) - (c[1] - a[1]) * (x[0] - a[0])))


def _crossings_brute_force(uv: np.ndarray, loop: np.ndarray) -> int:
    """Pairs of non-adjacent boundary edges that properly intersect, all pairs tried."""
    p = uv[loop]
    q = np.roll(p, -1, axis=0)
    b = len(loop)
    count = 0
    side = _side
    for i in range(b):
        for j in range(i + 2, b):
            if i == 0 and j == b - 1:
                continue
            if (side(p[i], q[i], p[j]) * side(p[i], q[i], q[j]) < 0
                    and side(p[j], q[j], p[i]) * side(p[j], q[j], q[i]) < 0):
                count += 1
    return count


def test_barrier_keeps_the_boundary_simple_where_slim_overlaps() -> None:
    v, f = ramp()
    disk = read_disk((v, f))
    uv0 = tutte_start(disk)
    iterations = 150
    peer = _slim(v, f, uv0, iterations)
    assert _crossings_brute_force(peer, disk.loop) > 0            # SLIM overlaps itself
    ours = BijectiveSolver(disk, uv0).solve(uv0, max_iterations=iterations, tolerance=0)
    assert _crossings_brute_force(ours.uv, disk.loop) == 0 == ours.boundary_crossings
    assert ours.flipped_faces == 0
    assert boundary_crossings(peer, disk.loop) == _crossings_brute_force(peer, disk.loop)
    assert 4.0 < ours.symmetric_dirichlet < 0.5 * (4.0 + ours.energy[0])


@pytest.mark.parametrize("seed", range(3))
def test_curved_disks_stay_bijective_and_beat_the_start(seed: int) -> None:
    v, f = ruffle(9, amplitude=1.0 + seed, waves=3 + seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        res = bijective((v, f), max_iterations=30, tolerance=1e-5)
    assert res.flipped_faces == 0 and res.boundary_crossings == 0
    assert res.energy[-1] < res.energy[0]
    assert res.symmetric_dirichlet >= 4.0


def test_planar_mesh_is_kept_up_to_a_rigid_motion() -> None:
    v, f = grid(7, 6, jitter=0.3, seed=1)
    res = bijective((v, f), max_iterations=300, tolerance=1e-14)
    assert res.symmetric_dirichlet == pytest.approx(4.0, abs=1e-9)
    d = lambda x: np.linalg.norm(x[:, None] - x[None], axis=-1)  # noqa: E731
    np.testing.assert_allclose(d(res.uv), d(v), atol=1e-4)


def test_not_converging_warns_and_progress_is_called() -> None:
    v, f = ruffle(7)
    seen = []
    with pytest.warns(ConvergenceWarning, match="Bijective parameterization stopped after 2"):
        res = bijective((v, f), max_iterations=2, tolerance=1e-12,
                        progress=lambda d, t, msg: seen.append((d, t)))
    assert not res.converged and seen == [(1, 2), (2, 2)]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        bijective((v, f), max_iterations=2, tolerance=0)


def test_errors() -> None:
    v, f = ruffle(5)
    with pytest.raises(InvalidInputError,
                       match=r"Expected `max_iterations` to be an integer >= 1, got 0\."):
        bijective((v, f), max_iterations=0)
    with pytest.raises(InvalidInputError,
                       match=r"Expected `tolerance` to be a number >= 0, got -1"):
        bijective((v, f), tolerance=-1.0)
    tetra = ([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
             [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]])
    with pytest.raises(NotADiskError, match="closed mesh"):
        bijective(tetra)
    flat = ([[0, 0, 0], [1, 0, 0], [2, 0, 0], [1, 1, 0]], [[0, 1, 3], [1, 2, 3], [0, 2, 1]])
    with pytest.raises(DegenerateInputError, match="zero-area"):
        bijective(flat)
    with pytest.raises(NotADiskError, match="2 boundary loops"):
        bijective((v, np.delete(f, [5, 21], axis=0)))
