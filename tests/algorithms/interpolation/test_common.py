"""algorithms.interpolation._common, the inputs every interpolation method shares: shapes,
the cap on the frames' size, and the triangles a frame is drawn with."""

from __future__ import annotations

import igl
import numpy as np
import pytest

from algorithms.core.errors import InvalidInputError
from algorithms.interpolation._common import (
    MAX_FRAME_VALUES,
    check_frame_count,
    read_shape,
    read_times,
    surface_triangles,
)
from tests.algorithms.interpolation.interp_meshes import bar, tet_bar


def test_shapes_are_points_or_meshes() -> None:
    v, f = bar(nx=3)
    points, none = read_shape(v, name="source")
    assert points.shape == v.shape and none.shape == (0, 3)
    vertices, faces = read_shape({"vertices": v, "faces": f}, name="source")
    np.testing.assert_array_equal(vertices, v)
    np.testing.assert_array_equal(faces, f)
    with pytest.raises(InvalidInputError, match="per face") as info:
        read_shape(v, name="source", need_faces=True)
    assert info.value.field == "source"
    with pytest.raises(InvalidInputError, match="'vertices' and 'faces'") as info:
        read_shape({"vertices": v}, name="target")
    assert info.value.field == "target"


def test_frame_count_is_capped() -> None:
    check_frame_count(1000, 2, read_times(None))
    n = MAX_FRAME_VALUES // 22 + 1                  # 11 default frames of (n, 2) too many
    with pytest.raises(InvalidInputError, match="at most 10 frames") as info:
        check_frame_count(n, 2, read_times(None))
    assert info.value.field == "times"


def test_surface_triangles_for_drawing_frames_match_igl_boundary_facets() -> None:
    v, t = tet_bar(nx=4)

    def canonical(tris: np.ndarray) -> list:  # same cyclic orientation, any start corner
        return sorted(tuple(np.roll(r, -int(np.argmin(r)))) for r in np.asarray(tris))

    peer = igl.boundary_facets(t)
    peer = peer[0] if isinstance(peer, tuple) else peer
    assert canonical(surface_triangles(v, t)) == canonical(peer)
    flipped = t[:, [1, 0, 2, 3]]                 # negatively oriented: still drawn outwards
    assert canonical(surface_triangles(v, flipped)) == canonical(peer)
    _, f = bar(nx=3)
    assert surface_triangles(v, f) is f
    assert surface_triangles(v, np.zeros((0, 3), dtype=np.int64)) is None
