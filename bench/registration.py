"""The registration family against its peers, side by side in one run.

Prints one table: for each case our time, the peer's time on the same data, their ratio
(ours / peer: below 1 is faster), and the rotation error each ends with (degrees, against the
known rotation), so that speed is never bought with accuracy unseen. Every time is the median
of --repeats runs.

    python bench/registration.py [--repeats 3] [--quick]

Cases: ICP point_to_point, 100,000 ↔ 100,000 points (two independent samplings of a lumpy
closed surface, the target turned by 10° and shifted, 0.2% noise), 30 iterations, against a
plain numpy + ``cKDTree`` loop (query with ``workers=-1``, Kabsch by SVD, compose); both with
the same correspondence bound. Open3D's ``registration_icp`` is the reference peer; it is
not installed in the test environment (it needs the ``bench`` extra and
``libusb-1.0-0``), and its row is printed only when ``import open3d`` works. A benchmark never
asserts.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]

from _common import angle_deg, blob, print_ratio_table, timed, timed_pair  # noqa: E402

from algorithms.registration import icp  # noqa: E402

ITERATIONS = 30
ANGLE = 10.0


def plain_icp(src: np.ndarray, dst: np.ndarray, iterations: int, max_dist: float
              ) -> np.ndarray:
    """The loop users write: one tree, query, Kabsch on the pairs in range, compose."""
    tree = cKDTree(dst)
    transform = np.eye(4)
    moved = src
    for _ in range(iterations):
        dist, idx = tree.query(moved, workers=-1, distance_upper_bound=max_dist)
        keep = np.isfinite(dist)
        x, y = moved[keep], dst[idx[keep]]
        xm, ym = x.mean(axis=0), y.mean(axis=0)
        u, _, vt = np.linalg.svd((y - ym).T @ (x - xm))
        fix = np.diag([1.0, 1.0, np.sign(np.linalg.det(u @ vt))])
        rot = u @ fix @ vt
        step = np.eye(4)
        step[:3, :3] = rot
        step[:3, 3] = ym - rot @ xm
        transform = step @ transform
        moved = moved @ rot.T + step[:3, 3]
    return transform


def case_icp(n: int, repeats: int) -> list[tuple[str, float, float, str, str]]:
    rng = np.random.default_rng(0)
    src = blob(n, 1)
    rot = Rotation.from_rotvec(np.radians(ANGLE) * np.array([1.0, 2.0, 3.0]) / np.sqrt(14))
    truth = rot.as_matrix()
    dst = blob(n, 2) @ truth.T + [0.05, -0.03, 0.02] + rng.normal(0.0, 0.002, (n, 3))
    max_dist = 0.2

    def ours(tol: float) -> np.ndarray:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # max_iterations reached is expected here
            res = icp(src, dst, max_iterations=ITERATIONS, tolerance=tol,
                      max_correspondence_distance=max_dist)
        return res

    rows = []
    for tol, label in ((0.0, "30 iterations"), (1e-6, "Open3D's default stop 1e-6")):
        # alternate ours and the loop, so that a busy machine slows both alike
        ours_t, res, peer_t, peer_tf = timed_pair(
            lambda tol=tol: ours(tol), lambda: plain_icp(src, dst, ITERATIONS, max_dist),
            repeats)
        peer_err = f"{angle_deg(peer_tf[:3, :3], truth):.4f}°"
        rows.append((f"ICP p2p {n:,}↔{n:,}, {label} ({res.iterations} run) vs numpy+cKDTree "
                     f"loop (30)", ours_t, peer_t,
                     f"{angle_deg(res.rotation, truth):.4f}°", peer_err))
    try:
        import open3d as o3d  # noqa: PLC0415 - optional peer
    except ImportError:
        print("note: Open3D is not installed; its registration_icp row needs the bench extra "
              "(pip install '.[bench]', apt libusb-1.0-0). Issue #4 measured it at 1.6 s "
              "for this case on the reference machine.")
    else:
        a, b = o3d.geometry.PointCloud(), o3d.geometry.PointCloud()
        a.points, b.points = o3d.utility.Vector3dVector(src), o3d.utility.Vector3dVector(dst)
        crit = o3d.pipelines.registration.ICPConvergenceCriteria(max_iteration=ITERATIONS)
        est = o3d.pipelines.registration.TransformationEstimationPointToPoint()

        def o3d_run() -> np.ndarray:
            return np.asarray(o3d.pipelines.registration.registration_icp(
                a, b, max_dist, np.eye(4), est, crit).transformation)

        o3d_t, o3d_tf = timed(o3d_run, repeats)
        ours_t, res = timed(lambda: ours(1e-6), repeats)
        rows.append((f"ICP p2p {n:,}↔{n:,} vs Open3D registration_icp", ours_t, o3d_t,
                     f"{angle_deg(res.rotation, truth):.4f}°",
                     f"{angle_deg(o3d_tf[:3, :3], truth):.4f}°"))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--quick", action="store_true", help="a tenth of the sizes")
    args = parser.parse_args()
    k = 10 if args.quick else 1
    rows = case_icp(100_000 // k, args.repeats)
    from _reg_cpd import case_cpd  # noqa: PLC0415

    rows += case_cpd(args.repeats, args.quick)
    from _reg_ransac import case_ransac  # noqa: PLC0415

    rows += case_ransac(args.repeats, args.quick)
    print_ratio_table(rows, args.repeats)


if __name__ == "__main__":
    main()
