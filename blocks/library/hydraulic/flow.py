"""Flow laws shared by the hydraulic blocks (numba-compiled, callable from Python too)."""

import math

from numba import njit


@njit(cache=True)
def turbulent_flow(dp, area, cd, rho, dp_t):
    """Turbulent orifice flow regularised (linear) near zero pressure drop.

    q = Cd*A*sqrt(2/rho) * dp / (dp^2 + dp_t^2)^(1/4)   [m^3/s], dp = p_in - p_out [Pa]

    For |dp| >> dp_t this is the square-root law q = Cd*A*sqrt(2|dp|/rho)*sign(dp); near zero it is
    linear, q ~ Cd*A*sqrt(2/rho)*dp/sqrt(dp_t), so dq/ddp stays finite and the solver does not stall.
    The linear part is a regularisation, not a laminar flow law (the oil's viscosity is not in it): the
    flow is 2^(-1/4) = 0.84 of the square-root law at dp = dp_t and 0.99 at 5*dp_t, so dp_t should be
    well below the pressure drops the circuit works at.

    A linearisation about |dp| < dp_t (an open orifice passing no flow) takes the conductance
    dq/ddp = Cd*A*sqrt(2/(rho*dp_t)) there. Unlike a smoothed Coulomb friction's slope (Block.regularised)
    it is not flagged by `vphs linearise`: the square-root law does not jump at dp = 0 (q is continuous,
    only its slope is unbounded), and a real orifice near dp = 0 is laminar, a conductance too, over a
    band that the same law with dp_t = rho/2*(Re_t*nu/(Cd*D_h))^2 describes (Simscape's orifice; Re_t ~
    10..150 gives 1e2..2e4 Pa for a 1 mm orifice in 30 cSt oil). So the linear model has the machine's kind
    of law there, a conductance; its size is dp_t's, as dp_t^(-1/2) (a decade of dp_t moves it 3.2x, where a
    decade of a friction's v_w moves Fc/v_w 10x and the real friction has none). Where the damping that an
    open, flowless orifice gives the modes matters, set dp_t near that transition pressure.
    """
    return cd * area * math.sqrt(2.0 / rho) * dp / math.sqrt(math.sqrt(dp * dp + dp_t * dp_t))


@njit(cache=True)
def smooth_step(x, x0, width):
    """0 below x0, 1 above x0 + width, a C1 cubic (smoothstep) in between."""
    if width <= 0.0:
        return 1.0 if x >= x0 else 0.0
    s = (x - x0) / width
    if s <= 0.0:
        return 0.0
    if s >= 1.0:
        return 1.0
    return s * s * (3.0 - 2.0 * s)


@njit(cache=True)
def smooth_max0(x, width):
    """max(x, 0) with its kink rounded over |x| < width/2 (C1): 0 below -width/2, x above +width/2,
    (x + width/2)^2/(2*width) in between (width <= 0: the plain max)."""
    if width <= 0.0:
        return max(x, 0.0)
    h = 0.5 * width
    if x <= -h:
        return 0.0
    if x >= h:
        return x
    return (x + h) * (x + h) / (2.0 * width)


def opening_range_problem(values: dict, setting: str, full_open: str = "p_open", valve: str = "valve") -> str | None:
    """What is wrong with a valve's opening range (build time, plain Python): the full-open pressure
    (``full_open``) must be above the cracking one (``setting``), or the area would jump from closed to open."""
    if values[full_open] <= values[setting]:
        return (f"{full_open} = {values[full_open] / 1e5:g} bar must be above {setting} = {values[setting] / 1e5:g} bar "
                f"(the {valve} opens over {setting} ... {full_open})")
    return None


def leakage_problem(values: dict, area: str, closed: str) -> str | None:
    """What is wrong with a closed ``closed``'s leakage area (build time, plain Python): A_leak above the
    open area ``area`` would make the path pass more the further it closes (its flow no longer monotone)."""
    if values["A_leak"] > values[area]:
        return (f"A_leak = {values['A_leak']:g} m^2 must not exceed {area} = {values[area]:g} m^2 "
                f"(the closed {closed} would pass more than the open one)")
    return None
