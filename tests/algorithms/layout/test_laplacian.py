"""Tests for layout.laplacian: hand cases, Tutte's guarantee (no flipped face with a convex
boundary and non-negative weights, also on meshes with very obtuse triangles), the
cotangent pitfall, agreement with libigl's harmonic map, and every error branch."""

from __future__ import annotations

import igl
import numpy as np
import pytest

from algorithms.core import DegenerateInputError, InvalidInputError
from algorithms.core.laplacian import mesh_laplacian
from algorithms.core.mesh import Mesh, face_angles
from algorithms.layout import Graph, LaplacianLayoutResult, laplacian

SQUARE_V = [[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5]]
SQUARE_F = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]


# --- layer 1: by hand -----------------------------------------------------------------------
def test_hand_square_with_centre():
    res = laplacian((SQUARE_V, SQUARE_F))
    assert isinstance(res, LaplacianLayoutResult)
    # equal boundary edges: the corners go to 0°, 90°, 180°, 270° in loop order
    np.testing.assert_allclose(res.positions[:4], [[1, 0], [0, 1], [-1, 0], [0, -1]],
                               atol=1e-15)
    np.testing.assert_allclose(res.positions[4], [0, 0], atol=1e-15)
    assert res.pinned.tolist() == [0, 1, 2, 3]
    # four rim edges of length √2 (energy 2 each), four spokes of length 1
    assert res.energy == pytest.approx(12.0, rel=1e-14)
    assert res.flipped_faces == 0 and res.degenerate_faces == 0


def test_hand_path_graph_with_stiffness():
    # springs 1 and 3: the middle node sits at (1·x0 + 3·x2) / 4
    g = {"nodes": 3, "edges": [[0, 1], [1, 2]], "weights": [1.0, 3.0]}
    res = laplacian(graph=g, pins={"indices": [0, 2], "positions": [[0, 0], [4, 8]]})
    np.testing.assert_allclose(res.positions[1], [3, 6], atol=1e-14)
    # energy 1·|(3,6)|² + 3·|(1,2)|² = 45 + 15
    assert res.energy == pytest.approx(60.0, rel=1e-14)
    assert res.flipped_faces == 0 and res.degenerate_faces == 0


def test_graph_dataclass_and_uniform_default():
    g = Graph(4, np.array([[0, 1], [1, 2], [2, 3]]))
    res = laplacian(graph=g, pins={"indices": [0, 3], "positions": [[0, 0], [3, 0]]})
    np.testing.assert_allclose(res.positions[:, 0], [0, 1, 2, 3], atol=1e-14)


def test_uniform_boundary_spacing():
    v, f = np.array([[0, 0], [3, 0], [3, 1], [0, 1], [1.5, 0.5]]), np.array(SQUARE_F)
    even = laplacian((v, f), boundary_spacing="uniform").positions[:4]
    np.testing.assert_allclose(even, [[1, 0], [0, 1], [-1, 0], [0, -1]], atol=1e-15)
    # arc length: edges 3, 1, 3, 1 of 8 -> angles 0, 3/8, 4/8, 7/8 of a turn
    arc = laplacian((v, f)).positions[:4]
    t = 2 * np.pi * np.array([0, 3, 4, 7]) / 8
    np.testing.assert_allclose(arc, np.c_[np.cos(t), np.sin(t)], atol=1e-15)


# --- layer 2: Tutte's theorem and invariants ------------------------------------------------
@pytest.mark.parametrize("weighting", ["uniform", "tangent", "cotangent"])
def test_delaunay_disk_has_no_flips(meshes, weighting):
    v, f = meshes["disk"](6)
    res = laplacian((v, f), weighting=weighting)
    assert res.flipped_faces == 0 and res.degenerate_faces == 0
    # every vertex inside the closed unit disk (convex hull of the pins)
    assert np.linalg.norm(res.positions, axis=1).max() <= 1 + 1e-12


@pytest.mark.parametrize("weighting", ["uniform", "tangent"])
def test_obtuse_planar_mesh_has_no_flips(meshes, weighting):
    v, f = meshes["squashed_disk"](6)
    assert np.degrees(face_angles(v, f).max()) > 170  # really obtuse
    res = laplacian((v, f), weighting=weighting)
    assert res.flipped_faces == 0 and res.degenerate_faces == 0


