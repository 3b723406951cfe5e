"""Lower guiding arm (LGA) mechanics, thesis sections 2.8-2.9: theta1(d1), inertias, effective masses, gravity.

Not a block: numba functions (``@njit(cache=True)``, callable from Python as well) used by the blocks
`lga_jib_load` and `lga_telescope_load` and by the tests. Everything is SI (m, kg, rad, N); the thesis
prints lengths in mm. The thesis's own LGA is ``THESIS`` below (``thesis_geometry()`` packs it).

Frame and coordinates (fig. 2.34 is missing from the text; this is the reading settled on)
-------------------------------------------------------------------------------------------
- Joint A (the jib-tilt pivot) is the origin. Global X is horizontal, pointing away from the slewing
  axis; global Y is vertical and points DOWN (gravity is +g*Y). Why down: eq. 2.63 sums the moment of the
  weight, +X_G*m*g, with the moment of a cylinder force Fc1 acting along the cylinder axis B->C at angle
  theta2; with Fc1 > 0 a push (the usual meaning of a cylinder force) and moments positive about +Z this
  balance holds only with gravity along +Y. The other reading (Y up, the jib cylinder in tension) flips the
  signs of both gravity forces: pass g < 0 for it.
- theta1: angle of the main arm's local xi axis from X, positive towards +Y (the arm tilts down).
  A(theta) = [[cos, -sin], [sin, cos]] (eq. 2.44), B = dA/dtheta = [[-sin, -cos], [cos, -sin]].
- d1: jib-tilt cylinder length |BC|; C is fixed on the main arm at c = (2191, 340) mm (arm frame), B on
  the base at b = (-775, 0) mm (global).
- d2: telescope extension, the distance along the arm from A to the telescope's rear end, which is the
  origin of the telescope's local frame: R_cs2 = A1*(d2, eta_cs2), eta_cs2 = -50 mm (eq. 2.55). Eqs.
  2.48-2.49 as printed measure d2 to the telescope's tip instead ((d2 - L2/2), (L3/2 + d2)); one
  definition is used throughout here: eq. 2.55's.

Kinematics (eqs. 2.30-2.35)
---------------------------
  d1^2 = |A1*c - b|^2                                            (2.30)
       = (2191 cos t - 340 sin t + 775)^2 + (2191 sin t + 340 cos t)^2   [mm]   (2.31)
  h(theta) = d1*dd1/dtheta = (A1*c - b)^T (B1*c) = -b^T B1 c     [m^2]    (2.32)
           = C1 cos theta1 + C2 sin theta1,  C1 = -263500 mm^2, C2 = -1698025 mm^2   (2.33)
  theta1_dot = d1_dot * d1 / h(theta1)                            (2.35)
theta1 = f1(d1) (eq. 2.34, appendix D's closed form is not transcribed) is solved by a safeguarded Newton
iteration on F(theta) = d1(theta)^2 - d1^2, F' = 2h, inside a bracket [lo, hi] on which d1(theta) is
monotonic (no dead centre h = 0 inside: there the cylinder's line passes through A and the effective mass
is infinite; the thesis's dead centres are theta1 = -8.82 deg and 171.18 deg). d1 outside the bracket's
range gives the nearer end (clamped).

Local inertias (eqs. 2.36-2.43)
-------------------------------
Main arm and telescope are square tubes (side S, length L) along their local xi axis (r_m1 = (L1/2, ..)
shows xi runs along the arm). The thesis prints J_xi = J_eta = 7/24*m*S^2 + m*L/12 and J_zeta = m*S^2/3.
"m*L/12" is m*L^2/12 (units). As printed, J_zeta (the axis of jib tilt, out of the plane) would be
m*S^2/3 = 12 kg*m^2 for the 3 m, 401 kg arm, below the m*L^2/12 = 301 kg*m^2 of any 3 m beam about a
transverse axis, and the long-axis J_xi would contain L^2: the labels xi and zeta are swapped. Settled on:
  J_xi   = m*S^2/3                      (long axis; exact for a thin-walled square tube)
  J_eta  = J_zeta = 7/24*m*S^2 + m*L^2/12   (transverse axes)                  (2.36-2.41)
(With the printed labels J_A would be 515 kg*m^2 smaller: 4075 instead of 4590 kg*m^2 at theta1 = d2 = 0.)
Gripper head, a box a x b x c (a along xi, horizontal; c along eta; b out of the plane), kept horizontal:
  J3_zeta = m3*(a^2 + c^2)/12,  J3_eta = m3*(a^2 + b^2)/12                    (2.42, 2.43)
Baseplate, a disc of outer/inner RADIUS R/r (the text says diameter; the formula is the radius one):
  J4 = m4*(R^2 + r^2)/2

Centre of gravity and jib inertia J_A (eqs. 2.55-2.58)
------------------------------------------------------
  P1 = A1*r_m1,  P2 = A1*((d2, eta_cs2) + r_m2),  P3 = A1*(d2 + L2, eta_cs2) + r_m3
The gripper hangs at the telescope's tip (R_cs3, printed "R_c2": read as the tip A1*(d2 + L2, eta_cs2)) and
is horizontal (theta3 = 0, A3 = I), its centre r_m3 = (xi3, eta3) from the tip in the global frame; r_m3
is not in the text: chosen (a/2, 0), the box beginning at the tip (eq. 2.49's "L3/2").
  m_G = m1 + m2 + m3,  R_G = (m1*P1 + m2*P2 + m3*P3)/m_G                       (2.55, 2.56)
  J_G = sum_i [J_i,zeta + m_i*|R_G - P_i|^2]                                  (2.57)
  J_A = J_G + m_G*|R_G|^2   (= sum_i [J_i,zeta + m_i*|P_i|^2])                 (2.58)
J_A is eq. 2.58 as the thesis takes it, and it mixes two pictures of the gripper: its centre P3 keeps a
fixed horizontal offset from the tip (the gripper held level), yet its own J3_zeta is counted as though it
turned with the arm. A gripper held level, translating with the tip, would add m3*|tip|^2 and no J3_zeta:
against that, J_A here is 19.5 % higher at theta1 = 10 deg, 14.8 % at 45 deg and 5.6 % at 80 deg (d2 =
0.2 m), and J_A' (below) comes only from the mix. Which is right depends on what holds the gripper level,
which the thesis does not say; its effective masses and results use eq. 2.58, so eq. 2.58 is kept.

Effective masses (eqs. 2.59-2.62)
---------------------------------
  m1_eff = J_A * theta1_dot^2/d1_dot^2 = J_A * (d1/h)^2                        (2.61 with 2.35)
  m2_eff = m2 + m3                                                            (2.62)
The slope dm1_eff/dd1 (for the Lagrange term 1/2*m'(d1)*d1_dot^2 of a position-dependent mass) is
analytic: with h' = dh/dtheta = b^T A1 c and J_A' = 2*m3*r_m3 . (B1*(d2 + L2, eta_cs2)),
  dm/dtheta = J_A'*d1^2/h^2 + 2*J_A/h - 2*J_A*d1^2*h'/h^3,   dm/dd1 = dm/dtheta * d1/h.

Gravity (eqs. 2.63-2.65)
------------------------
  R_c = A1*c (A to C: "Rcx, Rcy"),  theta2 = atan2(R_cy - b_y, R_cx - b_x)   (cylinder axis B->C from X)
  0 = X_G*m_tot*g - Fc1*R_cy*cos(theta2) + Fc1*R_cx*sin(theta2)               (2.63)
  Fc1 = X_G*m_tot*g / (R_cy*cos(theta2) - R_cx*sin(theta2))                   (2.64)
m_tot = m1 + m2 + m3 (printed "m1 + m2 + m4": the baseplate m4 does not tilt and eq. 2.55's X_G is the
centre of parts 1-3). Fc1 > 0 pushes (compresses the cylinder, acting against its extension). It equals
the virtual-work form m_tot*g*X_G*d1/(-h), i.e. the gripper's weight acts on the arm at its centre, as
for a gripper fixed to it (or levelled by a cylinder that reacts on the arm). A gripper levelled by a
linkage to the base, translating with the tip, would give m_tot*g*(dY_G/dtheta)*d1/h instead: Fc1 here
is 9.5 % higher at theta1 = 45 deg and 41 % at 80 deg (d2 = 0.2 m). The thesis's eq. 2.64 is kept.
  Fc2 = sin(theta1)*(m2 + m3)*g                                               (2.65)
Fc2 > 0 pulls the telescope out (along +xi: its extension direction) for theta1 in (0, pi).

Slewing and trolley (eqs. 2.44-2.54)
------------------------------------
  J_i,Y = J_i,xi*sin^2(theta1) + J_i,eta*cos^2(theta1)                         (2.46)
  J_S = sum_{i=1,2} [m_i*(e + X_i)^2 + J_i,Y] + m3*(e + X_3)^2 + J3_eta + J4   (2.47-2.51)
with X_i the horizontal coordinates of P_i above (the printed 2.47-2.49 use L1/2*cos(theta1) etc., i.e. the
same centres without the small eta offsets). e, the distance from joint A to the slewing axis, is not
given numerically in the text: THESIS["e"] = 0.6 m is a CHOICE (the baseplate's inner radius).
Its slopes, for the rate dJ_S/dt = dJ_S/dtheta1*theta1_dot + dJ_S/dd2*d2_dot (block lga_slewing_load):
with dX_i/dtheta1 = -Y_i (the arm-fixed centres; for the gripper -(Y_3 - eta3): its offset stays level)
and dX_2/dd2 = dX_3/dd2 = cos(theta1),
  dJ_S/dtheta1 = -2*[m1*(e + X_1)*Y_1 + m2*(e + X_2)*Y_2 + m3*(e + X_3)*(Y_3 - eta3)]
                 + (J1_xi - J1_eta + J2_xi - J2_eta)*sin(2*theta1)
  dJ_S/dd2     = 2*cos(theta1)*[m2*(e + X_2) + m3*(e + X_3)]
  n_tot = n_g*D_irg/d_p                                                       (2.52)
  J_sm = J_S/n_tot^2  (+ J_m + J_g of the motor and gearbox, which belong to them)   (2.53)
  J_tt = m_tt*r_p^2/n_g^2   (+ J_m + J_g)                                     (2.54)
Eq. 2.54 prints r_p^2/n_g; both forms have the unit kg*m^2 (n_g is dimensionless), but the kinetic energy
1/2*m*v^2 with v = r_p*w_motor/n_g gives n_g^2, as eq. 2.28 has it: n_g^2 is used.
"""

