"""Operating points inside a block's regularisation band: where a linearisation takes a smoothing for physics.

A law that jumps at zero (a Coulomb friction's force, Fc*sign(v)) cannot be integrated as it is; the blocks
smooth it over a declared band (Fc*tanh(v/v_w)), and a simulation crosses the band as the machine crosses
the jump. A linearisation about a point inside the band does not: there the law's slope is the smoothing's,
Fc/v_w (3e5 N*s/m for 300 N over 1 mm/s), which the linear model takes as a damper of that size. The modes
that move the body are then damped, or made real, by the regularisation's width, not by the machine (a real
Coulomb friction at rest sticks until the force on it exceeds Fc, or slips; it is no damper): about a held
boom, v_w = 1 mm/s gave two real modes at -68 and -83 1/s where v_w = 1 cm/s gave 12 Hz at zeta = 0.095 and
Fc = 0 gave 12 Hz at zeta = 0.007.

A block declares the signals it smooths so (``Block.regularised``: a port's speed), what the smoothed law's
size reads at the point (``Block.regularised_reads``: a motor's port pressures) and, from its parameters,
each one's band, |signal| < width, and the smoothed law itself (``Block.regularisations``). The compiled
``observe`` of a circuit built to be linearised (``regularised=True``) computes the signals and the reads
after the checked signals (:func:`blocks.valid_ranges.monitors`); :func:`band_notes` reads them at the operating point and gives a line for each signal that lies
inside its band where the law has a slope there, quoting that slope (the one the linear model takes:
Fc/v_w*sech(v/v_w)^2 for a tanh) beside its value through 0.
"""

from __future__ import annotations

import math

import numpy as np

from blocks.block import ACROSS, THROUGH, PortKind, Regularisation

TANH_BAND = 3.0
"""A law a*tanh(s/s_w) smoothing a*sign(s) is the smoothing's over |s| < 3*s_w: beyond, it is within 0.5 % of
a*sign(s) and its slope under 1 % of the one through 0, a/s_w (sech(3)^2 = 0.0099); at |s| = s_w, the
width blocks declare, the slope is still 42 % of it."""
STICKS = "a real Coulomb friction at rest sticks, or slips once the force on it exceeds its breakaway"


def tanh_band(signal: str, size, width: float, width_name: str, slope_text: str, slope_unit: str,
              what: str = "the Coulomb friction", real: str = STICKS, negligible: float = 0.0
              ) -> tuple[Regularisation, ...]:
    """The band of a law size*tanh(signal/width) that smooths size*sign(signal): |signal| < TANH_BAND*width.
    ``size`` is a number, or a function (s, reads) -> number where it follows the point (a motor's friction
    the pressures it reads, a Stribeck friction the speed); none where it is the number 0 (nothing jumps)."""
    if not callable(size):
        if size == 0.0:
            return ()
        size = (lambda value: lambda s, reads: value)(float(size))
    return (Regularisation(signal, TANH_BAND * width, f"{TANH_BAND:g}*{width_name}",
                           lambda s, reads: size(s, reads) * math.tanh(s / width), slope_text, slope_unit, what,
                           real, negligible),)


def stribeck_band(signal: str, coulomb: float, stribeck: float, speed: float, width: float, width_name: str,
                  slope_text: str, slope_unit: str) -> tuple[Regularisation, ...]:
    """The band of a Stribeck friction's (coulomb + stribeck*exp(-(s/speed)^2))*tanh(s/width); none where
    both are 0."""
    if coulomb + stribeck == 0.0:
        return ()
    return tanh_band(signal, lambda s, reads: coulomb + stribeck * math.exp(-(s / speed) ** 2), width, width_name,
                     slope_text, slope_unit)


def band_notes(circuit, point) -> list[str]:
    """A line for each regularised signal that lies inside its band at ``point`` (a
    :class:`blocks.linearise.OperatingPoint`) where the smoothed law has a slope: the block, the signal's
    value and the band, the slope the linear model takes there (and through 0, by its formula), and what the
    machine does instead. None where the law is flat at the point (a motor's friction with no pressure
    across it: nothing is taken for physics)."""
    vec = circuit.vectors(point.overrides)
    y = np.zeros(circuit.n_observed)
    circuit.module.observe(point.t, np.asarray(point.x, dtype=float), vec.theta, y)
    observed = {(m.comp, m.ref): (value, m.unit) for m, value in zip(circuit.monitors, y[len(circuit.outputs):])}
    if not circuit.regularised:
        raise ValueError("band_notes: the circuit was built without its regularised signals "
                         "(Circuit(..., regularised=True))")
    notes = []
    for comp, spec in circuit.flat.components.items():
        cls = spec.cls
        if not cls.regularised:
            continue
        reads = {ref: observed[(comp, ref)][0] for ref in cls.regularised_reads}
        for band in cls.regularisations(circuit.block_values(comp, vec.values)):
            value, unit = observed[(comp, band.signal)]
            if not abs(value) < band.width:
                continue
            here, through_zero = band.slope(value, reads), band.slope(0.0, reads)
            if not here > band.negligible:
                continue
            symbol = _symbol(cls, band.signal)
            notes.append(f"{comp}: the point lies inside {band.what}'s smoothing band (|{symbol}| = {abs(value):.3g} "
                         f"{unit} < {band.width_text} = {band.width:.3g} {unit}): there its slope, {here:.3g} "
                         f"{band.slope_unit} ({band.slope_text} = {through_zero:.3g} {band.slope_unit} at {symbol} "
                         f"= 0), is the regularisation's, not physics: a mode that moves {symbol} takes it for a "
                         f"damper ({band.real})")
    return notes


def _symbol(cls, ref: str) -> str:
    """How a regularised signal is written: a port's across variable (v, w, p), a port's through one (q,
    tau, f), a signal port by its name."""
    port_name, _, through = ref.partition(".")
    port = cls.port(port_name)
    if port.kind is PortKind.SIGNAL:
        return port_name
    return THROUGH[port.kind][0] if through else ACROSS[port.kind][0]