@pytest.mark.parametrize("seed", range(20))
def test_tangent_weights_never_flip_on_spiky_surfaces(meshes, seed):
    v, f = meshes["spiky_grid"](seed)
    res = laplacian((v, f), weighting="tangent")
    assert res.flipped_faces == 0 and res.degenerate_faces == 0
    assert np.linalg.norm(res.positions, axis=1).max() <= 1 + 1e-12


def test_cotangent_weights_flip_on_spiky_surfaces(meshes):
    """The pitfall the tangent weights avoid: negative cotangent weights fold faces."""
    flips = [laplacian(meshes["spiky_grid"](seed), weighting="cotangent").flipped_faces
             for seed in range(20)]
    assert max(flips) > 0


@pytest.mark.parametrize("weighting", ["uniform", "cotangent", "tangent"])
def test_free_vertices_balance_their_springs(meshes, weighting):
    v, f = meshes["cap"](2)
    res = laplacian((v, f), weighting=weighting)
    lap = mesh_laplacian(v, f, kind=weighting)
    free = np.setdiff1d(np.arange(len(v)), res.pinned)
    force = (lap @ res.positions)[free]
    assert np.abs(force).max() < 1e-10 * np.abs(lap.data).max()
    np.testing.assert_allclose(np.linalg.norm(res.positions[res.pinned], axis=1), 1.0,
                               atol=1e-14)


def test_energy_is_the_quadratic_form(meshes):
    v, f = meshes["cap"](2)
    res = laplacian((v, f), weighting="tangent")
    lap = mesh_laplacian(v, f, kind="tangent").toarray()
    assert res.energy == pytest.approx(np.trace(res.positions.T @ lap @ res.positions),
                                       rel=1e-12)


def test_pins_in_three_dimensions(meshes):
    # harmonic interpolation of 3-D pins: a layout in 3-D, flips not counted
    v, f = meshes["grid"](5)
    corners = np.array([0, 4, 20, 24])
    pos = np.c_[v[corners], [0.0, 1.0, 1.0, 2.0]]
    res = laplacian((v, f), pins={"indices": corners, "positions": pos})
    assert res.positions.shape == (25, 3)
    np.testing.assert_allclose(res.positions[corners], pos, atol=0)
    assert res.flipped_faces == 0 and res.degenerate_faces == 0


def test_mesh_object_and_mapping_inputs(meshes):
    v, f = meshes["disk"](3)
    a = laplacian(Mesh(v, f)).positions
    b = laplacian({"vertices": v, "faces": f}).positions
    np.testing.assert_array_equal(a, b)


# --- layer 3: agreement with libigl ---------------------------------------------------------
def test_cotangent_layout_matches_igl_harmonic(meshes):
    v, f = meshes["cap"](3)
    bnd = igl.boundary_loop(f)
    circle = igl.map_vertices_to_circle(v, bnd.astype(np.int32))
    ours = laplacian((v, f), weighting="cotangent",
                     pins={"indices": bnd, "positions": circle}).positions
    theirs = igl.harmonic(v, f, bnd, circle, 1)
    np.testing.assert_allclose(ours, theirs, atol=1e-10)


def test_default_circle_matches_igl_map_vertices_to_circle(meshes):
    v, f = meshes["cap"](3)
    res = laplacian((v, f))
    theirs = igl.map_vertices_to_circle(v, res.pinned.astype(np.int32))
    # igl starts at angle 0 too and spaces by arc length; the direction may differ
    ours = res.positions[res.pinned]
    if not np.allclose(ours, theirs, atol=1e-12):
        ours = ours * [1, -1]
    np.testing.assert_allclose(ours, theirs, atol=1e-12)


# --- errors ---------------------------------------------------------------------------------
PATH = {"nodes": 3, "edges": [[0, 1], [1, 2]]}
PIN = {"indices": [0], "positions": [[0.0, 0.0]]}


