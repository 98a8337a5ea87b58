"""OWSLib, an OGC API – Processes client written without us in mind, works unchanged: it lists
the processes, describes one, and executes one synchronously with the right answer."""

from __future__ import annotations

import numpy as np
import pytest
from owslib.ogcapi.processes import Processes
from scipy.spatial.transform import Rotation

pytestmark = pytest.mark.e2e


def test_owslib_lists_describes_and_executes(server) -> None:  # noqa: ANN001
    api = Processes(server.url)
    ids = [p["id"] for p in api.processes()]
    assert "alignment.rigid" in ids and "registration.icp" in ids
    description = api.process("alignment.rigid")
    assert description["id"] == "alignment.rigid"
    assert {"source", "target"} <= set(description["inputs"])
    assert "transform" in description["outputs"]

    rng = np.random.default_rng(7)
    source = rng.normal(size=(25, 3))
    rotation = Rotation.from_euler("zyx", [25, -10, 40], degrees=True).as_matrix()
    target = source @ rotation.T + [0.5, 1.5, -2.0]
    results = api.execute("alignment.rigid", {"source": source.tolist(),
                                               "target": target.tolist()})
    np.testing.assert_allclose(results["rotation"], rotation, atol=1e-10)
    np.testing.assert_allclose(results["translation"], [0.5, 1.5, -2.0], atol=1e-10)
    assert results["rmse"] < 1e-10

    # OGC qualified values ({"value": ...}) and the raw response of one output
    raw = api.execute("alignment.rigid", {"source": {"value": source.tolist()},
                                          "target": {"value": target.tolist()}},
                      outputs={"rmse": {}}, response="raw")
    assert raw < 1e-10
