"""registration.ransac against Open3D's FPFH RANSAC, for bench/registration.py.

The case mirrors Open3D's global registration tutorial on a generated scan pair: the
source is a plane's cut keeping 70 % of an asymmetric lumpy closed surface, the target an
independent sampling of the whole surface turned by a large rotation (about 150°, its axis
drawn per seed) and moved, both with Gaussian noise of 0.005 (0.13 % of the diagonal);
voxel 0.05, FPFH radius 0.25 (5 voxels, at most 100 neighbours), normals from 30
neighbours within 0.1 for Open3D, inlier distance 0.075 (1.5 voxels), edge-length checker
0.9, at most 100,000 hypotheses, confidence 0.999, mutual filter on.

Two rows, the same pipeline on both sides:

- RANSAC alone: ours with ``refine=False``; Open3D: down-sampling, normals, features and
  RANSAC;
- RANSAC and its refinement: ours with its ICP refinement (at most 20,000 source points,
  a random subsample, point-to-plane onto the down-sampled target with the normals of the
  feature step, within 1.5 voxels, 30 iterations); Open3D followed by its point-to-plane
  ``registration_icp`` of the same kind of points: 20,000 source points drawn at random
  (all of them when fewer) onto the down-sampled target, whose normals its feature step
  computed in the same call, within 1.5 voxels, at most 30 iterations. Nothing is cached
  from one call to the next on either side.

Errors: rotation error against the known rotation, in degrees. Open3D is optional (the
``bench`` extra); without it the rows show our side only.

    python bench/_reg_ransac.py [--quick]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np
from scipy.spatial.transform import Rotation

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]

from _common import angle_deg as _angle_deg  # noqa: E402
from _common import apply_policy, compare, report  # noqa: E402
from _common import blob as _blob  # noqa: E402

from algorithms.registration import ransac  # noqa: E402
from algorithms.registration.ransac import REFINE_ITERATIONS, REFINE_POINTS  # noqa: E402

VOXEL = 0.05
NOISE = 0.005


def _scan_pair(n: int, seed: int) -> dict[str, Any]:
    rng = np.random.default_rng(seed)
    full = _blob(n, 2 * seed + 1)
    height = full @ np.array([0.6, -0.48, 0.64])
    src = full[height <= np.quantile(height, 0.7)]
    src = src + rng.normal(0.0, NOISE, src.shape)
    axis = np.array([1.0, 2.0, -2.0]) / 3.0 + rng.normal(0.0, 0.2, 3)
    truth = Rotation.from_rotvec(np.radians(150.0) * axis / np.linalg.norm(axis)).as_matrix()
    dst = _blob(n, 2 * seed + 2) @ truth.T + [0.4, -0.2, 0.3]
    dst = dst + rng.normal(0.0, NOISE, dst.shape)
    return {"src": src, "dst": dst, "rot": truth, "seed": seed}


def _error(d: dict[str, Any], rot: np.ndarray) -> dict[str, float]:
    return {"rot°": _angle_deg(rot, d["rot"])}


def case_ransac(quick: bool) -> None:
    n = 20_000 if quick else 200_000

    def ours(refine: bool) -> Any:
        def run(d: dict[str, Any]) -> np.ndarray:
            return ransac(d["src"], d["dst"], voxel_size=VOXEL, refine=refine,
                          seed=d["seed"]).rotation
        return run

    def data(seed: int) -> dict[str, Any]:
        return _scan_pair(n, seed)

    probe = data(0)
    size = f"{len(probe['src']):,}↔{len(probe['dst']):,}"
    threads = ("kd-tree workers -1 from 8,192 points, the ICP refinement's search split "
               "over the cores (1 core under the 1-thread policy)")
    try:
        import open3d as o3d  # noqa: PLC0415 - optional peer
    except ImportError:
        print("note: Open3D is not installed (the bench extra): ours alone")
        for refine, label in ((False, "no refinement"), (True, "+ ICP refinement")):
            compare("registration", f"RANSAC+FPFH {size}, {label}", data, ours(refine), None,
                    _error, ours_threads=threads)
        return

    reg = o3d.pipelines.registration

    def with_clouds(seed: int) -> dict[str, Any]:
        d = data(seed)
        a, b = o3d.geometry.PointCloud(), o3d.geometry.PointCloud()
        a.points, b.points = o3d.utility.Vector3dVector(d["src"]), \
            o3d.utility.Vector3dVector(d["dst"])
        rng = np.random.default_rng(seed)
        m = len(d["src"])
        pick = np.sort(rng.choice(m, REFINE_POINTS, replace=False)) if m > REFINE_POINTS \
            else np.arange(m)
        part = o3d.geometry.PointCloud()
        part.points = o3d.utility.Vector3dVector(d["src"][pick])
        d["o3d"] = (a, b, part)
        return d

    def o3d_global(d: dict[str, Any]) -> Any:
        a, b, _ = d["o3d"]
        o3d.utility.random.seed(d["seed"])
        feats, downs = [], []
        for cloud in (a, b):
            down = cloud.voxel_down_sample(VOXEL)
            down.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=2 * VOXEL,
                                                                       max_nn=30))
            feats.append(reg.compute_fpfh_feature(
                down, o3d.geometry.KDTreeSearchParamHybrid(radius=5 * VOXEL, max_nn=100)))
            downs.append(down)
        dist = 1.5 * VOXEL
        res = reg.registration_ransac_based_on_feature_matching(
            downs[0], downs[1], feats[0], feats[1], True, dist,
            reg.TransformationEstimationPointToPoint(False), 3,
            [reg.CorrespondenceCheckerBasedOnEdgeLength(0.9),
             reg.CorrespondenceCheckerBasedOnDistance(dist)],
            reg.RANSACConvergenceCriteria(100000, 0.999))
        return res, downs[1]

    def o3d_rotation(d: dict[str, Any]) -> np.ndarray:
        return np.asarray(o3d_global(d)[0].transformation)[:3, :3]

    def o3d_refined(d: dict[str, Any]) -> np.ndarray:
        res, target = o3d_global(d)            # target: down-sampled, normals computed here
        part = d["o3d"][2]
        out = reg.registration_icp(part, target, 1.5 * VOXEL, res.transformation,
                                   reg.TransformationEstimationPointToPlane(),
                                   reg.ICPConvergenceCriteria(
                                       max_iteration=REFINE_ITERATIONS))
        return np.asarray(out.transformation)[:3, :3]

    peer_threads = "TBB (open3d.utility.set_max_threads)"
    compare("registration", f"RANSAC+FPFH {size}, no refinement", with_clouds, ours(False),
            o3d_rotation, _error, peer_name="Open3D FPFH RANSAC", ours_threads=threads,
            peer_threads=peer_threads)
    compare("registration", f"RANSAC+FPFH {size} + point-to-plane ICP "
            f"(≤ {REFINE_POINTS:,} source points onto the down-sampled target)", with_clouds,
            ours(True), o3d_refined, _error, peer_name="Open3D FPFH RANSAC + registration_icp",
            ours_threads=threads, peer_threads=peer_threads)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="a tenth of the sizes")
    args = parser.parse_args()
    apply_policy()
    case_ransac(args.quick)
    report("registration: RANSAC")


if __name__ == "__main__":
    main()
