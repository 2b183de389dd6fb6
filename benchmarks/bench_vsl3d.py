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

Speed: on one rendered capture (about 300k raw points): voxel grid (2 mm), k-d tree build, KNN
(k = 1 and 10) and radius queries against brute force on the same queries, normals, FPFH,
pre-rejective RANSAC, SAC-IA and ICP.

Run: .venv/bin/python benchmarks/bench_vsl3d.py [--trials 50] [--method prerejective_ransac]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from vslsp.errors import VslspError
from vslsp.sim.cloud_scene import TRAY_POSITION, CloudScene, random_layout
from vslsp.vsl3d.alignment import FEATURE_VOXEL, describe
from vslsp.vsl3d.cloud import DepthCamera, Frame, voxel_downsample
from vslsp.vsl3d.fpfh import compute_fpfh
from vslsp.vsl3d.kdtree import KDTree, brute_force_knn
from vslsp.vsl3d.normals import estimate_normals
from vslsp.vsl3d.registration import icp, prerejective_ransac, sac_ia, transform_error, transform_points
from vslsp.vsl3d.matching import find_best_match
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
    """A random layout of ``names``; the next seeds when one has no room for them all."""
    for attempt in range(20):
        try:
            return random_layout(names, seed + 100_000 * attempt)
        except VslspError:
            continue
    raise RuntimeError(f"no layout for seed {seed}")


def _trial(seed: int, method: str, max_yaw: float) -> dict:
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
            moved = get_object(pre, post, method=method, seed=seed)
        except VslspError as error:
            return {**result, "error": str(error)[:90]}
        result["seconds"] = time.process_time() - start
        result["motion"] = transform_error(moved.transform, truth, centre)
        result["right_object"] = bool(np.mean(np.all((moved.pre.points >= lower - 0.005)
                                                      & (moved.pre.points <= upper + 0.005), axis=1)) > 0.9)
    reshuffled = _layout(OBJECTS, seed + 10_000)
    x, y, _ = reshuffled[name]  # seen again from about the same side: a single view shows one side
    reshuffled[name] = (x, y, layout[name][2] + rng.uniform(-max_yaw, max_yaw))
    with CloudScene(reshuffled) as scene:
        world = _world(scene)
        truth = scene.pose(name) @ np.linalg.inv(before)
        start = time.process_time()
        try:
            match = find_best_match(world, moved.pre, method=method, seed=seed)
            result["match"] = transform_error(match.registration.transform, truth, moved.pre.centroid)
        except VslspError as error:
            result["match_error"] = str(error)[:90]
        result["match_seconds"] = time.process_time() - start
    return result


def accuracy(trials: int, method: str, max_yaw_deg: float) -> None:
    print(f"\n== accuracy: {trials} random demonstrations, method {method}, yaw change <= {max_yaw_deg:.0f} deg ==")
    results = []
    for seed in range(trials):
        outcome = _trial(seed, method, np.radians(max_yaw_deg))
        results.append(outcome)
        status = outcome.get("error") or (
            f"motion {outcome['motion'][0] * 1000:.2f} mm {outcome['motion'][1]:.2f} deg; "
            + (f"match {outcome['match'][0] * 1000:.2f} mm {outcome['match'][1]:.2f} deg"
               if "match" in outcome else f"match failed: {outcome.get('match_error')}"))
        print(f"  trial {seed:3d} {outcome['object']:5s} tray={outcome['tray']!s:5s} tilted={outcome['tilted']!s:5s} {status}")
    for key, label in (("motion", "getObject 6-DoF motion"), ("match", "findBestMatch pose")):
        errors = np.array([r[key] for r in results if key in r])
        ok = [key in r and r[key][0] < TOLERANCE_M and r[key][1] < TOLERANCE_DEG
              and (key != "motion" or r["right_object"]) for r in results]
        print(f"  {label}: success {sum(ok)}/{len(results)} ({np.mean(ok):.0%}) within {TOLERANCE_M * 1000:.0f} mm "
              f"and {TOLERANCE_DEG:.0f} deg")
        if len(errors):
            for column, unit, scale in ((0, "mm", 1000.0), (1, "deg", 1.0)):
                values = errors[:, column] * scale
                print(f"    error {unit}: median {np.median(values):.2f}, mean of successes "
                      f"{np.mean(values[np.array(ok)[[key in r for r in results]]]) if any(ok) else float('nan'):.2f}, "
                      f"90th percentile {np.percentile(values, 90):.2f}")
    for label, chosen in [(f"object {name}", lambda r, name=name: r["object"] == name) for name in MOVED] + [
            ("planar (x, y, yaw)", lambda r: not r["tilted"]), ("6-DoF (tilted)", lambda r: r["tilted"]),
            ("into the tray", lambda r: r["tray"])]:
        subset = [r for r in results if chosen(r)]
        counts = [sum(key in r and r[key][0] < TOLERANCE_M and r[key][1] < TOLERANCE_DEG for r in subset)
                  for key in ("motion", "match")]
        print(f"    {label:20s}: getObject {counts[0]}/{len(subset)}, findBestMatch {counts[1]}/{len(subset)}")
    seconds = [r["seconds"] for r in results if "seconds" in r]
    match_seconds = [r["match_seconds"] for r in results if "match_seconds" in r]
    print(f"  CPU time per getObject: median {np.median(seconds):.2f} s; per findBestMatch: median "
          f"{np.median(match_seconds):.2f} s")


