"""Sensor gain error on a measured channel: y' = (1 + g)*y, applied to the logged signal (post-processing)."""

from blocks.calibrate.candidates.base import Candidate, Place, register


@register
class SensorGain(Candidate):
    name = "sensor_gain"
    title = "sensor gain"
    description = "a gain error g of a measured channel, y' = (1 + g)*y (on the logged signal, not in the netlist)"

    def places(self, ctx):
        return [Place(self.name, f"{self.name}@{ch.name}", f"channel {ch.name}", f"gain:{ch.name}", "1", 0.0,
                      -0.5, 0.5, 1e-3, (-0.1, 0.1), kind="channel", target={"channel": ch.name}, one_sided=False,
                      meaning="relative gain error", plot_against=ch.name)
                for ch in ctx.exp.channels]

    def patch(self, doc, place):
        raise TypeError("a sensor gain patches the compared signal, not the netlist")
