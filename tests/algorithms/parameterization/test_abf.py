"""ABF++ parameterization: hand cases (one triangle, a symmetric cone), the Newton step
against the dense KKT solve, the angle problem against scipy's SLSQP, the layout step
against igl.lscm (given the surface's own angles), constraints met and
laid out exactly, planar meshes kept, a 10k-face curved disk flattened with no flips and
no more angle distortion than LSCM, and the same errors as the other methods."""

from __future__ import annotations

import warnings

import igl
import numpy as np
import pytest
import trimesh
from scipy.optimize import minimize

from algorithms.core.errors import (
    ConvergenceWarning,
    DegenerateInputError,
    InvalidInputError,
)
from algorithms.core.mesh import face_angles
from algorithms.parameterization import NotADiskError, abf, conformal, harmonic
from algorithms.parameterization._disk import read_disk
from algorithms.parameterization.abf import AngleSystem, angles_to_uv
from tests.algorithms.parameterization.param_meshes import bumpy, cap, grid


def _pairwise(x: np.ndarray) -> np.ndarray:
    return np.linalg.norm(x[:, None] - x[None], axis=-1)


def _similar(a: np.ndarray, b: np.ndarray) -> float:
    """Largest deviation of ``a``'s pairwise distances from ``s`` times ``b``'s, relative
    to ``b``'s largest distance (``s`` fitted)."""
    da, db = _pairwise(a), _pairwise(b)
    s = float((da * db).sum() / (db * db).sum())
    return float(np.abs(da - s * db).max() / (s * db.max()))


def _angle_energy(system: AngleSystem, angles: np.ndarray) -> float:
    return float(np.sum(system.weight * (angles.ravel() - system.beta) ** 2))


def test_one_triangle_by_hand() -> None:
    # a 3-4-5 right triangle in a tilted plane; the farthest pair (1, 2) is pinned at
    # (0, 0) and (5, 0), so vertex 0 lands at (9/5, 12/5) (left of 1 -> 2: counter-clockwise)
    rot = trimesh.transformations.rotation_matrix(0.7, [1, 2, 3])[:3, :3]
    v = np.array([[0.0, 0, 0], [3, 0, 0], [0, 4, 0]]) @ rot.T + [1, 2, 3]
    res = abf((v, [[0, 1, 2]]))
    np.testing.assert_allclose(res.uv, [[9 / 5, 12 / 5], [0, 0], [5, 0]], atol=1e-12)
    assert res.pinned.tolist() == [1, 2]
    assert res.iterations == 0 and res.converged and res.energy < 1e-28
    np.testing.assert_allclose(res.angles, [[np.pi / 2, np.arctan2(4, 3), np.arctan2(3, 4)]],
                               atol=1e-14)


def test_a_symmetric_cone_flattens_to_a_regular_hexagon() -> None:
    # apex over the centre of a regular hexagon: by symmetry the only flat angles are π/3
    # (planarity at the apex, triangle sums), so the map is a regular hexagon
    t = 2 * np.pi * np.arange(6) / 6
    v = np.r_[[[0, 0, 0.8]], np.c_[np.cos(t), np.sin(t), np.zeros(6)]]
    f = [[0, 1 + k, 1 + (k + 1) % 6] for k in range(6)]
    res = abf((v, f))
    assert res.converged and res.iterations >= 1
    np.testing.assert_allclose(res.angles, np.pi / 3, atol=1e-10)
    flat = np.r_[[[0, 0]], np.c_[np.cos(t), np.sin(t)]]
    assert _similar(res.uv, flat) < 1e-10
    assert res.angle_distortion > 0.05            # the cone is not developable
    assert res.flipped_faces == 0


def test_newton_step_equals_the_dense_kkt_solve() -> None:
    v, f = bumpy(5, 4, seed=3)
    system = AngleSystem(read_disk((v, f)))
    rng = np.random.default_rng(0)
    alpha = system.beta + 0.01 * rng.standard_normal(system.beta.shape)
    lam = 0.05 * rng.standard_normal(system.n_faces + 2 * system.n_interior)
    grad, cons, cot = system.residuals(alpha, lam)
    n = alpha.shape[0]
    h = 1e-6
    eye = np.eye(n)
    # Jacobian of the constraints and Hessian of the Lagrangian by central differences
    jac = np.stack([(system.residuals(alpha + h * e, lam)[1]
                     - system.residuals(alpha - h * e, lam)[1]) / (2 * h) for e in eye], 1)
    hess = np.stack([(system.residuals(alpha + h * e, lam)[0]
                      - system.residuals(alpha - h * e, lam)[0]) / (2 * h) for e in eye], 1)
    np.testing.assert_allclose(hess, np.diag(np.diag(hess)), atol=1e-6)   # diagonal
    k = jac.shape[0]
    kkt = np.block([[hess, jac.T], [jac, np.zeros((k, k))]])
    dense = np.linalg.solve(kkt, -np.r_[grad, cons])
    dalpha, dlam = system.newton_step(alpha, lam, grad, cons, cot)
    np.testing.assert_allclose(dalpha, dense[:n], atol=1e-7)
    np.testing.assert_allclose(dlam, dense[n:], atol=1e-6)


