"""Tests for deformation.arap and ArapSolver: hand cases, invariants (handles met exactly,
energy never increasing, rigid motions free), agreement with libigl's ARAP."""

from __future__ import annotations

import dataclasses
import re
import warnings
from typing import get_args

import igl
import numpy as np
import pytest

from algorithms.core import Cancelled, DegenerateInputError, InvalidInputError
from algorithms.core.linsolve import BACKENDS, BREAK_EVEN, available_backends
from algorithms.core.mesh import Mesh
from algorithms.deformation import ArapResult, ArapSolver, arap
from algorithms.deformation.arap import Backend
from tests.algorithms.deformation.deformation_meshes import (
    blob,
    bumpy_sheet,
    grid,
    random_rotation,
    tube,
)


def bend_tube():
    """A bar: bottom ring fixed, top ring swung sideways and down (a strong bend)."""
    v, f = tube()
    bottom = np.flatnonzero(v[:, 2] == 0.0)
    top = np.flatnonzero(v[:, 2] == v[:, 2].max())
    idx = np.concatenate([bottom, top])
    pos = v[idx].copy()
    pos[len(bottom):] = v[top] @ random_rotation(np.random.default_rng(1)).T * 0.0 + \
        v[top] + [2.0, 0.0, -1.0]
    return v, f, idx, pos


def rel_rms(x, ref, rest):
    return np.sqrt(((x - ref) ** 2).sum(1).mean()) / np.sqrt(((ref - rest) ** 2).sum(1).mean())


def igl_arap(v, f, idx, pos, energy, iterations):
    data = igl.ARAPData()
    data.max_iter = iterations
    data.energy = {"spokes": igl.ARAP_ENERGY_TYPE_SPOKES,
                   "spokes_and_rims": igl.ARAP_ENERGY_TYPE_SPOKES_AND_RIMS}[energy]
    igl.arap_precomputation(v, f, v.shape[1], idx.astype(np.int32), data)
    return igl.arap_solve(pos, data, v.copy())


# --- layer 1: by hand -------------------------------------------------------------------------


def test_hand_handles_at_rest_give_the_rest_shape():
    v, f = grid(4, 3)
    res = arap((v, f), {"indices": [0, 11], "positions": v[[0, 11]]})
    assert isinstance(res, ArapResult)
    np.testing.assert_allclose(res.mesh.vertices, v, atol=1e-12)
    np.testing.assert_array_equal(res.mesh.faces, f)
    assert res.iterations == 1 and res.converged
    assert abs(res.energy[0]) < 1e-12 and res.handle_residual == 0.0


def test_hand_one_triangle_all_handles_rotated():
    # every vertex pinned: nothing to solve, the energy of a rigid motion is zero
    v = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 2.0, 0.0]])
    rot = random_rotation(np.random.default_rng(0))
    res = arap((v, [[0, 1, 2]]), {"indices": [0, 1, 2], "positions": v @ rot.T + 3.0})
    np.testing.assert_allclose(res.mesh.vertices, v @ rot.T + 3.0, atol=1e-15)
    assert abs(res.energy[0]) < 1e-13


def test_hand_stretched_pair_of_triangles_energy():
    # A unit square (two right triangles), handles pull the right edge out by 1: with
    # everything pinned the energy is the formula evaluated by hand. Spokes energy, cot
    # weights: the diagonal has weight ½(cot 90° + cot 90°) = 0, the sides ½ cot 45° = ½.
    v = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    f = np.array([[0, 1, 2], [0, 2, 3]])
    pos = v + [[0, 0], [1, 0], [1, 0], [0, 0]]
    res = arap((v, f), {"indices": [0, 1, 2, 3], "positions": pos}, energy="spokes",
               max_iterations=1, tolerance=0.0)
    # Each corner sees one stretched side (length 1 -> 2, weight ½) and one unchanged side
    # (weight ½, direction perpendicular); the best rotation is the identity for every
    # corner (the stretch is along an edge), leaving ½·|(2,0) - (1,0)|² = ½ per corner that
    # touches a stretched side: four corners, each counted once per side -> 4 · ½ = 2.
    assert res.energy[0] == pytest.approx(2.0, abs=1e-12)


