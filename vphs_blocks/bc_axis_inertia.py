"""Bridge-crane axis inertia on the motor shaft (thesis section 2.7, table 2.14)."""

from blocks.block import Block, Param, rotational
from blocks.registry import register

@register("bc_axis_inertia")
class BcAxisInertia(Block):
    """Effective inertia of a bridge-crane axis on its motor shaft: J = J0 + m_L*r^2/n_g^2 (eqs. 2.28-2.29).

    J_shaft = J0 + m_L*r^2/n_g^2   [kg*m^2],   tau_shaft = 0

    Bridge and trolley travel (eq. 2.28, rack and pinion): J_m = (m + m_L)*r^2/n_g^2, r the pinion radius,
    n_g the gearbox ratio; the structure's own part m*r^2/n_g^2 is J0 as table 2.14 gives it.
    Slewing (eq. 2.29): J_m = 1/2*m*r_S^2/n_G^2 + m_L*r_tp^2/n_G^2: the guide mast a cylinder of radius
    r_S = 0.8 m (its part is J0), the load a point mass at the tool-point radius r = r_tp = 2.1 m, and
    n_G = 44.6*1200/132 = 405.45 (gearbox x ring gear / pinion). Presets, from table 2.14:

      preset          J0 [kg*m^2]  r        n_g     structure m [kg]  m*r^2/n^2 (slewing 1/2*m*r_S^2/n^2)
      bridge_travel   0.085        75 mm    39.0    22997             0.0851
      trolley_travel  0.027        55 mm    38.4    13006             0.0267
      slewing         0.011        2.1 m    405.45  5741              0.0112
      lga_trolley_travel  m_tt*r_p^2/n_g^2 = 1500 kg*(55 mm)^2/39.1^2 = 0.002968 (eq. 2.54 with n_g^2;
                          section 2.8.5's printed r_p = 110 mm read as the pinion's diameter: table 2.3's
                          78 l/min through the 19 cm^3/rev motor gives its 600 mm/s only with r_p = 54.6 mm)

    J0 agrees with the table's masses to the table's last digit. The motor's own inertia (J_m,mBT =
    0.0034, J_m,mTT = 0.0017, J_m,mS = 0.005 kg*m^2) belongs to the motor block, not here. The load m_L (the
    pipe) is a parameter without default: say what the axis carries (0 for none).
    """

    ports = (rotational("shaft", "the motor shaft net carrying this inertia", stores=True),)
    params = (
        Param("J0", "kg*m^2", None, 0.0, 1e6, "the axis structure's inertia on the motor shaft (table 2.14)"),
        Param("m_L", "kg", None, 0.0, 1e7, "load (pipe) mass carried by the axis"),
        Param("r", "m", None, 0.0, 100.0, "pinion radius (travel) or tool-point radius r_tp (slewing)"),
        Param("n_g", "1", None, 1e-6, 1e6, "reduction motor shaft -> pinion (travel) or -> slewing axis"),
    )
    presets = {
        "bridge_travel": {"J0": "0.085 kg*m^2", "r": "75 mm", "n_g": 39.0},
        "trolley_travel": {"J0": "0.027 kg*m^2", "r": "55 mm", "n_g": 38.4},
        "slewing": {"J0": "0.011 kg*m^2", "r": "2.1 m", "n_g": "44.6*1200/132"},
        "lga_trolley_travel": {"J0": "1500*0.055**2/39.1**2", "r": "55 mm", "n_g": 39.1},
    }

    @staticmethod
    def derivatives(J0, m_L, r, n_g):
        return 0.0, J0 + m_L * r * r / (n_g * n_g)
