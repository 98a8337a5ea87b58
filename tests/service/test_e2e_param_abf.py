"""parameterization.abf over HTTP against a live server: a curved sheet flattened (uv per
vertex, the angles it realises, quality figures, Newton history), a planar sheet kept up to
a similarity, and bad inputs, non-disk meshes included, as a 422 problem+json naming the
input."""

from __future__ import annotations

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
TETRA = {"vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
         "faces": [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]}
_KEEP = ~np.isin(np.arange(len(_F)), [4, 13])   # the two triangles of the centre cell
HOLED = {"vertices": _V.tolist(), "faces": _F[_KEEP].tolist()}


def _angles(uv: np.ndarray, f: np.ndarray) -> np.ndarray:
    p = uv[f]
    out = np.empty(f.shape)
    for k in range(3):
        a, b = p[:, (k + 1) % 3] - p[:, k], p[:, (k + 2) % 3] - p[:, k]
        out[:, k] = np.arctan2(np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]),
                               (a * b).sum(axis=1))
    return out


def test_abf_flattens_the_curved_sheet(http) -> None:  # noqa: ANN001
    r = execute(http, "parameterization.abf", {"mesh": SHEET, "tolerance": 1e-10})
    assert r.status_code == 200, r.text
    doc = r.json()
    uv = np.array(doc["uv"])
    assert uv.shape == (16, 2) and np.isfinite(uv).all()
    assert doc["converged"] is True and len(doc["gradient_norm"]) == doc["iterations"] + 1
    assert doc["gradient_norm"][-1] <= 1e-10 < doc["gradient_norm"][0]
    assert doc["flipped_faces"] == 0 and doc["degenerate_faces"] == 0
    assert doc["angle_distortion"] > 0 and doc["area_distortion"] > 0
    angles = np.array(doc["angles"])
    np.testing.assert_allclose(angles.sum(axis=1), np.pi, atol=1e-10)
    np.testing.assert_allclose(_angles(uv, _F), angles, atol=1e-8)   # laid out exactly
    np.testing.assert_allclose(doc["mesh"]["vertices"], SHEET["vertices"])
    assert len(doc["pinned"]) == 2


def test_abf_keeps_a_planar_sheet_up_to_a_similarity(http) -> None:  # noqa: ANN001
    flat = np.c_[_XS.ravel(), _YS.ravel()] + 0.2 * np.sin(np.arange(16.0))[:, None]
    r = execute(http, "parameterization.abf", {"mesh": {"vertices": flat.tolist(),
                                                        "faces": SHEET["faces"]}})
    assert r.status_code == 200, r.text
    doc = r.json()
    uv = np.array(doc["uv"])
    d_uv = np.linalg.norm(uv[:, None] - uv[None], axis=-1)
    d_in = np.linalg.norm(flat[:, None] - flat[None], axis=-1)
    s = (d_uv * d_in).sum() / (d_in * d_in).sum()
    np.testing.assert_allclose(d_uv, s * d_in, atol=1e-10 * s * d_in.max())
    assert doc["iterations"] == 0 and doc["angle_distortion"] < 1e-10


@pytest.mark.parametrize("inputs, field, fragment", [
    ({"mesh": TETRA}, "mesh", "closed mesh"),
    ({"mesh": HOLED}, "mesh", "2 boundary loops"),
    ({"mesh": {"vertices": SHEET["vertices"] + [[9, 9, 9]], "faces": SHEET["faces"]}},
     "mesh", "vertex 16 in no face"),
    ({"mesh": SHEET, "max_iterations": 0}, "max_iterations", ""),
    ({"mesh": SHEET, "tolerance": -1}, "tolerance", ""),
])
def test_invalid_inputs_are_422_naming_the_input(http, inputs, field,  # noqa: ANN001
                                                 fragment) -> None:
    r = execute(http, "parameterization.abf", inputs)
    assert r.status_code == 422, r.text
    assert r.headers["content-type"] == "application/problem+json"
    body = r.json()
    assert body["status"] == 422
    assert body["errors"][0]["input"] == field, body
    assert fragment in body["errors"][0]["message"], body
