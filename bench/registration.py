"""The registration family against its peers, through the harness of ``_common.compare``.

Every row: ours and the peer alternately after a warm-up, seeds 0..2 (the data and the
rotation change with the seed), the median and range of the times, the threads each side
was allowed and the accuracy of every seed (rotation error in degrees against the known
rotation, translation error, iterations). ``bench/run.py`` runs this file once per thread
policy.

    python bench/registration.py [--quick | --large]

Cases:

- ICP point_to_point, 10,000 and 100,000 points a side (``--quick``: 10,000): two
  independent samplings of a lumpy closed surface, the target turned by 10° about a random
  axis, shifted, with 0.2 % noise, correspondence bound 0.2; 30 iterations on both sides
  (no early stop: ours ``tolerance=0``, Open3D's relative fitness and RMSE 0), and each with
  its default stopping rule (at most 30 iterations; ours ``tolerance=1e-6``, Open3D 1e-6 /
  1e-6), against Open3D's ``registration_icp``; and the 30 iterations against a plain numpy
  + ``cKDTree`` loop (query with the policy's ``workers``, Kabsch by SVD, compose), and
  against the floor of an iteration (``floor_icp``: one query of every source point, both
  sets sorted in spatial order outside the timing, and a 3 × 3 SVD; the goal is at most
  1.3× its time);
- ICP point_to_plane, the same pairs, 30 iterations on both sides, both given the same
  target normals (Open3D's 10-nearest estimate, made outside the timing);
- ICP symmetric (Rusinkiewicz 2019) against Open3D's ``registration_symmetric_icp``, the
  same pairs, 30 iterations, both given the same source and target normals (Open3D's
  source cloud with normals is a separate copy: Open3D transforms a cloud's normals with
  its points every iteration, which the other rows must not pay for);
- ``--large``: ICP point_to_point at 1,000,000 points a side against Open3D, 10 iterations
  (the first, costliest ones: a 30-iteration run takes minutes a side), one run per seed,
  the warm-up on the 10,000-point case; nothing else;
- under the default policy only: ours at default threads against ours pinned to one core in
  the same process (``one_core``), for ICP (default stop) and CPD: default must never be
  slower;
- rigid CPD with scale (``_reg_cpd``) against pycpd, and its memory bound;
- FPFH RANSAC, alone and refined (``_reg_ransac``), against Open3D's tutorial pipeline.

A benchmark never asserts.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from scipy.spatial import cKDTree
from scipy.spatial.transform import Rotation

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]

from _common import (  # noqa: E402
    angle_deg,
    apply_policy,
    blob,
    compare,
    report,
    single_thread,
    workers,
)
from threadpoolctl import threadpool_limits  # noqa: E402

from algorithms.registration import icp  # noqa: E402
from algorithms.registration.icp import _spatial_order  # noqa: E402

ITERATIONS = 30
ANGLE = 10.0
MAX_DIST = 0.2


def plain_icp(src: np.ndarray, dst: np.ndarray, iterations: int, max_dist: float
              ) -> np.ndarray:
    """The loop users write: one tree, query, Kabsch on the pairs in range, compose."""
    tree = cKDTree(dst)
    transform = np.eye(4)
    moved = src
    for _ in range(iterations):
        dist, idx = tree.query(moved, workers=workers(), distance_upper_bound=max_dist)
        keep = np.isfinite(dist)
        rot, shift = kabsch(moved[keep], dst[idx[keep]])
        step = np.eye(4)
        step[:3, :3] = rot
        step[:3, 3] = shift
        transform = step @ transform
        moved = moved @ rot.T + shift
    return transform


def kabsch(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The rotation and translation that best map the rows of ``x`` onto those of ``y``
    (Kabsch: the SVD of the centred cross-covariance, with the reflection fix)."""
    xm, ym = x.mean(axis=0), y.mean(axis=0)
    u, _, vt = np.linalg.svd((y - ym).T @ (x - xm))
    rot = u @ np.diag([1.0, 1.0, np.sign(np.linalg.det(u @ vt))]) @ vt
    return rot, ym - rot @ xm


def floor_icp(d: dict[str, Any]) -> np.ndarray:
    """The floor of an ICP iteration: per iteration one ``cKDTree.query`` (one neighbour, the
    policy's ``workers``) of the whole moved source, both sets already in spatial order
    (sorted outside the timing), and the 3 × 3 SVD of a Kabsch fit of the whole map;
    nothing else (no skipped queries, no trimming, no stopping rule). BLAS on one thread,
    as the package runs it: its threads, spinning between the small products, would slow
    the queries' workers (at 100,000 points on 2 cores the loop took as long with every
    core as with one), and a floor is the best the loop can do."""
    src, dst = d["src_sorted"], d["dst_sorted"]
    tree = cKDTree(dst)
    rot, shift = np.eye(3), np.zeros(3)
    with threadpool_limits(1):
        for _ in range(ITERATIONS):
            dist, idx = tree.query(src @ rot.T + shift, workers=workers(),
                                   distance_upper_bound=MAX_DIST)
            keep = dist <= MAX_DIST
            rot, shift = kabsch(src[keep], dst[idx[keep]])
    out = np.eye(4)
    out[:3, :3], out[:3, 3] = rot, shift
    return out


