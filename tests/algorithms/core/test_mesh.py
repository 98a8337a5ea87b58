"""Tests for algorithms.core.mesh: validation of meshes and handles, combinatorics, metrics."""

from __future__ import annotations

import pickle

import igl
import numpy as np
import pytest
import trimesh

from algorithms.core import DegenerateInputError, InvalidInputError
from algorithms.core.mesh import (
    FACE_BLOCK,
    Handles,
    Mesh,
    as_handles,
    as_mesh,
    boundary_edges,
    boundary_loops,
    components,
    degenerate_faces,
    edges,
    face_angles,
    face_areas,
    face_normals,
    signed_areas,
)


def grid(nx: int = 5, ny: int = 4, jitter: float = 0.0, seed: int = 0):
    """A planar grid of (nx × ny) vertices split into counter-clockwise triangles."""
    rng = np.random.default_rng(seed)
    x, y = np.meshgrid(np.linspace(0, 1, nx), np.linspace(0, 1, ny))
    v = np.c_[x.ravel(), y.ravel()]
    v += rng.uniform(-jitter, jitter, v.shape) / max(nx, ny)
    idx = np.arange(nx * ny).reshape(ny, nx)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel()
    return v, np.r_[np.c_[a, b, d], np.c_[a, d, c]].astype(np.int64)


def annulus(n_around: int = 16, n_rings: int = 3):
    """A planar ring: two boundary loops, the outer one longer when sampled denser."""
    rings = []
    for k in range(n_rings):
        r = 1.0 + k / (n_rings - 1)
        m = n_around * (k + 1)
        t = np.linspace(0, 2 * np.pi, m, endpoint=False)
        rings.append(np.c_[r * np.cos(t), r * np.sin(t)])
    v = np.vstack(rings)
    tri = __import__("scipy.spatial", fromlist=["Delaunay"]).Delaunay(v)
    f = tri.simplices
    centroid_r = np.linalg.norm(v[f].mean(axis=1), axis=1)
    return v, f[centroid_r > 1.0 + 1e-9].astype(np.int64)


def sphere(subdivisions: int = 2):
    m = trimesh.creation.icosphere(subdivisions=subdivisions)
    return np.asarray(m.vertices, dtype=np.float64), np.asarray(m.faces, dtype=np.int64)


# --- as_mesh ------------------------------------------------------------------------------


def test_as_mesh_returns_checked_arrays():
    m = as_mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    assert isinstance(m, Mesh)
    assert m.vertices.dtype == np.float64 and m.faces.dtype == np.int64
    assert (m.n_vertices, m.n_faces, m.dim) == (3, 1, 3)
    assert "n_vertices=3" in repr(m)


def test_as_mesh_accepts_planar_integral_floats_and_unreferenced_vertices():
    m = as_mesh([[0, 0], [1, 0], [0, 1], [5, 5]], [[0.0, 1.0, 2.0]])
    assert m.dim == 2 and m.faces.tolist() == [[0, 1, 2]]


def test_as_mesh_pickles():
    v, f = grid()
    m = pickle.loads(pickle.dumps(as_mesh(v, f)))
    np.testing.assert_array_equal(m.faces, f)


@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_as_mesh_rejects_nonfinite_vertices(bad):
    v, f = grid()
    v[7, 1] = bad
    with pytest.raises(InvalidInputError, match=r"`mesh\.vertices` to hold finite numbers, "
                       r"got (nan|inf) at row 7\.") as info:
        as_mesh(v, f)
    assert info.value.field == "mesh.vertices"


@pytest.mark.parametrize("shape", [(5,), (5, 1), (5, 4)])
def test_as_mesh_rejects_vertex_shapes(shape):
    with pytest.raises(InvalidInputError, match=r"`mesh\.vertices`") as info:
        as_mesh(np.zeros(shape), [[0, 1, 2]])
    assert info.value.field == "mesh.vertices"


def test_as_mesh_rejects_four_coordinates_naming_the_choice():
    with pytest.raises(InvalidInputError, match=r"\(n, 2\) or \(n, 3\) array .* got shape \(5, 4\)"):
        as_mesh(np.zeros((5, 4)), [[0, 1, 2]])


