"""The gas-loaded accumulator (blocks/library/hydraulic/accumulator.py) in a circuit: a pump charging it
through a short line (netlists/accumulator_charge.yaml), against two exact laws.

- Volume: the pump's oil is in the line (compressed) or in the accumulator,
  Q*t = V_line/beta*(p(t) - p(0)) + V_oil(t) - V_oil(0), whatever the accumulator does.
- Gas: the oil pressure is the gas pressure plus what drives the flow through the port,
  p = (p0 + p_atm)*(V0/(V0 - V_oil))^kappa - p_atm + (dV_oil/dt)/G_in, with dV_oil/dt = Q less what
  the line's compression takes, V_line/beta*dp/dt (a few Pa of the drop here).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from blocks.circuit import Circuit
from blocks.library.hydraulic.accumulator import EMPTY_FRACTION, Accumulator

NETLIST = Path(__file__).parent / "netlists" / "accumulator_charge.yaml"
Q, V_LINE, BETA = 6e-3 / 60, 1e-5, 8e8
V0, P0, P_ATM, G_IN = 1e-3, 50e5, 101325.0, 1e-7


def gas_pressure(v_oil, kappa, p_atm=P_ATM):
    return (P0 + p_atm) * (V0 / (V0 - v_oil)) ** kappa - p_atm


def test_the_pumped_oil_is_in_the_line_or_the_accumulator():
    r = Circuit.from_file(NETLIST).simulate()
    for side in ("i", "a"):
        stored = V_LINE / BETA * (r[f"p_{side}"] - r[f"p_{side}"][0]) + r[f"V_{side}"] - r[f"V_{side}"][0]
        assert np.max(np.abs(stored - Q * r.t)) < 1e-9 * V0, side  # 1e-12 m^3 against 5e-4 pumped


def test_charging_follows_the_polytropic_gas_law_in_absolute_pressure():
    r = Circuit.from_file(NETLIST).simulate()
    late = r.t > 0.5  # started empty at 40 bar: the line reaches the precharge within ms, then it takes Q
    for side, kappa in (("i", 1.0), ("a", 1.4)):
        v, p = r[f"V_{side}"][late], r[f"p_{side}"][late]
        inflow = Q - V_LINE / BETA * np.gradient(r[f"p_{side}"], r.t)[late]
        err = np.max(np.abs(p - gas_pressure(v, kappa) - inflow / G_IN))
        assert err < 10.0, (side, err)  # Pa, of 50 to 100 bar: the output between the solver's steps is
        # interpolated, good to about 1e-7 of V_oil here, which the gas law makes about 1 Pa
        for wrong in (gas_pressure(v, kappa, p_atm=0.0), gas_pressure(v, 2.4 - kappa)):  # gauge law, kappa swapped
            assert np.max(np.abs(p - inflow / G_IN - wrong)) > 1e4  # over 0.1 bar: the test tells them apart
    assert r["V_i"][-1] > 0.45 * V0  # 5 s of 6 l/min: half a litre in


def test_the_block_alone_and_an_empty_accumulator_gives_no_oil():
    values = {"V0": V0, "p0": P0, "kappa": 1.4, "G_in": G_IN, "p_atm": P_ATM}
    q_net, dv = Accumulator.derivatives(80e5, 0.3e-3, **values)
    assert dv == -q_net == G_IN * (80e5 - gas_pressure(0.3e-3, 1.4))
    # discharging: the full flow until the last 0.1 % of V0, then fading to nothing when empty
    assert Accumulator.derivatives(30e5, 0.3e-3, **values)[1] == G_IN * (30e5 - gas_pressure(0.3e-3, 1.4))
    assert Accumulator.derivatives(30e5, 0.0, **values)[1] == 0.0
    assert Accumulator.derivatives(30e5, -1e-9, **values)[1] == 0.0
    near = Accumulator.derivatives(30e5, 0.5 * EMPTY_FRACTION * V0, **values)[1]
    assert G_IN * (30e5 - gas_pressure(0.5 * EMPTY_FRACTION * V0, 1.4)) < near < 0.0  # fading
    # empty and filling: the full inflow
    assert Accumulator.derivatives(60e5, 0.0, **values)[1] == G_IN * (60e5 - P0)


def test_an_empty_accumulator_leaves_a_net_below_its_precharge_alone(tmp_path):
    """Before: the empty bladder's stop gave up 0.1 % of V0, which took a 0.1 l net from 0 to 43 bar."""
    (tmp_path / "rest.yaml").write_text(
        "components:\n  acc: {type: accumulator, params: {V0: '4 l', p0: '50 bar'}}\n"
        "nets:\n  B: {ports: [acc.port], volume: '0.1 l', initial: '0 bar'}\n"
        "outputs:\n  p: B\n  V: acc.V_oil\nsimulation: {t_end: '1 s', dt_out: '10 ms'}\n")
    r = Circuit.from_file(tmp_path / "rest.yaml").simulate()
    assert np.max(np.abs(r["p"])) == 0.0 and np.max(np.abs(r["V"])) == 0.0


def test_a_start_outside_the_accumulator_is_refused():
    """Before: the charge formula used below the precharge gave V_oil = -3.54 l, and the net went to
    -38860 bar with exit 0."""
    values = {"V0": V0, "p0": P0, "kappa": 1.4, "G_in": G_IN, "p_atm": P_ATM}
    assert Accumulator.check_values({**values, "initial.V_oil": 0.0}) is None
    for start in (-3.54e-3, V0, 1.2 * V0):
        assert "must be in [0, V0 = 1 l)" in Accumulator.check_values({**values, "initial.V_oil": start})


def test_a_precharge_with_no_absolute_pressure_is_refused():
    """p0 = p_atm = 0 leaves no gas: the block would swallow any oil at 0 Pa, past V0."""
    values = {"V0": V0, "p0": 0.0, "kappa": 1.4, "G_in": G_IN, "p_atm": 0.0}
    assert "p0 + p_atm must be positive" in Accumulator.check_values(values)
    assert Accumulator.check_values({**values, "p_atm": P_ATM}) is None
