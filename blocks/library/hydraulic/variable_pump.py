"""Variable-displacement pump with a pressure compensator."""

from blocks.block import Block, Param, State, hydraulic, rotational, signal_out
from blocks.library.hydraulic.displacement import friction_band, pump_flow_and_torque, vapour_pressure_param
from blocks.library.hydraulic.flow import smooth_step
from blocks.library.signal.linear import clamp
from blocks.registry import register


@register("variable_pump")
class VariablePump(Block):
    """Variable-displacement pump with a pressure compensator (pressure cut-off); stores its own inertia.

    dp = p_p - p_s                                         pressure rise from suction s to outlet p [Pa]
    eps_target = eps_max*(1 - smooth_step(dp, p_c, dp_c))  full stroke below p_c, none above p_c + dp_c [1]
    d(eps)/dt = (eps_target - eps)/tau_c                   the stroking mechanism's first-order lag [1/s]
    e = min(max(eps, 0), eps_max)                          displacement fraction in use; output displacement
    f = smooth_step(p_in, p_vap - dp_f, dp_f)             fill of the chambers from p_in = p_s (w >= 0), p_p (w < 0)
    q = f*e*D_max*w - G_leak*dp                            flow delivered from s to p [m^3/s]
    q_s = -q,  q_p = +q
    tau_h = -e*D_max*dp                                    torque of the oil on the shaft [N*m]
    tau = tau_h - (1/eta_hm - 1)*|tau_h|*tanh(w/w_w)       torque on the shaft [N*m]
    J_shaft = J_p                                          inertia added to the shaft net [kg*m^2]

    smooth_step is the C1 cubic from 0 at dp = p_c to 1 at p_c + dp_c. eps_target lies in [0, eps_max],
    so a lag that starts in [0, eps_max] stays there; the clip e only guards against the solver's overshoot
    and a start above eps_max (the default start is full stroke, eps = 1, as the compensator's spring holds
    a pump at rest): e is then eps_max until eps has fallen to it. eps_max < 1 is a displacement limiter.

    Steady state: the pump delivers what the outlet takes, e*D_max*w = q_load + G_leak*dp. Below p_c it is a
    fixed pump of eps_max*D_max; once the load takes less, dp rises into [p_c, p_c + dp_c] and the
    compensator strokes back to deliver only that (flow on demand at a pressure drooping over dp_c from
    full to zero flow); dead-headed it delivers only its leakage. The compensator senses p_p - p_s (the
    suction is usually the tank).

    Sign convention, power and filling as for `pump` with D = e*D_max: w > 0 pumps from s to p; the shaft
    supplies -tau*w = e*D_max*dp*w/eta_hm while pumping; running backwards against a pressurised outlet
    it motors; a suction drawn below the vapour pressure fills the chambers with vapour (f < 1), which
    limits the flow to what the suction line lets in.

    Linearised about a point inside the friction's smoothing band, |w| < 3*w_w, the friction's slope is the
    regularisation's, (1/eta_hm - 1)*e*D_max*|p_p - p_s|/w_w [N*m*s/rad] through w = 0: a damper of the smoothing's
    size, where a real one at rest sticks or slips. `vphs linearise` says so.
    """

    ports = (
        hydraulic("s", "suction (inlet), usually the tank line"),
        hydraulic("p", "pressure (outlet): oil is delivered here for w > 0"),
        rotational("shaft", "drive shaft (w > 0 pumps from s to p)", stores=True),
        signal_out("displacement", "displacement fraction in use, e = eps clipped to [0, eps_max]", "1"),
    )
    params = (
        Param("D_max", "m^3/rad", None, 0.0, 1.0, "full (maximum) displacement per radian"),
        Param("p_c", "Pa", None, 0.0, 1e9, "compensator setting: p_p - p_s at which the pump starts to destroke"),
        Param("dp_c", "Pa", 5e5, 0.0, 1e8, "compensator band: zero displacement at p_c + dp_c", positive=True),
        Param("tau_c", "s", 0.03, 0.0, 10.0, "time constant of the displacement's first-order lag", positive=True),
        Param("eps_max", "1", 1.0, 0.0, 1.0, "displacement limiter: the largest displacement fraction"),
        Param("G_leak", "m^3/(s*Pa)", 0.0, 0.0, 1e-6, "internal leakage conductance (p -> s)"),
        Param("J_p", "kg*m^2", None, 0.0, 1e6, "inertia of the rotating group, added to the shaft net"),
        Param("eta_hm", "1", 1.0, 0.5, 1.0,
              "hydro-mechanical efficiency: shaft power e*D_max*dp*w/eta_hm when pumping"),
        Param("w_w", "rad/s", 0.1, 1e-6, 1e3, "speed width over which the friction torque changes sign"),
        vapour_pressure_param(),
    )
    states = (State("eps", "1", 1.0, 1.0, "displacement fraction of the stroking mechanism (1 = full stroke)"),)

    @classmethod
    def check_values(cls, values: dict) -> str | None:
        start = values.get("initial.eps", 1.0)
        if not 0.0 <= start <= 1.0:
            return f"initial eps = {start:g} is outside [0, 1] (the displacement fraction, 1 = full stroke)"
        return None

    regularised = ("shaft",)
    regularised_reads = ("s", "p", "eps")

    @classmethod
    def regularisations(cls, values: dict):
        """The friction's tanh band, its size from the pressures and the setting at the point (none at
        eta_hm = 1)."""
        d_max, e_max = values["D_max"], values["eps_max"]
        return friction_band(1.0 / values["eta_hm"] - 1.0, lambda reads: min(max(reads["eps"], 0.0), e_max) * d_max,
                             "p", "s", values["w_w"], "(1/eta_hm - 1)*e*D_max*|p_p - p_s|/w_w",
                             "the pump's Coulomb friction")

    @staticmethod
    def outputs(eps, eps_max):
        return (clamp(eps, 0.0, eps_max),)

    @staticmethod
    def derivatives(s, p, shaft, eps, D_max, p_c, dp_c, tau_c, eps_max, G_leak, J_p, eta_hm, w_w, p_vap):
        dp = p - s
        target = eps_max * (1.0 - smooth_step(dp, p_c, dp_c))
        e = clamp(eps, 0.0, eps_max)
        q, tau = pump_flow_and_torque(e * D_max, s, p, shaft, G_leak, eta_hm, w_w, p_vap)
        return -q, q, tau, J_p, (target - eps) / tau_c
