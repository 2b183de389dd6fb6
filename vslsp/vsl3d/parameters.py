"""The tuned rules of VSL-3D as parameter objects (frozen dataclasses, one per algorithm; see
:mod:`vslsp.parameters`): each field says what it controls and its valid range, checked on
construction; the default instance is what the experiments run.

- :class:`CloudMatching`: getObject on clouds (:func:`vslsp.vsl3d.vsl.get_object`: the KNN
  subtraction, the clusters, the motion's registration) and findBestMatch
  (:func:`vslsp.vsl3d.matching.find_best_match`: the global match, its verification, the
  window search).
- :class:`Alignment`: one cloud aligned onto another (:func:`vslsp.vsl3d.alignment.align`).
- :class:`Grasping`: the grasp and the place from the matched cloud
  (:func:`vslsp.vsl3d.grasping.plan_grasp`, :func:`~vslsp.vsl3d.grasping.place_for`).

A benchmark sweeps a field by passing ``dataclasses.replace(DEFAULT_CLOUD_MATCHING, ...)``
(``benchmarks/bench_vsl3d.py --param cloud.confident_fitness=0.8``).
"""

from __future__ import annotations

from dataclasses import dataclass

from vslsp.errors import InputError
from vslsp.parameters import check_ranges


@dataclass(frozen=True)
class CloudMatching:
    """How a moved object is read from two clouds and how a recorded observation is found in a
    new cloud (lengths in m)."""

    # getObject: a point with no counterpart in the other capture within this distance has
    # changed (the paper's KNN distance threshold); also the depth tolerance of what a capture
    # saw (0.0005..0.1).
    change_threshold: float = 0.01
    # Changed points closer than this belong to one object: bridges self-occlusion gaps (a mug
    # and its handle); two objects moved at once must end farther apart to be told apart
    # (0.001..0.5).
    cluster_distance: float = 0.03
    # A changed region of fewer points is noise (150 voxels of 2 mm: 6 cm^2) (1..1000000).
    min_cluster_points: int = 150
    # An observation's frame (cuboid) reaches this far beyond its points (0..0.5).
    frame_margin: float = 0.01
    # getObject, and the window search, also start ICP from this many turns about the vertical
    # (objects rest on a table) (1..360).
    turns: int = 12
    # getObject registers two single views of the moved object, which share less of its surface
    # than a view and the same view moved (a box's wall or a new support hides a part): this
    # share must fit (0..1).
    motion_min_fitness: float = 0.4
    # The starts of getObject's alignment rank poorly on the sparse clouds of two views of a
    # turned object (a flip of a partly hidden object can rank above the true turn): this many
    # are refined (1..1000).
    motion_refined: int = 16
    # Free space is what the sensor saw through at a pixel and all around it, this many pixels
    # each way: a pose a millimetre off puts a box's rim beside its silhouette, where the pixel
    # sees the table behind, and that is no evidence against the pose. The margin excuses every
    # point within it of any silhouette, so it is kept small: a wider one excuses a large share
    # of a wrong match's points and lets it pass ``max_seen_through`` (0..10).
    silhouette_px: int = 1
    # findBestMatch: at most this share of a match may lie where the sensor saw free space (a
    # true pose floats in front of the sensor's surfaces only at its rim) (0..1).
    max_seen_through: float = 0.1
    # A global match whose plausibility (fitness less the tilt's penalty) is below this may be
    # a look-alike (the flat box's top face on the other box): the windows are searched as well
    # and the best fit wins (0..1).
    confident_fitness: float = 0.75
    # The plausibility by which a window's match must beat a weak, verified global one (a view
    # of one object may fit another's side about as well as the object itself) (0..1).
    clearly_better: float = 0.05
    # Objects and boxes rest on a support as they did when recorded: a pose that tips the
    # observation over is judged by its fitness less this much per unit of (1 - cos tilt), in the
    # alignment's ranking and when the global match and the windows' are compared. A single
    # view fits tipped poses deceptively well (a box upside down, a near-cube on its side, an
    # object's far side flipped onto its near side), so an upright pose must lose by more than
    # the tilt's penalty before a tipped one wins; an object that really fell over fits its
    # tipped pose far better than any upright one (0..2).
    upright_weight: float = 0.4
    # Windows are found among the points this far above the lowest surfaces (table, a box's
    # floor) (0..0.2).
    support_clearance: float = 0.012
    # Objects farther apart than this are separate windows (0.001..0.2).
    window_gap: float = 0.01
    # A window reaches this far beyond its cluster (0..0.5).
    window_margin: float = 0.02

    def __post_init__(self) -> None:
        check_ranges(
            self,
            {
                "change_threshold": (0.0005, 0.1),
                "cluster_distance": (0.001, 0.5),
                "min_cluster_points": (1, 1_000_000),
                "frame_margin": (0.0, 0.5),
                "turns": (1, 360),
                "motion_min_fitness": (0.0, 1.0),
                "motion_refined": (1, 1000),
                "silhouette_px": (0, 10),
                "max_seen_through": (0.0, 1.0),
                "confident_fitness": (0.0, 1.0),
                "clearly_better": (0.0, 1.0),
                "upright_weight": (0.0, 2.0),
                "support_clearance": (0.0, 0.2),
                "window_gap": (0.001, 0.2),
                "window_margin": (0.0, 0.5),
            },
        )


