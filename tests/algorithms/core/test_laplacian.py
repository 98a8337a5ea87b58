"""Tests for algorithms.core.laplacian: weights, Laplacians (L = D - W) and mass matrices,
against hand computations, invariants and libigl."""

from __future__ import annotations

import igl
import numpy as np
import pytest
import scipy.sparse as sp
import trimesh
from scipy.sparse.csgraph import laplacian as csgraph_laplacian

from algorithms.core import InvalidInputError
from algorithms.core.laplacian import (
    cotangent_entries,
    cotangent_laplacian,
    cotangent_weights,
    face_weights,
    laplacian,
    mass_matrix,
    mesh_laplacian,
    normalized_laplacian,
    tangent_entries,
    tangent_weights,
    uniform_weights,
)
from algorithms.core.mesh import boundary_loops, edges, face_angles, face_areas

KINDS = ("uniform", "cotangent", "tangent")


def bumpy_sphere(subdivisions: int = 2, seed: int = 0):
    m = trimesh.creation.icosphere(subdivisions=subdivisions)
    rng = np.random.default_rng(seed)
    v = np.asarray(m.vertices) * rng.uniform(0.7, 1.3, (len(m.vertices), 1))
    return v, np.asarray(m.faces, dtype=np.int64)


def obtuse_grid(nx: int = 9, ny: int = 7, seed: int = 1):
    """A strongly jittered planar grid: many obtuse triangles, some negative cot weights."""
    rng = np.random.default_rng(seed)
    x, y = np.meshgrid(np.linspace(0, 1, nx), np.linspace(0, 0.6, ny))
    v = np.c_[x.ravel(), y.ravel()]
    inner = (x.ravel() > 0) & (x.ravel() < 1) & (y.ravel() > 0) & (y.ravel() < 0.6)
    v[inner] += rng.uniform(-0.35, 0.35, (inner.sum(), 2)) / nx
    idx = np.arange(nx * ny).reshape(ny, nx)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel()
    return v, np.r_[np.c_[a, b, d], np.c_[a, d, c]].astype(np.int64)


def lift(v2):
    return np.c_[v2, np.zeros(len(v2))]


def triangular_lattice(n: int = 6):
    """Equilateral triangles (incentre = circumcentre)."""
    pts, idx = [], {}
    for j in range(n):
        for i in range(n):
            idx[i, j] = len(pts)
            pts.append([i + 0.5 * j, j * np.sqrt(3) / 2])
    faces = []
    for j in range(n - 1):
        for i in range(n - 1):
            faces.append([idx[i, j], idx[i + 1, j], idx[i, j + 1]])
            faces.append([idx[i + 1, j], idx[i + 1, j + 1], idx[i, j + 1]])
    return np.array(pts), np.array(faces, dtype=np.int64)


# --- hand-computed cases ------------------------------------------------------------------


def test_right_triangle_by_hand():
    # corner 0 at the right angle: ½cot 90° = 0 on edge (1, 2); ½cot 45° = ½ on the legs
    v = np.array([[0, 0], [1, 0], [0, 1]], dtype=float)
    f = np.array([[0, 1, 2]])
    np.testing.assert_allclose(cotangent_entries(v, f), [[0.0, 0.5, 0.5]], atol=1e-15)
    L = cotangent_laplacian(v, f).toarray()
    np.testing.assert_allclose(L, [[1, -0.5, -0.5], [-0.5, 0.5, 0], [-0.5, 0, 0.5]], atol=1e-15)
    # tangent: r = A / s = 0.5 / ((2 + √2) / 2); weight r / ℓ per edge
    r = 0.5 / ((2 + np.sqrt(2)) / 2)
    np.testing.assert_allclose(tangent_entries(v, f), [[r / np.sqrt(2), r, r]])


def test_uniform_laplacian_of_a_triangle():
    L = mesh_laplacian([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]], kind="uniform")
    assert L.toarray().tolist() == [[2, -1, -1], [-1, 2, -1], [-1, -1, 2]]


def test_tangent_equals_cotangent_on_equilateral_triangles():
    v, f = triangular_lattice()
    np.testing.assert_allclose(mesh_laplacian(v, f, "tangent").toarray(),
                               mesh_laplacian(v, f, "cotangent").toarray(), atol=1e-12)


# --- agreement with libigl ----------------------------------------------------------------


