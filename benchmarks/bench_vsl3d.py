"""VSL-3D benchmark (paper, section "VSL-3D"): accuracy of getObject's 6-DoF motion and of
findBestMatch against the simulator's ground truth over random demonstrations, and the speed
of each point cloud stage on a rendered world cloud.

Accuracy: per trial a seeded random table-cleaning scene (duck, duckling, teddy, mug, blob,
tray); the tutor moves the duck, the teddy, the duckling or the mug (in turn; the blob's
rotation is ambiguous, and the mug's shows only in its handle) to a free spot or, in a quarter
of the trials, into the tray, turning it by up to ``--max-yaw`` degrees and, in half of them,
tilting it by up to 17 degrees about x and y. getObject must name the right object and recover
the motion within 5 mm (at the object's centre) and 3 degrees. The
recorded pre-action observation is then looked for in a reshuffled scene (findBestMatch; the
object turned by up to ``--max-yaw`` from where it was recorded, since a single view records
one side of it), with the same tolerance against the object's true pose change.

Speed and accuracy beside Open3D 0.20 (the ``bench`` extra), stage by stage on the same
rendered clouds, wall time best of 5 runs: voxel grid (2 mm; how far the raw points lie from
their sample), k-d tree build, KNN (k = 1 and 10) and radius queries (against brute force),
normals (against the true face normals of a cube in the scene), normals + FPFH (the share of
nearest-feature correspondences that are true), RANSAC-based global registration and
point-to-plane ICP (against the known motion). Each row prints both times and their ratio.

VSL-3D runs each stage on one thread (trials run in parallel processes, one per core, so a
stage's threads would only compete with the other trials); Open3D spreads some stages over
threads of its own (its radius search takes 49 ms of CPU in 25 ms on two idle cores, whatever
``OMP_NUM_THREADS`` says). The speed section therefore runs pinned to one core: core for core;
``--all-cores`` lifts the pin (Open3D's wall-clock gain from its threads then shows in the
ratio).

``--param cloud.FIELD=VALUE`` (repeatable) runs the accuracy trials with a field of the cloud
matching rules (:class:`vslsp.vsl3d.parameters.CloudMatching`) changed, e.g.
``--param cloud.confident_fitness=0.8 --skip-speed``: the sweep of one rule, seed for seed
against the default run.

Run: .venv/bin/python benchmarks/bench_vsl3d.py [--trials 20] [--method prerejective_ransac] [--param cloud.F=V]
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

from vslsp.errors import VslspError
from vslsp.outcomes import NoMatch
from vslsp.parameters import with_settings
from vslsp.sim.cloud_scene import TRAY_POSITION, CloudScene, random_layout
from vslsp.vsl3d.alignment import FEATURE_VOXEL
from vslsp.vsl3d.cloud import DepthCamera, Frame, voxel_downsample
from vslsp.vsl3d.fpfh import compute_fpfh
from vslsp.vsl3d.kdtree import KDTree, brute_force_knn
from vslsp.vsl3d.matching import find_best_match
from vslsp.vsl3d.normals import estimate_normals
from vslsp.vsl3d.parameters import DEFAULT_CLOUD_MATCHING, CloudMatching
from vslsp.vsl3d.registration import (
    feature_neighbours,
    icp,
    prerejective_ransac,
    transform_error,
    transform_points,
)
from vslsp.vsl3d.vsl import VOXEL, WorldCloud, get_object

WORKSPACE = Frame((0.25, -0.40, 0.006), (0.90, 0.40, 0.40))
OBJECTS = ["duck", "teddy", "duckling", "mug", "blob"]
MOVED = ("duck", "teddy", "duckling", "mug")  # the mug's turn shows only in its handle
TOLERANCE_M, TOLERANCE_DEG = 0.005, 3.0
MAX_TILT = 0.3  # rad


def _world(scene: CloudScene) -> WorldCloud:
    image = scene.capture()
    return WorldCloud.capture(image.depth, DepthCamera.of(image.camera), WORKSPACE)


def _layout(names: list[str], seed: int) -> dict:
    """A random layout of ``names`` with the spot the tutor moves to on the table (height 0); seeds
    derived from ``seed`` when one has no room for them all (random_layout's own redraws step by
    100 000: these step by a prime past them)."""
    for attempt in range(20):
        try:
            return random_layout(names, seed + 1_000_003 * attempt, heights={"spot": 0.0})
        except VslspError:
            continue
    raise RuntimeError(f"no layout for seed {seed}")


def _trial(seed: int, method: str, max_yaw: float, parameters: CloudMatching = DEFAULT_CLOUD_MATCHING) -> dict:
    rng = np.random.default_rng(seed)
    layout = _layout(OBJECTS + ["spot"], seed)
    spot = layout.pop("spot")
    name = MOVED[seed % len(MOVED)]
    into_tray = rng.random() < 0.25
    tilted = rng.random() < 0.5
    x, y = TRAY_POSITION if into_tray else spot[:2]
    yaw = layout[name][2] + rng.uniform(-max_yaw, max_yaw)
    roll, pitch = rng.uniform(-MAX_TILT, MAX_TILT, 2) if tilted else (0.0, 0.0)
    result = {"object": name, "tray": into_tray, "tilted": tilted}
    with CloudScene(layout) as scene:
        pre = _world(scene)
        before = scene.pose(name)
        lower, upper = scene.bounds(name)
        centre = (lower + upper) / 2.0
        support = scene.surface_height(x, y) if into_tray else 0.0
        scene.tutor_move(name, scene.resting_pose(name, x, y, yaw, roll, pitch, support))
        post = _world(scene)
        truth = scene.pose(name) @ np.linalg.inv(before)
        start = time.process_time()
        try:
            moved = get_object(pre, post, method=method, seed=seed, parameters=parameters)
        except VslspError as error:
            return {**result, "error": str(error)[:90]}
        result["seconds"] = time.process_time() - start
        result["motion"] = transform_error(moved.transform, truth, centre)
        result["right_object"] = bool(
            np.mean(np.all((moved.pre.points >= lower - 0.005) & (moved.pre.points <= upper + 0.005), axis=1)) > 0.9
        )
    reshuffled = _layout(OBJECTS, seed + 10_000)
    x, y, _ = reshuffled[name]  # seen again from about the same side: a single view shows one side
    reshuffled[name] = (x, y, layout[name][2] + rng.uniform(-max_yaw, max_yaw))
    with CloudScene(reshuffled) as scene:
        world = _world(scene)
        truth = scene.pose(name) @ np.linalg.inv(before)
        start = time.process_time()
        try:
            match = find_best_match(world, moved.pre, method=method, seed=seed, parameters=parameters)
            if isinstance(match, NoMatch):
                result["match_error"] = f"no match: {match.reason}"[:90]
            else:
                result["match"] = transform_error(match.registration.transform, truth, moved.pre.centroid)
        except VslspError as error:
            result["match_error"] = str(error)[:90]
        result["match_seconds"] = time.process_time() - start
    return result


def accuracy(trials: int, method: str, max_yaw_deg: float, parameters: CloudMatching = DEFAULT_CLOUD_MATCHING) -> None:
    print(f"\n== accuracy: {trials} random demonstrations, method {method}, yaw change <= {max_yaw_deg:.0f} deg ==")
    if parameters != DEFAULT_CLOUD_MATCHING:
        print(f"   cloud matching: {parameters}")
    results = []
    for seed in range(trials):
        outcome = _trial(seed, method, np.radians(max_yaw_deg), parameters)
        results.append(outcome)
        status = outcome.get("error") or (
            f"motion {outcome['motion'][0] * 1000:.2f} mm {outcome['motion'][1]:.2f} deg; "
            + (
                f"match {outcome['match'][0] * 1000:.2f} mm {outcome['match'][1]:.2f} deg"
                if "match" in outcome
                else f"match failed: {outcome.get('match_error')}"
            )
        )
        print(
            f"  trial {seed:3d} {outcome['object']:5s} tray={outcome['tray']!s:5s} "
            f"tilted={outcome['tilted']!s:5s} {status}"
        )
    for key, label in (("motion", "getObject 6-DoF motion"), ("match", "findBestMatch pose")):
        errors = np.array([r[key] for r in results if key in r])
        ok = [
            key in r
            and r[key][0] < TOLERANCE_M
            and r[key][1] < TOLERANCE_DEG
            and (key != "motion" or r["right_object"])
            for r in results
        ]
        print(
            f"  {label}: success {sum(ok)}/{len(results)} ({np.mean(ok):.0%}) within {TOLERANCE_M * 1000:.0f} mm "
            f"and {TOLERANCE_DEG:.0f} deg"
        )
        if len(errors):
            for column, unit, scale in ((0, "mm", 1000.0), (1, "deg", 1.0)):
                values = errors[:, column] * scale
                print(
                    f"    error {unit}: median {np.median(values):.2f}, mean of successes "
                    f"{np.mean(values[np.array(ok)[[key in r for r in results]]]) if any(ok) else float('nan'):.2f}, "
                    f"90th percentile {np.percentile(values, 90):.2f}"
                )
    for label, chosen in [(f"object {name}", lambda r, name=name: r["object"] == name) for name in MOVED] + [
        ("planar (x, y, yaw)", lambda r: not r["tilted"]),
        ("6-DoF (tilted)", lambda r: r["tilted"]),
        ("into the tray", lambda r: r["tray"]),
    ]:
        subset = [r for r in results if chosen(r)]
        counts = [
            sum(key in r and r[key][0] < TOLERANCE_M and r[key][1] < TOLERANCE_DEG for r in subset)
            for key in ("motion", "match")
        ]
        print(f"    {label:20s}: getObject {counts[0]}/{len(subset)}, findBestMatch {counts[1]}/{len(subset)}")
    seconds = [r["seconds"] for r in results if "seconds" in r]
    match_seconds = [r["match_seconds"] for r in results if "match_seconds" in r]
    print(
        f"  CPU time per getObject: median {np.median(seconds):.2f} s; per findBestMatch: median "
        f"{np.median(match_seconds):.2f} s"
    )


def _timed(function, repeat: int = 5):
    """Best wall time (s) of ``repeat`` calls and the last value (the minimum: the machine's
    cores are shared, and the least disturbed run measures the code)."""
    best, value = np.inf, None
    for _ in range(repeat):
        start = time.perf_counter()
        value = function()
        best = min(best, time.perf_counter() - start)
    return best, value


def _open3d():
    """Open3D (the ``bench`` extra); its import needs libusb, which the ``libusb-package``
    wheel carries: loaded first so that the dynamic linker finds it."""
    import ctypes

    try:
        import libusb_package

        ctypes.CDLL(str(libusb_package.get_library_path()), mode=ctypes.RTLD_GLOBAL)
    except (ImportError, OSError):
        pass
    import open3d

    return open3d


class Table:
    """The side-by-side table: a row per stage, VSL-3D and Open3D time and accuracy, the ratio."""

    def __init__(self) -> None:
        self.rows: list[tuple[str, float, float, str, str]] = []

    def add(self, stage: str, ours: float, theirs: float, our_accuracy: str, their_accuracy: str) -> None:
        self.rows.append((stage, ours, theirs, our_accuracy, their_accuracy))
        print(
            f"  {stage:34s} VSL-3D {ours * 1000:8.1f} ms | Open3D {theirs * 1000:8.1f} ms | "
            f"ratio {ours / theirs:5.2f}x | accuracy VSL-3D {our_accuracy} ; Open3D {their_accuracy}"
        )

    def summary(self) -> None:
        within = [row for row in self.rows if row[1] <= 2.0 * row[2]]
        print(
            f"  stages within 2x of Open3D's time: {len(within)}/{len(self.rows)}"
            + "".join(f"\n    over: {row[0]} ({row[1] / row[2]:.2f}x)" for row in self.rows if row not in within)
        )


def _angles(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Unsigned angles (deg) between unit vectors (N, 3) and (N, 3), sign-blind."""
    return np.degrees(np.arccos(np.clip(np.abs(np.einsum("ij,ij->i", a, b)), 0.0, 1.0)))


