"""Fixed-displacement hydraulic motor."""

import math

from blocks.block import Block, Param, hydraulic, rotational
from blocks.library.hydraulic.displacement import chamber_fill, motor_friction_band, vapour_pressure_param
from blocks.registry import register


@register("hydraulic_motor")
class HydraulicMotor(Block):
    """Fixed-displacement hydraulic motor with laminar internal leakage; stores its own inertia.

    f = smooth_step(p_in, p_vap - dp_f, dp_f)   fill of the chambers from p_in = p_a (w >= 0), p_b (w < 0)
    q_m = f*D*w + G_leak*(p_a - p_b)        flow through the motor from a to b [m^3/s]
    q_a = -q_m,  q_b = +q_m
    tau_h = D*(p_a - p_b)                   hydraulic torque [N*m]
    tau = tau_h - (1 - eta_hm)*|tau_h|*tanh(w/w_w)   torque on the shaft [N*m]
    J_shaft = J_m                           inertia added to the shaft net [kg*m^2]

    The second term is the motor's mechanical loss (thesis section 2.6): a Coulomb-like friction of
    (1 - eta_hm) of the hydraulic torque's magnitude, opposing the motion, smoothed over the speed width
    w_w. eta_hm = 1 (the default) is the lossless motor.

    Linearised about a point inside the friction's smoothing band, |w| < 3*w_w, the friction's slope is the
    regularisation's, (1 - eta_hm)*D*|p_a - p_b|/w_w [N*m*s/rad] through w = 0: a damper of the smoothing's size,
    where a real one at rest sticks or slips. `vphs linearise` says so.

    D is the displacement per radian [m^3/rad] (D = V_rev/(2*pi)). Sign convention: p_a > p_b drives the
    shaft forward (w > 0), which draws oil from a and delivers it to b. Hydraulic power consumed by the
    ideal part, (p_a - p_b)*D*w, equals tau_h*w; the shaft gets tau*w, the friction dissipating
    (1 - eta_hm)*|tau_h*w| (|w| >> w_w), and the leakage dissipates G_leak*(p_a - p_b)^2. The friction is
    (1 - eta_hm)*|tau_h| in pumping too (an overrunning load, tau_h*w < 0), so the efficiency from shaft
    to oil is then 1/(2 - eta_hm) (0.909 for eta_hm = 0.9), not eta_hm.

    Filling: f = 1 while the port the chambers fill from is at or above the fluid's vapour pressure p_vap
    (the equations are then those without f, bit for bit). Below it, over dp_f = 0.005 bar, the chambers
    take in vapour: an overrunning load that draws its motor's inlet line down to the vapour pressure
    (a meter-out circuit braking with too little make-up oil) passes only the oil the line lets in, so the
    outlet gets no more, and its braking pressure falls as the outlet drains: the load runs away, as on the
    machine, instead of braking on oil the line does not hold. The torque is the full D*(p_a - p_b): the
    vapour-filled chambers are flooded from the outlet as they open to it (the outlet's pressure, while it
    lasts, still brakes; the vacuum at the inlet brakes with about D*1 bar).
    """

    ports = (
        hydraulic("a", "inlet: higher pressure here drives the shaft forward"),
        hydraulic("b", "outlet"),
        rotational("shaft", "motor shaft", stores=True),
    )
    params = (
        Param("D", "m^3/rad", None, 0.0, 1.0, "displacement per radian"),
        Param("G_leak", "m^3/(s*Pa)", 0.0, 0.0, 1e-6, "internal leakage conductance (a -> b)"),
        Param("J_m", "kg*m^2", None, 0.0, 1e6, "inertia of the rotating group, added to the shaft net"),
        Param("eta_hm", "1", 1.0, 0.0, 1.0, "hydro-mechanical efficiency: friction (1 - eta_hm)*|tau_h|"),
        Param("w_w", "rad/s", 0.1, 1e-6, 1e3, "speed width over which the friction torque changes sign"),
        vapour_pressure_param(),
    )

    regularised = ("shaft",)
    regularised_reads = ("a", "b")

    @classmethod
    def regularisations(cls, values: dict):
        """The friction's tanh band, its size from the pressures at the point (none at eta_hm = 1)."""
        return motor_friction_band(values)

    @staticmethod
    def derivatives(a, b, shaft, D, G_leak, J_m, eta_hm, w_w, p_vap):
        dp = a - b
        f = chamber_fill(a, b, shaft, p_vap)
        q = f * D * shaft + G_leak * dp
        tau_h = D * dp
        tau = tau_h - (1.0 - eta_hm) * abs(tau_h) * math.tanh(shaft / w_w)
        return -q, q, tau, J_m
