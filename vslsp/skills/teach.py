"""Kinesthetic teaching of push and pull in the simulator, and the paper's figure.

The tutor guides the iCub's hand (:meth:`vslsp.sim.tutor.Tutor.kinesthetic`) from varied
start poses: first the reach (over the cube's near side for push, past its far side for pull,
coming down onto the table), then the straight move that carries the cube across the line.
The recorded hand trajectories are expressed in the object frame and a DMP is fitted to the
reaches; the move is the mean recorded displacement.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vslsp.dmp import DMP
from vslsp.errors import InputError
from vslsp.outputs import atomic_file
from vslsp.sim import TABLE_Z, LandmarkSpec, LineWorld, SceneSpec
from vslsp.sim.robot import HAND_YAW, READY_POSITION
from vslsp.skills.library import Skill, from_object_frame, to_object_frame

PALM_HEIGHT = TABLE_Z + 0.019  # hand frame height that keeps the palm ~6 mm above the table
# Where the tutor puts the hand, in the object frame (n away from the robot, t along the line):
# the contact point of the palm sits beside the hand frame, hence the lateral offsets.
TUTOR_CONTACT = {"push": np.array([-0.07, -0.005]), "pull": np.array([0.10, -0.04])}
TUTOR_MOVE = {"push": 0.11, "pull": -0.16}
# How much the tutor varies the move's length (fraction of TUTOR_MOVE), so that each skill
# learns how far the cube goes for how far the hand moves (its effect model).
TUTOR_MOVE_SPREAD = {"push": (0.6, 1.05), "pull": (0.6, 1.05)}
# How high the hand frame is at the contact point. A push meets the cube's side at mid-height:
# lower, the fingers (which reach 4-5 cm past the hand frame and do not collide with the
# table) scoop under the cube's edge and tip it over, and the cube then travels 5-16 cm for
# the same hand move (measured); at this height it travels the hand's move, upright.
CONTACT_HEIGHT = {"push": PALM_HEIGHT + 0.022, "pull": PALM_HEIGHT}
# The hand comes down onto the contact point from this far above (lower for push: near the
# body the arm cannot lift the raised hand much higher).
APPROACH = {"push": 0.05, "pull": 0.06}


@dataclass(frozen=True)
class KinestheticDemonstration:
    """One kinesthetic demonstration, in the object frame: the reach and the move (t, y (T, 3))."""

    reach: tuple[np.ndarray, np.ndarray]
    move: tuple[np.ndarray, np.ndarray]
    crossed: bool
    travel: float = float("nan")  # how far (m) the cube moved along the line's normal


def hand_yaw(normal: np.ndarray) -> float:
    """The hand's yaw for a push or pull along ``normal``: fingers 30° toward the body's midline."""
    return HAND_YAW + float(np.arctan2(normal[1], normal[0]))


def demonstration_scene(skill: str, rng: np.random.Generator) -> SceneSpec:
    landmark = LandmarkSpec(x=float(rng.uniform(0.21, 0.24)), angle=float(rng.uniform(-0.3, 0.3)))
    colour = str(rng.choice(["red", "green", "blue", "yellow", "orange", "purple"]))
    spec = SceneSpec.random(int(rng.integers(1 << 30)), colours=(colour,), far=(skill == "pull",), landmark=landmark)
    return spec


def record_demonstration(skill: str, seed: int) -> KinestheticDemonstration:
    """The tutor demonstrates ``skill`` once, on a fresh random scene."""
    if skill not in TUTOR_CONTACT:
        raise InputError(f"unknown skill {skill!r}; use push or pull")
    rng = np.random.default_rng(seed)
    spec = demonstration_scene(skill, rng)
    cube = spec.cubes[0]
    normal = spec.landmark.normal
    with LineWorld(spec) as world:
        robot = world.robot
        assert robot is not None  # LineWorld(spec) builds the iCub
        xy = np.array(world.cube_pose(cube.name)[:2])
        contact = np.array([*(TUTOR_CONTACT[skill] + rng.normal(0, 0.003, 2)), CONTACT_HEIGHT[skill]])
        start = READY_POSITION + rng.uniform([-0.03, -0.03, -0.01], [0.03, 0.03, 0.03])
        via_local = np.array([contact + [0, 0, APPROACH[skill]], contact])
        via = np.vstack([start, from_object_frame(via_local, xy, normal)])
        # The tutor varies how far the hand moves, so that the skill learns how far the cube goes.
        length = TUTOR_MOVE[skill] * rng.uniform(*TUTOR_MOVE_SPREAD[skill])
        end = from_object_frame((contact + [length, 0, 0])[None], xy, normal)[0]
        yaw = hand_yaw(normal)
        robot.move_hand(start[None, :], yaw=yaw)
        reach = world.tutor.kinesthetic(via, duration=float(rng.uniform(1.6, 2.2)), seed=seed, yaw=yaw)
        move = world.tutor.kinesthetic(
            np.vstack([via[-1], end]), duration=float(rng.uniform(0.9, 1.2)), seed=seed + 1, yaw=yaw, tremor=0.0
        )
        robot.park()
        world.settle()
        crossed = world.is_far(cube.name) == (skill == "push")
        travel = float(np.dot(np.array(world.cube_pose(cube.name)[:2]) - xy, normal))
    return KinestheticDemonstration(
        reach=(reach.t, to_object_frame(reach.position, xy, normal)),
        move=(move.t, to_object_frame(move.position, xy, normal)),
        crossed=crossed,
        travel=travel,
    )


def learn_skill(skill: str, demonstrations: list[KinestheticDemonstration], n_basis: int = 50) -> Skill:
    """Fit the reach DMP and the move displacement from demonstrations (object frame)."""
    good = [d for d in demonstrations if d.crossed]
    if not good:
        raise InputError(f"none of the {len(demonstrations)} {skill} demonstrations moved the cube across the line")
    reaches = [d.reach for d in good]
    dmp = DMP(3, n_basis=n_basis).fit(reaches)
    goal = np.mean([y[-1] for _, y in reaches], axis=0)
    move = np.mean([y[-1] - y[0] for _, y in (d.move for d in good)], axis=0)
    meta: dict[str, object] = {"demonstrations_recorded": len(demonstrations), "demonstrations_used": len(good)}
    lengths = np.array([abs(y[-1, 0] - y[0, 0]) for _, y in (d.move for d in demonstrations)])
    travels = np.array([abs(d.travel) for d in demonstrations])
    if len(demonstrations) >= 3 and np.ptp(lengths) > 0.02 and np.all(np.isfinite(travels)):
        # The effect model: how far the cube goes (m) for how far the hand moves, least squares;
        # kept only when the demonstrations agree with it (else the skill keeps its mean move).
        slope, offset = np.polyfit(lengths, travels, 1)
        rmse = float(np.sqrt(np.mean((travels - (slope * lengths + offset)) ** 2)))
        if 0.5 <= slope <= 1.5 and rmse < 0.01:
            meta["travel_model"] = {
                "slope": round(float(slope), 4),
                "offset": round(float(offset), 4),
                "rmse_mm": round(rmse * 1000, 1),
            }
    return Skill(skill, dmp, goal, move, reaches, meta)


def plot_skill(skill: Skill, path, starts: np.ndarray | None = None) -> None:
    """The paper's figure: demonstrations black, reproductions from new starts red, goal green."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if starts is None:
        rng = np.random.default_rng(0)
        mean_start = np.mean([y[0] for _, y in skill.demos], axis=0)
        starts = mean_start + rng.uniform(-0.04, 0.04, size=(5, 3))
    rollouts = skill.reach.rollout(starts, np.tile(skill.goal, (len(starts), 1))).y
    figure, axes = plt.subplots(1, 3, figsize=(13, 4))
    for axis, (i, j, label) in zip(axes, [(0, 1, "n-t (top view)"), (0, 2, "n-z (side view)"), (1, 2, "t-z")]):
        for k, (_, y) in enumerate(skill.demos):
            axis.plot(y[:, i], y[:, j], "k-", lw=1, label="demonstrations" if k == 0 else None)
        for k, y in enumerate(rollouts):
            axis.plot(y[:, i], y[:, j], "r-", lw=1, label="reproductions" if k == 0 else None)
        axis.plot(skill.goal[i], skill.goal[j], "o", color="green", ms=9, label="goal")
        axis.set_title(label)
        axis.set_xlabel("nt z"[i * 2] + " (m)" if i != 1 else "t (m)")
        axis.grid(alpha=0.3)
    axes[0].legend(loc="best", fontsize=8)
    figure.suptitle(
        f"{skill.name}: reach-{'before' if skill.name == 'push' else 'after'} in the object frame "
        f"({skill.reach.n_demos} demonstrations, fit RMSE {skill.reach.fit_rmse * 1000:.2f} mm)"
    )
    figure.tight_layout()
    with atomic_file(path) as stream:
        figure.savefig(stream, dpi=110, format="png")
    plt.close(figure)
