"""Rotational friction with a Stribeck peak: Coulomb, Stribeck and viscous parts against the frame."""

import math

from blocks.block import Block, Param, rotational
from blocks.regularisation import stribeck_band
from blocks.registry import register


@register("stribeck_friction")
class StribeckFriction(Block):
    """Rotational Stribeck friction against the fixed frame: Coulomb + decaying breakaway excess + viscous.

    tau = -((Tc + dTs*exp(-(w/w_s)^2))*tanh(w/w_w) + b*w)   [N*m]

    Tc is the Coulomb (kinetic) torque, dTs >= 0 the breakaway excess (static friction Ts = Tc + dTs,
    reached near standstill and decaying over the Stribeck speed w_s), b the viscous coefficient and
    w_w [rad/s] the declared width of the tanh regularisation of sign(w) (linear through w = 0; at |w| =
    w_w the Coulomb part has reached 76 %). w_w << w_s for a visible Stribeck dip. tau acts on the net and
    always opposes w. With dTs = 0 this is the library's rot_friction.

    Linearised about a point inside the smoothing's band, |w| < 3*w_w (beyond it tanh is within 0.5 % of
    sign(w), its slope under 1 %), the law's slope is the regularisation's, (Tc + dTs)/w_w [N*m*s/rad] through w = 0: a
    damper of the smoothing's size, where a real friction at rest sticks or slips. `vphs linearise` says
    so.
    """

    ports = (rotational("port", "the braked shaft net"),)
    params = (
        Param("Tc", "N*m", 0.0, 0.0, 1e9, "Coulomb (kinetic) friction torque"),
        Param("dTs", "N*m", 0.0, 0.0, 1e9, "breakaway excess: static friction torque minus Tc"),
        Param("w_s", "rad/s", 1.0, 1e-6, 1e4, "Stribeck speed: the excess decays as exp(-(w/w_s)^2)"),
        Param("b", "N*m*s/rad", 0.0, 0.0, 1e9, "viscous friction coefficient"),
        Param("w_w", "rad/s", 0.01, 1e-9, 1e3, "speed width of the sign smoothing (regularisation width)"),
    )

    regularised = ("port",)

    @classmethod
    def regularisations(cls, values: dict):
        return stribeck_band("port", values["Tc"], values["dTs"], values["w_s"], values["w_w"], "w_w",
                             "(Tc + dTs)/w_w", "N*m*s/rad")

    @staticmethod
    def derivatives(port, Tc, dTs, w_s, b, w_w):
        r = port / w_s
        return (-((Tc + dTs * math.exp(-r * r)) * math.tanh(port / w_w) + b * port),)
