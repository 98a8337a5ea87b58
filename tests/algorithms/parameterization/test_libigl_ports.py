"""Cases ported from libigl's own Python tests of its parameterization functions, each
naming the original: ``tests/test_all.py`` (libigl-python-bindings 2.6) and the older
``tests/test_basic.py`` (removed in 2.6; read at commit 90a8801). Those tests run on
libigl's data files (``camelhead.off``, ``bunny_small.off``; not in the wheel) and check
little beyond shapes, so each is ported as a comparison with ``igl`` on the same call: the
tests' own ``triangulated_grid(3, 3)``, a disk cut from the sphere in pyvista's wheel (the
camel head's stand-in: a curved disk with one boundary loop) and a generated bumpy disk.

Not ported: ``test_all.py::test_bijective`` (``bijective_composite_harmonic_mapping`` maps
onto a *given* boundary; :func:`~algorithms.parameterization.bijective` has a free
boundary and no counterpart) and ``test_basic.py::test_slim`` (SLIM with the boundary
pinned; ours frees it)."""

from __future__ import annotations

import igl
import numpy as np
import pytest
import scipy.sparse as sp
from numpy.testing import assert_allclose, assert_array_equal

from algorithms.parameterization import arap, conformal, harmonic, tutte
from tests.algorithms.parameterization.param_meshes import bumpy
from tests.algorithms.registration._real_meshes import real_mesh


def _sphere_cap() -> tuple[np.ndarray, np.ndarray]:
    """pyvista's sphere without its faces above ``z = 0.25`` (of a unit bounding-box
    diagonal): a curved disk of 361 vertices, 30 on the boundary."""
    m = real_mesh("sphere.ply")
    v = np.asarray(m.vertices, float)
    f = np.asarray(m.faces, np.int64)
    v = (v - v.mean(axis=0)) / np.linalg.norm(m.extents)
    f = f[(v[f][:, :, 2] < 0.25).all(axis=1)]
    used = np.unique(f)
    remap = np.full(len(v), -1)
    remap[used] = np.arange(len(used))
    return v[used], remap[f]


def _disk(name: str) -> tuple[np.ndarray, np.ndarray]:
    return _sphere_cap() if name == "sphere_cap" else bumpy(seed=2)


DISKS = ["sphere_cap", "bumpy"]


# libigl: tests/test_basic.py::test_map_vertices_to_circle, ::test_boundary_loop
@pytest.mark.parametrize("name", DISKS)
def test_map_vertices_to_circle(name: str) -> None:
    v, f = _disk(name)
    res = harmonic((v, f))
    loop = igl.boundary_loop(f)
    assert_array_equal(res.pinned, loop)            # the same loop, start and direction
    assert_allclose(res.uv[loop], igl.map_vertices_to_circle(v, loop), atol=1e-14)


# libigl: tests/test_basic.py::test_arap3 (its first half: boundary_loop,
# map_vertices_to_circle, harmonic(V, F, bnd, bnd_uv, 1))
@pytest.mark.parametrize("name", DISKS)
def test_harmonic_parameterization(name: str) -> None:
    v, f = _disk(name)
    bnd = igl.boundary_loop(f)
    peer = igl.harmonic(v, f, bnd, igl.map_vertices_to_circle(v, bnd), 1)
    assert_allclose(harmonic((v, f)).uv, peer, atol=1e-12)


# libigl: tests/test_basic.py::test_harmonic_uniform_laplacian (harmonic with the uniform
# Laplacian; 2.6 dropped it, so the same minimisation through igl.min_quad_with_fixed and
# igl.adjacency_matrix)
@pytest.mark.parametrize("name", DISKS)
def test_harmonic_uniform_laplacian(name: str) -> None:
    v, f = _disk(name)
    ours = tutte((v, f), weighting="uniform")
    adj = sp.csc_matrix(igl.adjacency_matrix(f), dtype=float)
    lap = sp.csc_matrix(sp.diags(np.asarray(adj.sum(axis=1)).ravel()) - adj)
    bnd = igl.boundary_loop(f)
    peer = igl.min_quad_with_fixed(lap, np.zeros((len(v), 2)), bnd,
                                   igl.map_vertices_to_circle(v, bnd),
                                   sp.csc_matrix((0, len(v))), np.zeros((0, 2)), True)
    assert_allclose(ours.uv, peer, atol=1e-12)
    assert ours.flipped_faces == 0


