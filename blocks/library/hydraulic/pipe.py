"""A pipe or hose as one lumped segment: its oil's inertia, its friction and its volume."""

import math

from numba import njit

from blocks.block import Block, Param, State, fluid_params, hydraulic
from blocks.library.hydraulic.flow import smooth_step
from blocks.registry import register

RE_LAMINAR = 2000.0  # below: laminar friction; above RE_LAMINAR + RE_BAND: turbulent (Blasius)
RE_BAND = 2000.0


@njit(cache=True)
def friction_drop(q, length, diameter, rho, nu):
    """Pressure drop [Pa] of a steady flow q [m^3/s] in a smooth round pipe (the block's docstring)."""
    area = 0.25 * math.pi * diameter * diameter
    v = q / area
    reynolds = abs(v) * diameter / nu
    laminar = 32.0 * rho * nu * length * v / (diameter * diameter)
    turbulent = 0.1582 * rho * length * nu ** 0.25 * diameter ** -1.25 * v * abs(v) ** 0.75
    w = smooth_step(reynolds, RE_LAMINAR, RE_BAND)
    return (1.0 - w) * laminar + w * turbulent


@register("pipe")
class Pipe(Block):
    """Pipe or hose a -> b as one lumped segment: the oil's inertia, wall friction, half its volume at each end.

    A = pi*d^2/4,  v = q/A,  Re = |v|*d/nu
    rho*l/A * dq/dt = p_a - p_b - dp_f(q)                                  [q in m^3/s]
    dp_f = (1 - w)*32*rho*nu*l*v/d^2 + w*0.3164*Re^(-1/4) * l/d * rho*v*|v|/2
    w = smooth_step(Re, 2000, 2000)   (laminar Hagen-Poiseuille below Re 2000, Blasius above 4000;
                                       Blasius is within 3 % of the smooth pipe's Prandtl-Karman law up
                                       to Re 1e5, 14 % low at 1e6: oil lines rarely pass 1e5)
    V_a = V_b = A*l/2   (the pipe's volume, added to the nets at its ends)

    The friction law is a smooth pipe's at steady flow (the laminar drop 128*mu*l*q/(pi*d^4)); the blend
    over 2000 < Re < 4000 is continuous and, both laws rising with |q| and the turbulent one above the
    laminar there, monotone. One segment carries the line's first mode at sqrt(2*beta/rho)/l rad/s (a pipe
    shut at its far end; the wave's quarter-wave frequency pi/2*c/l, c = sqrt(beta/rho), is 11 % higher):
    for wave effects, put several pipes of length l/n in series (n segments: within 1 % for n >= 5 or so).
    The ends' nets get the pipe's volume; a net needs no other volume when a pipe ends on it.

    q > 0 flows from a to b: the block delivers -q to net a and +q to net b.
    """

    ports = (hydraulic("a", "inlet end (positive flow leaves this net)", stores=True),
             hydraulic("b", "outlet end", stores=True))
    params = (
        Param("l", "m", None, 0.0, 1e4, "length", positive=True),
        Param("d", "m", None, 0.0, 10.0, "inner diameter", positive=True),
    ) + fluid_params()[:2]
    states = (State("q", "m^3/s", 0.0, 1e-4, "flow from a to b"),)

    @staticmethod
    def derivatives(a, b, q, l, d, rho, nu):
        area = 0.25 * math.pi * d * d
        half = 0.5 * area * l
        return -q, q, half, half, (a - b - friction_drop(q, l, d, rho, nu)) * area / (rho * l)
