"""Element families that connect the bodies, each computing its own coefficients.

* :mod:`.mounts`: suspensions (rubber mounts) and their generalized Maxwell branches;
* :mod:`.bearings`: bearing coefficients (constant, tabulated over speed, journal) in model
  axes (:func:`~.bearings.evaluate`), with :mod:`._bearing_validation` for their tables;
* :mod:`.journal_bearing`: the short plain journal bearing (Ocvirk);
* :mod:`.shaft`: flexible shafts: materials, shear coefficients, Timoshenko beam elements
  (uniform and tapered), a bare shaft's matrices and mass properties.
"""
