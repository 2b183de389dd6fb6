"""Learned skills: push and pull (DMP reach + straight move), their library, teaching, execution."""

from vslsp.skills.library import SKILL_NAMES, Skill, SkillLibrary, default_library_path

__all__ = ["SKILL_NAMES", "Skill", "SkillLibrary", "default_library_path"]