def test_layout_from_the_surface_angles_is_igl_lscm() -> None:
    # the layout step is LSCM with the triangles the angles define: given the surface's own
    # angles it is LSCM itself, equal to libigl's with the same two pins
    v, f = bumpy(seed=4)
    disk = read_disk((v, f))
    uv, pins = angles_to_uv(disk, face_angles(v, f))
    d = np.linalg.norm(v[pins[1]] - v[pins[0]])
    peer, _ = igl.lscm(v, f, pins, np.array([[0.0, 0.0], [d, 0.0]]))
    np.testing.assert_allclose(uv, peer, atol=1e-10 * d)


def test_angles_match_scipy_slsqp_on_the_same_problem() -> None:
    v, f = bumpy(5, 4, seed=1)
    res = abf((v, f), tolerance=1e-12)
    system = AngleSystem(read_disk((v, f)))
    w, beta = system.weight, system.beta

    def constraints(a: np.ndarray) -> np.ndarray:
        return system.residuals(a, np.zeros(system.n_faces + 2 * system.n_interior))[1]

    peer = minimize(lambda a: float(np.sum(w * (a - beta) ** 2)), beta,
                    jac=lambda a: 2 * w * (a - beta), method="SLSQP",
                    constraints=[{"type": "eq", "fun": constraints}],
                    options={"ftol": 1e-14, "maxiter": 500})
    assert peer.success, peer.message
    np.testing.assert_allclose(res.angles.ravel(), peer.x, atol=1e-6)
    assert res.energy <= peer.fun * (1 + 1e-6)


@pytest.mark.parametrize("seed", range(3))
def test_constraints_hold_and_the_layout_realises_the_angles(seed: int) -> None:
    v, f = bumpy(seed=seed)
    res = abf((v, f), tolerance=1e-11)
    assert res.converged and res.iterations <= 8
    assert res.gradient_norm[-1] <= 1e-11 and res.gradient_norm.shape == (res.iterations + 1,)
    np.testing.assert_allclose(res.angles.sum(axis=1), np.pi, atol=1e-12)
    disk = read_disk((v, f))
    inner = np.setdiff1d(np.arange(len(v)), disk.loop)
    sums = np.bincount(f.ravel(), weights=res.angles.ravel(), minlength=len(v))
    np.testing.assert_allclose(sums[inner], 2 * np.pi, atol=1e-11)
    # consistent angles are laid out exactly: the map's own angles are the ones found
    np.testing.assert_allclose(face_angles(res.uv, f), res.angles, atol=1e-9)
    assert res.flipped_faces == 0 and res.degenerate_faces == 0


def test_angle_energy_is_below_that_of_other_flat_maps() -> None:
    # the angles of any flat map of the disk satisfy ABF's constraints: ABF's minimum
    # cannot be above theirs
    v, f = cap(rings=6, sectors=20)
    v = v * [1.0, 0.7, 1.0]                      # an elliptic cap: no rotational symmetry
    res = abf((v, f))
    system = AngleSystem(read_disk((v, f)))
    for other in (conformal((v, f)).uv, harmonic((v, f)).uv):
        assert res.energy < _angle_energy(system, face_angles(other, f))


def test_a_planar_mesh_is_kept_up_to_a_similarity() -> None:
    v, f = grid(9, 7, jitter=0.3, seed=4)
    res = abf((v, f))
    assert res.iterations == 0 and res.converged
    assert _similar(res.uv, v) < 1e-12
    assert res.angle_distortion < 1e-12 and res.area_distortion < 1e-12
    # a regular grid rolled onto a cylinder: its quads are planar rectangles of the chord's
    # width, so it is developable and comes back as the grid of that chord
    v, f = grid(9, 7)
    r = 3.0
    rolled = np.c_[r * np.sin(v[:, 0] / r), v[:, 1], r * (1 - np.cos(v[:, 0] / r))]
    back = abf((rolled, f))
    chord = 2 * r * np.sin(0.5 / r)
    assert back.converged and back.iterations == 0
    assert _similar(back.uv, v * [chord, 1.0]) < 1e-12


