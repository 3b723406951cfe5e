"""Laminar line loss in series at a port: dp = R*q (long thin lines, viscous flow meters)."""

from blocks.calibrate.candidates.base import Candidate, Place, register, safe, series_ports, start_pressure
from blocks.calibrate.candidates.line_loss_turbulent import insert_loss


@register
class LineLossLaminar(Candidate):
    name = "line_loss_laminar"
    title = "laminar line loss"
    description = ("a pressure drop R*q in series at a port (line_loss block, a 1 ml node between it and the "
                   "port); zero R is the declared connection")

    def places(self, ctx):
        out = []
        for net, port, logged in series_ports(ctx):
            out.append(Place(self.name, f"{self.name}@{port}", f"net {net}, in series at {port}",
                             f"cal_kl_{safe(port)}", "Pa*s/m^3", 0.0, 0.0, 1e16, 0.1 * ctx.p_ref / ctx.q_ref,
                             (0.0, 50e5 / ctx.q_ref), target={"net": net, "port": port, "initial": start_pressure(ctx, net)},
                             meaning=f"dp = R*q; at the reference flow {ctx.q_ref * 60000:.4g} l/min: R*q_ref",
                             plot_against=ctx.first_input_of_unit("m^3/s")))
        return out

    def patch(self, doc, place):
        insert_loss(doc, place, "R")
