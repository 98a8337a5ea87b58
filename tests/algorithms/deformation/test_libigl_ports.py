"""Cases ported from libigl's own Python tests of ``harmonic`` and ARAP, each naming the
original: ``tests/test_all.py`` (libigl-python-bindings 2.6) and the older
``tests/test_basic.py`` (removed in 2.6; read at commit 90a8801). Those tests run on
libigl's data files (``camelhead.off``, ``bunny_small.off``; not in the wheel) and check
shapes, so each is ported as a comparison with ``igl`` on the same call: the tests' own
triangulated square and ``triangulated_grid(3, 3)``, and meshes from pyvista's wheel (its
sphere, closed; a disk cut from it as the camel head's stand-in; its nut).

Conventions: ``igl.harmonic(V, F, b, bc, k)`` interpolates whatever ``bc`` holds; our
:func:`~algorithms.deformation.harmonic` and :func:`~algorithms.deformation.biharmonic`
apply it to the handles' *displacements* (their Notes), so ours equals
``V + igl.harmonic(V, F, b, targets - V[b], k)``. libigl's ARAP in 2-D defaults to one
rotation per triangle (``ARAP_ENERGY_TYPE_ELEMENTS``); ours has one per vertex (spokes, or
spokes and rims), so 2-D cases compare with ``ARAP_ENERGY_TYPE_SPOKES_AND_RIMS`` set
explicitly and the default is checked to differ."""

from __future__ import annotations

import igl
import numpy as np
import pytest
from numpy.testing import assert_allclose

from algorithms.deformation import ArapSolver, biharmonic, harmonic
from tests.algorithms.parameterization.test_libigl_ports import _sphere_cap
from tests.algorithms.registration._real_meshes import real_mesh


def _deform(v: np.ndarray, f: np.ndarray, b: np.ndarray, targets: np.ndarray,
            k: int) -> np.ndarray:
    handles = {"indices": b, "positions": targets}
    res = harmonic((v, f), handles) if k == 1 else biharmonic((v, f), handles, order=k)
    return res.mesh.vertices


# libigl: tests/test_all.py::test_harmonic (triangulated_square, b = [0, 3] at
# (1, 0) and (0, 1), k = 1 and 2)
@pytest.mark.parametrize("k", [1, 2])
def test_harmonic_triangulated_square(k: int) -> None:
    v = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
    f = np.array([[0, 1, 2], [0, 2, 3]])
    b = np.array([0, 3])
    bc = np.array([[1.0, 0.0], [0.0, 1.0]])
    ours = _deform(v, f, b, bc, k)
    assert_allclose(ours, v + igl.harmonic(v, f, b, bc - v[b], k), atol=1e-14)
    assert_allclose(ours[b], bc, atol=1e-15)


def _closed(name: str) -> tuple[np.ndarray, np.ndarray]:
    m = real_mesh(name)
    return (np.asarray(m.vertices, float) / np.linalg.norm(m.extents),
            np.asarray(m.faces, np.int64))


# libigl: tests/test_basic.py::test_harmonic (b = [1, 2, 10, 7], k = 1), here with the
# handles moved and k = 1, 2, 3 (Q = L (M⁻¹ L)^(k-1), Voronoi mass)
@pytest.mark.parametrize("name", ["sphere.ply", "nut.ply"])
@pytest.mark.parametrize("k", [1, 2, 3])
def test_harmonic_moved_handles(name: str, k: int) -> None:
    v, f = _closed(name)
    b = np.array([1, 2, 10, 7])
    targets = v[b] + 0.1 * np.random.default_rng(k).standard_normal((4, 3))
    peer = v + igl.harmonic(v, f, b, targets - v[b], k)
    assert_allclose(_deform(v, f, b, targets, k), peer, atol=1e-7)


# libigl: tests/test_basic.py::test_harmonic as written (bc = V[b]: the handles where they
# are). libigl interpolates the positions themselves, which pulls the surface out of shape;
# ours moves the displacement (zero) and returns the rest shape — the documented difference.
@pytest.mark.parametrize("name", ["sphere.ply", "nut.ply"])
def test_harmonic_handles_at_rest(name: str) -> None:
    v, f = _closed(name)
    b = np.array([1, 2, 10, 7])
    assert_allclose(_deform(v, f, b, v[b], 1), v, atol=0)
    peer = igl.harmonic(v, f, b, v[b], 1)
    assert np.abs(peer - v).max() > 0.1                  # libigl's semantics differ


def _lower_cap() -> tuple[np.ndarray, np.ndarray]:
    """The lower part of pyvista's sphere (below z = -0.05): a disk that is a graph over
    the xy-plane, so its projection (the 2-D case) has no degenerate triangle."""
    v, f = _sphere_cap()
    f = f[(v[f][:, :, 2] < -0.05).all(axis=1)]
    used = np.unique(f)
    remap = np.full(len(v), -1)
    remap[used] = np.arange(len(used))
    return v[used], remap[f]


