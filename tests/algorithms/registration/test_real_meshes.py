"""Registration on real scanned and modelled meshes: the small PLY files pyvista's wheel ships
(airplane, ant, nut; the nut's six-fold symmetry makes it a poor test of rotations). ``make test`` installs that wheel without its dependencies (VTK is never
imported: the files are only read, by trimesh)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation

from algorithms.registration import cpd, icp, multiway


def real_mesh(name: str) -> trimesh.Trimesh:
    spec = importlib.util.find_spec("pyvista")
    if spec is None or not spec.submodule_search_locations:
        pytest.fail("The pyvista wheel (for its example meshes) is not installed: run `make "
                    "test`, which installs it with --no-deps.")
    path = Path(spec.submodule_search_locations[0]) / "examples" / name
    return trimesh.load(path, process=False)


def surface_points(name: str, n: int, seed: int) -> np.ndarray:
    """``n`` points sampled on the mesh, scaled to a 1-unit bounding box diagonal."""
    mesh = real_mesh(name)
    points, _ = trimesh.sample.sample_surface(mesh, n, seed=seed)
    points = points - points.mean(axis=0)
    return points / np.linalg.norm(mesh.extents)


def angle_deg(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.degrees(Rotation.from_matrix(a @ b.T).magnitude()))


@pytest.mark.parametrize("name", ["airplane.ply", "ant.ply", "nut.ply"])
def test_icp_recovers_a_20_degree_turn_of_a_real_shape(name: str) -> None:
    src = surface_points(name, 2000, 0)
    rot = Rotation.from_rotvec(np.radians(20) * np.array([1.0, -2.0, 0.5]) / np.sqrt(5.25))
    dst = rot.apply(src) + [0.05, -0.02, 0.03]
    res = icp(src, dst, metric="point_to_plane", max_iterations=100)
    assert res.converged, res.reason
    assert angle_deg(res.rotation, rot.as_matrix()) < 0.1


def test_icp_with_pca_init_finds_any_turn_of_the_ant() -> None:
    src = surface_points("ant.ply", 1500, 1)
    rot = Rotation.from_euler("xyz", [150, -60, 110], degrees=True)
    dst = rot.apply(src) + [0.3, 0.1, -0.2]
    res = icp(src, dst, init="pca", max_iterations=60)
    assert angle_deg(res.rotation, rot.as_matrix()) < 0.1


def test_cpd_rigid_recovers_scale_and_rotation_of_the_ant() -> None:
    src = np.asarray(real_mesh("ant.ply").vertices, dtype=np.float64)
    src = (src - src.mean(axis=0)) / np.linalg.norm(np.ptp(src, axis=0))
    rot = Rotation.from_euler("zyx", [35, -20, 15], degrees=True)
    dst = 1.4 * rot.apply(src) + [0.2, -0.1, 0.3]
    res = cpd(src, dst, model="rigid")
    assert res.scale == pytest.approx(1.4, rel=1e-4)
    assert angle_deg(res.rotation, rot.as_matrix()) < 0.05


def test_multiway_puts_three_views_of_the_airplane_together() -> None:
    points = surface_points("airplane.ply", 3000, 2)
    rng = np.random.default_rng(2)
    truths = [Rotation.identity()] + [Rotation.from_rotvec(np.radians(8) * rng.normal(size=3))
                                     for _ in range(2)]
    views = [truths[i].apply(points[i * 300:i * 300 + 2400]) + 0.02 * rng.normal(size=3)
             for i in range(3)]
    res = multiway(views, correspondences=False)
    for i in range(1, 3):
        # transforms[i] maps view i into view 0's frame: the inverse of its turn
        assert angle_deg(res.rotations[i], truths[i].inv().as_matrix()) < 1.0


import warnings

from algorithms.core import ConvergenceWarning
from algorithms.registration import ransac


@pytest.mark.parametrize("name, seeds", [("airplane.ply", 20), ("ant.ply", 10)])
def test_ransac_registers_cropped_noisy_real_shapes(name: str, seeds: int) -> None:
    # Issue #4's acceptance on real shapes: two crops by a plane along a random axis, each
    # keeping 85 % (70 % shared), the target with 0.5 % noise, turned by a Haar-random
    # rotation and moved; default parameters; at least 19 of 20 seeds under 2° (seeds 0-19
    # of the ant also all pass; 10 of them here, to keep the test under 40 s).
    errors = []
    for seed in range(seeds):
        rng = np.random.default_rng(seed)
        points = surface_points(name, 6000, seed)
        axis = rng.normal(size=3)
        proj = points @ (axis / np.linalg.norm(axis))
        src = points[proj <= np.quantile(proj, 0.85)]
        dst = points[proj >= np.quantile(proj, 0.15)]
        rot = Rotation.random(random_state=seed)
        dst = rot.apply(dst + rng.normal(0, 0.005, dst.shape)) + rng.normal(size=3)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            res = ransac(src, dst, seed=seed)
        errors.append(angle_deg(res.rotation, rot.as_matrix()))
    assert sum(e < 2.0 for e in errors) >= seeds - 1, np.round(errors, 2)
