"""registration.fpfh against Open3D's ``compute_fpfh_feature`` on the same points and normals:
what ``max_neighbors`` means (Open3D's ``max_nn`` counts the query point itself).

The case: 3,000 points of the registration benches' lumpy closed surface, normals from
Open3D (30 nearest), FPFH radius 0.25 with the cap binding for most points. Rows: our FPFH
with ``max_neighbors = max_nn`` (the convention now) and with ``max_neighbors = max_nn + 1``
(what the old meaning, which did not count the point, amounted to), each against Open3D's
features with that ``max_nn``: the largest absolute difference of a histogram bin (bins sum
to 200 per block). Open3D is optional (the ``bench`` extra and ``libusb-1.0-0``).

Rows through ``_common.compare`` (ours and Open3D alternately after a warm-up, on the
points of seeds 0..2, the threads allowed).

    python bench/fpfh_open3d.py [--quick]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np
from scipy.spatial import cKDTree

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]

from _common import apply_policy, blob, compare, report  # noqa: E402

from algorithms.registration.features import _fpfh  # noqa: E402

RADIUS = 0.25


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="the same size (it is small)")
    parser.parse_args()
    apply_policy()
    try:
        import open3d as o3d
    except ImportError:
        print("Open3D is not installed (pip install '.[bench]'); nothing to compare.")
        return

    def data(seed: int) -> dict[str, Any]:
        pts = blob(3000, seed)
        cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(pts))
        cloud.estimate_normals(o3d.geometry.KDTreeSearchParamKNN(30))
        tree = cKDTree(pts)
        return {"pts": pts, "cloud": cloud, "normals": np.asarray(cloud.normals).copy(),
                "tree": tree, "counts": tree.query_ball_point(pts, RADIUS, return_length=True)}

    for max_nn in (20, 50, 100):
        def peer(d: dict[str, Any], max_nn: int = max_nn) -> np.ndarray:
            param = o3d.geometry.KDTreeSearchParamHybrid(radius=RADIUS, max_nn=max_nn)
            return np.asarray(o3d.pipelines.registration.compute_fpfh_feature(
                d["cloud"], param).data).T

        def ours(d: dict[str, Any], max_nn: int = max_nn) -> np.ndarray:
            return _fpfh(d["pts"], d["normals"], d["tree"], RADIUS, max_nn)

        def agree(d: dict[str, Any], a: np.ndarray, b: np.ndarray,
                  max_nn: int = max_nn) -> dict[str, float]:
            old = _fpfh(d["pts"], d["normals"], d["tree"], RADIUS, max_nn + 1)
            return {"max |diff|": float(np.abs(a - b).max()),
                    "old meaning": float(np.abs(old - b).max()),
                    "cap binds": float(np.mean(d["counts"] > max_nn))}

        compare("registration", f"FPFH 3,000 points, max_nn={max_nn}", data, ours, peer, None,
                agreement=agree, peer_name="Open3D compute_fpfh_feature",
                peer_threads="TBB (open3d.utility.set_max_threads)")
    report("FPFH vs Open3D")


if __name__ == "__main__":
    main()
