"""PID controller with filtered derivative, output limits and back-calculation anti-windup."""

from blocks.block import Block, Param, State, signal_in, signal_out
from blocks.library.signal.linear import UNLIMITED, clamp
from blocks.registry import register


@register("pid")
class PID(Block):
    """PID controller (parallel form) on the error e, filtered derivative, output limits, back-calculation.

    C(s) = Kp + Ki/s + Kd*s/(Tf*s + 1), acting on the error input e (form e = ref - meas with a ``sum``
    block, k2 = -1; a PI controller is Kd = 0).
    v = Kp*e + xi + Kd*(e - xd)/Tf        (unsaturated output)
    y = min(max(v, u_min), u_max)
    dxi/dt = Ki*e + Kaw*(y - v)           (integral part; back-calculation anti-windup)
    dxd/dt = (e - xd)/Tf                  (xd: e low-passed with time constant Tf, so that
                                           Kd*(e - xd)/Tf = Kd*s/(Tf*s + 1) e)
    Anti-windup: while saturated y - v pulls the integral back; at constant e it settles at
    v = u_lim + Ki*e/Kaw instead of growing without bound. Kaw ~ Ki/Kp (= 1/Ti) or 1/sqrt(Ti*Td) are the
    usual choices; Kaw = 0 disables it. It acts with Ki = 0 too (as a PID block with back-calculation
    does): while the output is limited xi moves, and once the output is back inside the limits it stays
    where it ended, an offset built by the saturation alone. A P or PD controller that can saturate
    takes Kaw = 0. Direct feedthrough of e (through Kp and Kd).
    Units: Kp in unit(y)/unit(e), Ki in that per s, Kd in that times s; Tf in s, Kaw in 1/s; y, u_min, u_max
    and xi in y's (SI) unit, xd in e's.
    Tolerance: xi has the nominal magnitude of y's quantity, xd that of e's, where the netlist fixes it, else 1.
    """

    ports = (signal_in("e", "control error (reference - measurement)"), signal_out("y", "controller output"))
    params = (
        Param("Kp", "SI", 1.0, None, None, "proportional gain"),
        Param("Ki", "SI", 0.0, None, None, "integral gain"),
        Param("Kd", "SI", 0.0, None, None, "derivative gain"),
        Param("Tf", "s", 0.01, 1e-9, None, "time constant of the derivative filter"),
        Param("u_min", "SI", -UNLIMITED, None, None, "lower output limit (SI; default unlimited)"),
        Param("u_max", "SI", UNLIMITED, None, None, "upper output limit (SI; default unlimited)"),
        Param("Kaw", "1/s", 1.0, 0.0, None, "back-calculation anti-windup gain (0: none; acts with Ki = 0 too)"),
    )
    states = (
        State("xi", "SI", 0.0, 1.0, "integral part of the output (its start is the initial integral action)",
              scale_of="y"),
        State("xd", "SI", 0.0, 1.0, "error low-passed by the derivative filter", scale_of="e"),
    )

    @staticmethod
    def outputs(e, xi, xd, Kp, Kd, Tf, u_min, u_max):
        return (clamp(Kp * e + xi + Kd * (e - xd) / Tf, u_min, u_max),)

    @staticmethod
    def derivatives(e, xi, xd, Kp, Ki, Kd, Tf, u_min, u_max, Kaw):
        v = Kp * e + xi + Kd * (e - xd) / Tf
        y = clamp(v, u_min, u_max)
        return Ki * e + Kaw * (y - v), (e - xd) / Tf

    @classmethod
    def check_values(cls, values: dict) -> str | None:
        """None if the parameter values fit together, else what is wrong (build time, not in the hot path)."""
        if values["u_min"] > values["u_max"]:
            return f"u_min = {values['u_min']:g} is above u_max = {values['u_max']:g}"
        return None