def one_core(fn: Callable[[Any], Any]) -> Callable[[Any], Any]:
    """``fn`` run as under the one-thread policy, in this process: pinned to one core
    (the package's policy reads the affinity: kd-tree and E-step workers 1) with every
    BLAS/OpenMP pool at one thread; the affinity and pools come back after the call."""
    def run(d: Any) -> Any:
        cpus = os.sched_getaffinity(0)
        os.sched_setaffinity(0, {min(cpus)})
        try:
            with threadpool_limits(1):
                return fn(d)
        finally:
            os.sched_setaffinity(0, cpus)
    return run


def self_rows() -> bool:
    """Whether the rows "ours at default threads vs ours on one core" are meaningful here
    (default policy, more than one core, affinity settable)."""
    return not single_thread() and hasattr(os, "sched_setaffinity") and \
        len(os.sched_getaffinity(0)) > 1


def icp_pair(n: int, seed: int) -> dict[str, Any]:
    """Source, target and the true transform of the ICP case for one seed."""
    rng = np.random.default_rng(seed)
    axis = rng.standard_normal(3)
    truth = Rotation.from_rotvec(np.radians(ANGLE) * axis / np.linalg.norm(axis)).as_matrix()
    shift = rng.uniform(-0.05, 0.05, 3)
    src = blob(n, 2 * seed + 1)
    dst = blob(n, 2 * seed + 2) @ truth.T + shift + rng.normal(0.0, 0.002, (n, 3))
    return {"src": src, "dst": dst, "rot": truth, "shift": shift}


def pose_error(d: dict[str, Any], tf: Any) -> dict[str, float]:
    """Rotation error (degrees) and translation error of a 4 × 4 transform, and its
    iterations when the side reports them (``(transform, iterations)``)."""
    it = None
    if isinstance(tf, tuple):
        tf, it = tf
    tf = np.asarray(tf)
    out = {"rot°": angle_deg(tf[:3, :3], d["rot"]),
           "|Δt|": float(np.linalg.norm(tf[:3, 3] - d["shift"]))}
    if it is not None:
        out["it"] = float(it)
    return out