# libigl: tests/test_basic.py::test_lscm (b = [1, 2, 3] pinned at (1, 0), (1, 1), (2, 2))
@pytest.mark.parametrize("name", DISKS)
def test_lscm_three_pins(name: str) -> None:
    v, f = _disk(name)
    b = np.array([1, 2, 3])
    bc = np.array([[1.0, 0.0], [1.0, 1.0], [2.0, 2.0]])
    ours = conformal((v, f), pins={"indices": b, "positions": bc})
    peer, _ = igl.lscm(v, f, b, bc)
    assert ours.uv.shape == peer.shape == (len(v), 2)
    assert_allclose(ours.uv, peer, atol=1e-12 * np.ptp(peer))
    assert_allclose(ours.uv[b], bc, atol=1e-12)


# libigl: tests/test_all.py::test_parameterization (lscm on triangulated_grid(3, 3) with
# b = [0, 1] at their own positions: a planar mesh comes back as itself)
def test_lscm_triangulated_grid() -> None:
    v, f = igl.triangulated_grid(3, 3)
    b = np.array([0, 1])
    ours = conformal((v, f), pins={"indices": b, "positions": v[b]})
    peer, _ = igl.lscm(v, f, b, v[b])
    assert_allclose(ours.uv, peer, atol=1e-13)
    assert_allclose(ours.uv, v, atol=1e-13)
    assert ours.energy == pytest.approx(0.0, abs=1e-14)   # of an area of 1


# libigl: tests/test_basic.py::test_lscm with the pins ours picks by default (the two
# boundary vertices farthest apart, at (0, 0) and (d, 0))
@pytest.mark.parametrize("name", DISKS)
def test_lscm_default_pins(name: str) -> None:
    v, f = _disk(name)
    ours = conformal((v, f))
    p = ours.pinned
    assert len(p) == 2
    d = float(np.linalg.norm(v[p[0]] - v[p[1]]))
    assert_allclose(ours.uv[p], np.array([[0.0, 0.0], [d, 0.0]]), atol=1e-15)
    peer, _ = igl.lscm(v, f, p, ours.uv[p])
    assert_allclose(ours.uv, peer, atol=1e-12 * np.ptp(peer))


# libigl: tests/test_basic.py::test_arap3 (its second half: ARAP parameterization from the
# harmonic map, boundary free). Ours scales the start to the surface's area and holds the
# boundary vertex of smallest index; libigl is given the same start and the same pin, and
# per-triangle rotations (ARAP_ENERGY_TYPE_ELEMENTS, the parameterization energy).
@pytest.mark.parametrize("name", DISKS)
def test_arap_parameterization_from_harmonic(name: str) -> None:
    v, f = _disk(name)
    bnd = igl.boundary_loop(f)
    uv = igl.harmonic(v, f, bnd, igl.map_vertices_to_circle(v, bnd), 1)
    uv *= np.sqrt(igl.doublearea(v, f).sum() / igl.doublearea(uv, f).sum())
    pin = np.array([bnd.min()])
    data = igl.ARAPData()
    data.max_iter = 10
    data.energy = igl.ARAP_ENERGY_TYPE_ELEMENTS
    igl.arap_precomputation(v, f, 2, pin, data)
    peer = igl.arap_solve(uv[pin], data, uv.copy())
    ours = arap((v, f), init="harmonic", max_iterations=10, tolerance=0)
    assert ours.iterations == 10
    assert_allclose(ours.uv, peer, atol=1e-10 * np.ptp(peer))
    assert np.all(np.diff(ours.energy) <= 1e-12 * ours.energy[0])
