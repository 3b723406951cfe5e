"""The Bosch Rexroth Oil Control VAA-B-SICN-ST motion-control (counterbalance) valve (thesis section 2.4.2,
chapter 3), and the numba helpers it shares with the VBSO over-centre valve (:mod:`vphs_blocks.mcv_vbso`)."""

import math

from numba import njit

from blocks.block import Block, Param, State, ValidRange, fluid_params, hydraulic
from blocks.library.hydraulic.flow import leakage_problem, smooth_max0, smooth_step, turbulent_flow
from blocks.library.signal.linear import lowpass2_acceleration
from blocks.registry import register

# ---- the steady flow force of chapter 3 (eq. 3.13): constants fitted by hand in the thesis ----
Z1 = 4.0847e5 * 1e5
"""z1 of eq. 3.13 [Pa^1.5*s/m^3]: pF = P(Q_lpm)*z1*Q/sqrt(dp), Q in m^3/s and dp in Pa."""
LPM = 60000.0
"""l/min per m^3/s (the thesis's Q_l/min = Q*60000)."""
FIT_CRACKS = (95.4e5, 211.5e5)
"""The crack settings eq. 3.13's polynomials were fitted at, lowest and highest [Pa] (table 3.2)."""


@njit(cache=True)
def _corner(x, width):
    """The rounded corner of smooth_unit: 2x^2/w - x^3/w^2 on 0 < x < w (f(0) = f'(0) = 0, f(w) = w, f'(w) = 1)."""
    s = x / width
    return width * s * s * (2.0 - s)


@njit(cache=True)
def smooth_unit(x, width):
    """Saturation of x to [0, 1] with C1-rounded corners, exact outside the two corner bands:
    0 for x <= 0, x for width <= x <= 1 - width, 1 for x >= 1; 2x^2/w - x^3/w^2 on (0, w) and the mirror
    image on (1 - w, 1). Exactly 0 for x <= 0, so a closed valve leaks nothing (width <= 0: the plain clip;
    width must be < 0.5)."""
    if x <= 0.0:
        return 0.0
    if x >= 1.0:
        return 1.0
    if width <= 0.0:
        return x
    if x < width:
        return _corner(x, width)
    if x > 1.0 - width:
        return 1.0 - _corner(1.0 - x, width)
    return x


@njit(cache=True)
def check_valve_flow(dp, A_max, p_crack, p_open, A_leak, Cd, rho, dp_t):
    """Flow [m^3/s] through a check valve in its free direction (dp = p_in - p_out), the library check
    valve's law: A = A_leak + (A_max - A_leak)*smooth_step(dp, p_crack, p_open - p_crack), turbulent orifice."""
    area = A_leak + (A_max - A_leak) * smooth_step(dp, p_crack, p_open - p_crack)
    return turbulent_flow(dp, area, Cd, rho, dp_t)


@njit(cache=True)
def flow_force_pressure(q, dp, p_crack, q_max, dp_t):
    """Steady flow force over the ring area, pF [Pa] (thesis eq. 3.13 and the three polynomials above it).

    pF = P(Q_lpm) * z1 * Q / (dp^2 + dp_t^2)^(1/4),  Q = max(q, 0) [m^3/s], Q_lpm = 60000*min(Q, q_max)
    P(x) = c4 x^4 + c3 x^3 + c2 x^2 + c1 x, chosen by the crack setting:
      p_crack > 180 bar:          1.66e-5, -3.0e-3,  0.071, 13.2
      120 bar <= p_crack <= 180:  -1.9e-5,  5.2e-3, -0.55,  28.9
      p_crack < 120 bar:          -4.4e-5,  0.011,  -1.0,   40.5
    """
    qp = max(q, 0.0)
    x = min(qp, q_max) * LPM
    if p_crack > 180e5:
        c4, c3, c2, c1 = 1.66e-5, -3.0e-3, 0.071, 13.2
    elif p_crack >= 120e5:
        c4, c3, c2, c1 = -1.9e-5, 5.2e-3, -0.55, 28.9
    else:
        c4, c3, c2, c1 = -4.4e-5, 0.011, -1.0, 40.5
    poly = (((c4 * x + c3) * x + c2) * x + c1) * x
    return poly * Z1 * qp / math.sqrt(math.sqrt(dp * dp + dp_t * dp_t))


