"""Step control of the path-following (continuation) drivers: one policy object for how a
path's step grows after a converged step and shrinks after a failed one.

The drivers that use it (the 3D voltage ramp of Chapter 5,
:func:`debench.models.buckling.solver.voltage_ramp`, in both its voltage- and
deflection-controlled phases, and the axisymmetric path,
:func:`debench.models.buckling.axisym.follow_path`) keep their own loops: what makes a step
acceptable differs between them (the 3D ramp also rejects a step that lowers the centre
deflection or jumps; the axisymmetric path ends at a state past the voltage maximum), but
the step sizes they try come from one :class:`StepControl`.

The policy, for a step of size ``h``:

* **converged** in at most ``easy_iterations`` Newton iterations (an *easy* step; every
  converged step with ``easy_iterations=None``): ``h <- min(grow h, cap)``;
* **failed** (Newton did not converge or the driver rejected the state): ``h <- h / 2``,
  refused (:meth:`StepControl.failed` returns False) when the halved step lies below
  ``min_size``;
* **cautious regrowth** (``regrow_after`` = k): a failure also lowers the cap to the halved
  step, which is then not exceeded until k easy steps in a row have passed; each such run
  raises the cap by ``grow`` up to ``max_size``. Near a limit point a step twice the one
  that just failed usually fails again, so the plain policy alternates failed and
  converged steps there.

Halving is exact in binary floating point, so refusing a halved step below ``m`` is the same
decision as refusing, before halving, a step below ``2 m``: a driver that used either rule
keeps its step sequence to the bit.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from debench.models import validation as val
from debench.models.errors import require


@dataclass
class StepControl:
    """The step size of one continuation (module docstring for the policy).

    Parameters
    ----------
    size : the first step (> 0, at most ``max_size``).
    max_size : the largest step.
    grow : factor (> 1) by which an easy step grows the next one.
    easy_iterations : a converged step is easy when its Newton took at most this many
        iterations; None: every converged step is.
    min_size : :meth:`failed` refuses to halve below it (>= 0).
    regrow_after : None, or the easy steps in a row after which a cap lowered by a failure
        grows again (cautious regrowth).

    ``size`` is the step to try next; ``cap`` the current bound on it.
    """

    size: float
    max_size: float
    grow: float = 2.0
    easy_iterations: int | None = 4
    min_size: float = 0.0
    regrow_after: int | None = None
    cap: float = field(init=False)
    _easy_run: int = field(init=False, default=0, repr=False)

    def __post_init__(self):
        self.size = val.positive("size", self.size)
        self.max_size = val.finite("max_size", self.max_size)
        require(self.size <= self.max_size,
                f"size must be <= max_size, got size = {self.size}, max_size = {self.max_size}")
        self.grow = val.finite("grow", self.grow)
        require(self.grow > 1, f"grow must be > 1, got {self.grow}")
        require(self.easy_iterations is None or self.easy_iterations >= 1,
                f"easy_iterations must be None or >= 1, got {self.easy_iterations}")
        self.min_size = val.nonnegative("min_size", self.min_size)
        require(self.regrow_after is None or self.regrow_after >= 1,
                f"regrow_after must be None or >= 1, got {self.regrow_after}")
        self.cap = self.max_size

    def converged(self, iterations: int) -> None:
        """A step converged in ``iterations`` Newton iterations: grow the next one when it
        was easy (and, with cautious regrowth, the cap after enough easy steps in a row)."""
        easy = self.easy_iterations is None or iterations <= self.easy_iterations
        if self.regrow_after is not None:
            self._easy_run = self._easy_run + 1 if easy else 0
            if self._easy_run >= self.regrow_after:
                self.cap, self._easy_run = min(self.grow * self.cap, self.max_size), 0
        if easy:
            self.size = min(self.size * self.grow, self.cap)

    def failed(self, min_size: float | None = None) -> bool:
        """A step failed: halve it (and with cautious regrowth lower the cap to it). Returns
        False when the halved step lies below ``min_size`` (default: the control's own),
        where the caller gives up or ends its path."""
        self.size *= 0.5
        if self.regrow_after is not None:
            self.cap, self._easy_run = min(self.cap, self.size), 0
        return self.size >= (self.min_size if min_size is None else min_size)


__all__ = ["StepControl"]