@pytest.mark.parametrize("make", [bumpy_sphere, lambda: (lift(obtuse_grid()[0]), obtuse_grid()[1])])
def test_cotangent_laplacian_is_minus_igl_cotmatrix(make):
    v, f = make()
    ours = cotangent_laplacian(v, f)
    ref = igl.cotmatrix(v, f)
    assert isinstance(ours, sp.csr_array)
    assert abs(ours + ref).max() <= 1e-12
    assert abs(mesh_laplacian(v, f, "cotangent") - cotangent_laplacian(v, f)).max() == 0


def test_cotangent_laplacian_of_planar_mesh_matches_igl_lifted():
    v, f = obtuse_grid()
    assert abs(cotangent_laplacian(v, f) + igl.cotmatrix(lift(v), f)).max() <= 1e-12


def test_cotangent_entries_match_igl():
    v, f = bumpy_sphere()
    np.testing.assert_allclose(cotangent_entries(v, f), igl.cotmatrix_entries(v, f), atol=1e-12)


def test_cotangent_weights_are_minus_offdiagonal_of_igl():
    v, f = bumpy_sphere()
    ref = igl.cotmatrix(v, f)
    ref = ref - sp.diags(ref.diagonal())
    assert abs(cotangent_weights(v, f) - ref).max() <= 1e-12


@pytest.mark.parametrize("kind, igl_type", [("voronoi", igl.MASSMATRIX_TYPE_VORONOI),
                                            ("barycentric", igl.MASSMATRIX_TYPE_BARYCENTRIC)])
@pytest.mark.parametrize("make", [bumpy_sphere, lambda: (lift(obtuse_grid()[0]), obtuse_grid()[1])])
def test_mass_matrix_matches_igl(kind, igl_type, make):
    v, f = make()
    ours = mass_matrix(v, f, kind)
    ref = igl.massmatrix(v, f, igl_type)
    assert abs(ours - ref).max() <= 1e-14
    assert (ours - sp.diags_array(ours.diagonal())).count_nonzero() == 0
    np.testing.assert_allclose(ours.diagonal().sum(), face_areas(v, f).sum(), rtol=1e-12)


def test_voronoi_mass_uses_obtuse_rule():
    # obtuse at corner 0: it gets half the area, the others a quarter each
    v = np.array([[0, 0.1], [-1, 0], [1, 0]])
    m = mass_matrix(v, [[0, 1, 2]], "voronoi").diagonal()
    area = 0.1
    np.testing.assert_allclose(m, [area / 2, area / 4, area / 4])


def test_mass_matrix_zero_for_unreferenced_vertex():
    v = np.array([[0, 0], [1, 0], [0, 1], [4, 4]], dtype=float)
    assert mass_matrix(v, [[0, 1, 2]]).diagonal()[3] == 0


# --- invariants ---------------------------------------------------------------------------


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("make", [bumpy_sphere, obtuse_grid])
def test_laplacians_are_symmetric_psd_with_zero_row_sums(kind, make):
    v, f = make()
    L = mesh_laplacian(v, f, kind)
    dense = L.toarray()
    np.testing.assert_allclose(dense.sum(axis=1), 0, atol=1e-12)
    np.testing.assert_allclose(dense, dense.T, atol=1e-14)
    smallest = np.linalg.eigvalsh(dense)[0]
    assert smallest >= -1e-10 * np.abs(dense).max()


@pytest.mark.parametrize("kind", KINDS)
def test_quadratic_form_is_sum_over_edges(kind):
    v, f = obtuse_grid()
    L = mesh_laplacian(v, f, kind)
    W = sp.diags_array(L.diagonal()) - L
    e = edges(f)
    x = np.random.default_rng(0).standard_normal(len(v))
    w = np.asarray(W[e[:, 0], e[:, 1]]).ravel()
    np.testing.assert_allclose(x @ (L @ x), np.sum(w * (x[e[:, 0]] - x[e[:, 1]]) ** 2), rtol=1e-10)


def test_tangent_weights_positive_where_cotangent_weights_are_negative():
    v, f = obtuse_grid()
    cot = cotangent_weights(v, f)
    tan = tangent_weights(v, f)
    assert (cot.data < 0).any()                     # the mesh does have the problem
    assert (tan.data > 0).all()
    assert np.array_equal(np.sort(cot.indices), np.sort(tan.indices))   # same edges


def test_tangent_entries_equal_half_angle_formula():
    v, f = obtuse_grid()
    half = np.tan(face_angles(v, f) / 2)
    # the edge opposite corner k joins corners k+1 and k+2
    a, b = half[:, [1, 2, 0]], half[:, [2, 0, 1]]
    np.testing.assert_allclose(tangent_entries(v, f), a * b / (a + b), rtol=1e-12)