# --- layer 2: invariants ----------------------------------------------------------------------


@pytest.mark.parametrize("energy", ["spokes", "spokes_and_rims"])
@pytest.mark.parametrize("similarity", [False, True])
def test_energy_never_increases_and_handles_are_exact(energy, similarity):
    v, f, idx, pos = bend_tube()
    res = arap((v, f), {"indices": idx, "positions": pos}, energy=energy,
               similarity=similarity, max_iterations=60, tolerance=0.0)
    e = np.array(res.energy)
    assert res.iterations == 60
    scale = abs(e[0])
    assert np.all(np.diff(e) <= 1e-12 * scale), np.diff(e).max()
    assert e[-1] < e[0]
    np.testing.assert_array_equal(res.mesh.vertices[idx], pos)   # exactly, not approximately
    assert res.handle_residual == 0.0


def test_many_iterations_keep_improving():
    # libigl #1539: ARAP "getting worse" with more iterations. Ours only goes down.
    v, f, idx, pos = bend_tube()
    few = arap((v, f), {"indices": idx, "positions": pos}, max_iterations=5, tolerance=0.0)
    many = arap((v, f), {"indices": idx, "positions": pos}, max_iterations=200, tolerance=0.0)
    assert many.energy[-1] <= few.energy[-1]
    np.testing.assert_allclose(many.energy[:5], few.energy, rtol=1e-12)
    # tolerance 0 runs every iteration, as libigl's arap_solve does, even once the energy
    # has stopped falling (it stops falling long before 200 here)
    assert (few.iterations, many.iterations) == (5, 200)
    assert not many.converged


@pytest.mark.parametrize("seed", range(5))
def test_rigid_motion_of_the_handles_is_reproduced(seed):
    rng = np.random.default_rng(seed)
    v, f = bumpy_sheet(seed=seed)
    rot, shift = random_rotation(rng), rng.normal(size=3)
    idx = rng.choice(v.shape[0], size=5, replace=False)
    moved = v @ rot.T + shift
    solver = ArapSolver((v, f), idx)
    # started from the moved shape, the rigid motion is a fixed point with zero energy
    res = solver.solve(moved[idx], initial=moved, max_iterations=3)
    np.testing.assert_allclose(res.mesh.vertices, moved, atol=1e-10)
    assert abs(res.energy[-1]) < 1e-10 * abs(np.sum(v ** 2))
    assert res.converged and res.iterations == 1
    # from the rest shape the energy falls towards zero (slowly: a large rotation)
    res = solver.solve(moved[idx], max_iterations=200, tolerance=0.0)
    assert res.energy[-1] < 1e-2 * res.energy[0]


def test_similarity_reproduces_a_uniform_scaling():
    v, f = blob(2)
    idx = np.array([0, 5, 17, 40])
    c = v.mean(axis=0)
    scaled = 2.5 * (v - c) + c
    similar = ArapSolver((v, f), idx, similarity=True)
    res = similar.solve(scaled[idx], initial=scaled, max_iterations=3)
    np.testing.assert_allclose(res.mesh.vertices, scaled, atol=1e-10)   # a fixed point
    assert abs(res.energy[0]) < 1e-10 and res.converged
    from_rest = similar.solve(scaled[idx], max_iterations=100, tolerance=0.0)
    rigid = arap((v, f), {"indices": idx, "positions": scaled[idx]}, max_iterations=100,
                 tolerance=0.0)
    assert from_rest.energy[-1] < 1e-2 * from_rest.energy[0]
    # rotations alone cannot grow the blob: its energy stays far above
    assert rigid.energy[-1] > 100 * from_rest.energy[-1]
    err = np.abs(from_rest.mesh.vertices - scaled).max()
    assert err < 0.1 * np.abs(rigid.mesh.vertices - scaled).max()


