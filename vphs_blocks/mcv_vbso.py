"""The VBSO-DE-CC over-centre valve of the lower guiding arm's jib tilt and telescope (thesis section 2.4.3)."""

import math

from blocks.block import Block, Param, State, fluid_params, hydraulic
from blocks.library.hydraulic.flow import leakage_problem, smooth_max0, turbulent_flow
from blocks.library.signal.linear import lowpass2_acceleration
from blocks.registry import register
from vphs_blocks.mcv_vaa import check_valve_flow, smooth_unit


@register("mcv_vbso")
class OverCentreValveVBSO(Block):
    """VBSO-DE-CC over-centre valve: per line a check valve V->C parallel to a relief C->V piloted across, 2nd-order spools.

    Pressures: pv1 = p_V1, pv2 = p_V2, pc1 = p_C1, pc2 = p_C2. Line 1 is V1/C1, line 2 is V2/C2.

    Hydraulics (fig. 2.23: "one check valve in parallel with each relief valve"; no internal node):
        check valve, line i:  V_i -> C_i   A = A_leak + (A_cv - A_leak)*smooth_step(dp, p_cv_crack, p_cv_open - p_cv_crack)
                              (A_leak <= A_cv, checked when the values are set)
        relief valve, line i: C_i -> V_i   a_i = A_prv*sat(u_i)                                 (eqs. 2.24, 2.25)
        every orifice:        q = Cd*A*sqrt(2/rho) * dp/(dp^2 + dp_t^2)^(1/4)
    Delivered to the nets: q_V_i = q_r,i - q_cv,i, q_C_i = q_cv,i - q_r,i (the valve stores no oil).

    Spool equilibrium (section 2.4.3; forces over the ring area Ar, springs in Pa per unit stroke). One mid
    piston between the two reliefs carries the pilot force
        N = alpha*Ar*(pv1 - pv2)                                                       (2.16)
    N > 0 pushes on relief 2 (contact there, none at relief 1); N < 0 pushes on relief 1:
        line 2, N <= 0:  u2 = (-pv2 + pc2 - pcr2)/kp2                                   (2.19)
        line 2, N >  0:  u2 = (alpha*pv1 - pv2*(alpha + 1) - pcr2 + pc2)/kp2            (2.21)
        line 1, N >= 0:  u1 = (-pv1 + pc1 - pcr1)/kp1                                   (2.22)
        line 1, N <  0:  u1 = (alpha*pv2 - pv1*(alpha + 1) - pcr1 + pc1)/kp1            (2.23)
    The branches meet at pv1 = pv2, so with smax = max(., 0) rounded over |x| < dN/2:
        u2_eq = sat( (pc2 - pv2 - pcr2 + alpha*smax(pv1 - pv2, dN))/kp2 )
        u1_eq = sat( (pc1 - pv1 - pcr1 + alpha*smax(pv2 - pv1, dN))/kp1 )
    sat = clip to [0, 1] with corners rounded over u_w (exact in [u_w, 1 - u_w], exactly 0 for u <= 0).
    Spool dynamics: u_i'' = wn^2*(u_eq,i - u_i) - 2*zeta*wn*u_i' (table 2.11: 30 Hz, zeta = 1, kp = 900
    bar/unit, "temporary values" not measured; the defaults).

    Parameters: table 2.10 (VBSO-DE-CC-05.42.05-10-04-35: A_prv 43 mm^2, check valve crack 0.5 bar, full
    open 2.2 bar, area 82 mm^2) as the defaults and the preset; the crack settings p_crack1, p_crack2 and
    the pilot ratio are per installation (table 2.5: jib tilt 3.2, 100/230 bar; telescope 3.2, 100/140 bar).
    Data sheet (app. H, text of section 2.4.3): 140 l/min at 26 bar across the open relief, 140 l/min at
    7 bar through the check valve, crack 0.5 bar.
    """

    ports = (
        hydraulic("V1", "valve side, line 1 (from the directional valve)"),
        hydraulic("V2", "valve side, line 2"),
        hydraulic("C1", "actuator side, line 1"),
        hydraulic("C2", "actuator side, line 2"),
    )
    params = (
        Param("alpha", "1", None, 0.1, 50.0, "pilot ratio (table 2.5: per installation)"),
        Param("p_crack1", "Pa", None, 0.0, 1e9, "crack setting pcr1 of the relief in line 1, C1 -> V1 (table 2.5)"),
        Param("p_crack2", "Pa", None, 0.0, 1e9, "crack setting pcr2 of the relief in line 2, C2 -> V2 (table 2.5)"),
        Param("A_prv", "m^2", 43e-6, 0.0, 1e-2, "maximum discharge area of each relief valve (table 2.10)"),
        Param("A_cv", "m^2", 82e-6, 0.0, 1e-2, "fully open area of each check valve (table 2.10)"),
        Param("p_cv_crack", "Pa", 0.5e5, 0.0, 1e8, "crack pressure of the check valves (table 2.10)"),
        Param("p_cv_open", "Pa", 2.2e5, 0.0, 1e8, "full-open pressure of the check valves (table 2.10), > crack"),
        Param("kp1", "Pa", 900e5, 1.0, 1e10, "spring stiffness of relief 1 per unit stroke, over Ar (table 2.11)"),
        Param("kp2", "Pa", 900e5, 1.0, 1e10, "spring stiffness of relief 2 per unit stroke, over Ar (table 2.11)"),
        Param("wn", "rad/s", 2.0 * math.pi * 30.0, 1e-3, 1e5, "natural angular frequency of the spool response (table 2.11)"),
        Param("zeta", "1", 1.0, 0.0, 10.0, "damping ratio of the spool response (table 2.11)"),
        Param("dN", "Pa", 1e5, 0.0, 1e8, "width in pv1 - pv2 over which the contact switch is rounded (regularisation)"),
        Param("u_w", "1", 0.01, 0.0, 0.25, "width of the rounded corners of the saturation of u to [0, 1] (regularisation)"),
        Param("A_leak", "m^2", 1e-9, 0.0, 1e-4, "leakage area of each closed check valve (regularisation; 1e-9 m^2: 9 ml/min at 200 bar)"),
        Param("Cd", "1", 0.7, 0.01, 1.0, "discharge coefficient of every orifice"),
        Param("dp_t", "Pa", 1e4, 1.0, 1e7, "square-root law's regularisation width (q 16 % low at dp = dp_t, 1 % at 5*dp_t)"),
    ) + fluid_params()[:1]
    states = (
        State("u1", "1", 0.0, 1.0, "spool position of the relief valve in line 1 (C1 -> V1)"),
        State("du1", "1/s", 0.0, 10.0, "spool velocity, line 1"),
        State("u2", "1", 0.0, 1.0, "spool position of the relief valve in line 2 (C2 -> V2)"),
        State("du2", "1/s", 0.0, 10.0, "spool velocity, line 2"),
    )
    presets = {
        # tables 2.10 and 2.11 (the block's defaults, spelled out)
        "05.42.05-10-04-35": {"A_prv": "43 mm^2", "A_cv": "82 mm^2", "p_cv_crack": "0.5 bar",
                              "p_cv_open": "2.2 bar", "kp1": "900 bar", "kp2": "900 bar", "wn": "30 Hz",
                              "zeta": 1.0},
    }

    @classmethod
    def check_values(cls, values):
        if values["p_cv_open"] <= values["p_cv_crack"]:
            return (f"p_cv_open = {values['p_cv_open']:g} Pa must exceed p_cv_crack = "
                    f"{values['p_cv_crack']:g} Pa")
        if values["u_w"] >= 0.5:
            return f"u_w = {values['u_w']:g} must be below 0.5"
        return leakage_problem(values, "A_cv", "check valve")

    @staticmethod
    def derivatives(V1, V2, C1, C2, u1, du1, u2, du2, alpha, p_crack1, p_crack2, A_prv, A_cv, p_cv_crack,
                    p_cv_open, kp1, kp2, wn, zeta, dN, u_w, A_leak, Cd, dp_t, rho):
        q_cv1 = check_valve_flow(V1 - C1, A_cv, p_cv_crack, p_cv_open, A_leak, Cd, rho, dp_t)
        q_cv2 = check_valve_flow(V2 - C2, A_cv, p_cv_crack, p_cv_open, A_leak, Cd, rho, dp_t)
        q_r1 = turbulent_flow(C1 - V1, A_prv * smooth_unit(u1, u_w), Cd, rho, dp_t)
        q_r2 = turbulent_flow(C2 - V2, A_prv * smooth_unit(u2, u_w), Cd, rho, dp_t)
        u1_eq = smooth_unit((C1 - V1 - p_crack1 + alpha * smooth_max0(V2 - V1, dN)) / kp1, u_w)
        u2_eq = smooth_unit((C2 - V2 - p_crack2 + alpha * smooth_max0(V1 - V2, dN)) / kp2, u_w)
        return (q_r1 - q_cv1, q_r2 - q_cv2, q_cv1 - q_r1, q_cv2 - q_r2,
                du1, lowpass2_acceleration(u1_eq, u1, du1, wn, zeta),
                du2, lowpass2_acceleration(u2_eq, u2, du2, wn, zeta))
