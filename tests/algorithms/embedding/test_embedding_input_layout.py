"""t-SNE and SNE give the same bits for the same points whatever their memory layout: a view
at an odd byte offset (as an array unpickled from a network frame in a Dask worker), a
view of a protocol-5 pickle buffer, Fortran order, strided views, nested lists.

A misaligned input once changed the last bits of ``x @ x.T`` (numpy then calls BLAS ``gemm``
on per-operand copies instead of ``syrk``), hence of ``P``, and the descent amplified them
to differences of order 1 in the embedding: the service's answer was not the library's."""

from __future__ import annotations

import pickle

import numpy as np
import pytest
from sklearn.datasets import make_blobs

from algorithms.embedding import sne, tsne
from algorithms.embedding.tsne import affinities

BLOBS = make_blobs(60, n_features=5, centers=3, random_state=0)[0]
FAST = {"perplexity": 8, "max_iterations": 120, "exaggeration_iterations": 50}


def _at_offset(a: np.ndarray, offset: int) -> np.ndarray:
    """A copy of ``a`` in a buffer ``offset`` bytes past a 64-byte boundary."""
    buf = np.zeros(a.nbytes + 128, dtype=np.uint8)
    start = (-buf.ctypes.data) % 64 + offset
    v = np.frombuffer(buf, dtype=a.dtype, count=a.size, offset=start).reshape(a.shape)
    v[...] = a
    return v


def _unpickled_at_offset(a: np.ndarray, offset: int) -> np.ndarray:
    """``a`` through a protocol-5 pickle whose out-of-band buffer sits ``offset`` bytes into
    a frame (as the service's Dask worker receives a job's inputs)."""
    buffers: list[pickle.PickleBuffer] = []
    stream = pickle.dumps(a, protocol=5, buffer_callback=buffers.append)
    raw = buffers[0].raw()
    frame = bytearray(offset + raw.nbytes)
    frame[offset:] = raw
    return pickle.loads(stream, buffers=[memoryview(frame)[offset:]])


def _layouts(x: np.ndarray) -> dict[str, object]:
    wide = np.repeat(x, 2, axis=1)
    tall = np.repeat(x, 2, axis=0)
    out: dict[str, object] = {f"offset {o}": _at_offset(x, o) for o in (1, 3, 4, 7, 8, 40)}
    out.update({"pickle frame +3": _unpickled_at_offset(x, 3),
                "fortran": np.asfortranarray(x), "strided columns": wide[:, ::2],
                "strided rows": tall[::2], "list": x.tolist()})
    return out


def test_the_layouts_are_what_they_claim() -> None:
    lay = _layouts(BLOBS)
    for name in ("offset 1", "offset 3", "offset 7", "pickle frame +3"):
        assert not lay[name].flags.aligned, name
    assert lay["offset 8"].flags.aligned and lay["offset 40"].flags.aligned
    for name, x in lay.items():
        np.testing.assert_array_equal(x, BLOBS, err_msg=name)


def test_dense_affinities_do_not_depend_on_the_layout() -> None:
    ref = affinities(BLOBS, 8.0, dense=True)
    for name, x in _layouts(BLOBS).items():
        if isinstance(x, np.ndarray):
            np.testing.assert_array_equal(affinities(x, 8.0, dense=True), ref, err_msg=name)


@pytest.mark.parametrize("function, inputs", [
    (sne, {}),
    (tsne, {"method": "exact"}),
    (tsne, {"method": "exact", "n_components": 1, "learning_rate": 20.0}),
    (tsne, {"method": "fft", "init": "random", "seed": 2}),
])
def test_same_bits_whatever_the_layout(function, inputs) -> None:  # noqa: ANN001
    ref = function(BLOBS, **FAST, **inputs)
    for name, x in _layouts(BLOBS).items():
        res = function(x, **FAST, **inputs)
        np.testing.assert_array_equal(res.embedding, ref.embedding, err_msg=name)
        assert res.kl_divergence == ref.kl_divergence, name
        assert res.trustworthiness == ref.trustworthiness, name
        assert res.iterations == ref.iterations, name
