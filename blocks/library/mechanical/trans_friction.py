"""Translational Coulomb plus viscous friction against the frame."""

import math

from blocks.block import Block, Param, translational
from blocks.regularisation import tanh_band
from blocks.registry import register


@register("trans_friction")
class TransFriction(Block):
    """Translational Coulomb + viscous friction against the fixed frame, Coulomb part smoothed with tanh.

    f = -(Fc*tanh(v/v_w) + b*v)   [N]

    Fc is the Coulomb (kinetic) friction force [N], b the viscous coefficient [N*s/m], and v_w [m/s] the
    declared velocity width of the tanh regularisation (the friction force reaches 76 % of Fc at
    |v| = v_w and is linear through v = 0). f acts on the net and always opposes v.

    Linearised about a point inside the smoothing's band, |v| < 3*v_w (beyond it tanh is within 0.5 % of
    sign(v), its slope under 1 %), the law's slope is the regularisation's, Fc/v_w [N*s/m] through v = 0: a
    damper of the smoothing's size, where a real friction at rest sticks or slips. `vphs linearise` says
    so.
    """

    ports = (translational("port", "the braked body net"),)
    params = (
        Param("Fc", "N", None, 0.0, 1e10, "Coulomb friction force"),
        Param("b", "N*s/m", 0.0, 0.0, 1e10, "viscous friction coefficient"),
        Param("v_w", "m/s", 1e-3, 1e-9, 1e3, "velocity width of the Coulomb smoothing (regularisation width)"),
    )

    regularised = ("port",)

    @classmethod
    def regularisations(cls, values: dict):
        return tanh_band("port", values["Fc"], values["v_w"], "v_w", "Fc/v_w", "N*s/m")

    @staticmethod
    def derivatives(port, Fc, b, v_w):
        return (-(Fc * math.tanh(port / v_w) + b * port),)