@pytest.mark.parametrize("kwargs, error, field, match", [
    ({}, InvalidInputError, "mesh", "exactly one of `mesh` and `graph`, got none"),
    ({"mesh": (SQUARE_V, SQUARE_F), "graph": PATH}, InvalidInputError, "graph",
     "got `mesh` and `graph`"),
    ({"graph": PATH}, DegenerateInputError, "pins", "Expected `pins` with a `graph`"),
    ({"graph": {"nodes": 3, "edges": [[0, 1], [1, 3]]}, "pins": PIN}, InvalidInputError,
     "graph.edges", "below 3, got 3 at row 1"),
    ({"graph": {"nodes": 3, "edges": [[0, 1], [2, 2]]}, "pins": PIN}, InvalidInputError,
     "graph.edges", "two distinct nodes"),
    ({"graph": {"nodes": 3, "edges": [[0, 1, 2]]}, "pins": PIN}, InvalidInputError,
     "graph.edges", r"\(e, 2\)"),
    ({"graph": {"nodes": 3, "edges": [[0, 1], [1, 2]], "weights": [1, -1]}, "pins": PIN},
     InvalidInputError, "graph.weights", "non-negative"),
    ({"graph": {"nodes": 3, "edges": [[0, 1], [1, 2]], "weights": [1]}, "pins": PIN},
     InvalidInputError, "graph.weights", "shape"),
    ({"graph": {"nodes": 0, "edges": []}, "pins": PIN}, InvalidInputError, "graph.nodes",
     ">= 1"),
    ({"graph": {"nodes": 3, "edge": []}, "pins": PIN}, InvalidInputError, "graph",
     "missing 'edges'"),
    ({"graph": [[0, 1]], "pins": PIN}, InvalidInputError, "graph", "got list"),
    ({"graph": {"nodes": 4, "edges": [[0, 1], [2, 3]]}, "pins": PIN}, DegenerateInputError,
     "pins", "component of 2 vertices"),
    ({"graph": PATH, "pins": {"indices": [0, 5], "positions": [[0, 0], [1, 1]]}},
     InvalidInputError, "pins.indices", "below 3"),
    ({"graph": PATH, "pins": {"indices": [0, 0], "positions": [[0, 0], [1, 1]]}},
     InvalidInputError, "pins.indices", "unique"),
    ({"graph": PATH, "pins": {"indices": [0, 2], "positions": [[0, 0], [1, np.nan]]}},
     InvalidInputError, "pins.positions", "nan at row 1"),
    ({"graph": PATH, "pins": {"indices": [0, 2], "positions": [[0, 0]]}}, InvalidInputError,
     "pins.positions", "one row per index"),
    ({"graph": PATH, "pins": PIN, "weighting": "cotangent"}, InvalidInputError, "weighting",
     "need a mesh"),
    ({"mesh": (SQUARE_V, SQUARE_F), "weighting": "harmonic"}, InvalidInputError, "weighting",
     "one of"),
    ({"mesh": (SQUARE_V, SQUARE_F), "boundary_spacing": "even"}, InvalidInputError,
     "boundary_spacing", "one of"),
    ({"mesh": (SQUARE_V, [[0, 1, 4], [1, 2, 7]])}, InvalidInputError, "mesh.faces",
     "below 5"),
    ({"mesh": ([[0, 0], [1, 0], [2, 0]], [[0, 1, 2]])}, DegenerateInputError, "mesh.faces",
     "zero-area"),
])
def test_errors(kwargs, error, field, match):
    with pytest.raises(error, match=match) as info:
        laplacian(**kwargs)
    assert info.value.field == field


def test_closed_mesh_needs_pins():
    import trimesh

    s = trimesh.creation.icosphere(subdivisions=1)
    with pytest.raises(DegenerateInputError, match="closed mesh; give `pins`") as info:
        laplacian((s.vertices, s.faces))
    assert info.value.field == "mesh"
    res = laplacian((s.vertices, s.faces),
                    pins={"indices": [0, 1], "positions": [[0, 0], [1, 0]]})
    assert res.positions.shape == (len(s.vertices), 2)


def test_second_component_without_pin_names_the_mesh():
    v = [[0, 0], [1, 0], [0, 1], [5, 0], [6, 0], [5, 1]]
    f = [[0, 1, 2], [3, 4, 5]]  # two separate triangles: only the first loop is pinned
    with pytest.raises(DegenerateInputError, match="component of 3 vertices") as info:
        laplacian((v, f))
    assert info.value.field == "mesh"


def test_unreferenced_vertex_is_reported():
    v = [*SQUARE_V, [9, 9]]
    with pytest.raises(DegenerateInputError, match="vertex 5, isolated"):
        laplacian((v, SQUARE_F))
