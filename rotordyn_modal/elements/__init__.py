"""Element families that connect the bodies, each computing its own coefficients.

* :mod:`.mounts`: suspensions (rubber mounts) and their generalized Maxwell branches, with
  :mod:`._mount_validation` for their tables;
* :mod:`.bearings`: bearing coefficients (constant, tabulated over speed, journal) in model
  axes (:func:`~.bearings.evaluate`), with :mod:`._bearing_validation` for their tables;
* :mod:`.journal_bearing`: the short plain journal bearing (Ocvirk).

Flexible shafts (beam finite elements) will be a family of their own here.
"""
