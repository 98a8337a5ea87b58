"""interpolation.arap (Alexa et al. 2000): endpoints reproduced, a bending bar keeps its
edge lengths where the linear blend shrinks it (2-D, surface in 3-D, tetrahedra), a global
affine or rigid motion gives exactly the affine path, and every error branch."""

from __future__ import annotations

import numpy as np
import pytest

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.interpolation import affine, arap, poisson
from tests.algorithms.interpolation.interp_meshes import (
    bar,
    bend2,
    linear_blend_error,
    roll3,
    rot2,
    strip3,
    tet_bar,
)

T = np.linspace(0.0, 1.0, 11)


def _mesh(v: np.ndarray, f: np.ndarray) -> dict:
    return {"vertices": v, "faces": f}


def test_two_triangles_turned_by_hand() -> None:
    v = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    f = np.array([[0, 1, 2], [0, 2, 3]])
    res = arap(_mesh(v, f), v @ rot2(np.pi / 2).T, times=[0.5])
    # every face turns by 45 degrees about vertex 0, which stays put
    np.testing.assert_allclose(res.frames[0], v @ rot2(np.pi / 4).T, atol=1e-14)
    assert res.max_angle == pytest.approx(np.pi / 2)


@pytest.mark.parametrize("kind", ["bar", "strip", "tets"])
def test_endpoints_are_the_inputs(kind: str) -> None:
    v, f = {"bar": bar, "strip": strip3, "tets": tet_bar}[kind]()
    w = bend2(v, 2.0) if kind == "bar" else roll3(v, 2.0)
    res = arap(_mesh(v, f), _mesh(w, f), times=[0.0, 1.0])
    np.testing.assert_allclose(res.frames[0], v, atol=1e-10, rtol=0)
    np.testing.assert_allclose(res.frames[1], w, atol=1e-10, rtol=0)


@pytest.mark.parametrize("kind", ["bar", "strip", "tets"])
def test_bending_bar_keeps_its_edge_lengths_where_the_linear_blend_shrinks(kind: str) -> None:
    v, f = {"bar": bar, "strip": strip3, "tets": tet_bar}[kind]()
    w = bend2(v, np.pi) if kind == "bar" else roll3(v, np.pi)   # half a turn
    res = arap(_mesh(v, f), _mesh(w, f), times=T)
    assert res.max_edge_error.max() < 0.05
    assert linear_blend_error(v, w, f, T) > 0.5      # the blend's ends meet half-way
    assert res.min_det.min() > 0.5                    # no face collapses or turns over
    # the centre line keeps its length at every frame (to 5 %)
    centre = np.flatnonzero(np.isclose(v[:, 1], 0.0)) if kind == "bar" else None
    if centre is not None:
        order = centre[np.argsort(v[centre, 0])]
        for frame in res.frames:
            length = np.linalg.norm(np.diff(frame[order], axis=0), axis=1).sum()
            assert length == pytest.approx(10.0, rel=0.05)


def test_past_half_a_turn_faces_take_their_own_short_arcs_and_tear() -> None:
    # Alexa's per-face shortest arc: the documented limit that poisson's unwrapping lifts
    v, f = bar()
    w = bend2(v, 1.5 * np.pi)
    res = arap(_mesh(v, f), _mesh(w, f), times=T)
    assert res.max_angle <= np.pi
    assert res.max_edge_error.max() > 0.2


@pytest.mark.parametrize("method", [arap, poisson])
def test_a_global_affine_map_gives_the_affine_path(method) -> None:  # noqa: ANN001
    v, f = bar(nx=6)          # vertex 0 (the anchor) at (0, -0.5): move it to the origin
    v = v - v[0]
    a = np.array([[1.0, 2.0, 0.0], [-1.0, 0.5, 0.0], [0.0, 0.0, 1.0]])
    a[:2, :2] = rot2(2.5) @ np.array([[1.5, 0.3], [0.3, 0.8]])
    a[:2, 2] = [3.0, -1.0]
    res = method(_mesh(v, f), transform=a, times=T)
    peer = affine(_mesh(v, f), transform=a, times=T, pivot="origin")
    np.testing.assert_allclose(res.frames, peer.frames, atol=1e-10)


