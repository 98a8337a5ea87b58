"""registration.fpfh against Open3D's ``compute_fpfh_feature`` on the same points and normals:
what ``max_neighbors`` means (Open3D's ``max_nn`` counts the query point itself).

The case: 3,000 points of the registration benches' lumpy closed surface, normals from
Open3D (30 nearest), FPFH radius 0.25 with the cap binding for most points. Rows: our FPFH
with ``max_neighbors = max_nn`` (the convention now) and with ``max_neighbors = max_nn + 1``
(what the old meaning, which did not count the point, amounted to), each against Open3D's
features with that ``max_nn``: the largest absolute difference of a histogram bin (bins sum
to 200 per block). Open3D is optional (the ``bench`` extra and ``libusb-1.0-0``).

    python bench/fpfh_open3d.py [--repeats 3]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]

from _common import blob, print_ratio_table, timed, timed_pair  # noqa: E402

from algorithms.registration.features import _fpfh  # noqa: E402

RADIUS = 0.25


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    pts = blob(3000, 0)
    try:
        import open3d as o3d
    except ImportError:
        print("Open3D is not installed (pip install '.[bench]'); nothing to compare.")
        return
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(pts))
    cloud.estimate_normals(o3d.geometry.KDTreeSearchParamKNN(30))
    normals = np.asarray(cloud.normals).copy()
    tree = cKDTree(pts)
    counts = tree.query_ball_point(pts, RADIUS, return_length=True)
    rows = []
    for max_nn in (20, 50, 100):
        def peer(max_nn: int = max_nn) -> np.ndarray:
            param = o3d.geometry.KDTreeSearchParamHybrid(radius=RADIUS, max_nn=max_nn)
            return np.asarray(o3d.pipelines.registration.compute_fpfh_feature(
                cloud, param).data).T
        t_ours, ours, t_peer, theirs = timed_pair(
            lambda max_nn=max_nn: _fpfh(pts, normals, tree, RADIUS, max_nn), peer,
            args.repeats)
        _, old = timed(lambda max_nn=max_nn: _fpfh(pts, normals, tree, RADIUS, max_nn + 1),
                       1)
        binding = float(np.mean(counts > max_nn))
        rows.append((f"max_nn={max_nn} (cap binds at {binding:.0%})", t_ours, t_peer,
                     f"max |diff| {np.abs(ours - theirs).max():.2e}",
                     f"old meaning {np.abs(old - theirs).max():.2e}"))
    print_ratio_table(rows, args.repeats)


if __name__ == "__main__":
    main()
