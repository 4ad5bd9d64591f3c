"""What a critical-voltage solve of the perfect clamped film returns, in both Chapter 5
models (the 3D prism model, :func:`debench.models.buckling.solver.critical_voltage`, and
the axisymmetric one, :func:`debench.models.buckling.axisym.critical_voltage`): the
bifurcation lambda_1(S(v_cr)) = 0 of the condensed tangent at fixed voltage, the flat
state there and what the solve achieved. Each model's result adds its own discretisation
fields to these."""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True, kw_only=True)
class CriticalVoltage:
    """The critical voltage of one discretisation and how it was reached.

    ``v``: normalised critical voltage Phi/t0 sqrt(eps/mu_ref) of this discretisation, to
    ``vtol`` (the secant's last step in v); ``e``: normalised true field and
    ``thickness``: thickness stretch of the flat film at the centre at ``v``; ``lam``: the
    lowest eigenvalue at ``v`` (zero to the secant's accuracy); ``eig_residual``: its
    relative backward error ``||S x - lam M x|| / ||M x||``; ``newton_residual_rel``: the
    last Newton residual relative to its reference; ``iterations``: secant steps;
    ``history``: the (v, lambda_1) evaluated; ``ndof``: degrees of freedom of the state;
    ``order``: polynomial order of the fields.
    """

    v: float
    vtol: float
    e: float
    thickness: float
    lam: float
    eig_residual: float
    newton_residual_rel: float
    iterations: int
    ndof: int
    order: int
    history: tuple = field(default=())