def test_planar_mesh_in_2d_and_unused_vertices_stay():
    v, f = grid(6, 4, jitter=0.2)
    v = np.vstack([v, [[10.0, 10.0]]])            # a vertex no face uses
    left = np.flatnonzero(v[:, 0] == 0)
    right = np.flatnonzero(v[:, 0] == 5)
    idx = np.concatenate([left, right])
    pos = v[idx].copy()
    pos[len(left):] += [0.0, 2.0]
    res = arap((v, f), {"indices": idx, "positions": pos}, max_iterations=50)
    assert res.mesh.vertices.shape == v.shape
    np.testing.assert_array_equal(res.mesh.vertices[-1], [10.0, 10.0])
    assert np.all(np.diff(res.energy) <= 1e-12 * abs(res.energy[0]))


def test_solver_factors_once_for_many_targets():
    v, f, idx, pos = bend_tube()
    solver = ArapSolver((v, f), idx, energy="spokes")
    factor = solver.factor
    a = solver.solve(pos, max_iterations=8, tolerance=0.0)
    b = solver.solve(v[idx] + [0.0, 1.0, 0.0], initial=v + [0.0, 1.0, 0.0], max_iterations=8,
                     tolerance=0.0)
    again = solver.solve(pos, max_iterations=8, tolerance=0.0)
    assert solver.factor is factor
    one_shot = arap((v, f), {"indices": idx, "positions": pos}, energy="spokes",
                    max_iterations=8, tolerance=0.0)
    np.testing.assert_array_equal(a.mesh.vertices, again.mesh.vertices)
    np.testing.assert_allclose(a.mesh.vertices, one_shot.mesh.vertices, atol=1e-12)
    np.testing.assert_allclose(b.mesh.vertices, v + [0.0, 1.0, 0.0], atol=1e-9)  # translation


def test_progress_per_iteration_and_cancellation():
    v, f, idx, pos = bend_tube()
    calls = []
    arap((v, f), {"indices": idx, "positions": pos}, max_iterations=4, tolerance=0.0,
         progress=lambda done, total, msg="": calls.append((done, total, msg)))
    assert [c[:2] for c in calls] == [(1, 4), (2, 4), (3, 4), (4, 4)]
    assert "energy" in calls[0][2]

    def stop(done, total, msg=""):
        if done == 2:
            raise Cancelled("dismissed")

    with pytest.raises(Cancelled):
        arap((v, f), {"indices": idx, "positions": pos}, max_iterations=10, progress=stop)


def test_not_converging_warns_and_says_so():
    v, f, idx, pos = bend_tube()
    with pytest.warns(Warning, match="ARAP stopped after 2 iterations"):
        res = arap((v, f), {"indices": idx, "positions": pos}, max_iterations=2,
                   tolerance=1e-12)
    assert res.converged is False and res.iterations == 2
    with warnings.catch_warnings():
        warnings.simplefilter("error")   # tolerance 0: a fixed count, as libigl; no warning
        arap((v, f), {"indices": idx, "positions": pos}, max_iterations=2, tolerance=0.0)


def test_result_is_frozen():
    v, f = grid(3, 3)
    res = arap((v, f), {"indices": [0], "positions": [[0.0, 0.0]]})
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.iterations = 3  # type: ignore[misc]
    assert isinstance(res.mesh, Mesh)


# --- layer 3: agreement with libigl -----------------------------------------------------------


@pytest.mark.parametrize("energy", ["spokes", "spokes_and_rims"])
@pytest.mark.parametrize("mesh", ["tube", "blob"])
def test_matches_libigl_arap(energy, mesh):
    if mesh == "tube":
        v, f, idx, pos = bend_tube()
    else:
        v, f = blob(3)
        idx = np.flatnonzero((v[:, 2] > 1.4) | (v[:, 2] < -1.4))
        pos = v[idx].copy()
        pos[v[idx, 2] > 0] += [0.6, 0.2, 0.3]
    iterations = 10
    ref = igl_arap(v, f, idx, pos, energy, iterations)
    res = arap((v, f), {"indices": idx, "positions": pos}, energy=energy,
               max_iterations=iterations, tolerance=0.0)
    assert res.iterations == iterations
    # libigl fits rotations in single precision: agreement to ~1e-5, far inside 1e-3
    assert rel_rms(res.mesh.vertices, ref, v) < 1e-3
    np.testing.assert_array_equal(ref[idx], pos)