def test_as_mesh_rejects_too_many_vertices():
    v, f = grid()
    with pytest.raises(InvalidInputError, match=r"at most 10 points, got 20") as info:
        as_mesh(v, f, max_vertices=10)
    assert info.value.field == "mesh.vertices"


@pytest.mark.parametrize("faces, shape", [([0, 1, 2], r"\(3,\)"), ([[0, 1, 2, 3]], r"\(1, 4\)"),
                                          ([[0, 1]], r"\(1, 2\)")])
def test_as_mesh_rejects_face_shapes(faces, shape):
    with pytest.raises(InvalidInputError, match=rf"`mesh\.faces` to be an \(m, 3\) array of "
                       rf"vertex indices, got shape {shape}\.") as info:
        as_mesh(np.zeros((4, 3)), faces)
    assert info.value.field == "mesh.faces"


def test_as_mesh_rejects_ragged_faces():
    with pytest.raises(InvalidInputError, match=r"`mesh\.faces` .*ragged") as info:
        as_mesh(np.eye(3), [[0, 1, 2], [0, 1]])
    assert info.value.field == "mesh.faces"


def test_as_mesh_rejects_empty_faces():
    with pytest.raises(InvalidInputError, match=r"`mesh\.faces` to hold at least 1 face, got 0"):
        as_mesh(np.eye(3), np.zeros((0, 3), dtype=int))


def test_as_mesh_rejects_index_out_of_range_naming_the_row():
    v, f = grid()
    f[3, 2] = 20
    with pytest.raises(InvalidInputError, match=r"`mesh\.faces` to hold vertex indices below 20, "
                       r"got 20 at row 3\.") as info:
        as_mesh(v, f)
    assert info.value.field == "mesh.faces"


def test_as_mesh_rejects_negative_index():
    with pytest.raises(InvalidInputError, match=r"non-negative vertex indices, got -1 at row 0"):
        as_mesh(np.eye(3), [[0, 1, -1]])


def test_as_mesh_rejects_non_integral_index():
    with pytest.raises(InvalidInputError, match=r"integer vertex indices, got 1\.5 at row 0"):
        as_mesh(np.eye(3), [[0, 1.5, 2]])


def test_as_mesh_rejects_boolean_faces():
    with pytest.raises(InvalidInputError, match=r"`mesh\.faces` .*dtype bool"):
        as_mesh(np.eye(3), [[True, False, True]])


def test_as_mesh_rejects_repeated_vertex_in_face():
    v, f = grid()
    f[5] = [4, 9, 4]
    with pytest.raises(InvalidInputError, match=r"three distinct vertex indices per face, got "
                       r"\[4, 9, 4\] at row 5\.") as info:
        as_mesh(v, f)
    assert info.value.field == "mesh.faces"


def test_as_mesh_rejects_zero_area_face_naming_it():
    v = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0]], dtype=float)
    f = [[0, 1, 3], [0, 1, 2]]                       # the second is collinear
    with pytest.raises(DegenerateInputError, match=r"non-zero area, got a degenerate \(zero-area\) "
                       r"face \[0, 1, 2\] at row 1\.") as info:
        as_mesh(v, f)
    assert info.value.field == "mesh.faces"
    assert isinstance(info.value, InvalidInputError)
    assert as_mesh(v, f, allow_degenerate=True).n_faces == 2


def test_as_mesh_counts_degenerate_faces():
    v = np.array([[0, 0], [1, 0], [2, 0], [3, 0], [0, 1]], dtype=float)
    with pytest.raises(DegenerateInputError, match=r"at row 1 \(2 degenerate faces in all\)"):
        as_mesh(v, [[0, 1, 4], [0, 1, 2], [1, 2, 3]])


