"""One pick-and-place operation of the original VSL (paper, Algorithm 1 part II ``executeAction``
and the grasping paragraph of section "Methodology") executed by the Panda of a
:class:`~vslsp.sim.tabletop.TabletopWorld`.

Before moving, the heights of the pick and the place come from a downward depth probe, the
whole cycle rest → pick → place → rest of :func:`vslsp.geometry.trajectory.pick_and_place` is
solved by IK, and the operation is "unreachable" when a solution misses its hand pose. Then the
arm follows the joint path by position control; at the pick the fingers close until the normal
force on each reaches a threshold ("grasp failed" when no movable item is between them); at the
place ("object slipped" when the item is no longer between them) the hand comes down until the
item touches what is below, opens, and goes back to rest.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from vslsp.errors import InputError
from vslsp.geometry import trajectory
from vslsp.outcomes import Diagnosis
from vslsp.sim.panda import (
    CONTACT_THRESHOLD,
    FINGER_FORCE,
    FINGER_OPEN,
    IK_ANGLE_TOLERANCE,
    IK_POSITION_TOLERANCE,
    PARK,
    REST,
    UPPER,
    Panda,
)
from vslsp.sim.quiet import quiet

with quiet():
    import pybullet as pb

TIME_STEP = 1.0 / 240.0
PATH = trajectory.TrajectoryParameters(height=0.15, durations=(1.0, 1.4, 1.0), samples=25)
GRASP_DEPTH = 0.03  # the fingertips close this far below an item's top (the pads hold its whole side)
TIP_CLEARANCE = 0.003  # and at least this far above the surface they come down beside it
FINGER_WIDTH = 0.012  # room each finger needs beside the opening
FINGERTIP_DISTANCES = (0.015, 0.025, 0.035, 0.045, 0.055)  # m from the centre where closed fingertips can be
MIN_GRIP = 0.006  # m of an item's side the fingertips hold at the least
PLACE_CLEARANCE = 0.006  # the carried item arrives this far above the surface, then comes down
DESCENT_SPEED = 0.05  # m/s of the guarded descent
DESCENT_STEPS = 4  # physics steps between its checks for touch
MAX_DESCENT = 0.03
SWING_TIME = 0.5  # s between parked (out of view) and rest
RETREAT = 0.04  # m the hand rises straight up after the release
TOUCH_FORCE = 0.3  # N under the held item that ends the guarded descent
SQUEEZE = 0.004  # m the fingers' target lies inside the item once the threshold is reached
PROBE_OFFSETS = ((0.0, 0.0), (0.015, 0.0), (-0.015, 0.0), (0.0, 0.015), (0.0, -0.015))


@dataclass(frozen=True, eq=False)
class PickPlaceResult:
    """How a pick-and-place went: ``ok``, the ``diagnosis`` of a failure (None, GRASP_FAILED,
    OBJECT_SLIPPED, UNREACHABLE), the item ``held`` (ground truth, for reports and tests),
    the ``hand_path`` (T, 4) x, y, z, θ as executed and the simulated ``duration_s``."""

    ok: bool
    diagnosis: Diagnosis | None
    held: str | None
    hand_path: np.ndarray
    duration_s: float

    def to_dict(self) -> dict:
        return {
            "ok": self.ok,
            "diagnosis": self.diagnosis,
            "held": self.held,
            "hand_path": np.round(self.hand_path, 5).tolist(),
            "duration_s": round(self.duration_s, 4),
        }


def check_pose(label: str, pose: tuple[float, float, float] | np.ndarray) -> np.ndarray:
    """The pose (x m, y m, theta rad) as a (3,) array; an InputError unless three finite numbers."""
    array = np.asarray(pose, dtype=float).reshape(-1)
    if array.shape != (3,) or not np.all(np.isfinite(array)):
        raise InputError(f"the {label} pose must be three finite numbers (x m, y m, theta rad), got {array!r}")
    return array


def wrist_branch(pick: np.ndarray, place: np.ndarray) -> tuple[float, float]:
    """θ_pick and θ_place shifted by the same multiple of π (the fingers close alike) so that
    joint 7 stays furthest inside its limits; the item turns by θ_place − θ_pick (mod 2π). The
    wrist turns the shorter way, unless no shift keeps joint 7 inside its limits that way: then
    the longer way, which leaves the item turned the same (a turn of nearly half a revolution
    between a pick and a place that the arm's base sees from different directions can need
    more of joint 7 one way than its range holds, and less the other way: stacking, seed 40)."""
    shorter = float(np.angle(np.exp(1j * (place[2] - pick[2]))))
    best: tuple[float, float, float] | None = None
    for turn in (shorter, shorter - float(np.copysign(2.0 * np.pi, shorter))):
        for k in range(-2, 3):
            theta_pick = float(pick[2] + k * np.pi)
            theta_place = theta_pick + turn
            margin = min(
                UPPER[6] - abs(Panda.wrist_angle(x, y, t))
                for x, y, t in ((pick[0], pick[1], theta_pick), (place[0], place[1], theta_place))
            )
            if best is None or margin > best[0]:
                best = (margin, theta_pick, theta_place)
        if best is not None and best[0] > 0.0:
            break
    assert best is not None
    return best[1], best[2]


class Operation:
    """The state of one pick-and-place while it runs: the executed hand path and sim time."""

    def __init__(self, world) -> None:
        self.world = world
        self.panda: Panda = world.panda
        self.path: list[np.ndarray] = []
        self.steps = 0

    def step(self, n: int = 1) -> None:
        self.world.step(n)
        self.steps += n

    def record(self) -> None:
        position, theta = self.panda.hand()
        self.path.append(np.array([*position, theta]))

    def follow(self, joints: np.ndarray, times: np.ndarray) -> None:
        """Drive through joint samples (N, 7) at ``times`` (N,) s, interpolating every step."""
        for k in range(1, len(joints)):
            n = max(1, int(round((times[k] - times[k - 1]) / TIME_STEP)))
            for i in range(1, n + 1):
                self.panda.drive(joints[k - 1] + (joints[k] - joints[k - 1]) * i / n)
                self.step()
            self.record()

    def converge(self, q: np.ndarray, max_steps: int = 72, tolerance: float = 1e-3) -> None:
        self.panda.drive(q)
        for _ in range(max_steps):
            if np.max(np.abs(self.panda.joints() - q)) < tolerance:
                break
            self.step()

    def close_fingers(self, movable: list[int]) -> int | None:
        """Close until both fingers press one item with the threshold force (or they shut)."""
        self.panda.fingers_to(0.0, FINGER_FORCE)
        for _ in range(120):
            self.step()
            body = self.panda.between_fingers(movable)
            if body is not None and min(self.panda.finger_forces(body)) >= CONTACT_THRESHOLD:
                each = self.panda.finger_opening() / 2.0
                self.panda.fingers_to(max(0.0, each - SQUEEZE), FINGER_FORCE)
                self.step(12)
                return self.panda.between_fingers(movable)
            if self.panda.finger_opening() < 1e-3:
                break
        return None

    def release(self) -> None:
        """Open the fingers fully and wait until they are."""
        self.panda.fingers_to(FINGER_OPEN)
        for _ in range(60):
            self.step()
            if self.panda.finger_opening() > 2.0 * FINGER_OPEN - 2e-3:
                break

    def guarded_descent(self, joints: np.ndarray, held: int) -> None:
        """Lower the hand along joint samples (N, 7) :data:`DESCENT_STEPS` apart until ``held``
        presses on something other than the robot with :data:`TOUCH_FORCE`."""
        for q in joints:
            self.panda.drive(q)
            self.step(DESCENT_STEPS)
            self.record()
            pressed = sum(
                c[9] for c in pb.getContactPoints(held, physicsClientId=self.world.client) if c[2] != self.panda.body
            )
            if pressed >= TOUCH_FORCE:
                self.panda.drive(self.panda.joints())  # stop there: pressing on would jam the fingers
                return

    def result(self, diagnosis: Diagnosis | None, held: str | None) -> PickPlaceResult:
        path = np.array(self.path) if self.path else np.zeros((0, 4))
        return PickPlaceResult(diagnosis is None, diagnosis, held, path, self.steps * TIME_STEP)


def cycle(
    rest: np.ndarray, pick: np.ndarray, place: np.ndarray, theta_pick: float, theta_place: float, theta_rest: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple[int, int, int]]:
    """The paper's cycle through key points (3,) each: times (T,), hand points (T, 3), angles
    (T,) and where the pick, the place and the way home begin. After the release the hand first
    rises :data:`RETREAT` straight up (turning there, the open fingers would sweep the item's
    corners), then the place → rest segment starts from that point."""
    plan = trajectory.pick_and_place(rest, pick, place, theta_pick, theta_place, PATH, theta_rest=theta_rest)
    _, at_pick, at_place = plan.segments
    t_place = plan.t[at_place]
    lift_t = t_place + np.linspace(0.0, RETREAT / DESCENT_SPEED, 6)
    lift = place + np.outer(trajectory.time_scaling(lift_t, lift_t[0], lift_t[-1]), [0.0, 0.0, RETREAT])
    t, xyz, theta = trajectory.segment(
        lift[-1], rest, theta_place, theta_rest, lift_t[-1], lift_t[-1] + PATH.durations[2], PATH
    )
    return (
        np.concatenate([plan.t[: at_place + 1], lift_t[1:], t[1:]]),
        np.vstack([plan.xyz[: at_place + 1], lift[1:], xyz[1:]]),
        np.concatenate([plan.theta[: at_place + 1], np.full(5, theta_place), theta[1:]]),
        (at_pick, at_place, at_place + 5),
    )


def ring(world, centre: np.ndarray, theta: float, distances: tuple[float, ...], ignore: int | None = None) -> float:
    """The highest surface the depth probe sees at ``distances`` (m) either side of ``centre``
    (2,) along the closing axis at angle ``theta``: where the fingertips come down."""
    axis = np.array([np.cos(theta), np.sin(theta)])
    return max(world.probe(*(centre[:2] + sign * d * axis), ignore=ignore)[0] for d in distances for sign in (-1, 1))


def key_points(
    world, pick: np.ndarray, place: np.ndarray, theta_pick: float, theta_place: float, each: float
) -> tuple[np.ndarray, np.ndarray]:
    """The fingertips' pick and place points (3,) from the depth probe. At the pick: the top,
    and the highest surface under the item and beside it where the fingertips come down and
    close; at the place (seen through the item to be picked): the surface and what lies where
    the closed fingertips come down.
    The fingertips grip :data:`GRASP_DEPTH` below the top but stay :data:`TIP_CLEARANCE` above
    the surfaces beside the item at both ends (a landmark next to the place lifts the grip)."""
    top, target = world.probe(pick[0], pick[1])
    # Seen through the item, so a stacked item's support counts: the fingers, sweeping in from
    # the open position, must not close on the item below.
    sweep = tuple(d for d in FINGERTIP_DISTANCES if d < each + FINGER_WIDTH) + (each + FINGER_WIDTH,)
    beside = ring(world, pick, theta_pick, sweep, ignore=target)
    bottom = beside if beside < top else 0.0
    surface = max(world.probe(place[0] + dx, place[1] + dy, ignore=target)[0] for dx, dy in PROBE_OFFSETS)
    lift = ring(world, place, theta_place, FINGERTIP_DISTANCES, ignore=target) + TIP_CLEARANCE - surface
    tip_pick = max(top - GRASP_DEPTH, beside + TIP_CLEARANCE, min(bottom + lift, top - MIN_GRIP))
    tip_place = surface + (tip_pick - bottom) + PLACE_CLEARANCE
    return np.array([pick[0], pick[1], tip_pick]), np.array([place[0], place[1], tip_place])


def execute_pick_and_place(
    world, pick: tuple[float, float, float], place: tuple[float, float, float], grasp_width: float | None = None
) -> PickPlaceResult:
    """See :meth:`vslsp.sim.tabletop.TabletopWorld.pick_and_place`."""
    pick_pose, place_pose = check_pose("pick", pick), check_pose("place", place)
    if grasp_width is not None and not (np.isfinite(grasp_width) and grasp_width > 0.0):
        raise InputError(f"grasp_width must be a positive width in metres, got {grasp_width!r}")
    world.panda.reset(PARK)  # out of the depth probe's way
    theta_pick, theta_place = wrist_branch(pick_pose, place_pose)
    each = FINGER_OPEN if grasp_width is None else float(np.clip(grasp_width / 2.0 + 0.01, 0.005, FINGER_OPEN))
    pick_point, place_point = key_points(world, pick_pose, place_pose, theta_pick, theta_place, each)
    movable = [world.bodies[n] for n, item in world.specs.items() if item.movable]
    return execute_between(world, pick_point, place_point, theta_pick, theta_place, each, movable)


def execute_between(
    world,
    pick_point: np.ndarray,
    place_point: np.ndarray,
    theta_pick: float,
    theta_place: float,
    each: float,
    movable: list[int],
) -> PickPlaceResult:
    """The cycle rest -> pick -> place -> rest between the fingertips' key points (3,) each,
    closing along ``theta_pick`` and opening along ``theta_place`` (rad), the fingers opened to
    ``each`` m from the middle; the fingers close on one of the ``movable`` bodies. The key
    points come from the caller's own sensing (:func:`key_points` for the depth probe; VSL-3D's
    point clouds). ``world`` has ``panda``, ``bodies`` (name -> body), ``step`` and ``client``."""
    op = Operation(world)
    panda = op.panda
    panda.reset(REST)
    rest, theta_rest = panda.hand()
    panda.reset(PARK)
    t, xyz, theta, (at_pick, at_place, at_home) = cycle(
        rest, np.asarray(pick_point, float), np.asarray(place_point, float), theta_pick, theta_place, theta_rest
    )
    joints, position_error, angle_error = panda.plan(xyz, theta, REST)
    drop = DESCENT_SPEED * DESCENT_STEPS * TIME_STEP
    below = xyz[at_place] - np.outer(np.arange(1, int(MAX_DESCENT / drop) + 1) * drop, [0.0, 0.0, 1.0])
    descent, descent_error, _ = panda.plan(below, np.full(len(below), theta_place), joints[at_place])
    if max(position_error, descent_error) > IK_POSITION_TOLERANCE or angle_error > IK_ANGLE_TOLERANCE:
        return op.result(Diagnosis.UNREACHABLE, None)

    names = {body: name for name, body in world.bodies.items()}
    panda.fingers_to(each)
    op.follow(np.array([PARK, REST]), np.array([0.0, SWING_TIME]))
    op.follow(joints[: at_pick + 1], t[: at_pick + 1])
    op.converge(joints[at_pick])
    held = op.close_fingers(movable)
    if held is None:
        op.release()
        op.follow(joints[at_pick::-1], t[: at_pick + 1])
        op.follow(np.array([joints[0], PARK]), np.array([0.0, SWING_TIME]))
        return op.result(Diagnosis.GRASP_FAILED, None)

    op.follow(joints[at_pick : at_place + 1], t[at_pick : at_place + 1])
    op.converge(joints[at_place])
    diagnosis = None
    if panda.between_fingers([held]) is None:
        diagnosis = Diagnosis.OBJECT_SLIPPED
    else:
        op.guarded_descent(descent, held)
    op.release()
    op.follow(np.vstack([panda.joints(), joints[at_place + 1 : at_home + 1]]), t[at_place : at_home + 1])
    op.follow(joints[at_home:], t[at_home:])
    op.follow(np.array([joints[-1], PARK]), np.array([0.0, SWING_TIME]))
    return op.result(diagnosis, names[held])
