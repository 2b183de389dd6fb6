"""Push and pull as learned skills, and the library that stores them.

Paper section "Learning Sensorimotor Skills using Imitation Learning": push = reach-before +
move-forward, pull = reach-after + move-backward. The reach is a DMP learned in the
*object frame* (origin at the object, axes: the landmark's normal n pointing away from the
robot, the line direction t, and z up), so its goal is a place relative to the object and one
skill serves any object position and line pose. The move is a straight segment along ±n whose
length is learned from the same demonstrations.

Files (a folder per library, no pickle): ``library.json`` (metadata: parameters, number of
demonstrations, fit errors), ``<skill>_reach.npz`` (the DMP), ``<skill>_demos.npz`` (the
demonstrations it was learned from, in the object frame).
"""

from __future__ import annotations

import json
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from vslsp.dmp import DMP
from vslsp.errors import InputError

LIBRARY_FORMAT = "vslsp-skill-library"
SKILL_NAMES = ("push", "pull")
# Metadata kept across save / load (the rest of library.json is recomputed from the DMP).
SKILL_META = ("success_rate", "seed", "demonstrations_recorded", "demonstrations_used", "travel_model")
STEP = 0.005  # the hand follows its path in 5 mm Cartesian steps


def object_frame(object_xy: np.ndarray, normal: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rotation (3, 3) whose columns are n, t, z, and origin (3,) at the object (z = 0)."""
    n = np.array([normal[0], normal[1], 0.0]) / np.linalg.norm(normal[:2])
    t = np.array([-n[1], n[0], 0.0])
    return np.column_stack([n, t, [0.0, 0.0, 1.0]]), np.array([object_xy[0], object_xy[1], 0.0])


def to_object_frame(points: np.ndarray, object_xy: np.ndarray, normal: np.ndarray) -> np.ndarray:
    rotation, origin = object_frame(object_xy, normal)
    return (np.asarray(points) - origin) @ rotation


def from_object_frame(points: np.ndarray, object_xy: np.ndarray, normal: np.ndarray) -> np.ndarray:
    rotation, origin = object_frame(object_xy, normal)
    return np.asarray(points) @ rotation.T + origin


def resample(path: np.ndarray, step: float = STEP) -> np.ndarray:
    """Points (N, 3) along ``path`` spaced ``step`` apart (ends kept)."""
    lengths = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(path, axis=0), axis=1))])
    if lengths[-1] < 1e-9:
        return path[-1:]
    samples = np.linspace(0.0, lengths[-1], max(2, int(np.ceil(lengths[-1] / step)) + 1))
    return np.column_stack([np.interp(samples, lengths, path[:, k]) for k in range(path.shape[1])])


@dataclass
class Skill:
    """A learned skill: a reach DMP (object frame) to ``goal`` then a straight move of ``move``."""

    name: str
    reach: DMP
    goal: np.ndarray  # (3,) reach goal in the object frame (z absolute height)
    move: np.ndarray  # (3,) displacement of the move segment in the object frame
    demos: list[tuple[np.ndarray, np.ndarray]] = field(default_factory=list)  # object-frame reaches
    meta: dict = field(default_factory=dict)

    def hand_path(self, hand_start: np.ndarray, object_xy: np.ndarray, normal: np.ndarray,
                  travel: float | None = None) -> np.ndarray:
        """World hand waypoints (N, 3), 5 mm apart: the reach rollout, then the move.

        ``travel`` (m): how far the object should go along the normal; the move's length then
        comes from the effect model learned from the demonstrations (``meta["travel_model"]``),
        kept within 0.5-1.3 times the demonstrated move. Without it, the demonstrated move.
        """
        start = to_object_frame(np.asarray(hand_start, dtype=float)[None, :], object_xy, normal)[0]
        # Twice τ: the forcing term has died out and the hand has settled on the goal.
        reach = self.reach.rollout(start, self.goal, duration=2.0 * self.reach.tau).y
        displacement = self.move
        model = self.meta.get("travel_model")
        if travel is not None and model and model["slope"] > 0.1:
            demonstrated = float(np.linalg.norm(self.move))
            length = np.clip((abs(travel) - model["offset"]) / model["slope"], 0.5 * demonstrated, 1.3 * demonstrated)
            displacement = self.move * (length / demonstrated)
        move = np.linspace(self.goal, self.goal + displacement, 2)
        local = np.vstack([resample(reach), resample(move)[1:]])
        return from_object_frame(local, object_xy, normal)

    def summary(self) -> dict:
        return {
            "name": self.name, "demonstrations": self.reach.n_demos,
            "reach_fit_rmse_mm": round(self.reach.fit_rmse * 1000, 3),
            "goal_in_object_frame": [round(float(v), 4) for v in self.goal],
            "move_in_object_frame": [round(float(v), 4) for v in self.move],
            "n_basis": self.reach.n_basis, "alpha_z": self.reach.alpha_z, "alpha_x": self.reach.alpha_x,
            **self.meta,
        }


class SkillLibrary:
    """Named skills, saved to and loaded from a folder."""

    def __init__(self, skills: dict[str, Skill] | None = None) -> None:
        self.skills: dict[str, Skill] = dict(skills or {})

    def __getitem__(self, name: str) -> Skill:
        if name not in self.skills:
            raise InputError(f"the skill library has no skill {name!r} (it has {sorted(self.skills)}); "
                             f"teach it with `vslsp teach {name}`")
        return self.skills[name]

    def __contains__(self, name: str) -> bool:
        return name in self.skills

    def save(self, folder: str | Path) -> None:
        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        for name, skill in self.skills.items():
            skill.reach.save(folder / f"{name}_reach.npz")
            arrays = {f"t_{k}": t for k, (t, _) in enumerate(skill.demos)}
            arrays.update({f"y_{k}": y for k, (_, y) in enumerate(skill.demos)})
            np.savez(folder / f"{name}_demos.npz", **arrays)
        index = {
            "format": LIBRARY_FORMAT, "version": 1,
            "skills": {
                name: {**skill.summary(), "goal": skill.goal.tolist(), "move": skill.move.tolist(),
                       "reach_file": f"{name}_reach.npz", "demos_file": f"{name}_demos.npz"}
                for name, skill in self.skills.items()
            },
        }
        (folder / "library.json").write_text(json.dumps(index, indent=2) + "\n")

    @classmethod
    def load(cls, folder: str | Path) -> SkillLibrary:
        folder = Path(folder)
        index_file = folder / "library.json"
        try:
            index = json.loads(index_file.read_text())
        except FileNotFoundError as error:
            raise InputError(f"no skill library in {folder} (library.json is missing); "
                             "create one with `vslsp teach push` and `vslsp teach pull`") from error
        except (OSError, json.JSONDecodeError) as error:
            raise InputError(f"{index_file} is corrupt ({error}); re-create it with `vslsp teach`") from error
        if not isinstance(index, dict) or index.get("format") != LIBRARY_FORMAT:
            raise InputError(f"{index_file} is not a vslsp skill library")
        skills = {}
        for name, entry in index.get("skills", {}).items():
            try:
                reach = DMP.load(folder / entry["reach_file"])
                goal, move = np.array(entry["goal"], dtype=float), np.array(entry["move"], dtype=float)
                if goal.shape != (3,) or move.shape != (3,):
                    raise ValueError("goal and move must have 3 values")
                demos = []
                demos_file = folder / entry["demos_file"]
                if demos_file.exists():
                    with np.load(demos_file, allow_pickle=False) as data:
                        for k in range(sum(key.startswith("t_") for key in data.files)):
                            demos.append((data[f"t_{k}"], data[f"y_{k}"]))
            except (KeyError, TypeError, ValueError, OSError, EOFError, zipfile.BadZipFile) as error:
                raise InputError(f"skill {name!r} in {index_file} is corrupt ({error}); "
                                 f"re-create it with `vslsp teach {name}`") from error
            meta = {k: v for k, v in entry.items() if k in SKILL_META}
            skills[name] = Skill(name, reach, goal, move, demos, meta)
        return cls(skills)


def default_library_path() -> Path:
    """The shipped library: ``skills/`` at the top of the repository."""
    return Path(__file__).resolve().parents[2] / "skills"
