"""Three-phase induction motor as a prime mover (Kloss's torque-speed curve)."""

from blocks.block import Block, Param, rotational
from blocks.registry import register


@register("induction_motor")
class InductionMotor(Block):
    """Three-phase induction motor on a shaft, by Kloss's torque-speed curve; stores its rotor inertia.

    s = (w_sync - w)/w_sync                     slip [1]
    tau = 2*T_b*s*s_b/(s^2 + s_b^2)             torque on the shaft [N*m]
    J_shaft = J_r                               inertia added to the shaft net [kg*m^2]

    This is Kloss's tau = 2*T_b/(s/s_b + s_b/s) written so that it is smooth through s = 0. The torque is
    T_b (the breakdown, or pull-out, torque: the largest) at s = s_b, zero at synchronous speed, and
    2*T_b*s_b/(1 + s_b^2) at standstill (the starting torque, s = 1); near synchronous speed it is
    ~ 2*T_b*s/s_b, a stiff droop of the speed with the load. Sign convention: w > 0 is the motor's
    direction of rotation and tau the torque it applies to the shaft net. Above synchronous speed (s < 0,
    the load overrunning the motor) the torque is negative: the machine generates, braking the shaft with
    up to T_b at s = -s_b; below standstill (w < 0, s > 1: plugging) it still drives forward.

    From a data sheet: w_sync = 2*pi*f/(pole pairs) (1500 rpm for four poles at 50 Hz); with the rated slip
    s_N = (w_sync - w_N)/w_sync and the breakdown ratio k = T_b/T_N (T_N = P_N/w_N), Kloss at the rated
    point gives s_b = s_N*(k + sqrt(k^2 - 1)). Fitted so to the rated and breakdown points, Kloss's curve
    gives too little starting torque for a cage motor (deep rotor bars raise it: data sheets give 1.5 to
    2.5 T_N, Kloss about 0.8 T_N for k = 2.8, s_N = 0.027), so a direct-on-line start takes longer here
    than on the machine; the running range, s <= s_b, is where it holds. Left out: the electrical transients (the torque pulsations of
    a direct-on-line start), the stator resistance (which makes the generating breakdown torque larger
    than the motoring one), magnetic saturation and the supply's voltage drop.
    """

    ports = (rotational("shaft", "motor shaft (w > 0 the motor's direction of rotation)", stores=True),)
    params = (
        Param("w_sync", "rad/s", None, 0.0, 1e5, "synchronous speed (2*pi*f/pole pairs; 1500 rpm = 157.08 rad/s)",
              positive=True),
        Param("T_b", "N*m", None, 0.0, 1e7, "breakdown (pull-out) torque, the largest torque", positive=True),
        Param("s_b", "1", None, 0.0, 1.0, "breakdown slip, the slip at which the torque is T_b", positive=True),
        Param("J_r", "kg*m^2", None, 0.0, 1e4, "rotor inertia, added to the shaft net"),
    )

    @staticmethod
    def derivatives(shaft, w_sync, T_b, s_b, J_r):
        s = (w_sync - shaft) / w_sync
        return 2.0 * T_b * s * s_b / (s * s + s_b * s_b), J_r
