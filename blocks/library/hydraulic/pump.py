"""Fixed-displacement hydraulic pump."""

from blocks.block import Block, Param, hydraulic, rotational
from blocks.library.hydraulic.displacement import friction_band, pump_flow_and_torque, vapour_pressure_param
from blocks.registry import register


@register("pump")
class Pump(Block):
    """Fixed-displacement pump driven by its shaft, with laminar internal leakage; stores its own inertia.

    dp = p_p - p_s                                        pressure rise from suction s to outlet p [Pa]
    f = smooth_step(p_in, p_vap - dp_f, dp_f)            fill of the chambers from p_in = p_s (w >= 0), p_p (w < 0)
    q = f*D*w - G_leak*dp                                 flow delivered from s to p [m^3/s]
    q_s = -q,  q_p = +q
    tau_h = -D*dp                                         torque of the oil on the shaft [N*m]
    tau = tau_h - (1/eta_hm - 1)*|tau_h|*tanh(w/w_w)      torque on the shaft [N*m]
    J_shaft = J_p                                         inertia added to the shaft net [kg*m^2]

    D is the displacement per radian [m^3/rad] (D = V_rev/(2*pi)). Sign convention: w > 0 pumps, drawing
    oil from s and delivering it to p; the torque on the shaft is what the pump applies to it, so a
    pump working against dp > 0 brakes its shaft (tau < 0) and the prime mover must supply -tau.

    Power: pumping (dp*w > 0, |w| >> w_w) the shaft gives -tau*w = D*dp*w/eta_hm and the oil receives
    q*dp = D*dp*w - G_leak*dp^2: the loss term is a Coulomb-like friction opposing w, smoothed over w_w,
    dissipating (1/eta_hm - 1)*|D*dp*w|, and the leakage dissipates G_leak*dp^2 (volumetric efficiency
    1 - G_leak*dp/(D*w)). eta_hm = 1 (the default) is the lossless pump.

    Linearised about a point inside the friction's smoothing band, |w| < 3*w_w, the friction's slope is the
    regularisation's, (1/eta_hm - 1)*D*|p_p - p_s|/w_w [N*m*s/rad] through w = 0: a damper of the smoothing's size,
    where a real one at rest sticks or slips. `vphs linearise` says so.

    Filling: f = 1 while the side the chambers fill from is at or above the fluid's vapour pressure p_vap
    (the usual case; the equations are then those without f, bit for bit). Below it the chambers take in
    vapour, and f falls to 0 over dp_f = 0.005 bar: a pump delivers no more than its suction line lets in
    (the suction-limited flow of a starved pump), and a closed suction ends its delivery once its own oil
    is drawn out, instead of growing a cavity in the suction net without end. The torque keeps the full
    D*dp: the vapour-filled chambers are flooded from the outlet as they open to it, and the pistons work
    against its pressure (the power beyond f*D*w*dp is lost throttling that backflow).

    Motoring (dp*w < 0: the outlet pressure drives the shaft backwards, w < 0, e.g. an accumulator on p
    after the prime mover stops): oil flows from p back to s and the machine is a motor with
    tau*w = (2 - 1/eta_hm)*|D*dp*w| on the shaft (0.889 of the hydraulic power for eta_hm = 0.9, not
    eta_hm: the friction is the same (1/eta_hm - 1)*|tau_h| in every quadrant). Hence eta_hm >= 0.5: below,
    the friction would exceed the hydraulic torque. Driven backwards against no pressure, it draws oil
    out of p into s until the outlet line cavitates (then f falls, and with it the flow); a check valve at
    the outlet is the usual remedy.
    """

    ports = (
        hydraulic("s", "suction (inlet), usually the tank line"),
        hydraulic("p", "pressure (outlet): oil is delivered here for w > 0"),
        rotational("shaft", "drive shaft (w > 0 pumps from s to p)", stores=True),
    )
    params = (
        Param("D", "m^3/rad", None, 0.0, 1.0, "displacement per radian"),
        Param("G_leak", "m^3/(s*Pa)", 0.0, 0.0, 1e-6, "internal leakage conductance (p -> s)"),
        Param("J_p", "kg*m^2", None, 0.0, 1e6, "inertia of the rotating group, added to the shaft net"),
        Param("eta_hm", "1", 1.0, 0.5, 1.0, "hydro-mechanical efficiency: shaft power D*dp*w/eta_hm when pumping"),
        Param("w_w", "rad/s", 0.1, 1e-6, 1e3, "speed width over which the friction torque changes sign"),
        vapour_pressure_param(),
    )

    regularised = ("shaft",)
    regularised_reads = ("s", "p")

    @classmethod
    def regularisations(cls, values: dict):
        """The friction's tanh band, its size from the pressures at the point (none at eta_hm = 1)."""
        return friction_band(1.0 / values["eta_hm"] - 1.0, values["D"], "p", "s", values["w_w"],
                             "(1/eta_hm - 1)*D*|p_p - p_s|/w_w", "the pump's Coulomb friction")

    @staticmethod
    def derivatives(s, p, shaft, D, G_leak, J_p, eta_hm, w_w, p_vap):
        q, tau = pump_flow_and_torque(D, s, p, shaft, G_leak, eta_hm, w_w, p_vap)
        return -q, q, tau, J_p