def test_matches_libigl_arap_in_2d():
    v, f = grid(7, 5, jitter=0.15, seed=2)
    idx = np.flatnonzero((v[:, 0] == 0) | (v[:, 0] == 6))
    pos = v[idx].copy()
    pos[v[idx, 0] == 6] += [-1.0, 2.5]
    ref = igl_arap(v, f, idx, pos, "spokes", 10)
    res = arap((v, f), {"indices": idx, "positions": pos}, energy="spokes",
               max_iterations=10, tolerance=0.0)
    assert rel_rms(res.mesh.vertices, ref, v) < 1e-3


# --- errors -----------------------------------------------------------------------------------


def two_triangles():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [5, 0, 0], [6, 0, 0], [5, 1, 0]], float)
    return v, np.array([[0, 1, 2], [3, 4, 5]])


@pytest.mark.parametrize("kwargs, handles, error, field, fragment", [
    ({}, {"indices": [0], "positions": [[0, 0, 1]]}, DegenerateInputError, "handles",
     "component of 3 vertices (vertex 3 among them)"),
    ({}, {"indices": [0, 0], "positions": [[0, 0, 1]] * 2}, InvalidInputError,
     "handles.indices", "unique"),
    ({}, {"indices": [0, 9], "positions": [[0, 0, 1]] * 2}, InvalidInputError,
     "handles.indices", "below 6"),
    ({}, {"indices": [0, 3], "positions": [[0, 0, 1]]}, InvalidInputError,
     "handles.positions", "one row per index"),
    ({}, {"indices": [0, 3], "positions": [[0, 0], [1, 1]]}, InvalidInputError,
     "handles.positions", "(n, 3)"),
    ({}, {"indices": [0, 3], "positions": [[0, 0, np.nan], [1, 1, 1]]}, InvalidInputError,
     "handles.positions", "row 0"),
    ({"energy": "elements"}, {"indices": [0, 3], "positions": [[0, 0, 1]] * 2},
     InvalidInputError, "energy", "'spokes_and_rims'"),
    ({"similarity": "yes"}, {"indices": [0, 3], "positions": [[0, 0, 1]] * 2},
     InvalidInputError, "similarity", "true or false"),
    ({"max_iterations": 0}, {"indices": [0, 3], "positions": [[0, 0, 1]] * 2},
     InvalidInputError, "max_iterations", ">= 1"),
    ({"tolerance": -1.0}, {"indices": [0, 3], "positions": [[0, 0, 1]] * 2},
     InvalidInputError, "tolerance", ">= 0"),
])
def test_invalid_inputs(kwargs, handles, error, field, fragment):
    v, f = two_triangles()
    with pytest.raises(error, match=re.escape(fragment)) as info:
        arap((v, f), handles, **kwargs)
    assert info.value.field == field
    assert fragment in info.value.message


def test_bad_meshes():
    v, f = two_triangles()
    with pytest.raises(InvalidInputError, match="below 6, got 6 at row 1") as info:
        arap((v, [[0, 1, 2], [3, 4, 6]]), {"indices": [0, 3], "positions": v[[0, 3]]})
    assert info.value.field == "mesh.faces"
    flat = v.copy()
    flat[5] = [5.5, 0, 0]                                  # collinear with 3 and 4
    with pytest.raises(DegenerateInputError, match="degenerate .* at row 1") as info:
        arap((flat, f), {"indices": [0, 3], "positions": v[[0, 3]]})
    assert info.value.field == "mesh.faces"