from __future__ import annotations

import math
from collections import namedtuple

from numba import njit

LGA = namedtuple("LGA", "cx cy bx by m1 xi1 eta1 S1 L1 m2 xi2 eta2 S2 L2 eta_cs2 m3 xi3 eta3 a3 b3 c3")
LGA.__doc__ = """The LGA's geometry and masses (SI): joint C in the arm frame (cx, cy), joint B global (bx, by);
main arm m1, centre (xi1, eta1), side S1, length L1; telescope m2, centre (xi2, eta2) in its own frame, side
S2, length L2, frame offset eta_cs2 across the arm; gripper m3, centre (xi3, eta3) from the telescope tip
(horizontal frame), box a3 (along xi) x b3 (out of plane) x c3 (along eta)."""

# The thesis's LGA (section 2.8), SI. "chosen" marks values the text does not give.
THESIS = {
    "cx": 2.191, "cy": 0.340, "bx": -0.775, "by": 0.0,                     # eq. 2.30
    "m1": 401.3, "xi1": 1.5, "eta1": 0.05, "S1": 0.300, "L1": 3.0,         # part 1, main arm
    "m2": 265.2, "xi2": 1.565, "eta2": 0.075, "S2": 0.250, "L2": 3.13,     # part 2, telescope ("1565 m": mm)
    "eta_cs2": -0.050,                                                     # R_cs2 = A1*(d2, -50 mm)
    "m3": 175.2, "xi3": 0.63, "eta3": 0.0,                                 # part 3, gripper; xi3 = a/2 chosen
    "a3": 1.26, "b3": 0.40, "c3": 0.43,
    "m4": 362.0, "R4": 1.2, "r4": 0.6,                                     # part 4, baseplate (radii)
    "e": 0.6,                                                              # chosen: not in the text
    "m_tt": 1500.0, "r_p": 0.110, "n_g_tt": 39.1,                          # trolley travel, eq. 2.54
    "g": 9.81,
}


