"""The laws of displacement machines shared by the pumps and the motors (numba-compiled, callable from
Python too). Not a block."""

import math

from numba import njit

from blocks.block import Param
from blocks.library.hydraulic.cavitation import CAVITY_ONSET
from blocks.library.hydraulic.flow import smooth_step

MILLIBAR = 100.0  # Pa
FILL_BAND = 0.1 * CAVITY_ONSET  # Pa: below p_vap, the chambers' fill falls from 1 to 0 over this band


def friction_band(loss: float, displacement, high: str, low: str, w_w: float, slope_text: str, what: str):
    """The regularisation band (:func:`blocks.regularisation.tanh_band`) of a machine's Coulomb friction,
    loss*|D*(p_high - p_low)|*tanh(w/w_w): ``loss`` is (1 - eta_hm) for a motor, (1/eta_hm - 1) for a pump
    (none at 0), ``displacement`` D [m^3/rad] or a function of the point's reads (a variable pump's
    setting), ``high`` and ``low`` the ports the friction's pressure is read at. A slope below the one 1 mbar
    across the machine at full displacement would give is not said (a motor at rest between two equal line
    pressures: rounding leaves a few Pa across it)."""
    from blocks.regularisation import tanh_band

    if loss == 0.0:
        return ()
    size = displacement if callable(displacement) else (lambda d: lambda reads: d)(displacement)
    full = max(size({high: 1.0, low: 0.0, "eps": 1e30}), 0.0)  # the displacement at its largest setting
    return tanh_band("shaft", lambda s, reads: loss * abs(size(reads) * (reads[high] - reads[low])), w_w, "w_w",
                     slope_text, "N*m*s/rad", what, negligible=loss * full * MILLIBAR / w_w)


def motor_friction_band(values: dict):
    """A motor's friction band, (1 - eta_hm)*D*|p_a - p_b|*tanh(w/w_w) (ports a and b): :func:`friction_band`."""
    return friction_band(1.0 - values["eta_hm"], values["D"], "a", "b", values["w_w"],
                         "(1 - eta_hm)*D*|p_a - p_b|/w_w", "the motor's Coulomb friction")


def vapour_pressure_param() -> Param:
    """The pressure below which a machine's chambers fill with vapour: the fluid's vapour pressure, or never
    (-1e30 Pa) with the netlist's ``fluid: {cavitation: false}`` (the liquid at every pressure)."""
    return Param("p_vap", "Pa", None, None, 1e6, "vapour pressure (gauge): chambers filling below it take in vapour "
                 "(never with fluid cavitation: false)", fluid="cavitation_pressure")


@njit(cache=True)
def chamber_fill(p_forward, p_backward, w, p_vap):
    """The liquid fill f of a machine's chambers [1]: they fill from the port at p_forward when w >= 0, from
    the one at p_backward when w < 0; f = smooth_step(p_in, p_vap - FILL_BAND, FILL_BAND), 1 at and above
    the vapour pressure p_vap, 0 from FILL_BAND (0.005 bar) below it (see pump_flow_and_torque)."""
    return smooth_step(p_forward if w >= 0.0 else p_backward, p_vap - FILL_BAND, FILL_BAND)


@njit(cache=True)
def pump_flow_and_torque(D, p_s, p_p, w, G_leak, eta_hm, w_w, p_vap):
    """(q, tau) of a pump of displacement D [m^3/rad] turning at w [rad/s] between its suction p_s and its
    outlet p_p [Pa], dp = p_p - p_s.

    f = smooth_step(p_in, p_vap - dp_f, dp_f)               liquid fill of the chambers from the side they
                                                            fill from: p_in = p_s for w >= 0, p_p for w < 0
    q = f*D*w - G_leak*dp                                   delivered to the outlet [m^3/s]
    tau_h = -D*dp                                           torque the oil exerts on the shaft [N*m]
    tau = tau_h - (1/eta_hm - 1)*|tau_h|*tanh(w/w_w)        torque on the shaft [N*m]

    The loss term is a Coulomb-like friction opposing w, of the size that makes the shaft power
    -tau*w = D*dp*w/eta_hm while pumping (dp*w > 0, |w| >> w_w). The fill f is 1 at and above the fluid's
    vapour pressure p_vap (the expressions are then those without it, bit for bit) and falls to 0 over the
    band dp_f = FILL_BAND (0.005 bar) below it: chambers that fill from a net drawn below p_vap fill with
    vapour, so a pump delivers no more oil than its inlet gets (a closed or starved suction line ends its
    delivery instead of growing a cavity in it without end). The band is the top tenth of the one over
    which a net's liquid gives way to its vapour cavity (blocks.library.hydraulic.cavitation), where that
    cavity is still under 0.5 cm^3: the oil a pump draws from a closed net is the net's own, not a cavity's.
    The torque is not scaled by f: a chamber that comes round full of vapour is flooded from the outlet as
    it opens to it, and its piston then works against the outlet's full pressure; the power D*dp*w less
    the f*D*w*dp delivered is lost throttling that backflow (and the torque stays continuous through w = 0,
    where the side the chambers fill from changes).
    """
    f = chamber_fill(p_s, p_p, w, p_vap)
    dp = p_p - p_s
    q = f * D * w - G_leak * dp
    tau_h = -D * dp
    tau = tau_h - (1.0 / eta_hm - 1.0) * abs(tau_h) * math.tanh(w / w_w)
    return q, tau
