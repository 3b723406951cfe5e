"""Operating points inside a block's regularisation band: where a linearisation takes a smoothing for physics.

A law that jumps at zero (a Coulomb friction's force, Fc*sign(v)) cannot be integrated as it is; the blocks
smooth it over a declared band (Fc*tanh(v/v_w)), and a simulation crosses the band as the machine crosses
the jump. A linearisation about a point inside the band does not: there the law's slope is the smoothing's,
Fc/v_w (3e5 N*s/m for 300 N over 1 mm/s), which the linear model takes as a damper of that size. The modes
that move the body are then damped, or made real, by the regularisation's width, not by the machine (a real
Coulomb friction at rest sticks until the force on it exceeds Fc, or slips; it is no damper): about a held
boom, v_w = 1 mm/s gave two real modes at -68 and -83 1/s where v_w = 1 cm/s gave 12 Hz at zeta = 0.095 and
Fc = 0 gave 12 Hz at zeta = 0.007.

A block declares the signals it smooths so (``Block.regularised``: a port's speed) and, from its parameters,
each one's band, |signal| < width, and the smoothed law's slope through 0 (``Block.regularisations``). The
compiled ``observe`` computes them after the checked signals (:func:`blocks.valid_ranges.monitors`);
:func:`band_notes` reads them at the operating point and gives a line for each that lies inside its band.
"""

from __future__ import annotations

import numpy as np

from blocks.block import ACROSS, THROUGH, PortKind, Regularisation

TANH_BAND = 3.0
"""A law a*tanh(s/s_w) smoothing a*sign(s) is the smoothing's over |s| < 3*s_w: beyond, it is within 0.5 % of
a*sign(s) and its slope under 1 % of the one through 0, a/s_w (sech(3)^2 = 0.0099); at |s| = s_w, the
width blocks declare, the slope is still 42 % of it."""
STICKS = "a real Coulomb friction at rest sticks, or slips once the force on it exceeds its breakaway"


def tanh_band(signal: str, amplitude: float | None, width: float, width_name: str, slope_text: str,
              slope_unit: str, law: str = "the Coulomb friction", real: str = STICKS) -> tuple[Regularisation, ...]:
    """The band of a law amplitude*tanh(signal/width) that smooths amplitude*sign(signal): |signal| <
    TANH_BAND*width, the slope through 0 amplitude/width (``amplitude`` None: it depends on the point, and
    ``slope_text`` alone is said); none where the amplitude is 0 (nothing jumps)."""
    if amplitude == 0.0:
        return ()
    return (Regularisation(signal, TANH_BAND * width, f"{TANH_BAND:g}*{width_name}",
                           None if amplitude is None else amplitude / width, slope_text, slope_unit, law, real),)


def band_notes(circuit, point) -> list[str]:
    """A line for each regularised signal that lies inside its band at ``point`` (a
    :class:`blocks.linearise.OperatingPoint`): the block, the signal's value and the band, the slope the
    linear model takes there and what the machine does instead."""
    vec = circuit.vectors(point.overrides)
    y = np.zeros(circuit.n_observed)
    circuit.module.observe(point.t, np.asarray(point.x, dtype=float), vec.theta, y)
    notes, bands = [], {}
    for monitor, value in zip(circuit.monitors, y[len(circuit.outputs):]):
        cls = circuit.flat.components[monitor.comp].cls
        if monitor.ref not in cls.regularised:
            continue
        if monitor.comp not in bands:
            bands[monitor.comp] = {r.signal: r for r in
                                   cls.regularisations(circuit.block_values(monitor.comp, vec.values))}
        band = bands[monitor.comp].get(monitor.ref)
        if band is None or not abs(value) < band.width:
            continue
        unit, symbol = monitor.unit, _symbol(cls, monitor.ref)
        slope = band.slope_text if band.slope is None else f"{band.slope_text} = {band.slope:.3g} {band.slope_unit}"
        notes.append(f"{monitor.comp}: the point lies inside {band.law}'s smoothing band (|{symbol}| "
                     f"= {abs(value):.3g} {unit} < {band.width_text} = {band.width:.3g} {unit}): there its slope "
                     f"{slope} is the regularisation's, not physics, and the modes that move it are damped by the "
                     f"smoothing, not by the machine ({band.real})")
    return notes


def _symbol(cls, ref: str) -> str:
    """How a regularised signal is written: a port's across variable (v, w, p), a port's through one (q,
    tau, f), a signal port by its name."""
    port_name, _, through = ref.partition(".")
    port = cls.port(port_name)
    if port.kind is PortKind.SIGNAL:
        return port_name
    return THROUGH[port.kind][0] if through else ACROSS[port.kind][0]
