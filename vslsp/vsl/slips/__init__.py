"""The tutor's slips (issue 30; the paper's own limit, VSL "Results": "if the tutor accidentally
moves one object while operating another, the algorithm may fail"): every rule that finds what
moved in one demonstrated operation, tells the operated object from those the tutor's hand
disturbed, and records the operation the tutor meant. One module per pipeline's detection, and
the 2-D recorder's restore and record rules:

- :mod:`~vslsp.vsl.slips.detect`: 2-D, textured objects seen from above (the Panda's five
  tasks): changed regions, SIFT placements, the operated object the one that left its place for
  another (:func:`~vslsp.vsl.slips.detect.find_moved`);
- :mod:`~vslsp.vsl.slips.restore`: the post observation the tutor meant, the disturbed objects
  restored (:func:`~vslsp.vsl.slips.restore.separate`);
- :mod:`~vslsp.vsl.slips.record`: recording that observation (when the restore leaves a nudge
  beside the arrival; what was put on a nudged object);
- :mod:`~vslsp.vsl.slips.clouds`: 3-D, point clouds (VSL-3D): segments of the union of both
  clouds, the operated object the one carried from an emptied place
  (:func:`~vslsp.vsl.slips.clouds.get_operated_object`);
- :mod:`~vslsp.vsl.slips.colour`: coloured cubes and a landmark line (the iCub): the operated
  object the one whose ``(far b)`` changed (:func:`~vslsp.vsl.slips.colour.ground_moves`).

The perception they stand on is one image subtraction and thresholding,
:func:`vslsp.vision.change.changed_pixels` (3-D: :func:`vslsp.vsl3d.vsl.changed_points`); the
experiments only inject slips (:mod:`vslsp.worlds.slips`) and report what these rules found.
"""
