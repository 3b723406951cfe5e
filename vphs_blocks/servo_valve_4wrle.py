"""The Rexroth 4WRLE 16 servo solenoid valve of the bridge crane (thesis section 2.2), and the spool-edge
area law it shares with the PVG 32 (:mod:`vphs_blocks.pvg32`)."""

from numba import njit

from blocks.block import Block, Param, State, fluid_params, hydraulic, signal_in, signal_out
from blocks.library.hydraulic.flow import turbulent_flow
from blocks.library.signal.linear import clamp, lowpass2_acceleration
from blocks.registry import register


@njit(cache=True)
def spool_edge_areas(s, s_db, s_ramp, A_max, A_n):
    """Areas (A_PA, A_PB, A_AT, A_BT) [m^2] of a 4/3 spool with a W-type centre at normalised spool s.

    a = min(|s|, 1), o = max(0, a - s_db)/(1 - s_db)  (0 inside the dead band, 1 at full stroke)
    opening side (the side the spool moves to; s >= 0: P->A and B->T, s < 0: P->B and A->T):
        meter-in  P->port: A_max*o                    (0 inside the dead band)
        meter-out port->T: A_n + (A_max - A_n)*o      (the centre bleed A_n grows into the full edge)
    closing side (s >= 0: A->T, s < 0: B->T):
        bleed port->T: A_n*max(0, 1 - max(0, a - s_db)/s_ramp)   (A_n, closing linearly over s_ramp)
    The two branches agree at s = 0 (P-edges 0, both bleeds A_n), so every area is continuous in s.
    """
    a = min(abs(s), 1.0)
    beyond = max(0.0, a - s_db)
    o = beyond / (1.0 - s_db)
    meter_in = A_max * o
    meter_out = A_n + (A_max - A_n) * o
    bleed = A_n * max(0.0, 1.0 - beyond / s_ramp)
    if s >= 0.0:
        return meter_in, 0.0, bleed, meter_out
    return 0.0, meter_in, meter_out, bleed


@njit(cache=True)
def edge_flows(dp_pa, dp_pb, dp_at, dp_bt, a_pa, a_pb, a_at, a_bt, Cd, rho, dp_t):
    """What the four edges deliver to the nets (q_P, q_T, q_A, q_B) [m^3/s], each edge the turbulent law
    q_XY = turbulent_flow(dp_XY, A_XY) for the drop dp_XY it sees: q_P = -(q_PA + q_PB),
    q_T = q_AT + q_BT, q_A = q_PA - q_AT, q_B = q_PB - q_BT (they sum to 0: a valve stores no oil)."""
    q_pa = turbulent_flow(dp_pa, a_pa, Cd, rho, dp_t)
    q_pb = turbulent_flow(dp_pb, a_pb, Cd, rho, dp_t)
    q_at = turbulent_flow(dp_at, a_at, Cd, rho, dp_t)
    q_bt = turbulent_flow(dp_bt, a_bt, Cd, rho, dp_t)
    return -(q_pa + q_pb), q_at + q_bt, q_pa - q_at, q_pb - q_bt


def bleed_problem(values) -> str | None:
    """Build-time check shared with the PVG: None if the bleed A_n fits in the edge area A_max."""
    if values["A_n"] > values["A_max"]:
        return f"A_n = {values['A_n']:g} m^2 exceeds A_max = {values['A_max']:g} m^2"
    return None


