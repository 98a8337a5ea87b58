"""Cases ported from libigl's own Python tests of ``igl.grad``, each naming the original:
``tests/test_all.py::test_operators`` (libigl-python-bindings 2.6) and the older
``tests/test_basic.py::test_grad`` (removed in 2.6; read at commit 90a8801), which check
its shape on libigl's data files. Ported as a comparison with ``igl.grad`` on the same
call, on the test's triangulated square, a tetrahedron (libigl's ``single_tet``, as a
volume mesh) and the surface meshes in pyvista's wheel.

Convention: ``gradient_operator`` stacks each face's ``d`` components together (row
``f d + c``); ``igl.grad`` stacks all faces' ``x`` components, then ``y``, then ``z`` (row
``c m + f``): the same operator with its rows permuted."""

from __future__ import annotations

import igl
import numpy as np
import pytest
from numpy.testing import assert_allclose

from algorithms.core.mesh import face_normals
from algorithms.interpolation._faces import gradient_operator
from tests.algorithms.registration._real_meshes import real_mesh


def _mesh(name: str) -> tuple[np.ndarray, np.ndarray]:
    if name == "square":   # libigl: tests/test_all.py::triangulated_square
        return (np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float),
                np.array([[0, 1, 2], [0, 2, 3]]))
    if name == "tet":      # libigl: tests/test_all.py::single_tet (V, T)
        return (np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float),
                np.array([[0, 1, 2, 3]]))
    m = real_mesh(name)
    return np.asarray(m.vertices, float), np.asarray(m.faces, np.int64)


# libigl: tests/test_all.py::test_operators (G = igl.grad(V, F));
# tests/test_basic.py::test_grad
@pytest.mark.parametrize("name", ["square", "tet", "sphere.ply", "ant.ply", "airplane.ply"])
def test_grad(name: str) -> None:
    v, f = _mesh(name)
    m, d = len(f), v.shape[1]
    ours = gradient_operator(v, f)
    peer = igl.grad(v, f)
    assert ours.shape == peer.shape == (m * d, len(v))
    order = (np.arange(d)[None, :] * m + np.arange(m)[:, None]).ravel()  # face-major rows
    peer = peer.toarray()[order]
    scale = np.abs(peer).max()
    # measured: 3e-15 (sphere), 4e-14 (airplane), 6e-12 (ant) relative; ours solves each
    # face's 2×2 normal equations of its edge frame, libigl uses rotated edge vectors
    assert np.abs(ours.toarray() - peer).max() < 1e-10 * scale
    # on a linear function: its gradient on every face (projected onto a triangle's plane)
    g = np.array([0.3, -1.2, 0.7])
    expected = np.tile(g, (m, 1))
    if f.shape[1] == 3:
        n = face_normals(v, f)
        expected -= (n @ g)[:, None] * n
    assert_allclose((ours @ (v @ g)).reshape(m, d), expected, atol=1e-9)