def thesis_geometry() -> LGA:
    """The thesis's LGA packed for the functions below."""
    return LGA(*(float(THESIS[name]) for name in LGA._fields))


_NEWTON_MAX = 80  # iterations; each failed Newton step falls back to bisection, so 80 always suffices
_NEWTON_STEP = 1e-15  # [rad] stop when a Newton step is this small (round-off level of theta ~ 1 rad)


# ---------------------------------------------------------------- kinematics
@njit(cache=True)
def cylinder_length(theta, g):
    """d1(theta1) = |A1*c - b| [m] (eq. 2.31)."""
    c, s = math.cos(theta), math.sin(theta)
    dx = g.cx * c - g.cy * s - g.bx
    dy = g.cx * s + g.cy * c - g.by
    return math.sqrt(dx * dx + dy * dy)


@njit(cache=True)
def lever(theta, g):
    """h = d1*dd1/dtheta1 = -b^T B1 c [m^2] (eqs. 2.32-2.33: C1 cos + C2 sin for the thesis's LGA)."""
    c, s = math.cos(theta), math.sin(theta)
    return -(g.bx * (-g.cx * s - g.cy * c) + g.by * (g.cx * c - g.cy * s))


@njit(cache=True)
def lever_slope(theta, g):
    """dh/dtheta1 = b^T A1 c [m^2]."""
    c, s = math.cos(theta), math.sin(theta)
    return g.bx * (g.cx * c - g.cy * s) + g.by * (g.cx * s + g.cy * c)