def test_solver_backend_follows_the_solves_it_serves():
    # a few iterations: the backend that factors fastest; many (the default): fast solves
    v, f = two_triangles()
    installed = available_backends()
    few = ArapSolver((v, f), [0, 3], solves=BREAK_EVEN[installed[0]] - 1)
    assert few.factor.backend == installed[0]
    assert ArapSolver((v, f), [0, 3]).factor.backend == "cholespy"
    assert ArapSolver((v, f), [0, 3], solves=1, backend="cholespy").factor.backend == \
        "cholespy"                                          # asked for: taken
    with pytest.raises(InvalidInputError, match=">= 1") as info:
        ArapSolver((v, f), [0, 3], solves=0)
    assert info.value.field == "solves"


def test_solver_input_errors():
    v, f = two_triangles()
    with pytest.raises(DegenerateInputError, match="handle_indices") as info:
        ArapSolver((v, f), [0])
    assert info.value.field == "handle_indices"
    for kwargs, field, fragment in (({"energy": "rims"}, "energy", "'spokes'"),
                                    ({"backend": "mkl"}, "backend", "'auto'")):
        with pytest.raises(InvalidInputError, match=fragment) as info:
            ArapSolver((v, f), [0, 3], **kwargs)
        assert info.value.field == field
    assert set(get_args(Backend)[1:]) == set(BACKENDS)  # "auto" or any of the solver's backends
    solver = ArapSolver((v, f), [0, 3])
    with pytest.raises(InvalidInputError, match="one row per handle") as info:
        solver.solve([[0, 0, 0]])
    assert info.value.field == "handle_positions"
    with pytest.raises(InvalidInputError, match=">= 1") as info:
        solver.solve(v[[0, 3]], max_iterations=0)
    assert info.value.field == "max_iterations"
    with pytest.raises(InvalidInputError) as info:
        solver.solve(v[[0, 3]], initial=v[:4])
    assert info.value.field == "initial"


def _pyvista_mesh(name):
    """A PLY file from pyvista's wheel (read by trimesh, VTK never imported), its largest
    edge-connected part."""
    import importlib.util
    from pathlib import Path

    import scipy.sparse as sp
    import trimesh
    from scipy.sparse.csgraph import connected_components

    spec = importlib.util.find_spec("pyvista")
    if spec is None or not spec.submodule_search_locations:
        pytest.fail("The pyvista wheel (for its example meshes) is not installed: run "
                    "`make test`, which installs it with --no-deps.")
    m = trimesh.load(Path(spec.submodule_search_locations[0]) / "examples" / name)
    v, f = np.asarray(m.vertices, float), np.asarray(m.faces, np.int64)
    e = np.r_[f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]
    adj = sp.coo_array((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(len(v), len(v)))
    _, lab = connected_components(adj, directed=False)
    keep = lab == np.argmax(np.bincount(lab))
    new = np.cumsum(keep) - 1
    return v[keep], new[f[keep[f[:, 0]]]]


@pytest.mark.parametrize("energy", ["spokes", "spokes_and_rims"])
@pytest.mark.parametrize("name", ["sphere.ply", "airplane.ply", "ant.ply"])
def test_matches_libigl_arap_on_real_meshes(energy, name):
    # the agreement the docstring states, on meshes with negative cotangent weights
    v, f = _pyvista_mesh(name)
    c = igl.cotmatrix(v, f).tocoo()
    assert (c.data[c.row < c.col] < 0).sum() > 30
    ax = int(np.argmax(np.ptp(v, axis=0)))
    lo, span = v[:, ax].min(), np.ptp(v[:, ax])
    idx = np.flatnonzero((v[:, ax] < lo + 0.1 * span) | (v[:, ax] > lo + 0.9 * span))
    pos = v[idx].copy()
    pos[v[idx, ax] > lo + 0.5 * span, (ax + 1) % 3] += 0.2 * span
    ref = igl_arap(v, f, idx, pos, energy, 10)
    res = arap((v, f), {"indices": idx, "positions": pos}, energy=energy,
               max_iterations=10, tolerance=0.0)
    assert rel_rms(res.mesh.vertices, ref, v) < 1e-4
