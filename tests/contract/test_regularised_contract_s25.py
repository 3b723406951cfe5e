"""Contract of the regularised signals (Block.regularised, blocks/regularisation.py), walking the registry:
a block that declares some gives, where its law jumps (a friction not 0), a band for each of those signals
and for no other, of positive width, with the smoothed law's slope through 0 where the parameters fix it;
none where nothing jumps. A declaration naming no port, or regularised signals without regularisations(),
is refused at registration."""

from __future__ import annotations

import math

import pytest

from blocks import registry
from blocks.block import Block, Regularisation, check_declarations, signal_in, signal_out, translational
from blocks.library.mechanical.trans_friction import TransFriction
from blocks.library.mechanical.stribeck_friction import StribeckFriction
from blocks.regularisation import TANH_BAND
from test_registry_contract import default_params

REGISTRY = registry.all_types()
SMOOTHING = sorted(name for name, cls in REGISTRY.items() if cls.regularised)
# parameters with which the law jumps at all: a motor's or a pump's friction is 0 at the default eta_hm = 1,
# a Stribeck friction's at its default Tc = dTs = 0
JUMPING = {name: {"eta_hm": 0.9} for name in ("hydraulic_motor", "pump", "variable_pump", "parker_motor")} \
    | {"stribeck_friction": {"Tc": 1.0}, "trans_stribeck_friction": {"Fc": 100.0}}


def test_every_smoothed_coulomb_friction_is_declared():
    assert {"trans_friction", "rot_friction", "stribeck_friction", "trans_stribeck_friction", "hydraulic_motor",
            "pump", "variable_pump", "parker_motor"} <= set(SMOOTHING)
    assert not {"orifice", "valve_4_3", "counterbalance_valve", "spool_relief_valve"} & set(SMOOTHING)


@pytest.mark.parametrize("name", SMOOTHING)
def test_bands_where_the_law_jumps(name):
    cls = REGISTRY[name]
    values = default_params(cls) | JUMPING.get(name, {})
    bands = cls.regularisations(values)
    assert {b.signal for b in bands} == set(cls.regularised), f"{name}: a regularised signal without a band"
    # 10, 20, 30 bar on the ports (a pressure across the machine), a setting clamped to its maximum
    reads = {ref: 1e6 * (k + 1) for k, ref in enumerate(cls.regularised_reads)}
    for band in bands:
        assert isinstance(band, Regularisation)
        assert band.width > 0 and math.isfinite(band.width), band
        slope = band.slope(0.0, reads)
        assert slope > 0 and math.isfinite(slope), band
        assert band.slope(band.width, reads) < 0.011 * slope, band  # past the band the law is flat: sign(s)
        assert band.slope_text and band.what and len(band.real) > 10, band


def test_a_friction_s_band_and_slope_from_its_parameters():
    band, = TransFriction.regularisations({"Fc": 300.0, "b": 2000.0, "v_w": 1e-3})
    assert (band.signal, band.width, band.width_text) == ("port", pytest.approx(3e-3), "3*v_w")
    assert (band.slope(0.0, {}), band.slope_text, band.slope_unit) == (pytest.approx(3e5), "Fc/v_w", "N*s/m")
    assert band.slope(2e-3, {}) == pytest.approx(3e5 / math.cosh(2.0) ** 2, rel=1e-6)  # the slope the model takes
    assert TANH_BAND == 3.0 and math.tanh(TANH_BAND) > 0.995  # beyond the band tanh is sign to 0.5 %
    band, = StribeckFriction.regularisations({"Tc": 2.0, "dTs": 1.0, "w_s": 1.0, "b": 0.0, "w_w": 0.01})
    assert band.slope(0.0, {}) == pytest.approx(300.0) and band.slope_unit == "N*m*s/rad"  # (Tc + dTs)/w_w
    assert TransFriction.regularisations({"Fc": 0.0, "b": 2000.0, "v_w": 1e-3}) == ()  # nothing jumps
    assert REGISTRY["hydraulic_motor"].regularisations(default_params(REGISTRY["hydraulic_motor"])) == ()


def test_a_machine_s_friction_band_takes_its_size_from_the_pressures_at_the_point():
    """(1 - eta_hm)*D*|p_a - p_b|/w_w: 0 with no pressure across the motor (a review found the note said
    where the smoothing's slope was 0)."""
    motor = REGISTRY["hydraulic_motor"]
    values = default_params(motor) | {"eta_hm": 0.9, "D": 1e-5, "w_w": 0.1}
    band, = motor.regularisations(values)
    assert band.slope(0.0, {"a": 20e5, "b": 20e5}) == 0.0
    assert band.slope(0.0, {"a": 120e5, "b": 20e5}) == pytest.approx(0.1 * 1e-5 * 100e5 / 0.1, rel=1e-6)
    pump = REGISTRY["variable_pump"]
    values = default_params(pump) | {"eta_hm": 0.8, "D_max": 2e-5, "eps_max": 1.0, "w_w": 0.1}
    band, = pump.regularisations(values)
    assert band.slope(0.0, {"s": 0.0, "p": 100e5, "eps": 0.5}) == pytest.approx(0.25 * 0.5 * 2e-5 * 100e5 / 0.1,
                                                                                rel=1e-6)


def _throwaway(regularised, with_bands):
    class Smoothed(Block):
        """Throwaway block for the regularised declarations: f = -tanh(v).

        f = -tanh(v)
        """

        ports = (translational("port", "body"), signal_in("u", "input"), signal_out("y", "output"))

        @staticmethod
        def outputs(u):
            return (u,)

        @staticmethod
        def derivatives(port):
            return (-math.tanh(port),)

    Smoothed.regularised = regularised
    if with_bands:
        Smoothed.regularisations = classmethod(
            lambda cls, values: (Regularisation("port", 3.0, "3", lambda s, reads: math.tanh(s), "1", "N*s/m", "it",
                                                "it sticks"),))
    return Smoothed


@pytest.mark.parametrize("ref", ["v", "port.flow", "u.force"])
def test_a_regularised_signal_must_name_a_port_or_a_physical_ports_through_value(ref):
    with pytest.raises(TypeError, match=f"regularised signal '{ref}' is neither a port"):
        check_declarations(_throwaway((ref,), True))


def test_regularised_signals_need_their_bands():
    with pytest.raises(TypeError, match=r"declares regularised signals \['port'\] but no regularisations\(\)"):
        check_declarations(_throwaway(("port",), False))
    check_declarations(_throwaway(("port", "port.force"), True))


def test_a_regularised_read_must_name_a_port_or_a_state():
    block = _throwaway(("port",), True)
    block.regularised_reads = ("p_a",)
    with pytest.raises(TypeError, match="regularised_reads signal 'p_a' is neither a port"):
        check_declarations(block)
    block.regularised_reads = ("u",)
    check_declarations(block)
