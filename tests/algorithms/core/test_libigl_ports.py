"""Cases ported from libigl's own Python tests, each naming the original: the operator and
topology checks of ``tests/test_all.py`` (libigl-python-bindings 2.6) and of the older
``tests/test_basic.py`` (removed in 2.6; read at commit 90a8801). Those tests mostly check
shapes and dtypes on libigl's data files (``bunny_small.off``, ``fertility.off``, not in the
wheel), so each is ported as a comparison with ``igl`` on the same input: the tests' own
small meshes (a triangulated square, a tetrahedron, an icosahedron) and the real meshes in
pyvista's wheel (a sphere, an ant of 15 parts, an airplane of 7 parts, a nut; on the first
three 43-54 % of the triangles are obtuse, where the Voronoi mass switches rule).

Conventions: ``cotangent_laplacian`` is ``-igl.cotmatrix`` (ours is positive
semidefinite, libigl's negative semidefinite; :mod:`algorithms.core.laplacian`);
``edges`` are sorted rows ``i < j``, libigl's unsorted, so they are compared as sets."""

from __future__ import annotations

import igl
import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_equal

from algorithms.core.errors import InvalidInputError
from algorithms.core.laplacian import cotangent_entries, cotangent_laplacian, mass_matrix
from algorithms.core.mesh import (
    as_mesh,
    boundary_loops,
    components,
    edges,
    face_angles,
    face_areas,
    face_normals,
)
from tests.algorithms.registration._real_meshes import real_mesh

REAL = ["sphere.ply", "ant.ply", "airplane.ply", "nut.ply"]


def _square() -> tuple[np.ndarray, np.ndarray]:
    # libigl: tests/test_all.py::triangulated_square
    v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=float)
    return v, np.array([[0, 1, 2], [0, 2, 3]], dtype=np.int64)


def _tet() -> tuple[np.ndarray, np.ndarray]:
    # libigl: tests/test_all.py::single_tet (its boundary triangles)
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    return v, np.array([[2, 1, 0], [1, 3, 0], [3, 2, 0], [2, 3, 1]], dtype=np.int64)


def _mesh(name: str) -> tuple[np.ndarray, np.ndarray]:
    if name == "square":
        return _square()
    if name == "tet":
        return _tet()
    if name == "icosahedron":
        v, f = igl.icosahedron()
        return np.asarray(v, float), np.asarray(f, np.int64)
    m = real_mesh(name)
    return np.asarray(m.vertices, float), np.asarray(m.faces, np.int64)


ALL = ["square", "tet", "icosahedron", *REAL]


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).max() / np.abs(b).max())


# libigl: tests/test_all.py::test_operators (igl.cotmatrix(V, F));
# tests/test_basic.py::test_cotmatrix
@pytest.mark.parametrize("name", ALL)
def test_cotmatrix(name: str) -> None:
    v, f = _mesh(name)
    ours = cotangent_laplacian(v, f).toarray()
    peer = igl.cotmatrix(v, f).toarray()
    assert ours.shape == peer.shape == (len(v), len(v))
    assert _rel(ours, -peer) < 1e-13


# libigl: tests/test_basic.py::setUp and ::test_cotmatrix on its random "mesh"
# (np.random.seed(42); v = rand(10, 3), t = rand(10, 4), f = randint(0, 10, (20, 3))):
# libigl returns a 10×10 matrix with non-finite entries, five faces repeating a vertex; ours
# refuses such faces with a typed error naming the first (as_mesh), and on the other
# fifteen equals libigl.
def test_cotmatrix_random_faces() -> None:
    rs = np.random.RandomState(42)
    v = rs.rand(10, 3)
    rs.rand(10, 4)
    f = rs.randint(0, 10, size=(20, 3))
    assert igl.cotmatrix(v, f).shape == (10, 10)
    with pytest.raises(InvalidInputError, match=r"three distinct vertex indices per face, "
                       r"got \[7, 0, 7\] at row 0") as e:
        as_mesh(v, f)
    assert e.value.field == "mesh.faces"
    ok = f[(f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 0] != f[:, 2])]
    assert len(ok) == 15
    m = as_mesh(v, ok)
    assert _rel(cotangent_laplacian(m.vertices, m.faces).toarray(),
                -igl.cotmatrix(v, ok).toarray()) < 1e-13


# libigl: tests/test_all.py::test_operators (igl.cotmatrix_entries(V, F));
# tests/test_basic.py::test_cotmatrix_entries
@pytest.mark.parametrize("name", ALL)
def test_cotmatrix_entries(name: str) -> None:
    v, f = _mesh(name)
    peer = igl.cotmatrix_entries(v, f)
    assert _rel(cotangent_entries(v, f), peer) < 1e-13


