"""Cavitation in a hydraulic net: the oil's bulk modulus gives way to a vapour cavity below the vapour pressure.

Not a block: the law the compiled node equation applies to every hydraulic net's pressure state when the
netlist's ``fluid: {cavitation: true}`` (the default). A net's pressure p [Pa, gauge] obeys

    dp/dt = beta_eff(p)/V * sum(q)

    beta_eff(p) = beta                                                   p >= p_vap
                = B_cav + (beta - B_cav)*smooth_step(p, p_vap - dp_onset, dp_onset)   p < p_vap

with beta the net's bulk modulus, p_vap the fluid's vapour pressure (gauge), B_cav = CAVITY_MODULUS = 1 bar
and dp_onset = CAVITY_ONSET = 0.05 bar. Above p_vap nothing changes (the liquid, bit for bit). Below it the
pressure no longer measures compression but the vapour cavity: oil drawn out of a net at p_vap leaves a
cavity V_cav, and the pressure dips below p_vap by about B_cav*V_cav/V, 1 bar for a cavity as large as
the net's oil volume. What flows back in fills the cavity first, at that small stiffness, so the cavity
collapses after exactly the volume that opened it has returned, and only then does the liquid's stiffness
raise the pressure again. The blocks see p itself, a little under p_vap while the cavity lasts (by
CAVITY_ONSET plus B_cav*V_cav/V).

Without it (``cavitation: false``, the thesis's Simulink model), the pressure of a net drawn empty falls
as far as the liquid's bulk modulus takes it (hundreds of bar below zero), a tension oil cannot carry,
and the run is only warned of.

What it leaves out: dissolved air coming out of solution (above p_vap), and the block-internal pressure
nodes (the motion-control valve's ``pt``), which keep their own equation.
"""

import numpy as np
from numba import njit

from blocks.library.hydraulic.flow import smooth_step

CAVITY_MODULUS = 1e5  # Pa: the pressure dip below p_vap per unit cavity volume fraction V_cav/V
CAVITY_ONSET = 5e3  # Pa: the band below p_vap over which the liquid's stiffness gives way to the cavity's


@njit(cache=True)
def cavitating_bulk_modulus(p, beta, p_vap):
    """beta_eff(p) [Pa] of the module docstring: beta at and above p_vap, B_cav well below it (C1)."""
    if p >= p_vap:
        return beta
    return CAVITY_MODULUS + (beta - CAVITY_MODULUS) * smooth_step(p, p_vap - CAVITY_ONSET, CAVITY_ONSET)


def cavity_fraction(p, beta, p_vap) -> float:
    """The vapour cavity as a fraction of the net's oil volume at pressure ``p`` (a fixed volume):
    V_cav/V = integral from p to p_vap of (1/beta_eff(u) - 1/beta) du, 0 at and above p_vap."""
    if p >= p_vap:
        return 0.0
    u = np.linspace(p, p_vap, 2001)
    inverse = np.array([1.0 / cavitating_bulk_modulus(x, beta, p_vap) - 1.0 / beta for x in u])
    return float(np.sum((inverse[1:] + inverse[:-1]) * np.diff(u)) / 2.0)
