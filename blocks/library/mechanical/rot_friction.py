"""Rotational Coulomb plus viscous friction against the frame."""

import math

from blocks.block import Block, Param, rotational
from blocks.regularisation import tanh_band
from blocks.registry import register


@register("rot_friction")
class RotFriction(Block):
    """Rotational Coulomb + viscous friction against the fixed frame, Coulomb part smoothed with tanh.

    tau = -(Tc*tanh(w/w_w) + b*w)   [N*m]

    Tc is the Coulomb (kinetic) friction torque [N*m], b the viscous coefficient [N*m*s/rad], and w_w
    [rad/s] the declared speed width of the tanh regularisation (the friction torque reaches 76 % of Tc at
    |w| = w_w and is linear through w = 0). tau acts on the net and always opposes w.

    Linearised about a point inside the smoothing's band, |w| < 3*w_w (beyond it tanh is within 0.5 % of
    sign(w), its slope under 1 %), the law's slope is the regularisation's, Tc/w_w [N*m*s/rad] through w = 0: a
    damper of the smoothing's size, where a real friction at rest sticks or slips. `vphs linearise` says
    so.
    """

    ports = (rotational("port", "the braked shaft net"),)
    params = (
        Param("Tc", "N*m", None, 0.0, 1e9, "Coulomb friction torque"),
        Param("b", "N*m*s/rad", 0.0, 0.0, 1e9, "viscous friction coefficient"),
        Param("w_w", "rad/s", 0.1, 1e-9, 1e3, "speed width of the Coulomb smoothing (regularisation width)"),
    )

    regularised = ("port",)

    @classmethod
    def regularisations(cls, values: dict):
        return tanh_band("port", values["Tc"], values["w_w"], "w_w", "Tc/w_w", "N*m*s/rad")

    @staticmethod
    def derivatives(port, Tc, b, w_w):
        return (-(Tc * math.tanh(port / w_w) + b * port),)