@njit(cache=True)
def vaa_contact_force(p_pilot, pt, alpha, p_s2, kp2, u):
    """Contact force between the two spool pieces over the ring area, N/Ar [Pa] (eq. 2.4):
    N = alpha*(p_pilot - pt) + p_s2 - kp2*u;  N > 0: the pieces are in contact."""
    return alpha * (p_pilot - pt) + p_s2 - kp2 * u


@njit(cache=True)
def vaa_opening_raw(p_C, p_pilot, pt, alpha, p_crack, p_s2, kp1, kp2, p_F, dN):
    """Unsaturated static spool position of one line (eqs. 2.7/2.11, 2.12/2.13 and 3.13):

    u_n = (p_C - pt - (p_crack + p_s2) + p_F)/kp1                       no contact (eq. 2.7 / 2.12)
    N_n = vaa_contact_force(p_pilot, pt, alpha, p_s2, kp2, u_n)           eq. 2.4 at that position
    u   = u_n + smooth_max0(N_n, dN)/(kp1 + kp2)
        = (alpha*p_pilot + p_s2 - pt*(alpha + 1) + p_C - (p_crack + p_s2) + p_F)/(kp1 + kp2)  if N_n >= dN/2
                                                                          (contact: eq. 2.11 / 2.13)
    """
    u_n = (p_C - pt - (p_crack + p_s2) + p_F) / kp1
    n_n = vaa_contact_force(p_pilot, pt, alpha, p_s2, kp2, u_n)
    return u_n + smooth_max0(n_n, dN) / (kp1 + kp2)


