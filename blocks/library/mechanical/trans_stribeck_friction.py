"""Translational friction with a Stribeck peak: Coulomb, Stribeck and viscous parts against the frame."""

import math

from blocks.block import Block, Param, translational
from blocks.regularisation import stribeck_band
from blocks.registry import register


@register("trans_stribeck_friction")
class TransStribeckFriction(Block):
    """Translational Stribeck friction against the fixed frame: Coulomb + decaying breakaway excess + viscous.

    f = -((Fc + dFs*exp(-(v/v_s)^2))*tanh(v/v_w) + b*v)   [N]

    Fc is the Coulomb (kinetic) force, dFs >= 0 the breakaway excess (static friction Fs = Fc + dFs, reached
    near standstill and decaying over the Stribeck velocity v_s), b the viscous coefficient and v_w [m/s] the
    declared width of the tanh regularisation of sign(v) (linear through v = 0; at |v| = v_w the Coulomb
    part has reached 76 %). v_w << v_s for a visible Stribeck dip. A cylinder's seal friction is the usual
    case. f acts on the net and always opposes v. With dFs = 0 this is the library's trans_friction; it is
    stribeck_friction for a translating body.

    Linearised about a point inside the smoothing's band, |v| < 3*v_w (beyond it tanh is within 0.5 % of
    sign(v), its slope under 1 %), the law's slope is the regularisation's, (Fc + dFs)/v_w [N*s/m] through v = 0: a
    damper of the smoothing's size, where a real friction at rest sticks or slips. `vphs linearise` says
    so.
    """

    ports = (translational("port", "the braked body net (a cylinder's rod)"),)
    params = (
        Param("Fc", "N", 0.0, 0.0, 1e9, "Coulomb (kinetic) friction force"),
        Param("dFs", "N", 0.0, 0.0, 1e9, "breakaway excess: static friction force minus Fc"),
        Param("v_s", "m/s", 0.01, 1e-9, 1e3, "Stribeck velocity: the excess decays as exp(-(v/v_s)^2)"),
        Param("b", "N*s/m", 0.0, 0.0, 1e9, "viscous friction coefficient"),
        Param("v_w", "m/s", 1e-4, 1e-12, 1e2, "velocity width of the sign smoothing (regularisation width)"),
    )

    regularised = ("port",)

    @classmethod
    def regularisations(cls, values: dict):
        return stribeck_band("port", values["Fc"], values["dFs"], values["v_s"], values["v_w"], "v_w",
                             "(Fc + dFs)/v_w", "N*s/m")

    @staticmethod
    def derivatives(port, Fc, dFs, v_s, b, v_w):
        r = port / v_s
        return (-((Fc + dFs * math.exp(-r * r)) * math.tanh(port / v_w) + b * port),)
