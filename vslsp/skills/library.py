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
import math
import os
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from vslsp.data import skills_folder
from vslsp.dmp import DMP
from vslsp.errors import InputError
from vslsp.files import load_npz, read_json, shown
from vslsp.outputs import atomic_file, write_text

LIBRARY_FORMAT = "vslsp-skill-library"
LIBRARY_VERSION = 1
SKILL_NAME = re.compile(r"[A-Za-z0-9_-]{1,64}")
SKILL_NAMES = ("push", "pull")
# Metadata kept across save / load (the rest of library.json is recomputed from the DMP).
SKILL_META = ("success_rate", "seed", "demonstrations_recorded", "demonstrations_used", "travel_model")
STEP = 0.005  # the hand follows its path in 5 mm Cartesian steps
# Limits of the values read from a library folder (generous: far beyond a tabletop skill, far
# below what would make a rollout or a 5 mm resampling allocate without bound).
MAX_COORDINATE = 10.0  # m, any position, goal, move or amplitude
MAX_TAU = 60.0  # s, a reach's duration
MIN_DT = 1e-4  # s, the sample period
MAX_BASIS = 1000
MAX_WEIGHT = 1e6  # forcing-term weights (the shipped reaches' are below 1e3)
MAX_SAMPLES = 10**6  # samples of one demonstration
MAX_NPZ_BYTES = 256_000_000  # the arrays of one skill file, decoded (checked on their headers before loading)
MAX_INDEX_BYTES = 1_000_000  # library.json
MAX_REACH_SPREAD = 2.0  # m, how far a reach may stray from its goal
MAX_PATH_LENGTH = 20.0  # m, a hand path to resample in 5 mm steps


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

    def hand_path(
        self, hand_start: np.ndarray, object_xy: np.ndarray, normal: np.ndarray, travel: float | None = None
    ) -> np.ndarray:
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
        demonstrated = float(np.linalg.norm(self.move))
        if travel is not None and model and model["slope"] > 0.1 and demonstrated > 1e-6:
            length = np.clip((abs(travel) - model["offset"]) / model["slope"], 0.5 * demonstrated, 1.3 * demonstrated)
            displacement = self.move * (length / demonstrated)
        move = np.linspace(self.goal, self.goal + displacement, 2)
        length = float(np.sum(np.linalg.norm(np.diff(reach, axis=0), axis=1))) + float(np.linalg.norm(displacement))
        if not math.isfinite(length) or length > MAX_PATH_LENGTH:
            raise InputError(
                f"skill {self.name!r} gives a hand path of {length:.3g} m from {start.round(3).tolist()} "
                f"(at most {MAX_PATH_LENGTH} m); its reach DMP or travel model is wrong: re-teach it "
                f"(`vslsp teach {self.name}`)"
            )
        local = np.vstack([resample(reach), resample(move)[1:]])
        return from_object_frame(local, object_xy, normal)

    def summary(self) -> dict:
        return {
            "name": self.name,
            "demonstrations": self.reach.n_demos,
            "reach_fit_rmse_mm": round(self.reach.fit_rmse * 1000, 3),
            "goal_in_object_frame": [round(float(v), 4) for v in self.goal],
            "move_in_object_frame": [round(float(v), 4) for v in self.move],
            "n_basis": self.reach.n_basis,
            "alpha_z": self.reach.alpha_z,
            "alpha_x": self.reach.alpha_x,
            **self.meta,
        }