def test_a_10k_face_curved_disk_converges_without_flips_at_lscm_distortion_or_less() -> None:
    rng = np.random.default_rng(0)
    nx = 72                                      # 2 · 71² = 10,082 faces
    x, y = np.meshgrid(np.linspace(0, 1, nx), np.linspace(0, 1, nx))
    v = np.c_[x.ravel(), y.ravel(), 0.4 * np.sin(6 * x.ravel()) * np.cos(5 * y.ravel())]
    v[:, :2] += rng.uniform(-0.3, 0.3, (nx * nx, 2)) / nx
    idx = np.arange(nx * nx).reshape(nx, nx)
    a, b = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel()
    c, d = idx[1:, :-1].ravel(), idx[1:, 1:].ravel()
    f = np.r_[np.c_[a, b, d], np.c_[a, d, c]]
    res = abf((v, f))
    lscm = conformal((v, f))
    assert f.shape[0] == 10_082
    assert res.converged and res.iterations <= 10
    assert res.flipped_faces == 0 and res.degenerate_faces == 0
    assert res.angle_distortion <= lscm.angle_distortion
    assert res.area_distortion <= lscm.area_distortion


def test_no_flips_on_the_test_disks() -> None:
    for v, f in (bumpy(seed=5), cap(), cap(rings=10, sectors=30)):
        res = abf((v, f))
        assert res.converged and res.flipped_faces == 0 and res.degenerate_faces == 0


def _sphere() -> tuple[np.ndarray, np.ndarray]:
    s = trimesh.creation.icosphere(subdivisions=1)
    return np.asarray(s.vertices), np.asarray(s.faces)


def _holed() -> tuple[np.ndarray, np.ndarray]:
    v, f = grid(5, 5)
    keep = ~np.isin(f, [12]).any(axis=1)
    return np.delete(v, 12, axis=0), np.where(f[keep] > 12, f[keep] - 1, f[keep])


def _unused_vertex() -> tuple[np.ndarray, np.ndarray]:
    v, f = grid(3, 3)
    return np.r_[v, [[9, 9]]], f


def _two_disks() -> tuple[np.ndarray, np.ndarray]:
    v, f = grid(3, 3)
    return np.r_[v, v + [5, 0]], np.r_[f, f + len(v)]


@pytest.mark.parametrize("make, words", [
    (_sphere, "closed mesh"), (_holed, "2 boundary loops"),
    (_unused_vertex, "vertex 9 in no face"), (_two_disks, "2 connected components"),
])
def test_not_a_disk_gets_the_same_error_as_other_methods(make, words: str) -> None:  # noqa: ANN001
    v, f = make()
    with pytest.raises(NotADiskError, match=words) as ours:
        abf((v, f))
    with pytest.raises(NotADiskError) as theirs:
        conformal((v, f))
    assert str(ours.value) == str(theirs.value) and ours.value.field == "mesh"


def test_degenerate_and_malformed_input() -> None:
    v, f = grid(3, 3)
    v[4] = v[3]                                   # faces round vertex 4 lose their area
    with pytest.raises(DegenerateInputError, match="zero-area"):
        abf((v, f))
    with pytest.raises(InvalidInputError, match="`mesh`"):
        abf({"vertices": [[0, 0, 0]]})
    with pytest.raises(InvalidInputError,
                       match=r"Expected `max_iterations` to be an integer >= 1, got 0\."):
        abf(bumpy(), max_iterations=0)
    with pytest.raises(InvalidInputError,
                       match=r"Expected `tolerance` to be a number >= 0, got -1"):
        abf(bumpy(), tolerance=-1.0)


def test_not_converging_warns_and_progress_is_called() -> None:
    v, f = bumpy()
    seen = []
    with pytest.warns(ConvergenceWarning, match="ABF stopped after 1 iterations"):
        res = abf((v, f), max_iterations=1, tolerance=1e-14,
                  progress=lambda d, t, msg: seen.append((d, t)))
    assert not res.converged and res.iterations == 1 and seen == [(1, 1)]
    assert np.isfinite(res.uv).all()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        abf((v, f), max_iterations=20)
        ran = abf((v, f), max_iterations=2, tolerance=0)     # tolerance 0: no warning
    assert ran.iterations == 2 and not ran.converged
