"""The Parker F12/F11 bent-axis motors of the crane (thesis sections 2.5 and 2.6, table 2.13, appendix I)."""

import math

from blocks.block import Block, Param, fluid_params, hydraulic, rotational
from blocks.library.hydraulic.displacement import chamber_fill, motor_friction_band, vapour_pressure_param
from blocks.library.hydraulic.flow import turbulent_flow
from blocks.registry import register


@register("parker_motor")
class ParkerMotor(Block):
    """Parker F12/F11 motor: displacement, turbulent internal and drain leakage, friction (1 - eta_hm), inertia.

    Flows [m^3/s] (section 2.5, fig. 2.26: leakage as orifices, so it depends on inlet and back pressure):
        q_lm = Cd*A_lm*sqrt(2/rho) * (p_a - p_b)/((p_a - p_b)^2 + dp_t^2)^(1/4)        internal leakage a -> b
        q_da = Cd*A_ld*sqrt(2/rho) * (p_a - p_d)/(...)^(1/4),  q_db likewise from b    drains to port drain
        delivered: q_a = -(f*D*w + q_lm + q_da),  q_b = f*D*w + q_lm - q_db,  q_drain = q_da + q_db
        f = smooth_step(p_in, p_vap - dp_f, dp_f): the chambers' fill from p_in = p_a (w >= 0), p_b (w < 0),
        1 at and above the vapour pressure p_vap, 0 from dp_f = 0.005 bar below it (as hydraulic_motor)
    Torque on the shaft [N*m] (section 2.6, eq. 2.27 read as F_M = (1 - eta_hm)*dp*D_M/(2*pi), D_M per rev,
    i.e. (1 - eta_hm)*D*dp with D per radian; Coulomb, opposing the motion, plus the optional viscous term
    of fig. 2.31):
        tau_h = D*(p_a - p_b)   (not scaled by f: vapour-filled chambers are flooded from the outlet)
        tau = tau_h - (1 - eta_hm)*|tau_h|*tanh(w/w_w) - B_v*w
    Inertia: J_m is added to the shaft net.
    Volumetric efficiency (eq. 2.26, D_M per rev = 2*pi*D): eta_v = w*D_M/(2*pi*Q_M) = D*w/(-q_a).

    Sign convention as hydraulic_motor: p_a > p_b drives the shaft forward (w > 0), drawing oil from a and
    delivering it to b. tanh(w/w_w) smooths the sign of the Coulomb term over the declared speed width w_w
    (no stiction: section 2.1). The leakage law is the library's turbulent orifice, laminar below dp_t.

    Linearised about a point inside the friction's smoothing band, |w| < 3*w_w, the friction's slope is the
    regularisation's, (1 - eta_hm)*D*|p_a - p_b|/w_w [N*m*s/rad] through w = 0: a damper of the smoothing's size,
    where a real one at rest sticks or slips. `vphs linearise` says so.

    Presets (table 2.13 leakage areas, A_ld = 1e-4 mm^2 for all; displacement and inertia from appendix I):
    F12-030: 30 cm^3/rev, A_lm = 0.13 mm^2, J_m = 1.7e-3 kg*m^2 (appendix I; section 2.7's trolley-travel
    motor 0.0017; its bridge-travel value 0.0034 is the two F12-030 motors of that drive together).
    F12-060: 59.8 cm^3/rev (appendix I's frame-60 displacement), A_lm = 0.263 mm^2, J_m = 5.0e-3 kg*m^2
    (appendix I; section 2.7's slewing motor). F11-019: 19.0 cm^3/rev, A_lm = 0.083 mm^2; the thesis gives
    no inertia for it: J_m = 0.8e-3 kg*m^2 is an ESTIMATE scaled from the F12-030 as J ~ D^(5/3) (the same
    scaling predicts 5.4e-3 for the F12-060 against its 5.0e-3); set it when the data sheet is at hand.
    eta_hm = 0.9 for all (section 2.6).

    The volumetric efficiency these areas give at 210 bar (netlists/components/motor_volumetric_efficiency.yaml,
    all three motors alike, as section 2.5 assumes): 90 % at about 370 rpm, 95 % at 780 rpm, 98.7 % at
    3000 rpm. Section 2.5 says "about 95 % at high velocities" of fig. 2.27, to which it fitted the areas;
    the figure is missing, so the table's areas are kept, and the leakage at speed may be low by up to 4x.
    """

    ports = (
        hydraulic("a", "inlet: higher pressure here drives the shaft forward"),
        hydraulic("b", "outlet"),
        hydraulic("drain", "case drain (connect to the tank)"),
        rotational("shaft", "motor shaft", stores=True),
    )
    params = (
        Param("D", "m^3/rad", None, 0.0, 1e-2, "displacement per radian (D_M/(2*pi))"),
        Param("A_lm", "m^2", None, 0.0, 1e-3, "area of the internal leakage orifice a -> b"),
        Param("A_ld", "m^2", 1e-10, 0.0, 1e-3, "area of each drain leakage orifice (a -> drain, b -> drain)"),
        Param("J_m", "kg*m^2", None, 0.0, 10.0, "inertia of the rotating group, added to the shaft net"),
        Param("eta_hm", "1", 0.9, 0.0, 1.0, "hydro-mechanical efficiency: Coulomb friction (1 - eta_hm)*|tau_h|"),
        Param("w_w", "rad/s", 0.1, 1e-6, 1e3, "speed width over which the Coulomb friction changes sign"),
        Param("B_v", "N*m*s/rad", 0.0, 0.0, 1e6, "viscous friction coefficient on the shaft"),
        Param("Cd", "1", 0.7, 0.01, 1.0, "discharge coefficient of the leakage orifices"),
        Param("dp_t", "Pa", 1e5, 1.0, 1e7, "regularisation width of the leakage's square-root law (16 % under it at dp = dp_t)"),
    ) + fluid_params()[:1] + (vapour_pressure_param(),)
    presets = {
        "F12-030": {"D": "30 cm^3/rev", "A_lm": "0.13 mm^2", "A_ld": "1e-4 mm^2", "J_m": "1.7e-3 kg*m^2",
                    "eta_hm": 0.9},
        "F12-060": {"D": "59.8 cm^3/rev", "A_lm": "0.263 mm^2", "A_ld": "1e-4 mm^2", "J_m": "5.0e-3 kg*m^2",
                    "eta_hm": 0.9},
        "F11-019": {"D": "19.0 cm^3/rev", "A_lm": "0.083 mm^2", "A_ld": "1e-4 mm^2", "J_m": "0.8e-3 kg*m^2",
                    "eta_hm": 0.9},
    }

    regularised = ("shaft",)
    regularised_reads = ("a", "b")

    @classmethod
    def regularisations(cls, values: dict):
        """The friction's tanh band, its size from the pressures at the point (none at eta_hm = 1)."""
        return motor_friction_band(values)

    @staticmethod
    def derivatives(a, b, drain, shaft, D, A_lm, A_ld, J_m, eta_hm, w_w, B_v, Cd, dp_t, rho, p_vap):
        dp = a - b
        f = chamber_fill(a, b, shaft, p_vap)
        q_lm = turbulent_flow(dp, A_lm, Cd, rho, dp_t)
        q_da = turbulent_flow(a - drain, A_ld, Cd, rho, dp_t)
        q_db = turbulent_flow(b - drain, A_ld, Cd, rho, dp_t)
        q_m = f * D * shaft
        tau_h = D * dp
        tau = tau_h - (1.0 - eta_hm) * abs(tau_h) * math.tanh(shaft / w_w) - B_v * shaft
        return -(q_m + q_lm + q_da), q_m + q_lm - q_db, q_da + q_db, tau, J_m
