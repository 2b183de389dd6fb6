"""The paper's four worlds behind one interface, :class:`World` (:mod:`vslsp.worlds.base`): each
with its assets, seeded layouts and tutor.

- :mod:`~vslsp.worlds.icub`: the iCub line world of VSL-SP (:class:`~vslsp.worlds.icub.IcubLineWorld`);
- :mod:`~vslsp.worlds.panda_table`: the Panda table of VSL's real-world tasks
  (:class:`~vslsp.worlds.panda_table.PandaTable`);
- :mod:`~vslsp.worlds.rgbd_table`: the RGB-D table of VSL-3D (:class:`~vslsp.worlds.rgbd_table.RgbdTable`);
- :mod:`~vslsp.worlds.house_roof`: the house-roof board of VSL's simulation
  (:class:`~vslsp.worlds.house_roof.HouseBoard`).

The worlds stand on the simulator (:mod:`vslsp.sim`, the only importer of pybullet) and know no
algorithm: the experiments (:mod:`vslsp.experiments`) bring a world and an algorithm together.
"""

from vslsp.worlds.base import World

__all__ = ["World"]