class SkillLibrary:
    """Named skills, saved to and loaded from a folder."""

    def __init__(self, skills: dict[str, Skill] | None = None) -> None:
        self.skills: dict[str, Skill] = dict(skills or {})

    def __getitem__(self, name: str) -> Skill:
        if name not in self.skills:
            raise InputError(
                f"the skill library has no skill {name!r} (it has {sorted(self.skills)}); "
                f"teach it with `vslsp teach {name}`"
            )
        return self.skills[name]

    def __contains__(self, name: str) -> bool:
        return name in self.skills

    def require(self, names: tuple[str, ...] | list[str], source: str | Path = "the skill library") -> None:
        """Raise :class:`InputError` (before any work) unless every skill in ``names`` is there."""
        missing = [name for name in names if name not in self.skills]
        if missing:
            teach = " and ".join(f"`vslsp teach {name} --out {source}`" for name in missing)
            raise InputError(
                f"{source} has no {' and no '.join(repr(m) for m in missing)} skill "
                f"(it has {sorted(self.skills) or 'none'}); teach it with {teach}"
            )

    def save(self, folder: str | Path) -> None:
        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        for name, skill in self.skills.items():
            skill.reach.save(folder / f"{name}_reach.npz")
            arrays: dict[str, Any] = {f"t_{k}": t for k, (t, _) in enumerate(skill.demos)}
            arrays.update({f"y_{k}": y for k, (_, y) in enumerate(skill.demos)})
            with atomic_file(folder / f"{name}_demos.npz") as stream:
                np.savez(stream, **arrays)
        index = {
            "format": LIBRARY_FORMAT,
            "version": LIBRARY_VERSION,
            "skills": {
                name: {
                    **skill.summary(),
                    "goal": skill.goal.tolist(),
                    "move": skill.move.tolist(),
                    "reach_file": f"{name}_reach.npz",
                    "demos_file": f"{name}_demos.npz",
                }
                for name, skill in self.skills.items()
            },
        }
        write_text(
            folder / "library.json", json.dumps(index, indent=2) + "\n"
        )  # last: the index names only written files

    @classmethod
    def load(cls, folder: str | Path) -> SkillLibrary:
        """Read and fully check a library folder; anything wrong is an :class:`InputError` naming
        the file, the skill and the field, with the command that re-creates it."""
        return cls._read(Path(folder), strict=True)[0]

    @classmethod
    def salvage(cls, folder: str | Path) -> tuple[SkillLibrary, list[str]]:
        """The skills of ``folder`` that load, and a sentence per part that does not.

        For ``vslsp teach --force``, which re-teaches into a damaged library: an unreadable
        ``library.json`` gives an empty library, a damaged skill is left out.
        """
        return cls._read(Path(folder), strict=False)

    @classmethod
    def _read(cls, folder: Path, strict: bool) -> tuple[SkillLibrary, list[str]]:
        index_file = folder / "library.json"
        refuse_linked(index_file)
        fix_all = " and ".join(f"`vslsp teach {name} --out {folder} --force`" for name in SKILL_NAMES)
        if not os.path.lexists(index_file):
            if strict:
                raise InputError(
                    f"no skill library in {folder} (library.json is missing); create one with "
                    f"`vslsp teach push --out {folder}` and `vslsp teach pull --out {folder}`"
                )
            return cls(), []
        try:
            index = read_json(index_file, "skill library index", MAX_INDEX_BYTES)
        except InputError as error:
            problem = f"{shown(index_file)} is corrupt ({error}); re-create it with {fix_all}"
            if strict:
                raise InputError(problem) from error
            return cls(), [problem]
        wrong = _index_problem(index)
        if wrong is not None:
            problem = f"{index_file} is not a vslsp skill library ({wrong}); re-create it with {fix_all}"
            if strict:
                raise InputError(problem)
            return cls(), [problem]
        skills, problems = {}, []
        for name, entry in index["skills"].items():
            try:
                skills[name] = _read_skill(folder, name, entry)
            except _Invalid as error:
                fix = (
                    f"`vslsp teach {name} --out {folder} --force`"
                    if name in SKILL_NAMES
                    else f"remove {name!r} from {index_file}"
                )
                problem = f"skill {name!r} in {index_file} is corrupt: {error}; re-create it with {fix}"
                if strict:
                    raise InputError(problem) from error
                problems.append(problem)
        return cls(skills), problems


# -- checks on load: every value read from a library folder ---------------------------------------
class _Invalid(ValueError):
    """One wrong value in a skill's files: the message names the field and what is wrong."""


def _index_problem(index: object) -> str | None:
    """What is wrong with the top level of ``library.json``, or None."""
    if not isinstance(index, dict):
        return f"its top level is a JSON {type(index).__name__}, not an object"
    if index.get("format") != LIBRARY_FORMAT:
        return f"format is {index.get('format')!r}, not {LIBRARY_FORMAT!r}"
    if index.get("version", LIBRARY_VERSION) != LIBRARY_VERSION:
        return f"version {index.get('version')!r} is not supported (this is {LIBRARY_VERSION})"
    skills = index.get("skills")
    if not isinstance(skills, dict):
        return f'"skills" is a JSON {type(skills).__name__}, not an object of skill name -> entry'
    for name, entry in skills.items():
        if not SKILL_NAME.fullmatch(name):
            return f"skill name {name!r} is not a name (letters, digits, - and _)"
        if not isinstance(entry, dict):
            return f"the entry of skill {name!r} is a JSON {type(entry).__name__}, not an object"
    return None


def _number(
    value: object, field: str, low: float, high: float, *, integer: bool = False, low_open: bool = False
) -> float:
    """``value`` as a finite number in [low, high] ((low, high] with ``low_open``), else _Invalid."""
    kind = "an integer" if integer else "a number"
    if isinstance(value, bool) or not isinstance(value, int | float) or (integer and not isinstance(value, int)):
        raise _Invalid(f"{field} is {value!r}, not {kind}")
    if not math.isfinite(value):
        raise _Invalid(f"{field} is {value}: not finite")
    if value < low or value > high or (low_open and value == low):
        raise _Invalid(f"{field} is {value:g}, outside {'(' if low_open else '['}{low:g}, {high:g}]")
    return value


