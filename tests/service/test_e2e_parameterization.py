"""The parameterization processes over HTTP against a live server: each method on a small
curved sheet (uv per vertex, quality figures, LSCM equal to igl.lscm), and every input
error, non-disk meshes included, as a 422 problem+json naming the input."""

from __future__ import annotations

import igl
import numpy as np
import pytest

from tests.live import execute

pytestmark = pytest.mark.e2e

# a 4 × 4-vertex sheet bent over a ridge: a curved disk
_XS, _YS = np.meshgrid(np.arange(4.0), np.arange(4.0))
_V = np.c_[_XS.ravel(), _YS.ravel(), 0.3 * np.sin(_XS.ravel()) * np.cos(0.7 * _YS.ravel())]
_I = np.arange(16).reshape(4, 4)
_A, _B, _C, _D = _I[:-1, :-1].ravel(), _I[:-1, 1:].ravel(), _I[1:, :-1].ravel(), _I[1:, 1:].ravel()
_F = np.r_[np.c_[_A, _B, _D], np.c_[_A, _D, _C]]
SHEET = {"vertices": _V.tolist(), "faces": _F.tolist()}
# a closed tetrahedron, and the sheet with a hole (its centre faces removed)
TETRA = {"vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
         "faces": [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]}
_KEEP = ~np.isin(np.arange(len(_F)), [4, 13])   # the two triangles of the centre cell
HOLED = {"vertices": _V.tolist(), "faces": _F[_KEEP].tolist()}

CASES = [
    ("tutte", {}), ("tutte", {"boundary": "square", "weighting": "mean_value"}),
    ("harmonic", {}), ("conformal", {}), ("conformal", {"method": "spectral"}),
    ("arap", {"max_iterations": 20}), ("asap", {"max_iterations": 20}),
]


@pytest.mark.parametrize("method, options", CASES)
def test_each_method_flattens_the_sheet(http, method: str, options: dict) -> None:  # noqa: ANN001
    r = execute(http, f"parameterization.{method}", {"mesh": SHEET, **options})
    assert r.status_code == 200, r.text
    doc = r.json()
    uv = np.array(doc["uv"])
    assert uv.shape == (16, 2) and np.isfinite(uv).all()
    assert doc["flipped_faces"] == 0 and doc["degenerate_faces"] == 0
    assert doc["angle_distortion"] >= 0 and doc["area_distortion"] >= 0
    np.testing.assert_allclose(doc["mesh"]["vertices"], SHEET["vertices"])
    if method in ("arap", "asap"):
        e = doc["energy"]
        assert len(e) == doc["iterations"] + 1
        assert all(b <= a * (1 + 1e-12) for a, b in zip(e, e[1:], strict=False))


def test_lscm_over_http_equals_igl(http) -> None:  # noqa: ANN001
    pins = {"indices": [0, 15], "positions": [[0, 0], [3, 3]]}
    r = execute(http, "parameterization.conformal", {"mesh": SHEET, "pins": pins})
    assert r.status_code == 200, r.text
    peer, _ = igl.lscm(_V, _F.astype(np.int64), np.array([0, 15]),
                       np.array(pins["positions"], dtype=float))
    np.testing.assert_allclose(r.json()["uv"], peer, atol=1e-10)
    assert r.json()["pinned"] == [0, 15]


@pytest.mark.parametrize("method, inputs, field, fragment", [
    ("tutte", {"mesh": TETRA}, "mesh", "closed mesh"),
    ("harmonic", {"mesh": HOLED}, "mesh", "2 boundary loops"),
    ("conformal", {"mesh": TETRA, "method": "spectral"}, "mesh", "topological disk"),
    ("arap", {"mesh": HOLED}, "mesh", "2 boundary loops"),
    ("asap", {"mesh": {"vertices": SHEET["vertices"] + [[9, 9, 9]], "faces": SHEET["faces"]}},
     "mesh", "vertex 16 in no face"),
    ("tutte", {"mesh": SHEET, "boundary": "hexagon"}, "boundary", ""),
    ("conformal", {"mesh": SHEET, "pins": {"indices": [3], "positions": [[0, 0]]}},
     "pins", "at least 2 vertices"),
    ("conformal", {"mesh": SHEET, "method": "spectral",
                   "pins": {"indices": [0, 3], "positions": [[0, 0], [1, 0]]}},
     "pins", "method='spectral'"),
    ("conformal", {"mesh": SHEET, "pins": {"indices": [0, 99], "positions": [[0, 0], [1, 0]]}},
     "pins.indices", ""),
    ("arap", {"mesh": SHEET, "max_iterations": 0}, "max_iterations", ""),
])
def test_invalid_inputs_are_422_naming_the_input(http, method, inputs, field,  # noqa: ANN001
                                                 fragment) -> None:
    r = execute(http, f"parameterization.{method}", inputs)
    assert r.status_code == 422, r.text
    assert r.headers["content-type"] == "application/problem+json"
    body = r.json()
    assert body["status"] == 422
    assert body["errors"][0]["input"] == field, body
    assert fragment in body["errors"][0]["message"], body