def test_degenerate_faces_across_blocks():
    # faces made collinear on both sides of block boundaries (the check runs block by
    # block): exactly those are flagged, and as_mesh names the first and counts them all
    v, f = grid(150, 60)
    assert f.shape[0] > 2 * FACE_BLOCK
    v = np.c_[v, np.zeros(len(v))]
    bad = [3, FACE_BLOCK - 1, FACE_BLOCK, 2 * FACE_BLOCK + 7, f.shape[0] - 1]
    for row in bad:   # the third corner moved onto the line through the first two
        a, b, c = f[row]
        v = np.r_[v, [v[a] + 0.25 * (v[b] - v[a])]]
        f[row] = [a, b, len(v) - 1]
    expected = np.zeros(f.shape[0], dtype=bool)
    expected[bad] = True
    np.testing.assert_array_equal(degenerate_faces(v, f), expected)
    with pytest.raises(DegenerateInputError, match=r"at row 3 \(5 degenerate faces in all\)"):
        as_mesh(v, f)
    f[3] = grid(150, 60)[1][3]
    with pytest.raises(DegenerateInputError, match=rf"at row {FACE_BLOCK - 1} \(4 degenerate"):
        as_mesh(v, f)


def test_as_mesh_rejects_coincident_corners():
    v = np.array([[0, 0, 0], [1, 0, 0], [1, 0, 0]], dtype=float)
    with pytest.raises(DegenerateInputError, match=r"face \[0, 1, 2\] at row 0"):
        as_mesh(v, [[0, 1, 2]])


def test_as_mesh_custom_name_in_field():
    with pytest.raises(InvalidInputError) as info:
        as_mesh(np.eye(3), [[0, 1, 7]], name="target")
    assert info.value.field == "target.faces"
    assert "`target.faces`" in str(info.value)


def test_as_mesh_keeps_thin_but_valid_triangles():
    v = np.array([[0, 0], [1, 0], [0.5, 1e-9]])
    assert as_mesh(v, [[0, 1, 2]]).n_faces == 1


# --- as_handles ---------------------------------------------------------------------------


@pytest.fixture
def mesh3d() -> Mesh:
    return as_mesh(*sphere(1))


def test_as_handles_from_mapping(mesh3d):
    h = as_handles({"indices": [3, 1.0], "positions": [[0, 0, 1], [1, 2, 3]]}, mesh3d)
    assert isinstance(h, Handles)
    assert h.indices.dtype == np.int64 and h.indices.tolist() == [3, 1]
    np.testing.assert_array_equal(h.positions, [[0, 0, 1], [1, 2, 3]])
    assert as_handles(h, mesh3d).indices is h.indices
    assert "p=2" in repr(h)


def test_as_handles_without_mesh_checks_structure_only():
    h = as_handles({"indices": [10**6], "positions": [[0.0, 1.0]]}, None)
    assert h.indices.tolist() == [10**6]
    with pytest.raises(InvalidInputError, match=r"below 5"):
        as_handles(h, 5)


def test_as_handles_rejects_non_mapping(mesh3d):
    with pytest.raises(InvalidInputError, match=r"`handles` to be an object with keys 'indices' "
                       r"and 'positions', got list\.") as info:
        as_handles([1, 2], mesh3d)
    assert info.value.field == "handles"


def test_as_handles_rejects_missing_and_unknown_keys(mesh3d):
    with pytest.raises(InvalidInputError, match=r"got missing 'positions'\."):
        as_handles({"indices": [1]}, mesh3d)
    with pytest.raises(InvalidInputError, match=r"got unknown key 'weights'\."):
        as_handles({"indices": [1], "positions": [[0, 0, 0]], "weights": [1]}, mesh3d)


def test_as_handles_rejects_out_of_range(mesh3d):
    n = mesh3d.n_vertices
    with pytest.raises(InvalidInputError, match=rf"`handles\.indices` to hold vertex indices below "
                       rf"{n}, got {n} at position 1\.") as info:
        as_handles({"indices": [0, n], "positions": [[0, 0, 0], [1, 1, 1]]}, mesh3d)
    assert info.value.field == "handles.indices"


def test_as_handles_rejects_duplicate_indices(mesh3d):
    with pytest.raises(InvalidInputError, match=r"`handles\.indices` to be unique, got 4 twice "
                       r"\(positions 1 and 3\)\.") as info:
        as_handles({"indices": [2, 4, 5, 4], "positions": np.zeros((4, 3))}, mesh3d)
    assert info.value.field == "handles.indices"


