"""The local/global solver of ARAP and ASAP: the local step by hand, and libigl's ARAP
parameterization energy matched or beaten after the same iterations."""

from __future__ import annotations

import importlib

import igl
import numpy as np
import pytest

from algorithms.core.laplacian import cotangent_entries, cotangent_laplacian
from algorithms.parameterization import arap
from algorithms.parameterization._disk import read_disk
from algorithms.parameterization._local_global import (
    LocalGlobalSolver,
    fit_transforms,
    initial_map,
    local_global_energy,
)
from algorithms.parameterization._quality import face_frames, jacobians
from tests.algorithms.parameterization.param_meshes import bumpy


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
    ours = LocalGlobalSolver(disk.mesh, disk.loop[:1], similarity=False, solves=10).solve(
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


def test_global_step_matrix_by_the_definition() -> None:
    # the right-hand side of the global step is sum_t sum_k c_k (T_t e_k), added at the
    # edge's first end f_{k+1} and taken from its second f_{k+2}; built here edge by edge
    # in a dense matrix, independently of the solver's assembly by columns
    v, f = bumpy(seed=1)
    disk = read_disk((v, f))
    solver = LocalGlobalSolver(disk.mesh, disk.loop[:1], similarity=False, solves=1)
    fr = face_frames(v, f)
    cot = cotangent_entries(v, f)
    dense = np.zeros((len(v), 2 * len(f)))
    for t, face in enumerate(f):
        for k in range(3):
            e = fr[t, (k + 1) % 3] - fr[t, (k + 2) % 3]
            for c in range(2):
                dense[face[(k + 1) % 3], 2 * t + c] += cot[t, k] * e[c]
                dense[face[(k + 2) % 3], 2 * t + c] -= cot[t, k] * e[c]
    np.testing.assert_allclose(solver._C.toarray(), dense, rtol=0, atol=1e-14 * np.abs(dense).max())
    assert solver._C.nnz == 6 * len(f)      # each column: the face's three corners


@pytest.mark.parametrize("init", ["lscm", "harmonic"])
def test_arap_makes_the_cotangent_laplacian_once(init: str, monkeypatch) -> None:
    # the initial map and the global step share one (the same matrix: made once)
    calls = []

    def counted(*args, **kwargs):
        calls.append(1)
        return cotangent_laplacian(*args, **kwargs)

    for name in ("arap", "_local_global", "conformal"):
        module = importlib.import_module(f"algorithms.parameterization.{name}")
        monkeypatch.setattr(module, "cotangent_laplacian", counted)
    v, f = bumpy(seed=3)
    arap((v, f), init=init, max_iterations=2)
    assert len(calls) == 1