@njit(cache=True)
def theta1_from_d1(d1, g, lo, hi):
    """theta1 [rad] with cylinder_length(theta1) = d1, inside the bracket [lo, hi] (eq. 2.34 solved numerically).

    d1(theta) must be monotonic on [lo, hi] (no dead centre inside). Newton on F = d1(theta)^2 - d1^2 with
    F' = 2h, started by regula falsi; a step leaving the shrinking bracket is replaced by bisection. A d1
    outside [d1(lo), d1(hi)] returns the nearer end (clamped)."""
    target = d1 * d1
    f_lo = cylinder_length(lo, g) ** 2 - target
    f_hi = cylinder_length(hi, g) ** 2 - target
    if f_lo == 0.0:
        return lo
    if f_hi == 0.0:
        return hi
    if (f_lo > 0.0) == (f_hi > 0.0):
        return lo if abs(f_lo) < abs(f_hi) else hi
    a, b, fa = lo, hi, f_lo
    theta = lo + (hi - lo) * f_lo / (f_lo - f_hi)
    for _ in range(_NEWTON_MAX):
        f = cylinder_length(theta, g) ** 2 - target
        if f == 0.0:
            return theta
        if (f > 0.0) == (fa > 0.0):
            a, fa = theta, f
        else:
            b = theta
        slope = 2.0 * lever(theta, g)
        new = theta - f / slope if slope != 0.0 else 0.5 * (a + b)
        if not (min(a, b) < new < max(a, b)):
            new = 0.5 * (a + b)
        if abs(new - theta) <= _NEWTON_STEP:
            return new
        theta = new
    return theta


@njit(cache=True)
def theta1_dot(d1, d1_dot, theta, g):
    """theta1_dot = d1_dot*d1/h(theta1) [rad/s] (eq. 2.35)."""
    return d1_dot * d1 / lever(theta, g)


@njit(cache=True)
def jib_pose(d1, g, lo, hi):
    """(theta1, d1, k1) for a cylinder length d1: theta1 solved in [lo, hi] and k1 = dtheta1/dd1 = d1/h
    [rad/m]; outside the range theta1 is clamped to the nearer end, d1 is the end's own length and k1 = 0
    (the jib does not turn)."""
    theta = theta1_from_d1(d1, g, lo, hi)
    if lo < theta < hi:
        return theta, d1, theta1_dot(d1, 1.0, theta, g)
    return theta, cylinder_length(theta, g), 0.0


def dead_centres(g) -> tuple[float, float]:
    """The two angles in (-pi, pi] where h = 0 (the cylinder's line passes through A), ascending [rad]."""
    p = g.bx * g.cx + g.by * g.cy  # h = p*sin(theta) + q*cos(theta)
    q = g.bx * g.cy - g.by * g.cx
    psi = math.atan2(p, q)  # h = hypot(p, q)*cos(theta - psi)
    zeros = [math.remainder(psi + k * math.pi / 2.0, 2.0 * math.pi) for k in (-1, 1)]
    return tuple(sorted(zeros))