@register("mcv_vaa")
class MotionControlValveVAA(Block):
    """VAA-B-SICN-ST counterbalance valve: check valves V->C, piloted reliefs C->pt->V (cross-line), 2nd-order spools.

    Pressures (thesis table 2.6): p1 = p_V1, p2 = p_V2, p3 = p_C1, p4 = p_C2, pt = the internal node between
    the two relief valves and the check valves 2 (a state of this block, volume V_t). Line 1 is V1/C1,
    line 2 is V2/C2. Each relief is piloted from the opposite V port (line 2 by p1 = p_V1, line 1 by p2).

    Hydraulics (fig. 2.16, table 2.8; "four check valves and two variable orifices"):
        check valve 1, line i:  V_i -> C_i, free flow into the motor  (A_cv1, p_cv1_crack, p_cv1_open)
        relief valve, line i:   C_i -> pt, orifice of area a_i = A_prv*sat(u_i)            (eqs. 2.14, 2.15)
        check valve 2, line j:  pt -> V_j for j = 1 and 2, so the relieved flow leaves by the lower-pressure
                                V line (cross-line relief, text at fig. 2.14)          (A_cv2, p_cv2_crack, p_cv2_open)
        check valve law: A = A_leak + (A_max - A_leak)*smooth_step(dp, p_crack, p_open - p_crack)
                         (the library check valve's C1 cubic; the thesis's Simscape check valve opens
                         linearly between the same two pressures: same end points, same midpoint);
                         A_leak <= A_cv1, A_cv2 (checked when the values are set)
        every orifice:   q = Cd*A*sqrt(2/rho) * dp/(dp^2 + dp_t^2)^(1/4)
        d(pt)/dt = beta/V_t * (q_r1 + q_r2 - q_cv2,1 - q_cv2,2)
    Delivered to the nets: q_V1 = q_cv2,1 - q_cv1,1, q_V2 = q_cv2,2 - q_cv1,2, q_C1 = q_cv1,1 - q_r1,
    q_C2 = q_cv1,2 - q_r2 (what leaves the ports plus what pt stores sums to zero).

    Spool equilibrium (section 2.4.2, the garbled text rebuilt; all forces divided by the ring area Ar, so
    springs are in Pa per unit of the normalised stroke u in [0, 1]). The thesis's pcr1, pcr2 are the
    preloads of spring 1 (closing the main spool) and spring 2 (pushing the pilot piece onto it); the crack
    setting is pcr = pcr1 - pcr2 (chapter 3, under eq. 3.2). Here p_crack = pcr and p_s2 = pcr2, so
    pcr1 = p_crack + p_s2:
        N2 = alpha*(p1 - pt) + pcr2 - kp2*u2                                          (2.4), N2 > 0: contact
        N2 <= 0:  u2 = (p4 - pt - pcr1 [+ pF2])/kp1                                     (2.7)
        N2 >  0:  u2 = (alpha*p1 + pcr2 - pt*(alpha + 1) + p4 - pcr1 [+ pF2])/(kp1 + kp2)   (2.10, 2.11)
        line 1 (p1 -> p2, p4 -> p3):  u1 by (2.12) for N1 <= 0 and (2.13) for N1 > 0
    The two branches meet where N = 0, and N has the same sign at either branch's solution, so the branch
    is chosen by N at the no-contact position u_n of eq. 2.7, and the equilibrium reads
        u_eq = sat( u_n + smax(N(u_n), dN)/(kp1 + kp2) )
    smax = max(., 0) rounded over |N| < dN/2 (exact eq. 2.7 for N <= -dN/2, exact eq. 2.11 for N >= dN/2);
    sat = clip to [0, 1] with corners rounded over u_w (exact in [u_w, 1 - u_w], exactly 0 for u <= 0).
    At u = 0 and in contact eq. 2.11 gives the crack relation of chapter 3: with pt = pv2 + (pv1 - pc)
    and pc = p_C, pcr = pc*(alpha + 2) - pv1 - pv2*(alpha + 1)  (eq. 3.2; eq. 3.10's "pt = pv2 + (pc1 -
    pv1)" is a sign slip of eq. 3.7's assumption, which eq. 3.2 uses).
    The thesis gives no value for pcr2 (p_s2). The default, 400 bar (= kp2), keeps the pieces in contact
    over the whole stroke even without pilot (N = p_s2 - kp2*u >= 0 for u <= 1), as the thesis's Simulink
    model (built on eqs. 2.10 and 2.13 only) and its chapter-3 tests ("the two parts of the spool always
    were connected") assume; p_s2 = 0 lets the pieces part as soon as the main spool lifts without pilot
    assistance. Only the no-contact branch depends on it.

    Spool dynamics (fig. 2.17, table 2.9): u_i'' = wn^2*(u_eq,i - u_i) - 2*zeta*wn*u_i'. Table 2.9 gives
    12 Hz, zeta = 1.0 (the default); chapter 3.6 found 50 Hz (with 0.1 l at p3) fits the step tests best:
    set wn = "50 Hz" for that.

    Flow force (chapter 3, eq. 3.13; scaled by flow_force: 1 the thesis's fit, default 0 the chapter-2 model,
    values between give a continuous parameter for calibration): flow_force*pF_i is added to
    the main spool's balance (to the numerator of eqs. 2.7/2.11, as in eq. 3.13):
        pF = P(Q_lpm)*z1*Q/sqrt(dp),  dp = p_C,i - pt,  Q = the relief flow q_r,i >= 0 [m^3/s],
        z1 = 4.0847e5*1e5,  Q_lpm = 60000*Q, P(x) = c4 x^4 + c3 x^3 + c2 x^2 + c1 x with
        (1.66e-5, -3.0e-3, 0.071, 13.2) for p_crack > 180 bar, (-1.9e-5, 5.2e-3, -0.55, 28.9) for
        120 ... 180 bar, (-4.4e-5, 0.011, -1.0, 40.5) below 120 bar.
    Read as pF = P(Q_lpm)*Q*z1/sqrt(dp) with Q in m^3/s and dp in Pa: with it, eq. 3.14 evaluated on the
    measured multistep data gives kp ~ 850...900 bar/unit, the thesis's 895. sqrt(dp) is regularised as
    (dp^2 + dp_t^2)^(1/4); the polynomial's argument is held at q_ff_max (the fit's range, "only valid up
    to 100 l/min"). The polynomial is chosen by the parameter p_crack (a jump in parameter space only).
    With the flow force on, a run in which the flow out of C1 or C2 (C1.flow < 0 delivered: the port's net
    flow, the relief flow while it meters less the closed check valve's leak) goes beyond q_ff_max at an
    output sample is warned of: there the force is the fit's end value, an extrapolation the thesis did not
    make; so is a crack setting outside those of the fit (95.4 to 211.5 bar, table 3.2).

    Sizes (presets, table 2.8): VF050, VF150, VF250. Spring stiffnesses and the spool response are measured
    for the VF250 only (table 2.9: kp1 + kp2 = 895 bar/unit, split 495/400): they are the defaults for all
    sizes. p_crack and alpha are per installation (tables 2.4, 2.5) and must be given.
    """

    ports = (
        hydraulic("V1", "valve side, line 1 (from the directional valve)"),
        hydraulic("V2", "valve side, line 2"),
        hydraulic("C1", "motor side, line 1"),
        hydraulic("C2", "motor side, line 2"),
    )
    params = (
        Param("alpha", "1", None, 0.1, 50.0, "pilot ratio (tables 2.4, 2.5: per installation)"),
        Param("p_crack", "Pa", None, 0.0, 1e9, "crack setting pcr = pcr1 - pcr2 of both reliefs (eq. 3.2; tables 2.4, 2.5)"),
        Param("A_prv", "m^2", 72.1e-6, 0.0, 1e-2, "maximum discharge area of each relief valve (table 2.8 Am,prv)"),
        Param("A_cv1", "m^2", 151.5e-6, 0.0, 1e-2, "fully open area of check valve 1, V -> C (table 2.8 Am,cv1)"),
        Param("p_cv1_crack", "Pa", 0.5e5, 0.0, 1e8, "crack pressure of check valve 1 (table 2.8 pcr1)"),
        Param("p_cv1_open", "Pa", 2e5, 0.0, 1e8, "full-open pressure of check valve 1 (table 2.8 pmax,cv1), > crack"),
        Param("A_cv2", "m^2", 151.5e-6, 0.0, 1e-2, "fully open area of check valve 2, pt -> V (table 2.8 Am,cv2)"),
        Param("p_cv2_crack", "Pa", 0.1e5, 0.0, 1e8, "crack pressure of check valve 2 (table 2.8 pcr2)"),
        Param("p_cv2_open", "Pa", 2.5e5, 0.0, 1e8, "full-open pressure of check valve 2 (table 2.8 pmax,cv2), > crack"),
        Param("kp1", "Pa", 495e5, 1.0, 1e10, "stiffness of spring 1 per unit stroke, over Ar (table 2.9)"),
        Param("kp2", "Pa", 400e5, 0.0, 1e10, "stiffness of spring 2 per unit stroke, over Ar (table 2.9)"),
        Param("p_s2", "Pa", 400e5, 0.0, 1e9, "preload of spring 2 over Ar (pcr2 of eq. 2.4; not in the thesis)"),
        Param("wn", "rad/s", 2.0 * math.pi * 12.0, 1e-3, 1e5, "natural angular frequency of the spool response (table 2.9)"),
        Param("zeta", "1", 1.0, 0.0, 10.0, "damping ratio of the spool response (table 2.9)"),
        Param("flow_force", "1", 0.0, -5.0, 5.0,
              "scale of the steady flow force pF of eq. 3.13: 1 the thesis's fit, 0 the chapter-2 model"),
        Param("q_ff_max", "m^3/s", 100.0 / LPM, 1e-6, 1.0, "flow beyond which the pF polynomial's argument is held (its fit range)"),
        Param("V_t", "m^3", 1e-5, 1e-9, 1.0, "oil volume of the internal node pt"),
        Param("dN", "Pa", 1e5, 0.0, 1e8, "width over which the contact switch (sign of N) is rounded (regularisation)"),
        Param("u_w", "1", 0.01, 0.0, 0.25, "width of the rounded corners of the saturation of u to [0, 1] (regularisation)"),
        Param("A_leak", "m^2", 1e-9, 0.0, 1e-4, "leakage area of each closed check valve (regularisation; 1e-9 m^2: 9 ml/min at 200 bar)"),
        Param("Cd", "1", 0.7, 0.01, 1.0, "discharge coefficient of every orifice"),
        Param("dp_t", "Pa", 1e4, 1.0, 1e7, "square-root law's regularisation width (q 16 % low at dp = dp_t, 1 % at 5*dp_t)"),
    ) + fluid_params()[:1] + fluid_params()[2:]
    states = (
        State("pt", "Pa", 0.0, 1e5, "pressure of the internal node between the reliefs and the check valves 2"),
        State("u1", "1", 0.0, 1.0, "spool position of the relief valve in line 1 (C1 -> pt)"),
        State("du1", "1/s", 0.0, 10.0, "spool velocity, line 1"),
        State("u2", "1", 0.0, 1.0, "spool position of the relief valve in line 2 (C2 -> pt)"),
        State("du2", "1/s", 0.0, 10.0, "spool velocity, line 2"),
    )
    checked = ("C1.flow", "C2.flow")
    presets = {
        # table 2.8 (check valves and relief area fitted to the data-sheet flow curves); the springs and the
        # spool response (table 2.9) are measured on the VF250 only and are the block's defaults
        "VF050": {"A_prv": "15 mm^2", "A_cv1": "20.5 mm^2", "p_cv1_crack": "1 bar", "p_cv1_open": "4.2 bar",
                  "A_cv2": "20.5 mm^2", "p_cv2_crack": "0.1 bar", "p_cv2_open": "5 bar"},
        "VF150": {"A_prv": "39 mm^2", "A_cv1": "90.9 mm^2", "p_cv1_crack": "1 bar", "p_cv1_open": "3 bar",
                  "A_cv2": "90.9 mm^2", "p_cv2_crack": "0.1 bar", "p_cv2_open": "1.9 bar"},
        "VF250": {"A_prv": "72.1 mm^2", "A_cv1": "151.5 mm^2", "p_cv1_crack": "0.5 bar", "p_cv1_open": "2 bar",
                  "A_cv2": "151.5 mm^2", "p_cv2_crack": "0.1 bar", "p_cv2_open": "2.5 bar",
                  "kp1": "495 bar", "kp2": "400 bar", "wn": "12 Hz", "zeta": 1.0},
    }

    @classmethod
    def valid_ranges(cls, values: dict) -> tuple[ValidRange, ...]:
        """With the flow force on: the relief flow out of each C port within the fit's q_ff_max."""
        if values["flow_force"] == 0.0:
            return ()
        held = (f"the flow force's polynomial (eq. 3.13, fitted up to q_ff_max = {values['q_ff_max'] * LPM:.4g} "
                f"l/min of relief flow) is held at its end value")
        return tuple(ValidRange(f"{port}.flow", -values["q_ff_max"], math.inf, held) for port in ("C1", "C2"))

    @classmethod
    def parameter_warnings(cls, values: dict) -> tuple[str, ...]:
        """With the flow force on: a crack setting outside those its polynomials were fitted at."""
        lo, hi = FIT_CRACKS
        if values["flow_force"] == 0.0 or lo * (1.0 - 1e-9) <= values["p_crack"] <= hi * (1.0 + 1e-9):
            return ()
        return (f"p_crack = {values['p_crack'] / 1e5:.4g} bar is outside the crack settings the flow force was "
                f"fitted at ({lo / 1e5:g} to {hi / 1e5:g} bar, table 3.2): its polynomial for the nearest is "
                f"extrapolated",)

    @classmethod
    def check_values(cls, values):
        for k in ("1", "2"):
            if values[f"p_cv{k}_open"] <= values[f"p_cv{k}_crack"]:
                return (f"check valve {k}: p_cv{k}_open = {values[f'p_cv{k}_open']:g} Pa must exceed "
                        f"p_cv{k}_crack = {values[f'p_cv{k}_crack']:g} Pa")
        if values["u_w"] >= 0.5:
            return f"u_w = {values['u_w']:g} must be below 0.5"
        return leakage_problem(values, "A_cv1", "check valve 1") or leakage_problem(values, "A_cv2", "check valve 2")

    @staticmethod
    def derivatives(V1, V2, C1, C2, pt, u1, du1, u2, du2, alpha, p_crack, A_prv, A_cv1, p_cv1_crack,
                    p_cv1_open, A_cv2, p_cv2_crack, p_cv2_open, kp1, kp2, p_s2, wn, zeta, flow_force,
                    q_ff_max, V_t, dN, u_w, A_leak, Cd, dp_t, rho, beta):
        # check valves 1: V -> C
        q_cv1_1 = check_valve_flow(V1 - C1, A_cv1, p_cv1_crack, p_cv1_open, A_leak, Cd, rho, dp_t)
        q_cv1_2 = check_valve_flow(V2 - C2, A_cv1, p_cv1_crack, p_cv1_open, A_leak, Cd, rho, dp_t)
        # reliefs C -> pt, area from the spool positions (eqs. 2.14, 2.15)
        q_r1 = turbulent_flow(C1 - pt, A_prv * smooth_unit(u1, u_w), Cd, rho, dp_t)
        q_r2 = turbulent_flow(C2 - pt, A_prv * smooth_unit(u2, u_w), Cd, rho, dp_t)
        # check valves 2: pt -> V1 and pt -> V2 (cross-line relief)
        q_cv2_1 = check_valve_flow(pt - V1, A_cv2, p_cv2_crack, p_cv2_open, A_leak, Cd, rho, dp_t)
        q_cv2_2 = check_valve_flow(pt - V2, A_cv2, p_cv2_crack, p_cv2_open, A_leak, Cd, rho, dp_t)
        # steady flow force (eq. 3.13), scaled by flow_force (0: off, 1: the thesis's fit)
        pF1 = 0.0
        pF2 = 0.0
        if flow_force != 0.0:
            pF1 = flow_force * flow_force_pressure(q_r1, C1 - pt, p_crack, q_ff_max, dp_t)
            pF2 = flow_force * flow_force_pressure(q_r2, C2 - pt, p_crack, q_ff_max, dp_t)
        # static equilibria: line 1 piloted by p2 = V2 (eqs. 2.12/2.13), line 2 by p1 = V1 (eqs. 2.7/2.11)
        u1_eq = smooth_unit(vaa_opening_raw(C1, V2, pt, alpha, p_crack, p_s2, kp1, kp2, pF1, dN), u_w)
        u2_eq = smooth_unit(vaa_opening_raw(C2, V1, pt, alpha, p_crack, p_s2, kp1, kp2, pF2, dN), u_w)
        der_pt = beta / V_t * (q_r1 + q_r2 - q_cv2_1 - q_cv2_2)
        return (q_cv2_1 - q_cv1_1, q_cv2_2 - q_cv1_2, q_cv1_1 - q_r1, q_cv1_2 - q_r2, der_pt,
                du1, lowpass2_acceleration(u1_eq, u1, du1, wn, zeta),
                du2, lowpass2_acceleration(u2_eq, u2, du2, wn, zeta))
