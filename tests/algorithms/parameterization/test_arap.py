"""ARAP and ASAP parameterizations: monotone energy, planar meshes kept, libigl's ARAP
parameterization energy matched or beaten after the same iterations, ASAP -> LSCM."""

from __future__ import annotations

import warnings

import igl
import numpy as np
import pytest
from tests.algorithms.parameterization.param_meshes import bumpy, cap, grid

from algorithms.core.errors import ConvergenceWarning, InvalidInputError
from algorithms.parameterization import arap, asap, conformal
from algorithms.parameterization._disk import read_disk
from algorithms.parameterization._local_global import (
    LocalGlobalSolver,
    fit_transforms,
    initial_map,
    local_global_energy,
)
from algorithms.parameterization._quality import face_frames, jacobians


def _pairwise(x: np.ndarray) -> np.ndarray:
    return np.linalg.norm(x[:, None] - x[None], axis=-1)


def test_local_step_by_hand() -> None:
    t = 0.7
    rot = np.array([[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]])
    J = np.stack([2.0 * rot, rot @ np.diag([3.0, 1.0]), np.diag([1.0, -1.0])])
    R = fit_transforms(J, similarity=False)
    np.testing.assert_allclose(R[0], rot, atol=1e-15)
    np.testing.assert_allclose(R[1], rot, atol=1e-15)          # polar factor of rot·diag
    np.testing.assert_allclose(np.linalg.det(R), 1.0, atol=1e-15)
    S = fit_transforms(J, similarity=True)
    np.testing.assert_allclose(S[0], 2 * rot, atol=1e-15)
    np.testing.assert_allclose(S[1], 2 * rot, atol=1e-15)      # (σ1 + σ2)/2 = 2
    np.testing.assert_allclose(S[2], 0, atol=1e-15)            # a reflection: nearest is 0


@pytest.mark.parametrize("init", ["lscm", "harmonic"])
def test_arap_matches_or_beats_libigl_after_the_same_iterations(init: str) -> None:
    v, f = bumpy(seed=2)
    disk = read_disk((v, f))
    uv0 = initial_map(disk, init)
    ours = LocalGlobalSolver(disk.mesh, disk.loop[:1], similarity=False).solve(
        uv0, max_iterations=10, tolerance=0)
    data = igl.ARAPData()
    data.max_iter = 10
    data.energy = igl.ARAP_ENERGY_TYPE_ELEMENTS
    pin = disk.loop[:1]                   # the vertex we hold, held in libigl too
    igl.arap_precomputation(v, f, 2, pin.astype(np.int32), data)
    peer = igl.arap_solve(uv0[pin], data, uv0)
    fr = face_frames(v, f)
    area = 0.5 * fr[:, 1, 0] * fr[:, 2, 1]
    J = jacobians(fr, f, peer)
    e_peer = local_global_energy(area, J, fit_transforms(J, False))
    assert ours.iterations == 10
    assert ours.energy[-1] <= e_peer * (1 + 1e-9)
    # the same iterations: the same map
    np.testing.assert_allclose(ours.uv, peer, atol=1e-6 * np.ptp(peer))


@pytest.mark.parametrize("seed", range(3))
def test_arap_energy_never_increases_and_lowers_area_distortion(seed: int) -> None:
    v, f = bumpy(seed=seed)
    res = arap((v, f), init="harmonic", max_iterations=40, tolerance=0)
    assert np.all(np.diff(res.energy) <= 1e-12 * res.energy[0])
    assert res.energy[-1] < 0.5 * res.energy[0]
    assert res.flipped_faces == 0
    lscm = conformal((v, f))
    assert res.area_distortion < lscm.area_distortion


def test_arap_keeps_a_planar_mesh() -> None:
    v, f = grid(7, 6, jitter=0.3, seed=1)
    res = arap((v, f), max_iterations=500, tolerance=1e-14)
    np.testing.assert_allclose(_pairwise(res.uv), _pairwise(v), atol=1e-7)
    assert res.converged and res.energy[-1] < 1e-12


def test_asap_converges_to_lscm_with_the_same_pins() -> None:
    v, f = cap(rings=5, sectors=16)
    res = asap((v, f), init="harmonic", max_iterations=3000, tolerance=1e-13)
    assert np.all(np.diff(res.energy) <= 1e-12 * res.energy[0])
    disk = read_disk((v, f))
    from algorithms.parameterization.conformal import farthest_boundary_pair
    pins = farthest_boundary_pair(disk)
    lscm = conformal((v, f), pins={"indices": pins, "positions": res.uv[pins]})
    np.testing.assert_allclose(res.uv, lscm.uv, atol=1e-4 * np.ptp(lscm.uv))
    assert res.energy[-1] == pytest.approx(lscm.energy, rel=1e-4)


def test_asap_from_lscm_is_already_converged() -> None:
    v, f = bumpy()
    res = asap((v, f), init="lscm")
    assert res.converged and res.iterations <= 2
    assert res.energy[-1] == pytest.approx(res.energy[0], rel=1e-9)


def test_not_converging_warns_and_progress_is_called() -> None:
    v, f = bumpy()
    seen = []
    with pytest.warns(ConvergenceWarning, match="ARAP parameterization stopped after 2"):
        res = arap((v, f), init="harmonic", max_iterations=2, tolerance=1e-12,
                   progress=lambda d, t, msg: seen.append((d, t)))
    assert not res.converged and seen == [(1, 2), (2, 2)]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        arap((v, f), max_iterations=2, tolerance=0)          # tolerance 0: no warning


def test_option_errors() -> None:
    v, f = bumpy()
    with pytest.raises(InvalidInputError, match="`init`"):
        arap((v, f), init="tutte")
    with pytest.raises(InvalidInputError, match="`max_iterations`"):
        asap((v, f), max_iterations=0)
    with pytest.raises(InvalidInputError, match="`tolerance`"):
        arap((v, f), tolerance=-1)