def test_as_handles_rejects_2d_indices(mesh3d):
    with pytest.raises(InvalidInputError, match=r"flat list of vertex indices, got shape \(1, 2\)"):
        as_handles({"indices": [[1, 2]], "positions": np.zeros((2, 3))}, mesh3d)


def test_as_handles_rejects_empty(mesh3d):
    with pytest.raises(InvalidInputError, match=r"`handles\.indices` to hold at least 1 index"):
        as_handles({"indices": [], "positions": []}, mesh3d)


def test_as_handles_rejects_wrong_dimension(mesh3d):
    with pytest.raises(InvalidInputError, match=r"`handles\.positions` to be an \(n, 3\) array .*"
                       r"got shape \(1, 2\)") as info:
        as_handles({"indices": [1], "positions": [[0, 0]]}, mesh3d)
    assert info.value.field == "handles.positions"


def test_as_handles_rejects_count_mismatch(mesh3d):
    with pytest.raises(InvalidInputError, match=r"`handles\.positions` to hold one row per index "
                       r"\(2\), got 1\."):
        as_handles({"indices": [1, 2], "positions": [[0, 0, 0]]}, mesh3d)


def test_as_handles_rejects_nan_position(mesh3d):
    with pytest.raises(InvalidInputError, match=r"`handles\.positions` to hold finite numbers, got "
                       r"nan at row 1\."):
        as_handles({"indices": [1, 2], "positions": [[0, 0, 0], [0, np.nan, 0]]}, mesh3d)


# --- combinatorics ------------------------------------------------------------------------


def test_edges_hand_case():
    assert edges([[0, 1, 2], [2, 1, 3]]).tolist() == [[0, 1], [0, 2], [1, 2], [1, 3], [2, 3]]


def test_edges_euler_characteristic_of_sphere():
    v, f = sphere(2)
    e = edges(f)
    assert v.shape[0] - e.shape[0] + f.shape[0] == 2
    assert (e[:, 0] < e[:, 1]).all()
    assert (np.diff(e[:, 0] * len(v) + e[:, 1]) > 0).all()        # strictly sorted, unique


def test_edges_match_igl():
    v, f = sphere(2)
    ref = np.sort(igl.edges(f), axis=1)
    ref = ref[np.lexsort((ref[:, 1], ref[:, 0]))]
    np.testing.assert_array_equal(edges(f), ref)


def test_boundary_edges_of_grid_follow_face_orientation():
    v, f = grid(4, 3)
    be = boundary_edges(f)
    assert be.shape[0] == 2 * (4 - 1) + 2 * (3 - 1)
    # counter-clockwise faces: the boundary runs counter-clockwise, interior on the left
    d = v[be[:, 1]] - v[be[:, 0]]
    mid = 0.5 * (v[be[:, 1]] + v[be[:, 0]])
    to_centre = np.array([0.5, 0.5]) - mid
    assert ((d[:, 0] * to_centre[:, 1] - d[:, 1] * to_centre[:, 0]) > 0).all()


def test_boundary_edges_closed_mesh_is_empty():
    assert boundary_edges(sphere(1)[1]).shape == (0, 2)
    assert boundary_loops(sphere(1)[1]) == []


def test_boundary_loops_of_disk_match_igl():
    v, f = grid(6, 5, jitter=0.2)
    (loop,) = boundary_loops(f)
    ref = np.asarray(igl.boundary_loop(f))
    assert loop.shape == ref.shape and loop[0] == loop.min()
    # same cycle, up to where it starts and its direction
    doubled = np.concatenate([ref, ref])
    start = int(np.flatnonzero(ref == loop[0])[0])
    fwd = doubled[start:start + len(ref)]
    bwd = np.roll(ref[::-1], -int(np.flatnonzero(ref[::-1] == loop[0])[0]))
    assert np.array_equal(loop, fwd) or np.array_equal(loop, bwd)
    # consecutive loop vertices are boundary edges in face orientation
    be = {tuple(e) for e in boundary_edges(f).tolist()}
    assert all((int(a), int(b)) in be for a, b in zip(loop, np.roll(loop, -1)))


