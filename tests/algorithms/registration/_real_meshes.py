"""Real scanned and modelled meshes for the registration tests: the small PLY files
pyvista's wheel ships (airplane, ant, nut; the nut's six-fold symmetry makes it a poor test
of rotations). ``make test`` installs that wheel without its dependencies (VTK is never
imported: the files are only read, by trimesh)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest
import trimesh

__all__ = ["real_mesh", "surface_points"]


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
