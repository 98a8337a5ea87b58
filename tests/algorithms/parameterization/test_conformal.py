"""Conformal parameterization: LSCM against igl.lscm, spectral conformal on planar meshes
(a similarity) and curved ones, and the pin errors."""

from __future__ import annotations

import igl
import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.core.mesh import signed_areas
from algorithms.parameterization import conformal, harmonic
from algorithms.parameterization._disk import read_disk
from algorithms.parameterization.conformal import (
    conformal_energy_hermitian,
    conformal_energy_matrix,
)
from tests.algorithms.parameterization.param_meshes import bumpy, grid


def _similarity_residual(x: np.ndarray, y: np.ndarray) -> float:
    """Largest distance from y to the best similarity image of x, relative to y's size."""
    zx = x[:, 0] + 1j * x[:, 1]
    zy = y[:, 0] + 1j * y[:, 1]
    a = np.c_[zx, np.ones_like(zx)]
    coef, *_ = np.linalg.lstsq(a, zy, rcond=None)
    return float(np.abs(a @ coef - zy).max() / np.abs(zy - zy.mean()).max())


@pytest.mark.parametrize("seed", range(3))
def test_lscm_equals_igl_with_the_same_pins(seed: int) -> None:
    v, f = bumpy(seed=seed)
    res = conformal((v, f))
    peer, _ = igl.lscm(v, f, res.pinned, res.uv[res.pinned])
    np.testing.assert_allclose(res.uv, peer, atol=1e-8 * np.ptp(peer))
    # given pins, more than two, anywhere
    pins = {"indices": [0, 50, 90], "positions": [[0, 0], [3, 1], [1, 4]]}
    res = conformal((v, f), pins=pins)
    peer, _ = igl.lscm(v, f, np.array(pins["indices"]), np.array(pins["positions"], float))
    np.testing.assert_allclose(res.uv, peer, atol=1e-8 * np.ptp(peer))


def test_default_pins_are_the_farthest_boundary_pair() -> None:
    v, f = bumpy()
    res = conformal((v, f))
    loop = read_disk((v, f)).loop
    d = np.linalg.norm(v[loop][:, None] - v[loop][None], axis=-1)
    assert np.linalg.norm(v[res.pinned[0]] - v[res.pinned[1]]) == pytest.approx(d.max())
    np.testing.assert_allclose(res.uv[res.pinned], [[0, 0], [d.max(), 0]], atol=1e-15)


def test_energy_matrix_is_igl_lscm_over_two_and_vanishes_on_similarities() -> None:
    v, f = bumpy()
    q = conformal_energy_matrix(read_disk((v, f)).mesh)
    _, q_igl = igl.lscm(v, f, np.array([0, 5]), np.array([[0.0, 0], [1, 0]]))
    np.testing.assert_allclose((2 * q).toarray(), q_igl.toarray(), atol=1e-12)
    vp, fp = grid(6, 5, jitter=0.3)
    qp = conformal_energy_matrix(read_disk((vp, fp)).mesh)
    x = np.r_[0.3 * vp[:, 0] - 2 * vp[:, 1] + 1, 2 * vp[:, 0] + 0.3 * vp[:, 1] - 4]
    assert abs(x @ (qp @ x)) < 1e-12 * (x @ x)


def test_hermitian_energy_is_the_complex_form_of_q_and_lscm_solves_it() -> None:
    # K = P + iR <-> Q = [[P, -R], [R, P]] (Q is built from K; 2Q is igl.lscm's matrix,
    # tested above), Im K is the area term: 2 x^T (Im K) y is the area enclosed by the
    # boundary's image, the sum of the faces' signed areas, for any map; and LSCM through
    # K's n complex unknowns equals the pinned solve of the real (2n, 2n) system Q
    v, f = bumpy()
    mesh = read_disk((v, f)).mesh
    n = mesh.n_vertices
    k = conformal_energy_hermitian(mesh)
    q = conformal_energy_matrix(mesh)
    assert k.shape == (n, n) and abs(k - k.conj().T).max() == 0
    assert abs(sp.block_array([[k.real, -k.imag], [k.imag, k.real]]) - q).max() == 0
    uv = np.random.default_rng(0).standard_normal((n, 2))
    enclosed = 2 * uv[:, 0] @ (k.imag @ uv[:, 1])
    assert enclosed == pytest.approx(float(signed_areas(uv, f).sum()), rel=1e-12)
    res = conformal((v, f))
    pins = np.r_[res.pinned, n + res.pinned]
    free = np.setdiff1d(np.arange(2 * n), pins)
    x = np.zeros(2 * n)
    x[pins] = np.r_[res.uv[res.pinned, 0], res.uv[res.pinned, 1]]
    qc = q.tocsc()
    x[free] = sla.spsolve(qc[free][:, free], -(qc[free][:, pins] @ x[pins]))
    np.testing.assert_allclose(res.uv, np.c_[x[:n], x[n:]], atol=1e-10)
    z = res.uv[:, 0] + 1j * res.uv[:, 1]
    assert res.energy == pytest.approx(float(x @ (q @ x)), rel=1e-9, abs=1e-15)
    assert float((z.conj() @ (k @ z)).imag) == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("seed", range(4))