def test_boundary_loops_of_annulus_longest_first():
    v, f = annulus(12, 3)
    loops = boundary_loops(f)
    assert [len(lp) for lp in loops] == [36, 12]
    assert set(loops[0].tolist()) == set(range(36, 72))
    assert set(loops[1].tolist()) == set(range(12))


def test_components_counts_isolated_vertices():
    f = np.array([[0, 1, 2], [3, 4, 5]])
    count, labels = components(7, edges(f))
    assert count == 3
    assert labels.tolist() == [0, 0, 0, 1, 1, 1, 2]


def test_components_match_igl_vertex_components():
    v, f = sphere(1)
    f2 = np.vstack([f, f + len(v)])
    count, labels = components(2 * len(v), edges(f2))
    ref = igl.vertex_components(f2)
    assert count == 2
    np.testing.assert_array_equal(labels, ref)


def test_components_numbered_by_smallest_vertex():
    count, labels = components(5, [[4, 3], [1, 2]])
    assert count == 3 and labels.tolist() == [0, 1, 1, 2, 2]


# --- metrics ------------------------------------------------------------------------------


def test_one_triangle_by_hand():
    v = np.array([[0, 0, 0], [2, 0, 0], [0, 1, 0]], dtype=float)
    f = np.array([[0, 1, 2]])
    np.testing.assert_allclose(face_areas(v, f), [1.0])
    np.testing.assert_allclose(face_normals(v, f), [[0, 0, 1]])
    np.testing.assert_allclose(face_angles(v, f), [[np.pi / 2, np.arctan(0.5), np.arctan(2.0)]])
    np.testing.assert_allclose(signed_areas(v[:, :2], f), [1.0])
    np.testing.assert_allclose(signed_areas(v[:, :2], f[:, ::-1]), [-1.0])


def test_face_areas_of_a_planar_mesh_are_its_signed_areas_up_to_sign():
    v, f = grid(6, 5, jitter=0.1, seed=4)
    flipped = f.copy()
    flipped[::2] = flipped[::2, ::-1]
    expected = np.abs(signed_areas(v, flipped))
    np.testing.assert_allclose(face_areas(v, flipped), expected, rtol=1e-14)
    # the same mesh in space, tilted by a rotation: the same areas
    rot = np.linalg.qr(np.random.default_rng(4).standard_normal((3, 3)))[0]
    v3 = np.c_[v, np.zeros(len(v))] @ rot.T
    np.testing.assert_allclose(face_areas(v3, flipped), expected, rtol=1e-12)


def test_planar_normals_point_up_or_down():
    v, f = grid(3, 3)
    np.testing.assert_allclose(face_normals(v, f), np.tile([0, 0, 1.0], (len(f), 1)))
    np.testing.assert_allclose(face_normals(v, f[:, ::-1]), np.tile([0, 0, -1.0], (len(f), 1)))


def test_metrics_match_igl():
    v, f = sphere(2)
    v = v * np.random.default_rng(3).uniform(0.8, 1.2, (len(v), 1))
    np.testing.assert_allclose(face_areas(v, f), 0.5 * igl.doublearea(v, f), rtol=1e-12)
    np.testing.assert_allclose(face_angles(v, f), igl.internal_angles(v, f), atol=1e-12)
    np.testing.assert_allclose(face_normals(v, f), igl.per_face_normals(v, f, np.zeros(3)),
                               atol=1e-12)
    np.testing.assert_allclose(face_angles(v, f).sum(axis=1), np.pi, atol=1e-12)


def test_zero_area_normal_is_zero_not_nan():
    v = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0]], dtype=float)
    assert face_normals(v, [[0, 1, 2]]).tolist() == [[0.0, 0.0, 0.0]]


def test_signed_areas_rejects_3d():
    v, f = sphere(1)
    with pytest.raises(InvalidInputError, match=r"\(n, 2\) array for signed areas"):
        signed_areas(v, f)
