"""Double-acting hydraulic cylinder."""

from blocks.block import Block, Param, State, hydraulic, signal_out, translational
from blocks.library.hydraulic.flow import smooth_step
from blocks.registry import register


@register("cylinder")
class Cylinder(Block):
    """Double-acting cylinder: chambers A (piston side) and B (rod side), piston position x with end stops.

    V_A = V0_A + A_A*xc,  V_B = V0_B + A_B*(stroke - xc),  xc = min(max(x, 0), stroke)   [m^3]
    q_A = -A_A*v,  q_B = +A_B*v                                                            [m^3/s]
    f_rod = p_A*A_A - p_B*A_B + f_stop                                                     [N]
    dx/dt = v,  position = x   [m]   (a signal, for a position controller)

    End stops outside [0, stroke]: with penetration d (= -x below 0, x - stroke above the stroke),
    f_stop = max(0, k_stop*d - c_stop*v*smooth_step(d, 0, dx_stop))    below 0
    f_stop = min(0, -k_stop*d - c_stop*v*smooth_step(d, 0, dx_stop))   above the stroke
    the spring pushing back into the stroke and the damping faded in over the declared penetration dx_stop
    so the force stays continuous at contact; f_stop = 0 inside the stroke. A stop can only push: while the
    piston leaves it faster than the spring relaxes (v > k_stop/c_stop*d), the damping would pull the
    piston back into it, and the force is 0 instead.

    Sign convention: x and v = rod velocity are positive when the rod extends (chamber A grows). The
    chambers are the capacities this block stores on nets A and B; the flows are what the moving piston
    delivers to them (extending draws oil into A and pushes it out of B). f_rod acts on the rod's net.
    """

    ports = (
        hydraulic("A", "piston-side chamber", stores=True),
        hydraulic("B", "rod-side chamber", stores=True),
        translational("rod", "piston rod (v > 0 extends)"),
        signal_out("position", "piston position x from the retracted end (the state)", "m"),
    )
    params = (
        Param("A_A", "m^2", None, 0.0, 10.0, "piston-side effective area"),
        Param("A_B", "m^2", None, 0.0, 10.0, "rod-side (annulus) effective area"),
        Param("stroke", "m", None, 1e-6, 100.0, "stroke length"),
        Param("V0_A", "m^3", None, 1e-12, 10.0, "dead volume of chamber A (at x = 0)"),
        Param("V0_B", "m^3", None, 1e-12, 10.0, "dead volume of chamber B (at x = stroke)"),
        Param("k_stop", "N/m", 1e8, 0.0, 1e13, "end-stop stiffness"),
        Param("c_stop", "N*s/m", 1e5, 0.0, 1e10, "end-stop damping"),
        Param("dx_stop", "m", 1e-4, 0.0, 1.0, "penetration over which the end-stop damping fades in (regularisation width)"),
    )
    states = (State("x", "m", 0.0, 0.1, "piston position from the retracted end"),)

    @classmethod
    def check_values(cls, values: dict) -> str | None:
        start, stroke = values.get("initial.x", 0.0), values["stroke"]
        if values["A_B"] > values["A_A"]:  # the annulus is the piston's area less the rod's
            return (f"the rod-side area A_B = {values['A_B'] * 1e6:.5g} mm^2 is larger than the piston-side "
                    f"A_A = {values['A_A'] * 1e6:.5g} mm^2: B is the annulus, the piston's area less the rod's "
                    f"(A_B = A_A for a double-rod cylinder); if the chamber you call A is the rod side, swap the "
                    f"areas, dead volumes and nets")
        if not 0.0 <= start <= stroke:
            return (f"initial x = {start * 1e3:g} mm is outside the stroke [0, {stroke * 1e3:g} mm]: the piston would "
                    f"start inside an end stop")
        return None

    @staticmethod
    def outputs(x):
        return (x,)

    @staticmethod
    def derivatives(A, B, rod, x, A_A, A_B, stroke, V0_A, V0_B, k_stop, c_stop, dx_stop):
        xc = min(max(x, 0.0), stroke)
        f = A * A_A - B * A_B
        if x < 0.0:
            d = -x
            f += max(0.0, k_stop * d - c_stop * rod * smooth_step(d, 0.0, dx_stop))
        elif x > stroke:
            d = x - stroke
            f += min(0.0, -k_stop * d - c_stop * rod * smooth_step(d, 0.0, dx_stop))
        return -A_A * rod, A_B * rod, f, V0_A + A_A * xc, V0_B + A_B * (stroke - xc), rod