# libigl: tests/test_all.py::test_operators (massmatrix with the default, barycentric and
# Voronoi types); tests/test_basic.py::test_massmatrix
@pytest.mark.parametrize("name", ALL)
def test_massmatrix(name: str) -> None:
    v, f = _mesh(name)
    default = igl.massmatrix(v, f).diagonal()
    voronoi = igl.massmatrix(v, f, type=igl.MASSMATRIX_TYPE_VORONOI).diagonal()
    bary = igl.massmatrix(v, f, type=igl.MASSMATRIX_TYPE_BARYCENTRIC).diagonal()
    assert _rel(mass_matrix(v, f).diagonal(), default) < 1e-13        # same default kind
    assert _rel(mass_matrix(v, f, "voronoi").diagonal(), voronoi) < 1e-13
    assert _rel(mass_matrix(v, f, "barycentric").diagonal(), bary) < 1e-13


# libigl: tests/test_all.py::test_normals_and_distances (igl.doublearea);
# tests/test_basic.py::test_doublearea
@pytest.mark.parametrize("name", ALL)
def test_doublearea(name: str) -> None:
    v, f = _mesh(name)
    assert _rel(2.0 * face_areas(v, f), igl.doublearea(v, f)) < 1e-14


# libigl: tests/test_all.py::test_normals_and_distances (igl.per_face_normals with
# Z = (0, 0, 1) for degenerate faces); tests/test_basic.py::test_per_face_normals
@pytest.mark.parametrize("name", ALL)
def test_per_face_normals(name: str) -> None:
    v, f = _mesh(name)
    peer = igl.per_face_normals(v, f, np.array([0.0, 0.0, 1.0]))
    assert_allclose(face_normals(v, f), peer, atol=1e-14)


# libigl: tests/test_basic.py::test_internal_angles
@pytest.mark.parametrize("name", ALL)
def test_internal_angles(name: str) -> None:
    v, f = _mesh(name)
    assert_allclose(face_angles(v, f), igl.internal_angles(v, f), atol=1e-14)


# libigl: tests/test_all.py::test_operators (igl.edges(F)); tests/test_basic.py::test_edges
@pytest.mark.parametrize("name", ALL)
def test_edges(name: str) -> None:
    _, f = _mesh(name)
    peer = np.sort(igl.edges(f), axis=1)
    peer = peer[np.lexsort(peer.T[::-1])]
    assert_array_equal(edges(f), peer)


# libigl: tests/test_all.py::test_operators (igl.vertex_components(F));
# tests/test_basic.py::test_vertex_components
@pytest.mark.parametrize("name", ALL)
def test_vertex_components(name: str) -> None:
    v, f = _mesh(name)
    count, labels = components(len(v), edges(f))
    peer = igl.vertex_components(f)
    assert count == int(peer.max()) + 1
    # the same partition (labels may be numbered differently)
    pairs = np.unique(np.c_[labels, peer], axis=0)
    assert len(pairs) == count


def _canonical(loop: np.ndarray) -> list[int]:
    return np.roll(loop, -int(np.argmin(loop))).tolist()


# libigl: tests/test_all.py::test_boundary_loop (a tetrahedron upsampled once, Loop-
# subdivided once, its first and last faces removed: two holes)
def test_boundary_loop_all_two_holes() -> None:
    v, f = _tet()
    v, f = igl.upsample(v, f, number_of_subdivs=1)
    v, f = igl.loop(v, f, number_of_subdivs=1)
    f = f[1:-1]
    ours = sorted(_canonical(lp) for lp in boundary_loops(f))
    peer = sorted(_canonical(np.asarray(lp)) for lp in igl.boundary_loop_all(f))
    assert len(ours) == 2
    assert ours == peer                               # same loops, same direction


# libigl: tests/test_basic.py::test_boundary_loop, ::test_all_boundary_loop (on the
# pyvista sphere with a band of faces removed: one loop; and with a cap removed too: two)
@pytest.mark.parametrize("zs", [(0.25,), (0.25, -0.2)])
def test_boundary_loop_real(zs: tuple[float, ...]) -> None:
    v, f = _mesh("sphere.ply")
    v = (v - v.mean(axis=0)) / np.ptp(v, axis=0).max()
    z = v[f][:, :, 2]
    keep = (z < zs[0]).all(axis=1)
    if len(zs) > 1:
        keep &= (z > zs[1]).all(axis=1)
    f = f[keep]
    ours = boundary_loops(f)
    peer = [np.asarray(lp) for lp in igl.boundary_loop_all(f)]
    assert len(ours) == len(peer) == len(zs)
    assert sorted(map(_canonical, ours)) == sorted(map(_canonical, peer))
    # igl.boundary_loop returns the longest loop
    assert _canonical(ours[0]) == _canonical(np.asarray(igl.boundary_loop(f)))
