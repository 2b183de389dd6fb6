"""Gymnasium environments of vslsp's worlds (docs/gym.md): importing this module registers them.

========================  ======================================  ==========================================
id                        world                                   task (the reward: its success)
========================  ======================================  ==========================================
``vslsp/PandaTable-v0``   the Panda table (VSL, Table 1)          alphabet-ordering (animal-puzzle, tower-of-hanoi)
``vslsp/RGBDTable-v0``    the RGB-D table (VSL-3D)                table cleaning
``vslsp/ICubLine-v0``     the iCub line world (VSL-SP)            pull-in-order (keep-all-near)
========================  ======================================  ==========================================

``gymnasium.make("vslsp/PandaTable-v0")`` after ``import vslsp.gym``, or without the import
``gymnasium.make("vslsp.gym:vslsp/PandaTable-v0")`` (Gymnasium imports the module named before
the colon). Gymnasium 1.x loads no plugins through package entry points, so vslsp declares none.
This package needs the ``gym`` extra (``pip install vslsp[gym]``).
"""

from __future__ import annotations

from gymnasium.envs.registration import register, registry

from vslsp.gym.base import WorldEnv

__all__ = ["ENVIRONMENTS", "WorldEnv"]

#: The registered ids and their entry points.
ENVIRONMENTS = {
    "vslsp/PandaTable-v0": "vslsp.gym.panda_table:PandaTableEnv",
    "vslsp/RGBDTable-v0": "vslsp.gym.rgbd_table:RgbdTableEnv",
    "vslsp/ICubLine-v0": "vslsp.gym.icub_line:IcubLineEnv",
}

for _id, _entry_point in ENVIRONMENTS.items():
    if _id not in registry:  # importing the module again (a reload) registers nothing twice
        register(id=_id, entry_point=_entry_point)
