"""Chapter 3: pre-stretched circular dielectric elastomer actuator (Zeng 2020).

Circle A (active, homogeneous equibiaxial, Eqs. 3.28-3.30) + annulus B (passive,
Eqs. 3.33-3.38) of a Gent membrane with Zhao-Suo permittivity (3.27).

* :mod:`.params` -- :class:`Annulus`, :class:`CircularActuator`, thesis constants;
* :mod:`.circle_a` -- closed forms of circle A, breakdown line, free membrane;
* :mod:`.shooting` -- annulus by vectorised RK4 shooting with complex-step sensitivities;
* :mod:`.integrator` -- the shooting method's kernels: right-hand sides, batched RK4;
* :mod:`.lockstep` -- iterative solvers side by side, one integration per round;
* :mod:`.collocation` -- annulus by ``solve_bvp`` (independent cross-check);
* :mod:`.actuator` -- branches, voltage-stretch curves, failure events;
* :mod:`.analysis` -- states at a voltage, pull-in thresholds;
* :mod:`.chapter_pass` -- the whole chapter's results in one batched pass, memoised on its
  parameters (shared by the dataset builder and the catalogue producers).
"""

from .actuator import Branch, Curve, Event, branch, branches, curve, curves, curves_many
from .params import Annulus, CircularActuator

__all__ = ["Annulus", "Branch", "CircularActuator", "Curve", "Event", "branch", "branches",
           "curve", "curves", "curves_many"]
