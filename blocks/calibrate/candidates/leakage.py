"""Internal leakage between two nets joined by a component: q = G*(p_a - p_b) (laminar_orifice)."""

from blocks.calibrate.candidates.base import Candidate, Place, hydraulic_pairs, register, safe


@register
class Leakage(Candidate):
    name = "leakage"
    title = "internal leakage"
    description = "a laminar leak q = G*dp across two nets joined by a component (laminar_orifice); zero G: none"

    def places(self, ctx):
        out = []
        for a, b, joined_by in hydraulic_pairs(ctx):
            out.append(Place(self.name, f"{self.name}@{a}-{b}", f"between nets {a} and {b} (across {joined_by})",
                             f"cal_G_{safe(a)}_{safe(b)}", "m^3/(s*Pa)", 0.0, 0.0, 1e-3,
                             1e-4 * ctx.q_ref / 1e5, (0.0, ctx.q_ref / 100e5), target={"a": a, "b": b},
                             meaning="q = G*(p_a - p_b)", plot_against=ctx.across(a, b, "Pa")))
        return out

    def patch(self, doc, place):
        comp = doc.unique(f"cal_leak_{safe(place.target['a'])}_{safe(place.target['b'])}")
        doc.add_component(comp, "laminar_orifice", {"G": place.param})
        for end, net in (("a", place.target["a"]), ("b", place.target["b"])):
            doc.set_net_ports(net, doc.net_ports(net) + [f"{comp}.{end}"])
