"""Cavitation in a hydraulic net: below the vapour pressure, the oil drawn out leaves a vapour cavity.

Not a block: the law the compiled node equation applies to every hydraulic net's pressure state when the
netlist's ``fluid: {cavitation: true}`` (the default). A net's pressure p [Pa, gauge] obeys

    dp/dt = sum(q) / C(p)         C(p) = dV/dp, the net's compliance [m^3/Pa]

    C(p) = V/beta                                           p >= p_vap     (the liquid: dp/dt = beta/V*sum(q))
    C(p) = w*V/beta + (1 - w)*C_cav,  w = smooth_step(p, p_vap - dp_onset, dp_onset)    p < p_vap

with V the net's volume now (a cylinder chamber's changes), beta its bulk modulus, p_vap the fluid's vapour
pressure (gauge), C_cav = CAVITY_COMPLIANCE = 1e-7 m^3/Pa (0.1 bar per litre of vapour) and dp_onset =
CAVITY_ONSET = 0.05 bar. At and above p_vap nothing changes (the liquid's expression, bit for bit). Below
it the pressure no longer measures compression but the vapour cavity: oil drawn out of a net at p_vap,
pistons' displacement included, leaves a cavity V_cav, and the pressure sits below p_vap by less than
dp_onset + V_cav/C_cav (the onset band holds the first C_cav*dp_onset/2 = 250 cm^3; beyond, 0.1 bar per
litre). What flows back in fills the cavity first, so it collapses after exactly
the volume that opened it has returned (whatever the net's volume did meanwhile), and only then does the
liquid's stiffness raise the pressure again. The blocks see p itself, a little under p_vap while the cavity
lasts: by under 0.15 bar for a litre of vapour, 1.05 bar for 10 l.

The cavity at pressure p is V_cav = integral from p to p_vap of (C(u) - V/beta) du, which is
C_cav*integral (1 - w(u)) du to within V/(beta*C_cav) (1e-5 for a litre at 8e8 Pa): :func:`cavity_volume`.

Without it (``cavitation: false``, the thesis's Simulink model), the pressure of a net drawn empty falls
as far as the liquid's bulk modulus takes it (hundreds of bar below zero), a tension oil cannot carry,
and the run is only warned of.

Free air entrained in the oil (``fluid: {air: ...}``) is the other law of a net's compliance
(blocks.library.hydraulic.entrained_air, which takes this one's cavity below p_vap). What both leave out:
dissolved air coming out of solution, and the block-internal pressure nodes (the motion-control valve's
``pt``), which keep their own equation.
"""

from numba import njit

from blocks.library.hydraulic.flow import smooth_step

CAVITY_COMPLIANCE = 1e-7  # m^3/Pa: 0.1 bar below p_vap per litre of vapour
CAVITY_ONSET = 5e3  # Pa: the band below p_vap over which the liquid's stiffness gives way to the cavity's


@njit(cache=True)
def cavitating_pressure_rate(p, beta, volume, q, p_vap):
    """dp/dt [Pa/s] of a net at pressure p with the net inflow q [m^3/s] (module docstring)."""
    if p >= p_vap:
        return beta / volume * q
    w = smooth_step(p, p_vap - CAVITY_ONSET, CAVITY_ONSET)
    return q / (w * volume / beta + (1.0 - w) * CAVITY_COMPLIANCE)


def cavity_volume(p, p_vap) -> float:
    """The vapour cavity [m^3] of a net at pressure ``p`` (module docstring): C_cav times the integral of
    1 - w from p to p_vap, in closed form (w is the smoothstep s^2*(3 - 2s) over the onset band)."""
    if p >= p_vap:
        return 0.0
    below = p_vap - p
    if below >= CAVITY_ONSET:
        return CAVITY_COMPLIANCE * (below - CAVITY_ONSET / 2.0)
    s = 1.0 - below / CAVITY_ONSET  # w's argument at p; integral of (1 - w) from s to 1, times the band
    integral = (1.0 - s) - ((1.0 - s**3) - 0.5 * (1.0 - s**4))
    return CAVITY_COMPLIANCE * CAVITY_ONSET * integral