# ---------------------------------------------------------------- local inertias
@njit(cache=True)
def tube_inertias(m, S, L):
    """(J_xi, J_trans) of a square tube of side S and length L along xi [kg*m^2] (eqs. 2.36-2.41 as settled).

    J_xi = m*S^2/3 about the long axis; J_eta = J_zeta = 7/24*m*S^2 + m*L^2/12 about the transverse axes."""
    return m * S * S / 3.0, 7.0 / 24.0 * m * S * S + m * L * L / 12.0


@njit(cache=True)
def box_inertias(m, a, b, c):
    """(J_zeta, J_eta) of the gripper box [kg*m^2]: m*(a^2 + c^2)/12, m*(a^2 + b^2)/12 (eqs. 2.42-2.43)."""
    return m * (a * a + c * c) / 12.0, m * (a * a + b * b) / 12.0


@njit(cache=True)
def disc_inertia(m, R, r):
    """Baseplate about the slewing axis: m*(R^2 + r^2)/2 [kg*m^2], R and r the outer and inner radii."""
    return m * (R * R + r * r) / 2.0


# ---------------------------------------------------------------- centres and jib inertia
@njit(cache=True)
def mass_centres(theta, d2, g):
    """Global mass centres (X1, Y1, X2, Y2, X3, Y3) of main arm, telescope and gripper [m] (eq. 2.55 terms)."""
    c, s = math.cos(theta), math.sin(theta)
    x1, y1 = g.xi1 * c - g.eta1 * s, g.xi1 * s + g.eta1 * c
    u2, w2 = d2 + g.xi2, g.eta_cs2 + g.eta2
    x2, y2 = u2 * c - w2 * s, u2 * s + w2 * c
    ut, wt = d2 + g.L2, g.eta_cs2  # the telescope's tip, where the gripper hangs
    x3, y3 = ut * c - wt * s + g.xi3, ut * s + wt * c + g.eta3
    return x1, y1, x2, y2, x3, y3


@njit(cache=True)
def centre_of_gravity(theta, d2, g):
    """(X_G, Y_G, m_G) of parts 1-3 [m, m, kg] (eqs. 2.55-2.56)."""
    x1, y1, x2, y2, x3, y3 = mass_centres(theta, d2, g)
    m = g.m1 + g.m2 + g.m3
    return (g.m1 * x1 + g.m2 * x2 + g.m3 * x3) / m, (g.m1 * y1 + g.m2 * y2 + g.m3 * y3) / m, m


@njit(cache=True)
def jib_inertia(theta, d2, g):
    """J_A, the inertia of parts 1-3 about joint A (Z axis) [kg*m^2] (eqs. 2.57-2.58)."""
    x1, y1, x2, y2, x3, y3 = mass_centres(theta, d2, g)
    xg, yg, m = centre_of_gravity(theta, d2, g)
    j1 = tube_inertias(g.m1, g.S1, g.L1)[1]
    j2 = tube_inertias(g.m2, g.S2, g.L2)[1]
    j3 = box_inertias(g.m3, g.a3, g.b3, g.c3)[0]
    jg = (j1 + g.m1 * ((xg - x1) ** 2 + (yg - y1) ** 2)
          + j2 + g.m2 * ((xg - x2) ** 2 + (yg - y2) ** 2)
          + j3 + g.m3 * ((xg - x3) ** 2 + (yg - y3) ** 2))
    return jg + m * (xg * xg + yg * yg)


@njit(cache=True)
def jib_inertia_slope(theta, d2, g):
    """dJ_A/dtheta1 [kg*m^2/rad]: only the horizontal gripper's offset from the tip moves relative to A."""
    c, s = math.cos(theta), math.sin(theta)
    ut, wt = d2 + g.L2, g.eta_cs2
    return 2.0 * g.m3 * (g.xi3 * (-ut * s - wt * c) + g.eta3 * (ut * c - wt * s))


@njit(cache=True)
def jib_effective_mass(theta, d1, d2, g):
    """m1_eff = J_A*(theta1_dot/d1_dot)^2 = J_A*(d1/h)^2 [kg] (eq. 2.61)."""
    k = d1 / lever(theta, g)
    return jib_inertia(theta, d2, g) * k * k


@njit(cache=True)
def jib_effective_mass_slope(theta, d1, d2, g):
    """dm1_eff/dd1 [kg/m] at fixed d2 (analytic; see the module docstring)."""
    h = lever(theta, g)
    hp = lever_slope(theta, g)
    ja = jib_inertia(theta, d2, g)
    dm_dtheta = jib_inertia_slope(theta, d2, g) * d1 * d1 / (h * h) + 2.0 * ja / h - 2.0 * ja * d1 * d1 * hp / h ** 3
    return dm_dtheta * d1 / h


