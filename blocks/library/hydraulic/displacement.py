"""The law of a displacement pump, shared by the fixed and the variable pump (numba-compiled, callable
from Python too). Not a block."""

import math

from numba import njit


@njit(cache=True)
def pump_flow_and_torque(D, dp, w, G_leak, eta_hm, w_w):
    """(q, tau) of a pump of displacement D [m^3/rad] turning at w [rad/s] against dp = p_out - p_in [Pa].

    q = D*w - G_leak*dp                                     delivered to the outlet [m^3/s]
    tau_h = -D*dp                                           torque the oil exerts on the shaft [N*m]
    tau = tau_h - (1/eta_hm - 1)*|tau_h|*tanh(w/w_w)        torque on the shaft [N*m]

    The loss term is a Coulomb-like friction opposing w, of the size that makes the shaft power
    -tau*w = D*dp*w/eta_hm while pumping (dp*w > 0, |w| >> w_w).
    """
    q = D * w - G_leak * dp
    tau_h = -D * dp
    tau = tau_h - (1.0 / eta_hm - 1.0) * abs(tau_h) * math.tanh(w / w_w)
    return q, tau