def _cube_truth(points: np.ndarray, pose: np.ndarray, half: float) -> tuple[np.ndarray, np.ndarray]:
    """Which points (N,) lie on a face of the cube of ``pose`` (4, 4) and half side ``half``, at
    least 4 mm from its edges, and their true normals (N, 3)."""
    local = (points - pose[:3, 3]) @ pose[:3, :3]
    face = np.argmax(np.abs(local) / half, axis=1)
    on = np.abs(np.abs(local[np.arange(len(local)), face]) - half) < 0.002
    inner = np.sort(np.abs(local), axis=1)[:, :2].max(axis=1) < half - 0.004
    normals = np.zeros_like(local)
    normals[np.arange(len(local)), face] = 1.0
    return on & inner, normals @ pose[:3, :3].T


def speed(all_cores: bool = False) -> None:
    """Every point cloud stage of VSL-3D beside Open3D's on the same rendered clouds, pinned to
    one core unless ``all_cores``."""
    cores = sorted(os.sched_getaffinity(0))
    if not all_cores:  # before Open3D starts its threads: they take the mask they are born with
        os.sched_setaffinity(0, {cores[-1]})
    o3d = _open3d()
    where = "all cores" if all_cores else f"pinned to core {cores[-1]} of {len(cores)}: core for core"
    print(f"\n== VSL-3D beside Open3D {o3d.__version__} on the same rendered clouds (wall time, best of 5; {where}) ==")
    table = Table()
    layout = random_layout(OBJECTS, 1)
    layout["cube"] = (0.62, -0.12, 0.5)
    with CloudScene(layout) as scene:
        image = scene.capture()
        cube_pose = scene.pose("cube")
        cube_half = (scene.bounds("cube")[1][2] - scene.bounds("cube")[0][2]) / 2.0
    camera = DepthCamera.of(image.camera)
    raw, _ = camera.back_project(image.depth)
    cropped = raw[WORKSPACE.contains(raw)]
    o3d_raw = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(cropped))
    print(f"  cloud: {len(cropped)} points in the workspace of a {len(raw)}-point capture")
    # Voxel grid: accuracy is how far the raw points lie from their voxel's representative.
    t_ours, cloud = _timed(lambda: voxel_downsample(cropped, VOXEL))
    t_o3d, o3d_cloud = _timed(lambda: o3d_raw.voxel_down_sample(VOXEL))
    theirs = np.asarray(o3d_cloud.points)
    spread = [np.sqrt(np.mean(KDTree(c).query(cropped, 1)[0] ** 2)) * 1000 for c in (cloud, theirs)]
    table.add(
        "voxel grid 2 mm",
        t_ours,
        t_o3d,
        f"{len(cloud)} pts, raw->sample RMS {spread[0]:.2f} mm",
        f"{len(theirs)} pts, {spread[1]:.2f} mm",
    )
    # k-d tree: build, KNN and radius search, answers checked against brute force.
    t_ours, tree = _timed(lambda: KDTree(cloud))
    device_points = o3d.core.Tensor(cloud)
    t_o3d, nns = _timed(lambda: o3d.core.nns.NearestNeighborSearch(device_points))
    t_index, _ = _timed(lambda: nns.knn_index())
    table.add("k-d tree build (+ Open3D knn index)", t_ours, t_o3d + t_index, "-", "-")
    queries = cloud[np.random.default_rng(0).permutation(len(cloud))[:5000]]
    query_tensor = o3d.core.Tensor(queries)
    for k in (1, 10):
        reference, _ = brute_force_knn(cloud, queries, k)
        t_ours, (distance, _) = _timed(lambda k=k: tree.query(queries, k))
        t_o3d, (_, o3d_d2) = _timed(lambda k=k: nns.knn_search(query_tensor, k))
        errors = [np.abs(d - reference).max() for d in (distance, np.sqrt(o3d_d2.numpy()))]
        table.add(
            f"KNN k={k}, 5000 queries", t_ours, t_o3d, f"max error {errors[0]:.1e} m", f"max error {errors[1]:.1e} m"
        )
    nns.hybrid_index(0.006)
    t_ours, found = _timed(lambda: tree.query_radius(cloud, 0.006, 60))
    t_o3d, (_, _, counts) = _timed(lambda: nns.hybrid_search(device_points, 0.006, 60))
    same = np.mean(found.counts(len(cloud)) == counts.numpy().ravel())
    table.add(
        f"radius 6 mm (<= 60), {len(cloud)} queries",
        t_ours,
        t_o3d,
        f"{len(found.query)} pairs",
        f"{int(counts.numpy().sum())} pairs ({same:.1%} same counts)",
    )
    # Normals: the error against the cube's true face normals.
    on_cube, true_normals = _cube_truth(cloud, cube_pose, cube_half)
    o3d_cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(cloud))

    def o3d_normals():
        o3d_cloud.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=0.006, max_nn=60))
        o3d_cloud.orient_normals_towards_camera_location(camera.position)
        return np.asarray(o3d_cloud.normals)

    t_ours, normals = _timed(lambda: estimate_normals(cloud, 0.006, camera.position, tree))
    t_o3d, theirs = _timed(o3d_normals)
    errors = [np.median(_angles(n[on_cube], true_normals[on_cube])) for n in (normals.normals, theirs)]
    table.add(
        f"normals 6 mm, {len(cloud)} points",
        t_ours,
        t_o3d,
        f"median {errors[0]:.2f} deg on {on_cube.sum()} cube-face pts",
        f"median {errors[1]:.2f} deg",
    )
    # FPFH and global registration on an observation of the duck against a world in which it moved.
    with CloudScene({"duck": (0.5, 0.0, 0.7)}, tray=False) as scene:
        image = scene.capture()
        duck_camera = DepthCamera.of(image.camera)
        points, _ = duck_camera.back_project(image.depth)
        duck = voxel_downsample(points[WORKSPACE.contains(points)], VOXEL)
        truth_pose = scene.pose("duck")
    shift = np.eye(4)
    shift[:3, :3] = [[np.cos(0.5), -np.sin(0.5), 0], [np.sin(0.5), np.cos(0.5), 0], [0, 0, 1]]
    shift[:3, 3] = [0.05, -0.12, 0.0] + truth_pose[:3, 3] - shift[:3, :3] @ truth_pose[:3, 3]
    target = np.vstack([transform_points(shift, duck), cloud])
    sparse_source, sparse_target = voxel_downsample(duck, FEATURE_VOXEL), voxel_downsample(target, FEATURE_VOXEL)
    pipeline = registration = o3d.pipelines.registration

    def ours_features(points, viewpoint):
        sparse_tree = KDTree(points)
        return compute_fpfh(
            points,
            estimate_normals(points, 2.5 * FEATURE_VOXEL, viewpoint, sparse_tree),
            5.0 * FEATURE_VOXEL,
            sparse_tree,
        )

    def o3d_features(points, viewpoint):
        pcd = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(points))
        pcd.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=2.5 * FEATURE_VOXEL, max_nn=30))
        pcd.orient_normals_towards_camera_location(viewpoint)
        return pcd, pipeline.compute_fpfh_feature(
            pcd, o3d.geometry.KDTreeSearchParamHybrid(radius=5.0 * FEATURE_VOXEL, max_nn=100)
        )

    t_ours, target_features = _timed(lambda: ours_features(sparse_target, camera.position))
    t_o3d, (o3d_target, o3d_target_features) = _timed(lambda: o3d_features(sparse_target, camera.position))
    source_features = ours_features(sparse_source, duck_camera.position)
    o3d_source, o3d_source_features = o3d_features(sparse_source, duck_camera.position)
    moved_source = transform_points(shift, sparse_source)
    precision = []
    for source_f, target_f in (
        (source_features, target_features),
        (np.asarray(o3d_source_features.data).T, np.asarray(o3d_target_features.data).T),
    ):
        nearest = feature_neighbours(source_f, target_f, 1)[:, 0]
        precision.append(np.mean(np.linalg.norm(sparse_target[nearest] - moved_source, axis=1) < 1.5 * FEATURE_VOXEL))
    table.add(
        f"normals + FPFH 5 mm voxels, {len(sparse_target)} pts",
        t_ours,
        t_o3d,
        f"{precision[0]:.1%} true nearest-feature matches",
        f"{precision[1]:.1%}",
    )
    centre = duck.mean(axis=0)
    target_tree = KDTree(sparse_target)
    t_ours, coarse = _timed(
        lambda: prerejective_ransac(
            sparse_source,
            sparse_target,
            source_features,
            target_features,
            1.5 * FEATURE_VOXEL,
            seed=0,
            target_tree=target_tree,
        ),
        repeat=3,
    )
    distance = 1.5 * FEATURE_VOXEL
    checkers = [
        registration.CorrespondenceCheckerBasedOnEdgeLength(0.9),
        registration.CorrespondenceCheckerBasedOnDistance(distance),
    ]
    t_o3d, theirs = _timed(
        lambda: registration.registration_ransac_based_on_feature_matching(
            o3d_source,
            o3d_target,
            o3d_source_features,
            o3d_target_features,
            True,
            distance,
            registration.TransformationEstimationPointToPoint(False),
            3,
            checkers,
            registration.RANSACConvergenceCriteria(100000, 0.999),
        ),
        repeat=3,
    )
    errors = [transform_error(t, shift, centre) for t in (coarse.transform, np.asarray(theirs.transformation))]
    table.add(
        "global registration (RANSAC)",
        t_ours,
        t_o3d,
        f"{errors[0][0] * 1000:.1f} mm {errors[0][1]:.1f} deg",
        f"{errors[1][0] * 1000:.1f} mm {errors[1][1]:.1f} deg",
    )
    # ICP point-to-plane on the full-resolution clouds from a start 1 cm and 5 deg off the truth.
    start = np.eye(4)
    start[:3, :3] = [[np.cos(0.087), -np.sin(0.087), 0], [np.sin(0.087), np.cos(0.087), 0], [0, 0, 1]]
    start[:3, 3] = [0.01, -0.005, 0.0] + centre - start[:3, :3] @ centre
    start = shift @ start
    full_target = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(target))
    full_target.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=0.006, max_nn=60))
    full_target.orient_normals_towards_camera_location(camera.position)
    target_normals = np.asarray(full_target.normals)
    full_tree = KDTree(target)
    full_source = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(duck))
    t_ours, fine = _timed(
        lambda: icp(
            duck,
            target,
            start,
            max_distance=0.02,
            method="point_to_plane",
            target_normals=target_normals,
            target_tree=full_tree,
        )
    )
    t_o3d, theirs = _timed(
        lambda: registration.registration_icp(
            full_source,
            full_target,
            0.02,
            start,
            registration.TransformationEstimationPointToPlane(),
            registration.ICPConvergenceCriteria(1e-6, 1e-6, 50),
        )
    )
    errors = [transform_error(t, shift, centre) for t in (fine.transform, np.asarray(theirs.transformation))]
    table.add(
        "ICP point-to-plane",
        t_ours,
        t_o3d,
        f"{errors[0][0] * 1000:.2f} mm {errors[0][1]:.2f} deg",
        f"{errors[1][0] * 1000:.2f} mm {errors[1][1]:.2f} deg",
    )
    table.summary()
    if not all_cores:
        os.sched_setaffinity(0, set(cores))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--trials", type=int, default=20)
    parser.add_argument("--method", default="prerejective_ransac", choices=["prerejective_ransac", "sac_ia", "icp"])
    parser.add_argument("--max-yaw", type=float, default=60.0, help="largest turn about z in a move (deg)")
    parser.add_argument("--skip-speed", action="store_true")
    parser.add_argument("--all-cores", action="store_true", help="do not pin the speed comparison to one core")
    parser.add_argument(
        "--param", action="append", default=[], metavar="cloud.FIELD=VALUE", help="a cloud matching rule changed"
    )
    args = parser.parse_args()
    try:
        parameters = with_settings({"cloud": DEFAULT_CLOUD_MATCHING}, args.param)["cloud"]
    except VslspError as error:
        print(f"error: {error}", file=sys.stderr)
        raise SystemExit(2) from None
    if not args.skip_speed:
        speed(args.all_cores)
    if args.trials:
        accuracy(args.trials, args.method, args.max_yaw, parameters)


if __name__ == "__main__":
    main()