# ---------------------------------------------------------------- gravity
@njit(cache=True)
def cylinder_angle(theta, g):
    """theta2, the angle of the jib cylinder's axis B->C from X [rad]."""
    c, s = math.cos(theta), math.sin(theta)
    return math.atan2(g.cx * s + g.cy * c - g.by, g.cx * c - g.cy * s - g.bx)


@njit(cache=True)
def jib_gravity_force(theta, d2, grav, g):
    """Fc1 [N], > 0 compresses the jib cylinder (eq. 2.64); grav is the gravity along +Y (down) [m/s^2]."""
    c, s = math.cos(theta), math.sin(theta)
    rcx, rcy = g.cx * c - g.cy * s, g.cx * s + g.cy * c
    t2 = cylinder_angle(theta, g)
    xg, _, m = centre_of_gravity(theta, d2, g)
    return xg * m * grav / (rcy * math.cos(t2) - rcx * math.sin(t2))


@njit(cache=True)
def telescope_gravity_force(theta, m2, m3, grav):
    """Fc2 = sin(theta1)*(m2 + m3)*g [N], > 0 pulls the telescope out (eq. 2.65)."""
    return math.sin(theta) * (m2 + m3) * grav


# ---------------------------------------------------------------- slewing and trolley
@njit(cache=True)
def slewing_inertia(theta, d2, e, J4, g):
    """J_S about the slewing axis [kg*m^2] (eqs. 2.46-2.51); e: joint A to the slewing axis [m], J4: baseplate."""
    x1, _, x2, _, x3, _ = mass_centres(theta, d2, g)
    s2, c2 = math.sin(theta) ** 2, math.cos(theta) ** 2
    j1xi, j1eta = tube_inertias(g.m1, g.S1, g.L1)
    j2xi, j2eta = tube_inertias(g.m2, g.S2, g.L2)
    j3eta = box_inertias(g.m3, g.a3, g.b3, g.c3)[1]
    return (g.m1 * (e + x1) ** 2 + j1xi * s2 + j1eta * c2
            + g.m2 * (e + x2) ** 2 + j2xi * s2 + j2eta * c2
            + g.m3 * (e + x3) ** 2 + j3eta + J4)


@njit(cache=True)
def slewing_inertia_slopes(theta, d2, e, g):
    """(dJ_S/dtheta1 [kg*m^2/rad], dJ_S/dd2 [kg*m]), analytic (see the module docstring); J4 is constant."""
    c, s = math.cos(theta), math.sin(theta)
    x1, y1, x2, y2, x3, y3 = mass_centres(theta, d2, g)
    j1xi, j1eta = tube_inertias(g.m1, g.S1, g.L1)
    j2xi, j2eta = tube_inertias(g.m2, g.S2, g.L2)
    # dX_i/dtheta = -Y_i (the centres turn with the arm; the gripper's own offset eta3 does not)
    d_theta = (-2.0 * (g.m1 * (e + x1) * y1 + g.m2 * (e + x2) * y2 + g.m3 * (e + x3) * (y3 - g.eta3))
               + (j1xi - j1eta + j2xi - j2eta) * 2.0 * s * c)
    d_d2 = 2.0 * c * (g.m2 * (e + x2) + g.m3 * (e + x3))  # dX_2/dd2 = dX_3/dd2 = cos(theta1)
    return d_theta, d_d2


@njit(cache=True)
def slewing_ratio(n_g, D_irg, d_p):
    """n_tot = n_g*D_irg/d_p, motor shaft to slewing axis (eq. 2.52)."""
    return n_g * D_irg / d_p


@njit(cache=True)
def reflected_inertia(J, n):
    """J/n^2: an inertia seen through the reduction n on the motor shaft [kg*m^2] (eq. 2.53 without J_m, J_g)."""
    return J / (n * n)


@njit(cache=True)
def trolley_inertia(m_tt, r_p, n_g):
    """m_tt*r_p^2/n_g^2 on the motor shaft [kg*m^2] (eq. 2.54 with n_g^2, without J_m, J_g)."""
    return m_tt * r_p * r_p / (n_g * n_g)