def _circle_boundary(v: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, np.ndarray,
                                                             np.ndarray]:
    # as the libigl test writes it: linspace(0, 2π, len(b)), both ends at angle 0
    b = igl.boundary_loop(f)
    thetas = np.linspace(0, 2 * np.pi, len(b))[:, None]
    bc = np.hstack([np.cos(thetas), np.sin(thetas), np.zeros_like(thetas)])
    return b, bc, igl.harmonic(v, f, b, bc, 1)


def _igl_arap(v: np.ndarray, f: np.ndarray, b: np.ndarray, bc: np.ndarray,
              start: np.ndarray, energy: int, iterations: int) -> np.ndarray:
    data = igl.ARAPData()
    data.max_iter = iterations
    data.energy = energy
    igl.arap_precomputation(v, f, v.shape[1], b, data)
    return igl.arap_solve(bc, data, start.copy())


# libigl: tests/test_basic.py::test_arap1 (boundary pinned to the circle, harmonic start;
# the 3-D call igl.ARAP(v, f, 3, b) and the 2-D call on v[:, :2])
@pytest.mark.parametrize("dim", [2, 3])
def test_arap_boundary_on_circle(dim: int) -> None:
    v, f = _lower_cap()
    b, bc, start = _circle_boundary(v, f)
    v, bc, start = v[:, :dim].copy(), bc[:, :dim], start[:, :dim]
    peer = _igl_arap(v, f, b, bc, start, igl.ARAP_ENERGY_TYPE_SPOKES_AND_RIMS, 10)
    ours = ArapSolver((v, f), b).solve(bc, initial=start, max_iterations=10, tolerance=0)
    assert ours.iterations == 10
    assert_allclose(ours.mesh.vertices, peer, atol=1e-7 * np.ptp(peer))
    assert ours.handle_residual == 0.0
    if dim == 2:   # libigl's 2-D default is one rotation per triangle: not ours
        default = _igl_arap(v, f, b, bc, start, igl.ARAP_ENERGY_TYPE_DEFAULT, 10)
        elements = _igl_arap(v, f, b, bc, start, igl.ARAP_ENERGY_TYPE_ELEMENTS, 10)
        assert_allclose(default, elements, atol=0)
        assert np.abs(ours.mesh.vertices - default).max() > 1e-3


# libigl: tests/test_basic.py::test_arap4 (3-D, ARAP_ENERGY_TYPE_SPOKES)
def test_arap_spokes() -> None:
    v, f = _lower_cap()
    b, bc, start = _circle_boundary(v, f)
    peer = _igl_arap(v, f, b, bc, start, igl.ARAP_ENERGY_TYPE_SPOKES, 10)
    ours = ArapSolver((v, f), b, energy="spokes").solve(bc, initial=start,
                                                         max_iterations=10, tolerance=0)
    assert_allclose(ours.mesh.vertices, peer, atol=1e-7 * np.ptp(peer))


# libigl: tests/test_all.py::test_parameterization (its ARAP half: triangulated_grid(3, 3)
# in 2-D, b = [0, 1] at their rest positions, spokes and rims). In that test the x column
# of V is doubled through a view, so the rest shape is the grid stretched 2× in x; here the
# solve starts from the unstretched grid.
def test_arap_triangulated_grid() -> None:
    grid, f = igl.triangulated_grid(3, 3)
    rest = grid * [2.0, 1.0]
    b = np.array([0, 1])
    solver = ArapSolver((rest, f), b)
    # from the rest shape both stay there
    peer = _igl_arap(rest, f, b, rest[b], rest, igl.ARAP_ENERGY_TYPE_SPOKES_AND_RIMS, 10)
    assert_allclose(peer, rest, atol=1e-14)
    assert_allclose(solver.solve(rest[b], initial=rest).mesh.vertices, rest, atol=1e-14)
    # from the unstretched grid: the same 10 iterations, then both reach the rest shape
    peer = _igl_arap(rest, f, b, rest[b], grid, igl.ARAP_ENERGY_TYPE_SPOKES_AND_RIMS, 10)
    ours = solver.solve(rest[b], initial=grid, max_iterations=10, tolerance=0)
    assert_allclose(ours.mesh.vertices, peer, atol=1e-12)
    far = solver.solve(rest[b], initial=grid, max_iterations=500, tolerance=0)
    assert_allclose(far.mesh.vertices, rest, atol=1e-5)
    assert np.all(np.diff(far.energy) <= 1e-12 * far.energy[0])