@dataclass(frozen=True)
class Grasping:
    """Where the fingertips close on an object seen as a cloud and where they put it down
    (lengths in m)."""

    # Below the object's top where the fingertips close when half its height is too wide
    # (0.001..0.3).
    grasp_depth: float = 0.03
    # The fingertips stay this far above the object's lowest seen point (0..0.1).
    tip_clearance: float = 0.006
    # The guarded descent of the held object starts this far above the demonstrated height
    # (0..0.1).
    place_clearance: float = 0.008
    # Each finger opens this far beyond the object's side (0..0.1).
    finger_room: float = 0.008
    # The grasp's box also measures this far below the fingertips (the pads' reach) (0..0.1).
    band: float = 0.015
    # Fractions of the object's seen height where a grip is tried first, in order: half the
    # height holds a tall object without letting it pivot, and a short round one at its widest
    # (lower, the pads press down on its curve and wedge it against the table) (each 0..1).
    grip_heights: tuple[float, ...] = (0.5,)
    # At least this much of the object stands above the fingertips (0..0.3).
    min_grip: float = 0.015

    def __post_init__(self) -> None:
        check_ranges(
            self,
            {
                "grasp_depth": (0.001, 0.3),
                "tip_clearance": (0.0, 0.1),
                "place_clearance": (0.0, 0.1),
                "finger_room": (0.0, 0.1),
                "band": (0.0, 0.1),
                "grip_heights": (0.0, 1.0),
                "min_grip": (0.0, 0.3),
            },
        )
        if not self.grip_heights:
            raise InputError("Grasping.grip_heights is empty; give at least one fraction of the object's height")


@dataclass(frozen=True)
class Alignment:
    """How one cloud is aligned onto another (:func:`vslsp.vsl3d.alignment.align`: FPFH features,
    the global method's hypotheses, their scoring by the observation, ICP on the full clouds;
    lengths in m)."""

    # The voxel of the features' clouds, the paper's 5 mm (0.0005..0.1).
    feature_voxel: float = 0.005
    # The radius of the full-resolution target's normals, for point-to-plane ICP (0.0005..0.1).
    fine_radius: float = 0.006
    # The inlier distance of the last ICP round and of the reported fitness (0.0001..0.05).
    final_distance: float = 0.003
    # A pose fitting less than this share of the source within final_distance is no match (0..1).
    min_fitness: float = 0.5
    # A point put in free space (the sensor saw through it) weighs this many times a point without
    # a counterpart (which may be a side the other view does not show) (1..100).
    floating_weight: float = 3.0
    # Poses the global method proposes, its best by the features' inlier count (1..1000).
    hypotheses: int = 20
    # Distinct poses refined on the full resolution (1..1000).
    refined: int = 8
    # A refined pose putting more than this share of the source in free space is refined with
    # point pairs too (0..1).
    refine_floating: float = 0.1
    # The fitness of the visible part counts at least this share of the source (0..1).
    visible_floor: float = 0.5
    # Poses closer than this (m at the source's centre, and deg) are one (0..1 m, 0..180 deg).
    distinct_m: float = 0.01
    distinct_deg: float = 10.0

    def __post_init__(self) -> None:
        check_ranges(
            self,
            {
                "feature_voxel": (0.0005, 0.1),
                "fine_radius": (0.0005, 0.1),
                "final_distance": (0.0001, 0.05),
                "min_fitness": (0.0, 1.0),
                "floating_weight": (1.0, 100.0),
                "hypotheses": (1, 1000),
                "refined": (1, 1000),
                "refine_floating": (0.0, 1.0),
                "visible_floor": (0.0, 1.0),
                "distinct_m": (0.0, 1.0),
                "distinct_deg": (0.0, 180.0),
            },
        )


DEFAULT_CLOUD_MATCHING = CloudMatching()
DEFAULT_GRASPING = Grasping()
DEFAULT_ALIGNMENT = Alignment()
