"""The MeshInput and Handles input types of the catalog, and meshes in JSON results (no server)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from pydantic import Field, ValidationError, model_validator

from algorithms.core.mesh import Handles as HandlesData
from algorithms.core.mesh import Mesh, as_handles
from service import jsonio
from service.catalog.base import Params
from service.catalog.inputs import Handles, HandlesInput, MeshInput
from service.problems import pydantic_errors

TRIANGLES = {"vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]],
             "faces": [[0, 1, 2], [1, 3, 2]]}


class DeformParams(Params):
    mesh: MeshInput = Field(description="The mesh.")
    handles: Handles = Field(description="The handles.")

    @model_validator(mode="after")
    def _handles_in_mesh(self) -> DeformParams:
        as_handles(self.handles, self.mesh, name="handles")
        return self


class TwoMeshParams(Params):
    source: MeshInput = Field(description="Rest shape.")
    target: MeshInput | None = Field(None, description="Deformed shape.")


def errors_of(exc: ValidationError) -> list[dict[str, str]]:
    return pydantic_errors(exc.errors())


def test_valid_inputs_become_dataclasses():
    p = DeformParams.model_validate(
        {"mesh": TRIANGLES, "handles": {"indices": [0, 3], "positions": [[0, 0, 1], [1, 1, 1]]}},
        context={"max_points": 100})
    assert isinstance(p.mesh, Mesh) and isinstance(p.handles, HandlesData)
    assert p.mesh.vertices.dtype == np.float64 and p.mesh.faces.dtype == np.int64
    assert p.handles.indices.tolist() == [0, 3]
    assert HandlesInput is Handles


def test_dataclasses_are_accepted_as_they_are():
    first = DeformParams.model_validate(
        {"mesh": TRIANGLES, "handles": {"indices": [1], "positions": [[1, 0, 0]]}})
    again = DeformParams(mesh=first.mesh, handles=first.handles)
    np.testing.assert_array_equal(again.mesh.faces, first.mesh.faces)


def test_dump_gives_the_json_shape_back():
    p = DeformParams.model_validate(
        {"mesh": TRIANGLES, "handles": {"indices": [1], "positions": [[1, 0, 0]]}})
    dumped = p.model_dump(mode="json")
    assert dumped["mesh"] == {"vertices": [[float(c) for c in r] for r in TRIANGLES["vertices"]],
                              "faces": TRIANGLES["faces"]}
    assert dumped["handles"] == {"indices": [1], "positions": [[1.0, 0.0, 0.0]]}


def test_schema_describes_objects():
    props = DeformParams.model_json_schema(mode="validation")["properties"]
    assert props["mesh"]["type"] == "object"
    assert props["mesh"]["required"] == ["vertices", "faces"]
    assert props["mesh"]["properties"]["faces"]["items"]["maxItems"] == 3
    assert props["handles"]["type"] == "object"
    assert props["handles"]["required"] == ["indices", "positions"]
    json.dumps(props, allow_nan=False)


@pytest.mark.parametrize("mesh, field, message", [
    ({"vertices": [[0, 0, 0]] * 3, "faces": [[0, 1, 2]]}, "mesh.faces", "degenerate"),
    ({"vertices": TRIANGLES["vertices"], "faces": [[0, 1, 9]]}, "mesh.faces",
     "vertex indices below 4, got 9 at row 0"),
    ({"vertices": [[0, 0, float("nan")], [1, 0, 0], [0, 1, 0]], "faces": [[0, 1, 2]]},
     "mesh.vertices", "finite numbers, got nan at row 0"),
    ({"vertices": TRIANGLES["vertices"]}, "mesh", "got no 'faces'"),
    ({**TRIANGLES, "normals": []}, "mesh", "unknown key 'normals'"),
    ([[0, 0, 0]], "mesh", "got list"),
])
def test_mesh_errors_name_the_input(mesh, field, message):
    with pytest.raises(ValidationError) as info:
        DeformParams.model_validate({"mesh": mesh, "handles": {"indices": [0],
                                                               "positions": [[0, 0, 0]]}})
    (err,) = errors_of(info.value)
    assert err["input"] == field and message in err["message"]


def test_mesh_vertex_limit_from_context():
    with pytest.raises(ValidationError) as info:
        DeformParams.model_validate(
            {"mesh": TRIANGLES, "handles": {"indices": [0], "positions": [[0, 0, 0]]}},
            context={"max_points": 3})
    (err,) = errors_of(info.value)
    assert err["input"] == "mesh.vertices" and "at most 3 points, got 4" in err["message"]


def test_field_name_is_used():
    with pytest.raises(ValidationError) as info:
        TwoMeshParams.model_validate({"source": {"vertices": [[0, 0], [1, 0], [0, 1]],
                                                 "faces": [[0, 1, 3]]}})
    (err,) = errors_of(info.value)
    assert err["input"] == "source.faces"
    assert TwoMeshParams.model_validate({"source": TRIANGLES}).target is None


@pytest.mark.parametrize("handles, field, message", [
    ({"indices": [0, 0], "positions": [[0, 0, 0]] * 2}, "handles.indices", "0 twice"),
    ({"indices": [7], "positions": [[0, 0, 0]]}, "handles.indices", "below 4, got 7"),
    ({"indices": [1], "positions": [[0, 0]]}, "handles.positions", "got shape (1, 2)"),
    ({"indices": [1, 2], "positions": [[0, 0, 0]]}, "handles.positions", "one row per index"),
    ({"indices": [1]}, "handles", "got no 'positions'"),
    ({"indices": [-1], "positions": [[0, 0, 0]]}, "handles.indices", "non-negative"),
])
def test_handle_errors_name_the_input(handles, field, message):
    with pytest.raises(ValidationError) as info:
        DeformParams.model_validate({"mesh": TRIANGLES, "handles": handles})
    (err,) = errors_of(info.value)
    assert err["input"] == field and message in err["message"], err


def test_mesh_results_serialise_as_objects():
    p = DeformParams.model_validate(
        {"mesh": TRIANGLES, "handles": {"indices": [1], "positions": [[1, 0, 0]]}})
    out = json.loads(jsonio.dumps({"mesh": p.mesh, "handles": p.handles,
                                   "flipped": Mesh(p.mesh.vertices[:, ::-1], p.mesh.faces)}))
    assert out["mesh"] == {"vertices": p.mesh.vertices.tolist(), "faces": TRIANGLES["faces"]}
    assert out["handles"] == {"indices": [1], "positions": [[1.0, 0.0, 0.0]]}
    assert out["flipped"]["vertices"][1] == [0.0, 0.0, 1.0]       # non-contiguous array too
    assert p.mesh.nbytes == 4 * 3 * 8 + 2 * 3 * 8