@register("servo_4wrle")
class Servo4WRLE(Block):
    """4WRLE servo valve (4/3, W-centre bleed A/B->T, dead band): 2nd-order spool, four turbulent edges.

    Spool (thesis eq. 2.1, read as the standard form; the extracted text lost the s^2):
        X(s)/U(s) = wn^2/(s^2 + 2*zeta*wn*s + wn^2),  u_c = min(max(u, -1), 1)
        dx/dt = dx,   d(dx)/dt = wn^2*(u_c - x) - 2*zeta*wn*dx
    x is the normalised spool position (1 = full stroke, P->A); wn = 52.6 rad/s, zeta = 0.90 (section 2.2,
    the thesis's fit of the data-sheet step response; appendix F/G write 52.5).

    Edge areas at s = x (x beyond +-1 reads as +-1: the spool sits on its stop), fig. 2.5 being missing:
        a = min(|x|, 1),  o = max(0, a - x_db)/(1 - x_db)
        x >= 0:  A_PA = A_max*o,  A_BT = A_n + (A_max - A_n)*o,  A_AT = A_n*max(0, 1 - max(0, a - x_db)/x_ramp),  A_PB = 0
        x <  0:  the mirror image (P->B and A->T open, the B->T bleed closes)
    Reading of section 2.2 ("the area was ramped to zero over the next 20 %"): inside the dead band
    |x| <= x_db (2 %) the P edges are closed (positive overlap) and A->T, B->T each pass the centre bleed
    A_n (fig. 2.4: 3 l/min at 5 bar); out of the dead band the bleed on the closing side (A->T for x > 0)
    ramps linearly to 0 at |x| = x_db + x_ramp = 22 %; the meter-in edge opens linearly from 0 at 2 % to
    A_max at 100 %, and the return edge on the opening side grows linearly from the bleed A_n to A_max at
    100 % (a W spool's bleed notch is part of that edge, so it neither closes nor jumps). Every area is
    continuous in x and each edge reaches A_max at full stroke, where the data sheet gives 180 l/min.

    Flows (turbulent orifice law regularised over dp_t, blocks.library.hydraulic.flow):
        q_XY = Cd*A_XY*sqrt(2/rho) * (p_X - p_Y)/((p_X - p_Y)^2 + dp_t^2)^(1/4)   [m^3/s], X -> Y
    Delivered to the nets: q_P = -(q_PA + q_PB), q_T = q_AT + q_BT, q_A = q_PA - q_AT, q_B = q_PB - q_BT
    (the valve stores no oil: the four sum to 0).

    Areas from the orifice law Q = A*Cd*sqrt(2*dp/rho), Cd = 0.7, rho = 850 kg/m^3, dp = 5 bar per edge:
    180 l/min -> A_max = 124.9 mm^2, 3 l/min -> A_n = 2.08 mm^2 (section 2.2 prints 2.1 mm^2, appendix G
    2.08e-6 m^2: 2.1 mm^2 would give 3.03 l/min). dp_t defaults to 0.1 bar so that the law is the plain
    square-root law within 1e-4 at the data sheet's 5 bar.
    """

    ports = (
        hydraulic("P", "supply (pressure) port"),
        hydraulic("T", "tank (return) port"),
        hydraulic("A", "work port A (P -> A for u > 0)"),
        hydraulic("B", "work port B (P -> B for u < 0)"),
        signal_in("u", "command, -1 ... 1 (saturated): the demanded normalised spool position", "1"),
        signal_out("spool", "spool position x, normalised (1 = full stroke P -> A)", "1"),
    )
    params = (
        Param("A_max", "m^2", None, 0.0, 1e-2, "area of one metering edge at full stroke"),
        Param("A_n", "m^2", None, 0.0, 1e-2, "centre bleed area A->T and B->T inside the dead band"),
        Param("x_db", "1", 0.02, 0.0, 0.5, "dead band (positive overlap of the P edges), fraction of the stroke"),
        Param("x_ramp", "1", 0.20, 1e-6, 1.0, "spool travel beyond the dead band over which the closing-side bleed shuts"),
        Param("wn", "rad/s", 52.6, 1e-3, 1e5, "natural angular frequency of the spool response (eq. 2.1)"),
        Param("zeta", "1", 0.90, 0.0, 10.0, "damping ratio of the spool response (eq. 2.1)"),
        Param("Cd", "1", 0.7, 0.01, 1.0, "discharge coefficient of every edge"),
        Param("dp_t", "Pa", 1e4, 1.0, 1e7, "square-root law's regularisation width (q 16 % low at dp = dp_t, 1 % at 5*dp_t)"),
    ) + fluid_params()[:1]
    states = (
        State("x", "1", 0.0, 1.0, "normalised spool position"),
        State("dx", "1/s", 0.0, 50.0, "spool velocity (normalised stroke per second)"),
    )
    presets = {
        "4WRLE16": {"A_max": "124.9 mm^2", "A_n": "2.08 mm^2", "x_db": 0.02, "x_ramp": 0.20,
                    "wn": "52.6 rad/s", "zeta": 0.90, "Cd": 0.7},
    }

    @classmethod
    def check_values(cls, values):
        return bleed_problem(values)

    @staticmethod
    def outputs(x):
        return (x,)

    @staticmethod
    def derivatives(P, T, A, B, u, x, dx, A_max, A_n, x_db, x_ramp, wn, zeta, Cd, dp_t, rho):
        a_pa, a_pb, a_at, a_bt = spool_edge_areas(x, x_db, x_ramp, A_max, A_n)
        q_P, q_T, q_A, q_B = edge_flows(P - A, P - B, A - T, B - T, a_pa, a_pb, a_at, a_bt, Cd, rho, dp_t)
        ddx = lowpass2_acceleration(clamp(u, -1.0, 1.0), x, dx, wn, zeta)
        return q_P, q_T, q_A, q_B, dx, ddx