def test_uniform_mesh_matches_poisson_below_half_a_turn() -> None:
    # equal face areas: Alexa's unweighted sum and the area-weighted Poisson agree
    v, f = bar()
    w = bend2(v, 2.5)
    a = arap(_mesh(v, f), _mesh(w, f), times=T)
    p = poisson(_mesh(v, f), _mesh(w, f), times=T)
    np.testing.assert_allclose(a.frames, p.frames, atol=1e-10)


def test_progress_is_reported_per_frame() -> None:
    v, f = bar(nx=5)
    seen = []
    arap(_mesh(v, f), bend2(v, 1.0), times=T, progress=lambda *a: seen.append(a))
    assert [s[:2] for s in seen] == [(i + 1, 11) for i in range(11)]


def test_anchor_moves_on_a_straight_line() -> None:
    v, f = bar(nx=8)
    w = bend2(v, 2.0) + [5.0, 5.0]
    res = arap(_mesh(v, f), _mesh(w, f), times=T, anchor=7)
    expected = (1 - T)[:, None] * v[7] + T[:, None] * w[7]
    np.testing.assert_allclose(res.frames[:, 7], expected, atol=1e-12)


def test_two_components_each_hold_a_vertex_on_its_line() -> None:
    v, f = bar(nx=4, ny=2)
    v2 = np.concatenate([v, v + [10.0, 0.0]])
    f2 = np.concatenate([f, f + len(v)])
    w2 = np.concatenate([bend2(v, 1.0), bend2(v, -1.0) + [10.0, 3.0]])
    res = arap(_mesh(v2, f2), _mesh(w2, f2), times=T)
    np.testing.assert_allclose(res.frames[-1], w2, atol=1e-10)


def test_flipped_face_passes_through_zero_area() -> None:
    v = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    f = np.array([[0, 1, 2]])
    w = v * [1.0, -1.0]                              # mirrored: the triangle turns over
    res = arap(_mesh(v, f), _mesh(w, f), times=T)
    np.testing.assert_allclose(res.frames[-1], w, atol=1e-12)
    assert res.min_det[0] == pytest.approx(1.0) and res.min_det[-1] == pytest.approx(-1.0)


# -- errors ---------------------------------------------------------------------------------
def test_errors_name_their_input() -> None:
    v, f = bar(nx=4, ny=2)
    with pytest.raises(InvalidInputError, match="mesh") as info:
        arap(v, bend2(v, 1.0))
    assert info.value.field == "source"
    other = np.array([[0, 1, 5], [0, 5, 4], [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6]])
    with pytest.raises(InvalidInputError, match="same connectivity") as info:
        arap(_mesh(v, f), _mesh(v, other[::-1]))
    assert info.value.field == "target.faces"
    with pytest.raises(InvalidInputError) as info:
        arap(_mesh(v, f), _mesh(v[:-1], f[:1]))
    assert info.value.field == "target.vertices"
    with pytest.raises(InvalidInputError, match="a vertex index of `source`") as info:
        arap(_mesh(v, f), v, anchor=8)
    assert info.value.field == "anchor"
    with pytest.raises(InvalidInputError, match=">= 0") as info:
        arap(_mesh(v, f), v, anchor=-1)
    assert info.value.field == "anchor"
    with pytest.raises(InvalidInputError) as info:
        arap(_mesh(v, f), v, times=[0.2, 2.0])
    assert info.value.field == "times"
    flat = v.copy()
    flat[4:] = flat[:4]                              # every face degenerate
    with pytest.raises(DegenerateInputError) as info:
        arap(_mesh(flat, f), v)
    assert info.value.field == "source.faces"


def test_tetrahedra_are_checked() -> None:
    v, t = tet_bar(nx=3)
    bad = t.copy()
    bad[0, 1] = bad[0, 0]
    with pytest.raises(InvalidInputError, match="four distinct") as info:
        arap(_mesh(v, bad), v)
    assert info.value.field == "source.faces"
    with pytest.raises(InvalidInputError, match=r"\(n, 3\)") as info:
        arap(_mesh(v[:, :2], t), v[:, :2])
    assert info.value.field == "source.vertices"
