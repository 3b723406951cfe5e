"""Entrained (undissolved) air in the oil: the stiffness of a net falls at low pressure.

Not a block: the law the compiled node equation applies to every hydraulic net when the netlist's fluid
gives ``air:`` (absent: the pure liquid, the thesis's model, bit for bit). Oil carrying a volume fraction
``air`` of free air at atmospheric pressure is a mixture: per unit volume of liquid at gauge 0, the liquid
at gauge pressure p takes exp(-p/beta) and the air (a polytropic gas, index n: 1 isothermal, 1.4 adiabatic)
air/(1 - air) * (p_atm/p_abs)^(1/n), p_abs = p + p_atm. The mixture's bulk modulus, -V dp/dV, is then

    beta_e(p) = beta * (1 + r) / (1 + r*beta/(n*p_abs)),   r = air/(1 - air) * (p_atm/p_abs)^(1/n) * exp(p/beta)

(r is the ratio of the air's volume to the liquid's at p), and a net's pressure obeys

    dp/dt = beta_e(p)/V * sum(q)                                   p >= p_vap
    dp/dt = sum(q) / (V/beta_e(p_vap) + (1 - w)*C_cav)             p <  p_vap (fluid cavitation on)
    dp/dt = sum(q) / (V/beta_e(p_vap))                             p <  p_vap (cavitation: false)

with w, C_cav the cavitation law's (blocks.library.hydraulic.cavitation): below the vapour pressure a vapour
cavity opens beside the mixture, whose compliance stays that at p_vap; the cavity's volume is the
cavitation law's. p_atm = 1.01325 bar; p_abs is held at 1 Pa or more (a vapour pressure at absolute zero).

With 1 % of air and beta = 8e8 Pa (isothermal) the mixture's modulus is 7.9e8 Pa at 100 bar (gauge),
4.8e8 Pa at 10 bar, 3.8e7 Pa at 1 bar and 1e7 Pa at 0 bar: a line that is stiff at working pressure is
soft near the tank's. air = 0 gives
beta above p_vap exactly, and below it a compliance larger by V/beta (1e-12 m^3/Pa per litre beside C_cav's
1e-7) than the cavitation law alone.
"""

import math

from numba import njit

from blocks.library.hydraulic.cavitation import CAVITY_COMPLIANCE, CAVITY_ONSET
from blocks.library.hydraulic.flow import smooth_step

P_ATM = 101325.0  # Pa: the absolute pressure of gauge 0, at which ``air`` is given
P_ABS_MIN = 1.0  # Pa: the smallest absolute pressure the gas law is evaluated at


@njit(cache=True)
def effective_bulk_modulus(p, beta, air, n):
    """beta_e [Pa] of oil with the free-air fraction ``air`` (at atmospheric pressure) at gauge pressure p."""
    p_abs = max(p + P_ATM, P_ABS_MIN)
    r = air / (1.0 - air) * (P_ATM / p_abs) ** (1.0 / n) * math.exp(p / beta)
    return beta * (1.0 + r) / (1.0 + r * beta / (n * p_abs))


@njit(cache=True)
def aerated_pressure_rate(p, beta, volume, q, p_vap, air, n, cavitation):
    """dp/dt [Pa/s] of a net at pressure p with the net inflow q [m^3/s] (module docstring)."""
    if p >= p_vap:
        return effective_bulk_modulus(p, beta, air, n) / volume * q
    mixture = volume / effective_bulk_modulus(p_vap, beta, air, n)
    if not cavitation:
        return q / mixture
    w = smooth_step(p, p_vap - CAVITY_ONSET, CAVITY_ONSET)
    return q / (mixture + (1.0 - w) * CAVITY_COMPLIANCE)
