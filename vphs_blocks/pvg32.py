"""The Danfoss PVG 32 pressure-compensated proportional valve of the lower guiding arm (thesis section 2.3)."""

from numba import njit

from blocks.block import Block, Param, State, fluid_params, hydraulic, signal_in, signal_out
from blocks.library.signal.linear import clamp, lowpass2_acceleration
from blocks.registry import register
from vphs_blocks.servo_valve_4wrle import bleed_problem, edge_flows, spool_edge_areas


@njit(cache=True)
def compensated_drop(p_P, p_port, p_LS, dp_c, dp_ls):
    """Pressure drop [Pa] the compensator leaves across a meter-in edge P -> port.

    f  = min(1, max(0, (p_LS - p_port)/dp_ls))          LS limiting (fig. 2.7)
    dp = max(0, min(dp_c*f, p_P - p_port))
    """
    f = clamp((p_LS - p_port) / dp_ls, 0.0, 1.0)
    return max(0.0, min(dp_c * f, p_P - p_port))


@register("pvg32")
class PVG32(Block):
    """PVG 32 proportional valve: 4/3 spool with W-centre bleed, 2nd-order spool, compensator with LS limiting.

    Command u in -1 ... 1 (saturated, normalised spool position; u = 1 demands x_max towards P -> A).
    Spool (2nd order, table 2.2: wn = 30 rad/s, zeta = 0.8; x in metres):
        dx/dt = dx,   d(dx)/dt = wn^2*(x_max*u_c - x) - 2*zeta*wn*dx,   u_c = min(max(u, -1), 1)
    Edge areas: the 4WRLE's law (vphs_blocks.servo_valve_4wrle.spool_edge_areas, "the same functionality as
    the 4/3 servo valve", section 2.3.3) at s = x/x_max with s_db = x_db/x_max and s_ramp = x_ramp/x_max:
    P-edges closed and A->T, B->T = A_n (6.5 mm^2) inside the dead band +-0.8 mm; meter-in P->A (P->B)
    opening linearly from 0 at the dead band to A_max (58.7 mm^2) at 7 mm; the return edge on the opening
    side growing from A_n to A_max; the bleed on the closing side shutting linearly over x_ramp. x_ramp is
    not given for the PVG: 1.4 mm = 20 % of the stroke is read from the 4WRLE's "next 20 %" (section 2.2).

    Pressure compensator (section 2.3.3, fig. 2.7). The thesis feeds the spool from an ideal pressure
    source at p_port + 7 bar (through a 1000 rad/s lag that only breaks a Simulink algebraic loop); the
    same law is written here algebraically, as the drop the meter-in edge sees:
        f_X  = min(1, max(0, (p_LS_X - p_X)/dp_ls))        X = A or B, the port the edge feeds
        dp_X = max(0, min(dp_c*f_X, p_P - p_X))
        q_PX = Cd*A_PX*sqrt(2/rho) * dp_X/(dp_X^2 + dp_t^2)^(1/4)
    Below p_LS - dp_ls (60 bar) the edge sees dp_c = 7 bar whatever the load, so the flow follows the spool
    only; from there the drop falls linearly to 0 at p_LS (the LS relief opening "about 60 bar below"),
    so the flow falls to 0 at the LS setting; and the drop never exceeds what the supply leaves,
    p_P - p_X (compensator fully open), nor goes negative (the load-holding check: no flow back into P).
    The P port delivers what the meter-in edges take: q_P = -(q_PA + q_PB). The law is continuous (piecewise
    linear in the pressures, with kinks), and its pressure derivatives are bounded: 0 in the compensated
    range, dp_c/dp_ls in the LS range, 1 where the supply limits; the square root at zero drop is
    regularised by dp_t.
    Return edges are plain orifices: q_AT, q_BT = Cd*A*sqrt(2/rho)*(p - p_T)/((p - p_T)^2 + dp_t^2)^(1/4).
    Delivered to the nets: q_P = -(q_PA + q_PB), q_T = q_AT + q_BT, q_A = q_PA - q_AT, q_B = q_PB - q_BT.

    Areas (section 2.3.3, orifice law, Cd = 0.7, rho = 850 kg/m^3): 100 l/min at 7 bar -> A_max = 58.7 mm^2,
    60 l/min at 205 bar -> A_n = 6.5 mm^2. LS settings per axis: table 2.3 (presets).
    """

    ports = (
        hydraulic("P", "supply (pressure) port"),
        hydraulic("T", "tank (return) port"),
        hydraulic("A", "work port A (P -> A for u > 0)"),
        hydraulic("B", "work port B (P -> B for u < 0)"),
        signal_in("u", "command, -1 ... 1 (saturated): the demanded spool position as a fraction of x_max", "1"),
        signal_out("spool", "spool position x [m] (positive towards P -> A)", "m"),
    )
    params = (
        Param("p_LS_A", "Pa", None, 0.0, 1e9, "LS pressure limit of port A (flow P -> A falls to 0 there)"),
        Param("p_LS_B", "Pa", None, 0.0, 1e9, "LS pressure limit of port B (flow P -> B falls to 0 there)"),
        Param("A_max", "m^2", 58.7e-6, 0.0, 1e-2, "area of one metering edge at full stroke"),
        Param("A_n", "m^2", 6.5e-6, 0.0, 1e-2, "neutral bleed area A->T and B->T inside the dead band"),
        Param("x_max", "m", 7e-3, 1e-5, 0.1, "spool stroke to either side"),
        Param("x_db", "m", 0.8e-3, 0.0, 0.05, "dead band (overlap of the P edges) to either side"),
        Param("x_ramp", "m", 1.4e-3, 1e-7, 0.1, "spool travel beyond the dead band over which the closing-side bleed shuts"),
        Param("wn", "rad/s", 30.0, 1e-3, 1e5, "natural angular frequency of the spool response"),
        Param("zeta", "1", 0.8, 0.0, 10.0, "damping ratio of the spool response"),
        Param("dp_c", "Pa", 7e5, 0.0, 1e8, "pressure drop the compensator holds across the meter-in edge"),
        Param("dp_ls", "Pa", 60e5, 1.0, 1e9, "pressure band below p_LS over which the compensated drop falls to 0"),
        Param("Cd", "1", 0.7, 0.01, 1.0, "discharge coefficient of every edge"),
        Param("dp_t", "Pa", 1e4, 1.0, 1e7, "square-root law's regularisation width (q 16 % low at dp = dp_t, 1 % at 5*dp_t)"),
    ) + fluid_params()[:1]
    states = (
        State("x", "m", 0.0, 1e-3, "spool position"),
        State("dx", "m/s", 0.0, 0.05, "spool velocity"),
    )
    presets = {
        # table 2.3 (LS settings from the drawing sheets); areas, stroke and response are table 2.2's defaults
        "trolley": {"p_LS_A": "207 bar", "p_LS_B": "207 bar"},
        "jib_tilt": {"p_LS_A": "190 bar", "p_LS_B": "190 bar"},
        "telescope": {"p_LS_A": "140 bar", "p_LS_B": "140 bar"},
        "slewing": {"p_LS_A": "207 bar", "p_LS_B": "207 bar"},
    }

    @classmethod
    def check_values(cls, values):
        if values["x_db"] >= values["x_max"]:
            return f"dead band x_db = {values['x_db']:g} m must be below the stroke x_max = {values['x_max']:g} m"
        return bleed_problem(values)

    @staticmethod
    def outputs(x):
        return (x,)

    @staticmethod
    def derivatives(P, T, A, B, u, x, dx, p_LS_A, p_LS_B, A_max, A_n, x_max, x_db, x_ramp, wn, zeta, dp_c,
                    dp_ls, Cd, dp_t, rho):
        a_pa, a_pb, a_at, a_bt = spool_edge_areas(x / x_max, x_db / x_max, x_ramp / x_max, A_max, A_n)
        dp_pa = compensated_drop(P, A, p_LS_A, dp_c, dp_ls)
        dp_pb = compensated_drop(P, B, p_LS_B, dp_c, dp_ls)
        q_P, q_T, q_A, q_B = edge_flows(dp_pa, dp_pb, A - T, B - T, a_pa, a_pb, a_at, a_bt, Cd, rho, dp_t)
        ddx = lowpass2_acceleration(x_max * clamp(u, -1.0, 1.0), x, dx, wn, zeta)
        return q_P, q_T, q_A, q_B, dx, ddx
