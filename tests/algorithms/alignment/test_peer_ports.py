"""Cases ported from scipy's own tests of ``Rotation.align_vectors``
(scipy/spatial/transform/tests/test_rotation.py), each naming the original.

``align_vectors(a, b)`` fits ``a ≈ R b`` for vectors (no translation); ``rigid(source,
target)`` fits ``target ≈ R source + t`` for points. On vectors whose best fit has no
translation the two agree; scipy's two-vector cases (``improper_rotation``,
``parallel``, ``antiparallel``) have no counterpart here (two points fix no rotation)."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.testing import assert_allclose
from scipy.spatial.transform import Rotation

from algorithms.alignment import rigid
from algorithms.core.errors import InvalidInputError


def _with_origin(v: np.ndarray) -> np.ndarray:
    # the origin as one more point: vectors become points whose fit has t = 0
    return np.vstack([np.zeros((1, v.shape[1])), v])


# scipy: test_rotation.py::test_align_vectors_no_rotation
def test_align_vectors_no_rotation() -> None:
    x = np.array([[1, 2, 3], [4, 5, 6], [1, 0, 2]], float)
    res = rigid(x, x.copy())
    assert_allclose(res.rotation, np.eye(3), atol=1e-12)
    assert_allclose(res.rmse, 0.0, atol=1e-6)


# scipy: test_rotation.py::test_align_vectors_no_noise
def test_align_vectors_no_noise() -> None:
    rng = np.random.default_rng(14697284569885399755764481408308808739)
    c = Rotation.random(rng=rng)
    b = rng.normal(size=(5, 3))
    a = c.apply(b)
    res = rigid(_with_origin(b), _with_origin(a))
    est, _ = Rotation.align_vectors(a, b)
    assert_allclose(res.rotation, c.as_matrix(), atol=1e-7)
    assert_allclose(res.rotation, est.as_matrix(), atol=1e-7)
    assert_allclose(res.translation, 0.0, atol=1e-7)
    assert_allclose(res.rmse, 0.0, atol=1e-7)


# scipy: test_rotation.py::test_align_vectors_scaled_weights (scaling every weight
# changes nothing)
def test_align_vectors_scaled_weights() -> None:
    a = Rotation.random(10, rng=0).apply([1, 0, 0])
    b = Rotation.random(10, rng=1).apply([1, 0, 0])
    one = rigid(b, a, weights=np.ones(10))
    two = rigid(b, a, weights=2 * np.ones(10))
    assert_allclose(one.rotation, two.rotation, atol=1e-12)
    assert_allclose(one.rmse, two.rmse, rtol=1e-12)


# scipy: test_rotation.py::test_align_vectors_noise (1° angular noise: the error of the
# estimate within 1.5 sigma)
def test_align_vectors_noise() -> None:
    rng = np.random.default_rng(146972845698875399755764481408308808739)
    rot = Rotation.random(rng=rng)
    vectors = rng.normal(size=(100, 3))
    result = rot.apply(vectors)
    sigma = np.deg2rad(1)
    noise = Rotation.from_rotvec(rng.normal(size=(100, 3), scale=sigma))
    noisy = noise.apply(result)
    res = rigid(_with_origin(vectors), _with_origin(noisy),
                weights=np.r_[1e6, np.ones(100)])  # the origin pinned: t = 0
    est = Rotation.from_matrix(res.rotation)
    error = (rot * est.inv()).as_rotvec()
    assert_allclose(error, 0.0, atol=1.5 * sigma)
    scipy_est, _ = Rotation.align_vectors(noisy, vectors)
    assert_allclose(res.rotation, scipy_est.as_matrix(), atol=1e-4)


TRI = [[1, 2, 3], [2, 3, 5], [0, 1, 0]]


# scipy: test_rotation.py::test_align_vectors_invalid_input
@pytest.mark.parametrize("kwargs, field", [
    ({"source": [[1, 2, 3], [2, 3, 4]], "target": [[1, 2, 3]]}, "target"),
    ({"source": TRI, "target": TRI, "weights": [1, 2]}, "weights"),
    ({"source": TRI, "target": TRI, "weights": [-1, 1, 1]}, "weights"),
])
def test_align_vectors_invalid_input(kwargs, field) -> None:  # noqa: ANN001
    with pytest.raises(InvalidInputError) as err:
        rigid(**kwargs)
    assert err.value.field == field


# scipy: test_rotation.py::test_align_vectors_near_inf (huge weights on two vectors)
def test_align_vectors_huge_weights() -> None:
    rng = np.random.default_rng(0)
    rot = Rotation.random(rng=rng)
    b = rng.normal(size=(6, 3))
    a = rot.apply(b)
    # three points (the origin and two vectors) of weight 1e20 still fix the rotation
    res = rigid(_with_origin(b), _with_origin(a), weights=[1e20, 1e20, 1e20, 1, 1, 1, 1])
    assert_allclose(res.rotation, rot.as_matrix(), atol=1e-7)