def test_planar_mesh_is_its_own_conformal_map(seed: int) -> None:
    v, f = grid(9, 7, jitter=0.3, seed=seed)
    for method in ("lscm", "spectral"):
        res = conformal((v, f), method=method)
        assert _similarity_residual(v, res.uv) < 1e-8
        assert res.angle_distortion < 1e-8 and res.area_distortion < 1e-8
        assert res.flipped_faces == 0
    spectral = conformal((v, f), method="spectral")
    area = float(signed_areas(v, f).sum())
    uv = spectral.uv
    uv_area = float(signed_areas(uv, f).sum())
    assert uv_area == pytest.approx(area, rel=1e-10)       # scaled to the surface's area
    np.testing.assert_allclose(uv.mean(axis=0), [0, 0], atol=1e-12)
    assert spectral.pinned.size == 0


@pytest.mark.parametrize(("nx", "ny"), [(2, 2), (3, 3), (3, 2), (4, 3)])
def test_spectral_on_the_smallest_disks_is_their_own_conformal_map(nx: int, ny: int) -> None:
    # A short boundary: shift-invert Lanczos on the full problem exhausts its Krylov space
    # (the range of Q^-1 B has 2b dimensions) before it converges; ARPACK refused the 3 × 3
    # grid. The planar grid is its own conformal map, up to a similarity.
    v, f = grid(nx, ny)
    res = conformal((v, f), method="spectral")
    assert _similarity_residual(v, res.uv) < 1e-8
    assert res.flipped_faces == 0


def test_spectral_reduced_to_the_boundary_equals_lanczos_on_the_whole_mesh(
        monkeypatch: pytest.MonkeyPatch) -> None:
    # the dense Schur-complement path and ARPACK's shift-invert path solve the same problem
    import sys

    module = sys.modules["algorithms.parameterization.conformal"]
    v, f = bumpy(seed=2)
    dense = conformal((v, f), method="spectral")
    monkeypatch.setattr(module, "_DENSE_BOUNDARY", 0)
    lanczos = conformal((v, f), method="spectral")
    np.testing.assert_allclose(dense.uv, lanczos.uv, atol=1e-9)
    assert dense.energy == pytest.approx(lanczos.energy, rel=1e-9)


def test_spectral_on_a_curved_disk_beats_harmonic_and_is_an_eigenvector() -> None:
    v, f = bumpy(seed=4)
    res = conformal((v, f), method="spectral")
    assert res.flipped_faces == 0
    assert res.angle_distortion < 0.5 * harmonic((v, f)).angle_distortion
    # lscm with the spectral map's own two pins gives a map at least as conformal
    lscm = conformal((v, f), pins={"indices": [0, 1], "positions": res.uv[[0, 1]]})
    assert lscm.energy <= res.energy * (1 + 1e-9)


def test_pin_errors() -> None:
    v, f = bumpy()
    with pytest.raises(DegenerateInputError, match="at least 2 vertices"):
        conformal((v, f), pins={"indices": [3], "positions": [[0, 0]]})
    with pytest.raises(DegenerateInputError, match="two distinct points"):
        conformal((v, f), pins={"indices": [3, 4], "positions": [[1, 1], [1, 1]]})
    with pytest.raises(InvalidInputError, match=r"pins.positions.*\(p, 2\)"):
        conformal((v, f), pins={"indices": [3, 4], "positions": [[1, 1, 0], [0, 1, 0]]})
    with pytest.raises(InvalidInputError, match="no `pins` with method='spectral'"):
        conformal((v, f), method="spectral", pins={"indices": [3, 4],
                                                   "positions": [[1, 1], [0, 1]]})
    with pytest.raises(InvalidInputError, match="Expected `method` to be one of 'lscm', "
                       "'spectral', got 'abf'"):
        conformal((v, f), method="abf")
