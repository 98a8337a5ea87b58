"""Every way a mesh can fail to be a disk gets a NotADiskError naming `mesh`."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from algorithms.core.errors import InvalidInputError
from algorithms.parameterization import NotADiskError, arap, asap, conformal, harmonic, tutte
from tests.algorithms.parameterization.param_meshes import grid

METHODS = [tutte, harmonic, conformal, lambda m: conformal(m, method="spectral"), arap, asap]


def _sphere():
    s = trimesh.creation.icosphere(subdivisions=1)
    return np.asarray(s.vertices), np.asarray(s.faces)


def _annulus():
    v, f = grid(5, 5)
    keep = ~np.isin(f, [12]).any(axis=1)        # drop the faces round the centre vertex
    v2 = np.delete(v, 12, axis=0)
    f2 = f[keep]
    return v2, np.where(f2 > 12, f2 - 1, f2)


def _two_disks():
    v, f = grid(3, 3)
    return np.r_[v, v + [5, 0]], np.r_[f, f + len(v)]


def _fin():
    v, f = grid(3, 2)                            # a strip, plus a third face on edge (1, 4)
    v3 = np.c_[v, np.zeros(len(v))]
    return np.r_[v3, [[1, 0.5, 1]]], np.r_[f, [[1, 4, 6]]]


def _bowtie():
    v = [[0, 0], [1, 0], [0.5, 0.5], [1, 1], [0, 1]]
    return v, [[0, 1, 2], [2, 3, 4]]


def _flipped_face():
    v, f = grid(3, 3)
    f = f.copy()
    f[0] = f[0][::-1]
    return v, f


def _unused_vertex():
    v, f = grid(3, 3)
    return np.r_[v, [[9, 9]]], f


CASES = [
    (_sphere, "closed mesh"),
    (_annulus, "2 boundary loops"),
    (_two_disks, "2 connected components"),
    (_fin, "non-manifold edge"),
    (_bowtie, "non-manifold vertex 2"),
    (_flipped_face, "same direction"),
    (_unused_vertex, "vertex 9 in no face"),
]


@pytest.mark.parametrize("make, words", CASES)
@pytest.mark.parametrize("method", METHODS)
def test_not_a_disk(make, words: str, method) -> None:  # noqa: ANN001
    v, f = make()
    with pytest.raises(NotADiskError, match=words) as info:
        method((v, f))
    assert info.value.field == "mesh"
    assert isinstance(info.value, InvalidInputError)
    assert "topological disk" in str(info.value)


def test_a_disk_with_a_handle_is_refused_by_euler_characteristic() -> None:
    # a torus cut open along one loop keeps its handle: one boundary loop... two actually;
    # cutting a torus with a disk removed gives one boundary and χ = -1
    t = trimesh.creation.torus(major_radius=2, minor_radius=0.7, major_sections=12,
                               minor_sections=8)
    f = np.asarray(t.faces)[1:]                  # remove one face: one boundary loop
    with pytest.raises(NotADiskError, match="Euler characteristic V - E \\+ F = -1"):
        tutte((np.asarray(t.vertices), f))


def _half_edge_census(f: np.ndarray) -> tuple[dict, dict]:
    """A plain-Python count of each undirected edge's faces and of each directed half-edge."""
    faces_of: dict[tuple[int, int], int] = {}
    runs: dict[tuple[int, int], int] = {}
    for tri in np.asarray(f).tolist():
        for i, j in zip(tri, tri[1:] + tri[:1]):
            faces_of[min(i, j), max(i, j)] = faces_of.get((min(i, j), max(i, j)), 0) + 1
            runs[i, j] = runs.get((i, j), 0) + 1
    return faces_of, runs


@pytest.mark.parametrize("seed", range(6))
def test_the_named_edge_is_the_first_bad_one(seed: int) -> None:
    # faces flipped at random, and for odd seeds a fin on a random interior edge: the
    # message names the first (lowest) non-manifold edge with its face count, else the first
    # edge two faces run the same way, in that direction; checked against a plain count
    rng = np.random.default_rng(seed)
    v, f = grid(6, 5)
    f = f.copy()
    flip = rng.choice(len(f), size=3, replace=False)
    f[flip] = f[flip, ::-1]
    v = np.c_[v, np.zeros(len(v))]
    if seed % 2:
        i, j = (int(x) for x in f[rng.integers(len(f)), :2])
        v = np.r_[v, [[0.5, 0.5, 1.0]]]
        f = np.r_[f, [[i, j, len(v) - 1]]]
    faces_of, runs = _half_edge_census(f)
    fins = sorted(e for e, c in faces_of.items() if c > 2)
    twice = sorted((min(e), max(e), e) for e, c in runs.items() if c > 1)
    if fins:
        words = (f"non-manifold edge {fins[0]} shared by {max(faces_of.values())} faces")
    else:
        words = f"edge {twice[0][2]} traversed in the same direction by two faces"
    with pytest.raises(NotADiskError) as info:
        harmonic((v, f))
    assert words in str(info.value)