def test_cotangent_has_linear_precision_at_interior_vertices():
    v, f = obtuse_grid()
    L = cotangent_laplacian(v, f)
    boundary = boundary_loops(f)[0]
    interior = np.setdiff1d(np.arange(len(v)), boundary)
    lx = L @ (2 * v[:, 0] - 3 * v[:, 1] + 1)
    np.testing.assert_allclose(lx[interior], 0, atol=1e-12)


def test_laplacian_of_weights_equals_mesh_laplacian():
    v, f = bumpy_sphere(1)
    for kind, w in (("cotangent", cotangent_weights(v, f)), ("tangent", tangent_weights(v, f)),
                    ("uniform", uniform_weights(len(v), f))):
        assert abs(laplacian(w) - mesh_laplacian(v, f, kind)).max() <= 1e-13


def test_uniform_weights_are_the_adjacency():
    v, f = bumpy_sphere(1)
    W = uniform_weights(len(v), f)
    assert set(W.data.tolist()) == {1.0}
    assert W.nnz == 2 * edges(f).shape[0]
    np.testing.assert_array_equal(laplacian(W).toarray(), csgraph_laplacian(W.toarray()))


def test_face_weights_with_custom_entries():
    f = np.array([[0, 1, 2], [2, 1, 3]])
    W = face_weights(4, f, np.ones((2, 3))).toarray()
    assert W[1, 2] == 2 and W[2, 1] == 2 and W[0, 3] == 0 and W[0, 1] == 1


def test_laplacian_ignores_diagonal_of_weights():
    W = sp.csr_array(np.array([[5.0, 1], [1, 7]]))
    assert laplacian(W).toarray().tolist() == [[1, -1], [-1, 1]]


# --- normalised Laplacians ----------------------------------------------------------------


def test_symmetric_normalized_matches_scipy():
    v, f = bumpy_sphere(1)
    W = tangent_weights(v, f)
    ours = normalized_laplacian(W, "symmetric")
    ref = csgraph_laplacian(W.toarray(), normed=True)
    np.testing.assert_allclose(ours.toarray(), ref, atol=1e-14)


def test_row_normalized_is_inverse_degree_times_laplacian():
    v, f = obtuse_grid()
    W = uniform_weights(len(v), f)
    ours = normalized_laplacian(W, "row").toarray()
    d = W.sum(axis=1)
    np.testing.assert_allclose(ours, laplacian(W).toarray() / d[:, None], atol=1e-15)
    np.testing.assert_allclose(ours.sum(axis=1), 0, atol=1e-14)
    np.testing.assert_allclose(np.diag(ours), 1.0)


def test_normalized_isolated_vertex_row_is_zero():
    W = sp.csr_array(np.array([[0, 1.0, 0], [1, 0, 0], [0, 0, 0]]))
    for kind in ("row", "symmetric"):
        out = normalized_laplacian(W, kind).toarray()
        assert np.isfinite(out).all() and out[2].tolist() == [0, 0, 0]


def test_symmetric_normalized_rejects_negative_degree():
    W = sp.csr_array(np.array([[0, -1.0], [-1.0, 0]]))
    with pytest.raises(InvalidInputError, match=r"`W` to have non-negative degrees .* got -1\.0 at "
                       r"row 0\.") as info:
        normalized_laplacian(W, "symmetric")
    assert info.value.field == "W"


def test_rejects_unknown_kinds_and_non_square():
    v, f = bumpy_sphere(1)
    with pytest.raises(InvalidInputError, match=r"`kind` to be one of 'uniform', 'cotangent', "
                       r"'tangent', got 'harmonic'"):
        mesh_laplacian(v, f, "harmonic")
    with pytest.raises(InvalidInputError, match=r"`kind` to be one of 'voronoi', 'barycentric'"):
        mass_matrix(v, f, "full")
    with pytest.raises(InvalidInputError, match=r"`kind` to be one of 'row', 'symmetric'"):
        normalized_laplacian(uniform_weights(len(v), f), "random-walk")
    with pytest.raises(InvalidInputError, match=r"`W` to be a square \(n, n\) matrix, got shape "
                       r"\(2, 3\)"):
        laplacian(np.zeros((2, 3)))
    with pytest.raises(InvalidInputError, match=r"`W` to be a square"):
        normalized_laplacian(np.zeros((2, 3)))
