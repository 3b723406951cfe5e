"""Ideal angular speed source driven by a signal."""

from blocks.block import Block, rotational, signal_in
from blocks.registry import register


@register("speed_source")
class SpeedSource(Block):
    """Ideal angular speed source: the shaft net at ``port`` turns at the signal speed w whatever the torque.

    w_port = w   [rad/s]  (the net then has no speed state of its own; w = 0 fixes it to the frame)

    The torque it delivers, logged as ``<name>.port.torque`` [N*m], is what makes the rigid body follow w:

    tau = J*dw/dt - sum(r_k*tau_k)

    J = sum(r_k^2*J_k) the body's inertia and tau_k the torques the other blocks deliver to its nets
    (r_k the speed ratio of net k to this net through gears), so tau > 0 drives the net in its positive
    direction (a prime mover turning a pump at constant speed delivers minus the pump's shaft torque).
    It is computed where it is logged, not by the solver: dw/dt is the rate of w along the solution, a
    central difference over h = 1e-6*max(1, |t|) s (blocks/compiler/codegen.py). A sample on a kink of w
    (a ramp's start) gets the mean of the two rates; one within h of a jump of w (a step), where the
    torque is an impulse, gets J*jump/(2h), a number with no meaning.
    """

    ports = (rotational("port", "the shaft net driven at speed w"), signal_in("w", "prescribed speed", "rad/s"))
    prescribes = ("port",)

    @staticmethod
    def outputs(w):
        return (w,)