def _vector(value: object, field: str) -> np.ndarray:
    """A (3,) vector of finite values within MAX_COORDINATE metres."""
    if not isinstance(value, list) or len(value) != 3:
        raise _Invalid(f"{field} is {value!r}, not a list of 3 numbers (x, y, z in metres)")
    return np.array([_number(v, f"{field}[{k}]", -MAX_COORDINATE, MAX_COORDINATE) for k, v in enumerate(value)])


def _file_name(entry: dict, key: str, folder: Path) -> Path:
    name = entry.get(key)
    if not isinstance(name, str) or not name or Path(name).name != name or name in (".", ".."):
        raise _Invalid(f"{key} is {name!r}, not the name of a file in {folder}")
    refuse_linked(folder / name)
    return folder / name


def refuse_linked(path: Path) -> None:
    """A library holds regular files only: a symbolic link is refused on reading and writing, and
    the advice is never ``--force`` (which would write through the link onto its target)."""
    if path.is_symlink():
        raise InputError(
            f"{path} is a symbolic link (to {os.readlink(path)}), not a file of the skill library; vslsp "
            f"never reads or writes a library through a link: remove the link, or teach into another folder"
        )


def _arrays(path: Path, what: str) -> dict[str, np.ndarray]:
    """The arrays of an ``.npz`` file: regular, bounded, headers checked first, never unpickling anything."""
    if not os.path.lexists(path):
        raise _Invalid(f"{path.name} ({what}) is missing")
    try:
        return load_npz(path, what, MAX_NPZ_BYTES)
    except InputError as error:
        raise _Invalid(str(error)) from None


def _check_dmp_arrays(arrays: dict[str, np.ndarray], path: Path) -> None:
    """Check the values a DMP file holds before :meth:`DMP.load` builds the DMP from them (a huge
    ``n_basis`` would allocate before any check). Fields the DMP format does not have are skipped."""
    meta: object = {}
    if "meta" in arrays:
        try:
            meta = json.loads(str(arrays["meta"]))
        except (json.JSONDecodeError, ValueError) as error:
            raise _Invalid(f"{path.name}: meta is not JSON ({error})") from error
    if not isinstance(meta, dict):
        raise _Invalid(f"{path.name}: meta is a JSON {type(meta).__name__}, not an object")
    limits = {
        "n_dims": (3, 3, True),
        "n_basis": (2, MAX_BASIS, True),
        "alpha_z": (0, 1e4, False),
        "alpha_x": (0, 1e3, False),
        "tau": (0, MAX_TAU, False),
        "dt": (MIN_DT, MAX_TAU, False),
        "amplitude": (0, MAX_COORDINATE, False),
        "n_demos": (0, 10**6, True),
    }
    for key, (low, high, integer) in limits.items():
        values = meta.get(key)
        # A list (a value per dimension) is checked value by value.
        for k, value in enumerate(values if isinstance(values, list) else [values] if key in meta else []):
            _number(
                value,
                f"{path.name}: {key}" + (f"[{k}]" if isinstance(values, list) else ""),
                low,
                high,
                integer=integer,
                low_open=key in ("alpha_z", "alpha_x", "tau"),
            )
    if "weights" in arrays:  # its shape is the DMP's own check (DMP.load)
        _check_array(arrays["weights"], f"{path.name}: weights", MAX_WEIGHT)


def _check_array(array: np.ndarray, field: str, limit: float) -> None:
    """A numeric array of finite values with magnitudes up to ``limit``."""
    if array.dtype.kind not in "iuf":
        raise _Invalid(f"{field} are of type {array.dtype}, not numbers")
    if array.size > MAX_SAMPLES * 3:
        raise _Invalid(f"{field} hold {array.size} values, more than {MAX_SAMPLES * 3}")
    bad = int(np.count_nonzero(~np.isfinite(array)))
    if bad:
        raise _Invalid(f"{field} are not finite ({bad} NaN or infinite value(s))")
    largest = float(np.abs(array).max()) if array.size else 0.0
    if largest > limit:
        raise _Invalid(f"{field} reach {largest:.3g}, beyond any plausible value (at most {limit:g})")


