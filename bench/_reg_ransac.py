"""registration.ransac against Open3D's FPFH RANSAC, for bench/registration.py.

The case mirrors Open3D's global registration tutorial on a generated scan pair: the
source is a plane's cut keeping 70 % of an asymmetric lumpy closed surface, the target an
independent sampling of the whole surface turned by a large rotation (about 150°) and moved,
both with Gaussian noise of 0.005 (0.13 % of the diagonal); voxel 0.05, FPFH radius 0.25 (5
voxels, at most 100 neighbours), normals from 30 neighbours within 0.1 for Open3D, inlier
distance 0.075 (1.5 voxels), edge-length checker 0.9, at most 100,000 hypotheses,
confidence 0.999, mutual filter on. Two rows: RANSAC alone (ours with ``refine=False``;
Open3D: down-sampling, normals, features and RANSAC), and the whole registration (ours
with its ICP refinement; Open3D followed by its point-to-plane ``registration_icp`` on the
full sets, threshold 0.4 voxel, as in the tutorial). Errors are rotation errors against the
known rotation, in degrees. Open3D is optional (the ``bench`` extra and ``libusb-1.0-0``);
without it the rows show our side only and a note is printed.

    python bench/_reg_ransac.py [--repeats 3] [--quick]
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]

from _common import angle_deg as _angle_deg  # noqa: E402
from _common import blob as _blob  # noqa: E402
from _common import timed, timed_pair  # noqa: E402

from algorithms.registration import ransac  # noqa: E402

VOXEL = 0.05
NOISE = 0.005


def _scan_pair(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(0)
    full = _blob(n, 1)
    height = full @ np.array([0.6, -0.48, 0.64])
    src = full[height <= np.quantile(height, 0.7)]
    src = src + rng.normal(0.0, NOISE, src.shape)
    truth = Rotation.from_rotvec(np.radians(150.0) * np.array([1.0, 2.0, -2.0]) / 3.0)
    dst = _blob(n, 2) @ truth.as_matrix().T + [0.4, -0.2, 0.3]
    dst = dst + rng.normal(0.0, NOISE, dst.shape)
    return src, dst, truth.as_matrix()


def case_ransac(repeats: int, quick: bool) -> list[tuple[str, float, float, str, str]]:
    """Rows ``(label, ours_s, peer_s, our_err, peer_err)``; NaN times where Open3D is absent."""
    n = 20_000 if quick else 200_000
    src, dst, truth = _scan_pair(n)

    def ours(refine: bool):  # noqa: ANN202
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return ransac(src, dst, voxel_size=VOXEL, refine=refine, seed=0)

    try:
        import open3d as o3d  # noqa: PLC0415 - optional peer
    except ImportError:
        print("note: Open3D is not installed; its FPFH RANSAC rows need the bench extra "
              "(pip install '.[bench]', apt libusb-1.0-0). Issue #4 measured it at 2.5-3.4 s "
              "with 0.8-2.1° error on its tutorial pair on the reference machine.")
        rows = []
        for refine, label in ((False, "RANSAC+FPFH, no refinement"),
                              (True, "RANSAC+FPFH + ICP refinement")):
            t, res = timed(lambda refine=refine: ours(refine), repeats)
            rows.append((f"{label} {len(src):,}↔{len(dst):,} (Open3D absent)", t, float("nan"),
                         f"{_angle_deg(res.rotation, truth):.3f}°", "—"))
        return rows

    reg = o3d.pipelines.registration
    a, b = o3d.geometry.PointCloud(), o3d.geometry.PointCloud()
    a.points, b.points = o3d.utility.Vector3dVector(src), o3d.utility.Vector3dVector(dst)
    o3d.utility.random.seed(0)

    def o3d_global():  # noqa: ANN202
        feats = []
        downs = []
        for cloud in (a, b):
            down = cloud.voxel_down_sample(VOXEL)
            down.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=2 * VOXEL,
                                                                       max_nn=30))
            feats.append(reg.compute_fpfh_feature(
                down, o3d.geometry.KDTreeSearchParamHybrid(radius=5 * VOXEL, max_nn=100)))
            downs.append(down)
        dist = 1.5 * VOXEL
        return reg.registration_ransac_based_on_feature_matching(
            downs[0], downs[1], feats[0], feats[1], True, dist,
            reg.TransformationEstimationPointToPoint(False), 3,
            [reg.CorrespondenceCheckerBasedOnEdgeLength(0.9),
             reg.CorrespondenceCheckerBasedOnDistance(dist)],
            reg.RANSACConvergenceCriteria(100000, 0.999))

    def o3d_full():  # noqa: ANN202
        start = o3d_global().transformation
        if not b.has_normals():
            b.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=2 * VOXEL,
                                                                    max_nn=30))
        return reg.registration_icp(a, b, 0.4 * VOXEL, start,
                                    reg.TransformationEstimationPointToPlane())

    rows = []
    for refine, peer, label in ((False, o3d_global, "RANSAC+FPFH, no refinement"),
                                (True, o3d_full, "RANSAC+FPFH + point-to-plane ICP")):
        ours_t, res, peer_t, peer_res = timed_pair(lambda refine=refine: ours(refine), peer,
                                                   repeats)
        peer_rot = np.asarray(peer_res.transformation)[:3, :3]
        rows.append((f"{label} {len(src):,}↔{len(dst):,} vs Open3D", ours_t, peer_t,
                     f"{_angle_deg(res.rotation, truth):.3f}°",
                     f"{_angle_deg(peer_rot, truth):.3f}°"))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--quick", action="store_true", help="a tenth of the sizes")
    args = parser.parse_args()
    from _common import print_ratio_table  # noqa: PLC0415

    print_ratio_table(case_ransac(args.repeats, args.quick), args.repeats)


if __name__ == "__main__":
    main()