def _timed(function, repeat: int = 3):
    """Best CPU time (s) of ``repeat`` calls and the last value: CPU time, since the machine's
    two cores are shared and wall time there measures the neighbours as much as the code."""
    best, value = np.inf, None
    for _ in range(repeat):
        start = time.process_time()
        value = function()
        best = min(best, time.process_time() - start)
    return best, value


def speed() -> None:
    print("\n== speed of each stage on one rendered capture (CPU time, best of 3) ==")
    with CloudScene(random_layout(OBJECTS, 1)) as scene:
        image = scene.capture()
    camera = DepthCamera.of(image.camera)
    raw, _ = camera.back_project(image.depth)
    cropped = raw[WORKSPACE.contains(raw)]
    t, cloud = _timed(lambda: voxel_downsample(cropped, VOXEL))
    print(f"  back-projected {len(raw)} points, {len(cropped)} in the workspace; voxel grid 2 mm: "
          f"{t * 1000:.1f} ms -> {len(cloud)} points")
    t_build, tree = _timed(lambda: KDTree(cloud))
    print(f"  k-d tree build: {t_build * 1000:.1f} ms")
    queries = cloud[np.random.default_rng(0).permutation(len(cloud))[:5000]]
    for k in (1, 10):
        t_tree, (distance, _) = _timed(lambda: tree.query(queries, k))
        t_brute, (reference, _) = _timed(lambda: brute_force_knn(cloud, queries, k), repeat=1)
        assert np.allclose(distance, reference)
        print(f"  KNN k={k:2d}, 5000 queries: tree {t_tree * 1000:.0f} ms, brute force {t_brute * 1000:.0f} ms "
              f"-> {t_brute / t_tree:.0f}x (same answers)")
    t_radius, found = _timed(lambda: tree.query_radius(cloud, 0.006, 60))
    print(f"  radius 6 mm (<= 60), all {len(cloud)} points: {t_radius * 1000:.0f} ms, {len(found.query)} pairs")
    t_normals, normals = _timed(lambda: estimate_normals(cloud, 0.006, camera.position, tree))
    print(f"  normals (6 mm), {len(cloud)} points: {t_normals * 1000:.0f} ms")
    t_fpfh, _ = _timed(lambda: compute_fpfh(cloud, normals, 0.012, tree, max_neighbours=100), repeat=1)
    print(f"  FPFH (12 mm, <= 100 neighbours), {len(cloud)} points: {t_fpfh * 1000:.0f} ms")
    # Registration: the duck's observation against the whole world, as findBestMatch does.
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
    t_describe, (sparse_source, source_features, _) = _timed(lambda: describe(duck, duck_camera.position))
    t_describe_world, (sparse_target, target_features, target_tree) = _timed(
        lambda: describe(target, camera.position), repeat=1)
    print(f"  describe (5 mm voxels, normals, FPFH): observation {len(sparse_source)} points "
          f"{t_describe * 1000:.0f} ms; world {len(sparse_target)} points {t_describe_world * 1000:.0f} ms")
    centre = duck.mean(axis=0)
    for name, function in (("pre-rejective RANSAC", prerejective_ransac), ("SAC-IA", sac_ia)):
        t_global, coarse = _timed(lambda: function(sparse_source, sparse_target, source_features, target_features,
                                                   1.5 * FEATURE_VOXEL, seed=0, target_tree=target_tree), repeat=1)
        error = transform_error(coarse.transform, shift, centre)
        print(f"  {name}: {t_global * 1000:.0f} ms, coarse error {error[0] * 1000:.1f} mm {error[1]:.1f} deg")
    target_normals = estimate_normals(target, 0.006, camera.position).normals
    for method in ("point_to_point", "point_to_plane"):
        t_icp, fine = _timed(lambda: icp(duck, target, coarse.transform, max_distance=0.01, method=method,
                                         target_normals=target_normals))
        error = transform_error(fine.transform, shift, centre)
        print(f"  ICP {method.replace('_', '-')}: {t_icp * 1000:.0f} ms, error {error[0] * 1000:.2f} mm {error[1]:.2f} deg")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--trials", type=int, default=50)
    parser.add_argument("--method", default="prerejective_ransac", choices=["prerejective_ransac", "sac_ia", "icp"])
    parser.add_argument("--max-yaw", type=float, default=60.0, help="largest turn about z in a move (deg)")
    parser.add_argument("--skip-speed", action="store_true")
    args = parser.parse_args()
    if not args.skip_speed:
        speed()
    if args.trials:
        accuracy(args.trials, args.method, args.max_yaw)


if __name__ == "__main__":
    main()