def _check_reach(reach: DMP, path: Path) -> None:
    """The DMP's own fields after :meth:`DMP.load`: what the skill's rollouts rely on."""
    if reach.n_dims != 3:
        raise _Invalid(f"{path.name}: n_dims is {reach.n_dims}, not 3 (x, y, z)")
    _check_array(np.asarray(reach.weights, dtype=float), f"{path.name}: weights", MAX_WEIGHT)
    _number(reach.tau, f"{path.name}: tau", 0.0, MAX_TAU, low_open=True)
    _number(reach.dt, f"{path.name}: dt", MIN_DT, MAX_TAU)
    if reach.dt > reach.tau:
        raise _Invalid(f"{path.name}: dt {reach.dt:g} s is longer than tau {reach.tau:g} s")


def _read_demos(path: Path) -> list[tuple[np.ndarray, np.ndarray]]:
    arrays = _arrays(path, "demonstrations")
    count = sum(key.startswith("t_") for key in arrays)
    unknown = sorted(set(arrays) - {f"{v}_{k}" for v in "ty" for k in range(count)})
    if unknown:
        raise _Invalid(f"{path.name}: unexpected arrays {unknown[:5]} (expected t_0, y_0, t_1, y_1, ...)")
    demos = []
    for k in range(count):
        t, y = arrays[f"t_{k}"], arrays[f"y_{k}"]
        _check_array(t, f"{path.name}: t_{k}", MAX_TAU * 10)
        _check_array(y, f"{path.name}: y_{k}", MAX_COORDINATE)
        if t.ndim != 1 or y.shape != (len(t), 3) or len(t) < 2:
            raise _Invalid(
                f"{path.name}: demonstration {k} has t of shape {t.shape} and y of shape {y.shape}, "
                "not (T,) and (T, 3) with T >= 2"
            )
        if not np.all(np.diff(t) > 0):
            raise _Invalid(f"{path.name}: t_{k}, the sample times of demonstration {k}, do not increase")
        demos.append((t.astype(np.float64), y.astype(np.float64)))
    return demos


def _read_meta(entry: dict) -> dict:
    """The kept metadata (SKILL_META) of an entry, checked."""
    meta = {k: v for k, v in entry.items() if k in SKILL_META}
    if meta.get("success_rate") is not None:
        _number(meta["success_rate"], "success_rate", 0.0, 1.0)
    if meta.get("seed") is not None:
        _number(meta["seed"], "seed", 0, 2**63 - 1, integer=True)
    for key in ("demonstrations_recorded", "demonstrations_used"):
        if meta.get(key) is not None:
            _number(meta[key], key, 0, 10**6, integer=True)
    model = meta.get("travel_model")
    if model is not None:
        if not isinstance(model, dict) or not {"slope", "offset"} <= set(model):
            raise _Invalid(f'travel_model is {model!r}, not an object with "slope" and "offset"')
        _number(model["slope"], "travel_model.slope", -100.0, 100.0)
        _number(model["offset"], "travel_model.offset", -MAX_COORDINATE, MAX_COORDINATE)
        if model.get("rmse_mm") is not None:
            _number(model["rmse_mm"], "travel_model.rmse_mm", 0.0, 1e6)
    return meta


def _read_skill(folder: Path, name: str, entry: dict) -> Skill:
    """One skill entry of ``library.json`` and its files, every value checked (raises _Invalid)."""
    goal, move = _vector(entry.get("goal"), "goal"), _vector(entry.get("move"), "move")
    meta = _read_meta(entry)
    reach_path = _file_name(entry, "reach_file", folder)
    _check_dmp_arrays(_arrays(reach_path, "reach DMP"), reach_path)
    try:
        reach = DMP.load(reach_path)
    except InputError as error:
        raise _Invalid(str(error).split("; re-create it")[0]) from error
    _check_reach(reach, reach_path)
    demos_path = _file_name(entry, "demos_file", folder)
    demos = _read_demos(demos_path) if demos_path.exists() else []
    skill = Skill(name, reach, goal, move, demos, meta)
    # The reach from a demonstrated start (or 10 cm before the goal) must stay on the table.
    start = demos[0][1][0] if demos else goal - np.array([0.1, 0.0, 0.0])
    path = reach.rollout(start, goal, duration=2.0 * reach.tau).y
    spread = float(np.abs(path - goal).max()) if np.all(np.isfinite(path)) else math.inf
    if spread > MAX_REACH_SPREAD:
        raise _Invalid(
            f"{reach_path.name}: its rollout from a demonstrated start goes {spread:.3g} m from the goal "
            f"(at most {MAX_REACH_SPREAD} m on a table); the weights or tau are wrong"
        )
    return skill


def default_library_path() -> Path:
    """The shipped library folder (package data ``vslsp.data.skills``; ``skills/`` in the source tree)."""
    return skills_folder()