def case_icp(n: int, iterations: int = ITERATIONS, large: bool = False) -> None:
    try:
        import open3d as o3d  # noqa: PLC0415 - optional peer
    except ImportError:
        o3d = None
        print("note: Open3D is not installed (the bench extra): its ICP rows are skipped")

    def ours(tol: float, metric: str = "point_to_point") -> Any:
        def run(d: dict[str, Any]) -> Any:
            res = icp(d["src"], d["dst"], max_iterations=iterations, tolerance=tol,
                      max_correspondence_distance=MAX_DIST, metric=metric,
                      target_normals=d.get("normals") if metric != "point_to_point"
                      else None,
                      source_normals=d.get("src_normals") if metric == "symmetric"
                      else None)
            return res.transform, res.iterations
        return run

    def data_of(size: int) -> Callable[[int], dict[str, Any]]:
        def data(seed: int) -> dict[str, Any]:
            d = icp_pair(size, seed)
            if o3d is not None:  # Open3D's input format, made outside the timing
                a, b = o3d.geometry.PointCloud(), o3d.geometry.PointCloud()
                a.points = o3d.utility.Vector3dVector(d["src"])
                b.points = o3d.utility.Vector3dVector(d["dst"])
                d["o3d"] = (a, b)
                if not large:
                    # the normals of the plane metrics, made once (Open3D's 10 nearest),
                    # outside the timing: both sides use the same ones
                    b.estimate_normals(o3d.geometry.KDTreeSearchParamKNN(10))
                    d["normals"] = np.asarray(b.normals).copy()
                    a2 = o3d.geometry.PointCloud(a)  # a copy: only this one has normals
                    a2.estimate_normals(o3d.geometry.KDTreeSearchParamKNN(10))
                    d["src_normals"] = np.asarray(a2.normals).copy()
                    d["o3d_sym"] = (a2, b)
            return d
        return data

    data = data_of(n)
    label = f"ICP p2p {n:,}↔{n:,}"
    if large and o3d is None:
        return
    kd = ("nearest-point search split over every core from 2 × icp.PART_MIN source points "
          "(1 core under the 1-thread policy)")
    if o3d is not None:
        reg = o3d.pipelines.registration
        est = reg.TransformationEstimationPointToPoint()

        def o3d_icp(rel: float) -> Any:
            crit = reg.ICPConvergenceCriteria(relative_fitness=rel, relative_rmse=rel,
                                              max_iteration=iterations)

            def run(d: dict[str, Any]) -> Any:
                a, b = d["o3d"]
                return np.asarray(reg.registration_icp(a, b, MAX_DIST, np.eye(4), est,
                                                       crit).transformation)
            return run

        if large:
            compare("registration", f"{label}, {iterations} iterations", data, ours(0.0),
                    o3d_icp(0.0), pose_error, peer_name="Open3D registration_icp",
                    ours_threads=kd, peer_threads="TBB (open3d.utility.set_max_threads)",
                    warmup=lambda: data_of(10_000)(0), repeats=1)
            return
        compare("registration", f"{label}, 30 iterations", data, ours(0.0), o3d_icp(0.0),
                pose_error, peer_name="Open3D registration_icp", ours_threads=kd,
                peer_threads="TBB (open3d.utility.set_max_threads)")
        compare("registration", f"{label}, default stop 1e-6 (≤ 30 it.)", data, ours(1e-6),
                o3d_icp(1e-6), pose_error, peer_name="Open3D registration_icp",
                ours_threads=kd, peer_threads="TBB (open3d.utility.set_max_threads)")
        def o3d_fixed(register: Any, estimation: Any, clouds: str) -> Any:
            """Open3D's ``register`` for ITERATIONS iterations on ``d[clouds]``."""
            def run(d: dict[str, Any]) -> Any:
                a, b = d[clouds]
                crit = reg.ICPConvergenceCriteria(relative_fitness=0.0, relative_rmse=0.0,
                                                  max_iteration=ITERATIONS)
                return np.asarray(register(a, b, MAX_DIST, np.eye(4), estimation,
                                           crit).transformation)
            return run

        o3d_plane = o3d_fixed(reg.registration_icp,
                              reg.TransformationEstimationPointToPlane(), "o3d")
        compare("registration", f"ICP point_to_plane {n:,}↔{n:,}, 30 iterations (the same "
                "target normals)", data, ours(0.0, "point_to_plane"), o3d_plane, pose_error,
                peer_name="Open3D registration_icp", ours_threads=kd,
                peer_threads="TBB (open3d.utility.set_max_threads)")
        o3d_symmetric = o3d_fixed(reg.registration_symmetric_icp,
                                  reg.TransformationEstimationSymmetric(), "o3d_sym")
        compare("registration", f"ICP symmetric {n:,}↔{n:,}, 30 iterations (the same source "
                "and target normals)", data, ours(0.0, "symmetric"), o3d_symmetric,
                pose_error, peer_name="Open3D registration_symmetric_icp", ours_threads=kd,
                peer_threads="TBB (open3d.utility.set_max_threads)")
    if self_rows():  # goal: ours at default threads never slower than ours on one core
        compare("registration", f"{label}, default stop: ours default threads vs one core",
                data, ours(1e-6), one_core(ours(1e-6)), pose_error,
                peer_name="ours on one core", ours_threads=kd,
                peer_threads="1 core, BLAS 1, kd-tree workers 1")
    def sorted_data(seed: int) -> dict[str, Any]:
        d = data(seed)
        # the order ours sorts them in (icp._spatial_order)
        d["src_sorted"] = d["src"][_spatial_order(d["src"])]
        d["dst_sorted"] = d["dst"][_spatial_order(d["dst"])]
        return d

    # goal: an iteration of ours at most 1.3x the floor's (the same 30 iterations each)
    compare("registration", f"{label}, 30 iterations", sorted_data, ours(0.0), floor_icp,
            pose_error, peer_name="the floor: per iteration one query + a 3x3 SVD",
            ours_threads=kd, peer_threads=f"cKDTree workers {workers()}")
    compare("registration", f"{label}, 30 iterations", data, ours(0.0),
            lambda d: plain_icp(d["src"], d["dst"], ITERATIONS, MAX_DIST), pose_error,
            peer_name="numpy+cKDTree loop", ours_threads=kd,
            peer_threads=f"cKDTree workers {workers()}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="the small sizes only")
    parser.add_argument("--large", action="store_true",
                        help="ICP point_to_point at 1,000,000 points a side only")
    args = parser.parse_args()
    apply_policy()
    if args.large:
        case_icp(1_000_000, iterations=10, large=True)
        report("registration")
        return
    for n in (10_000,) if args.quick else (10_000, 100_000):
        case_icp(n)
    from _reg_cpd import case_cpd  # noqa: PLC0415

    case_cpd(args.quick)
    from _reg_ransac import case_ransac  # noqa: PLC0415

    case_ransac(args.quick)
    report("registration")


if __name__ == "__main__":
    main()
