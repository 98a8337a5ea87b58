"""algorithms.deformation._common, what every deformation method checks first: handles
against their mesh (:func:`check_handles`, which the service also runs before queueing a
job), and the pinned set (handles, then the vertices no face uses)."""

from __future__ import annotations

import numpy as np
import pytest

from algorithms.core.errors import DegenerateInputError, InvalidInputError
from algorithms.core.mesh import Handles, read_mesh
from algorithms.deformation import check_handles
from algorithms.deformation._common import pins_of
from tests.algorithms.deformation.deformation_meshes import grid


def test_check_handles_returns_the_checked_handles() -> None:
    v, f = grid(3, 3)
    h = check_handles({"vertices": v, "faces": f}, {"indices": [0, 8], "positions": v[[0, 8]]})
    assert isinstance(h, Handles)
    np.testing.assert_array_equal(h.indices, [0, 8])
    np.testing.assert_array_equal(h.positions, v[[0, 8]])
    pair = check_handles(read_mesh((v, f)), ([4], [[1.0, 1.0]]))   # an (indices, positions) pair
    np.testing.assert_array_equal(pair.indices, [4])


@pytest.mark.parametrize("handles, error, field, match", [
    ({"indices": [0, 0], "positions": [[0, 0]] * 2}, InvalidInputError, "handles.indices",
     "unique"),
    ({"indices": [0, 9], "positions": [[0, 0]] * 2}, InvalidInputError, "handles.indices",
     "below 9"),
    ({"indices": [0, 1], "positions": [[0, 0]]}, InvalidInputError, "handles.positions",
     "one row per index"),
    ({"indices": [0]}, InvalidInputError, "handles", "'indices' and 'positions'"),
])
def test_check_handles_names_what_is_wrong(handles, error, field, match) -> None:  # noqa: ANN001
    v, f = grid(3, 3)
    with pytest.raises(error, match=match) as info:
        check_handles((v, f), handles)
    assert info.value.field == field


def test_every_component_needs_a_handle() -> None:
    v, f = grid(3, 3)
    two_v, two_f = np.vstack([v, v + 5]), np.vstack([f, f + 9])
    with pytest.raises(DegenerateInputError, match=r"component of 9 vertices \(vertex 9 "
                       "among them\\) without one") as info:
        check_handles((two_v, two_f), {"indices": [0], "positions": [[0, 0]]}, name="pins")
    assert info.value.field == "pins"


def test_unused_vertices_are_pinned_after_the_handles() -> None:
    v, f = grid(3, 3)
    v = np.vstack([v, [[9.0, 9.0]]])                        # vertex 9: no face uses it
    pins = pins_of(read_mesh((v, f)), np.array([4]))
    np.testing.assert_array_equal(pins.indices, [4, 9])
    np.testing.assert_array_equal(pins.values(np.array([[0.0, 0.0]]), v), [[0, 0], [9, 9]])
