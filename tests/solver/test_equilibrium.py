"""The compiled equilibrium solver (blocks/solve/equilibrium.py, ``Circuit.equilibrium``) on circuits with
closed forms: two laminar restrictions in series fed by a flow source (the pressures Q/G2 and Q/G2 + Q/G1,
the eigenvalues of a 2x2 matrix), a turbulent orifice (the square law), and circuits without an isolated
equilibrium (a volume filled with no way out: singular)."""

from __future__ import annotations

import numpy as np
import pytest
import yaml

from blocks.circuit import Circuit

BETA, V1, V2 = 1e9, 1e-3, 2e-3  # Pa, m^3
G1, G2 = 2e-11, 1e-11  # m^3/(s Pa)
Q = 1e-4  # m^3/s (6 l/min)


def series_circuit(tmp_path, g2=G2) -> Circuit:
    netlist = {
        "fluid": {"rho": "850 kg/m^3", "nu": "3e-5 m^2/s", "beta": f"{BETA} Pa"},
        "parameters": {"Q_in": Q, "G_1": G1, "G_2": g2},
        "components": {"tank": {"type": "tank"}, "pump": {"type": "flow_source", "params": {"q": "Q_in"}},
                       "r1": {"type": "laminar_orifice", "params": {"G": "G_1"}},
                       "r2": {"type": "laminar_orifice", "params": {"G": "G_2"}}},
        "nets": {"T": ["tank.port", "pump.a", "r2.b"],
                 "A": {"ports": ["pump.b", "r1.a"], "volume": f"{V1} m^3"},
                 "B": {"ports": ["r1.b", "r2.a"], "volume": f"{V2} m^3"}},
        "outputs": {"pA": {"of": "A", "unit": "bar"}, "pB": {"of": "B", "unit": "bar"}},
        "simulation": {"t_end": "1 s", "dt_out": "10 ms"},
    }
    path = tmp_path / "series.yaml"
    path.write_text(yaml.safe_dump(netlist))
    return Circuit.from_file(path)


def test_series_restrictions_reach_the_closed_form_root_and_eigenvalues(tmp_path):
    c = series_circuit(tmp_path)
    eq = c.equilibrium()  # from the netlist's initial state (all pressures 0): a linear circuit, one step
    assert eq.status == 0 and eq.iterations <= 3
    assert eq["pB"] == pytest.approx(Q / G2, rel=1e-10)
    assert eq["pA"] == pytest.approx(Q / G2 + Q / G1, rel=1e-10)
    # C dp/dt = [[-G1, G1], [G1, -(G1 + G2)]] p + ..., C = diag(V1, V2)/beta
    A = np.array([[-G1, G1], [G1, -(G1 + G2)]]) * BETA / np.array([[V1], [V2]])
    assert eq.growth == pytest.approx(np.max(np.linalg.eigvals(A).real), rel=1e-6)
    assert eq.stable


def test_the_root_does_not_depend_on_the_start(tmp_path):
    c = series_circuit(tmp_path)
    a = c.equilibrium(guess=np.array([0.0, 0.0]))
    b = c.equilibrium(guess=np.array([3e7, -1e6]))
    assert a.status == b.status == 0
    assert np.max(np.abs(a.states - b.states)) < 1e-10 * Q / G2


def test_a_square_law_orifice_converges_from_far_to_the_square_law(tmp_path):
    netlist = {
        "fluid": {"rho": "850 kg/m^3", "nu": "3e-5 m^2/s", "beta": "1e9 Pa"},
        "components": {"tank": {"type": "tank"}, "pump": {"type": "flow_source", "params": {"q": "6 l/min"}},
                       "orif": {"type": "orifice", "params": {"A": "2 mm^2", "Cd": 0.7, "dp_t": "0.01 bar"}}},
        "nets": {"T": ["tank.port", "pump.a", "orif.b"], "P": {"ports": ["pump.b", "orif.a"], "volume": "1 l"}},
        "outputs": {"p": {"of": "P", "unit": "bar"}},
        "simulation": {"t_end": "1 s", "dt_out": "10 ms"},
    }
    (tmp_path / "orifice.yaml").write_text(yaml.safe_dump(netlist))
    c = Circuit.from_file(tmp_path / "orifice.yaml")
    eq = c.equilibrium()
    q, area = 1e-4, 2e-6
    dp = 850.0 / 2.0 * (q / (0.7 * area)) ** 2  # q = Cd A sqrt(2 dp / rho), dp >> dp_t
    assert eq.status == 0 and eq["p"] == pytest.approx(dp, rel=1e-6)
    assert c.equilibrium(max_iter=1).status == 2  # one iteration from 0 Pa is not enough


def test_a_volume_with_no_way_out_has_no_equilibrium(tmp_path):
    c = series_circuit(tmp_path, g2=0.0)  # r2 closed: the flow source fills A and B for ever
    eq = c.equilibrium()
    # the Jacobian is singular; its finite-difference copy may keep a pivot of rounding size (status 2: the
    # huge step it gives passes no line search) or lose it (status 1): either way no equilibrium
    assert eq.status in (1, 2) and not eq.stable and np.isnan(eq.values).all()


def test_a_filter_that_only_feeds_a_logged_signal_is_solved_on_its_own_row(tmp_path):
    """A first-order lag 1/(tau s + 1) on the pressure of net A feeds only a logged output: its state acts
    on no other state. It is found as such and solved after the pressures: y = pA exactly, and its own
    eigenvalue -1/tau counts for stability."""
    c = series_circuit(tmp_path)
    netlist = yaml.safe_load((tmp_path / "series.yaml").read_text())
    netlist["components"]["sensor"] = {"type": "pressure_sensor"}
    netlist["components"]["lag"] = {"type": "transfer_function_strict", "params": {"num": [1.0], "den": [0.5, 1.0]}}
    netlist["nets"]["A"]["ports"].append("sensor.port")
    netlist["nets"]["s"] = ["sensor.p", "lag.u"]
    netlist["outputs"]["lagged"] = {"of": "lag.y", "unit": "bar"}
    (tmp_path / "lag.yaml").write_text(yaml.safe_dump(netlist))
    c = Circuit.from_file(tmp_path / "lag.yaml")
    eq = c.equilibrium()
    p_b = Q / G2
    assert eq.status == 0 and eq["lagged"] == pytest.approx(p_b + Q / G1, rel=1e-9)
    lag = c.structure.block_states["lag"]["x"].index
    assert list(np.nonzero(eq.sinks)[0]) == [lag]
    slow = max(np.linalg.eigvals(np.array([[-BETA * G1 / V1, BETA * G1 / V1],
                                           [BETA * G1 / V2, -BETA * (G1 + G2) / V2]])).real)
    assert eq.stable and eq.growth == pytest.approx(max(slow, -1.0 / 0.5), rel=1e-4)


@pytest.mark.parametrize("rate, status", [(0.0, 0), (1.0, 4)])
def test_an_integrator_of_nothing_rests_anywhere_and_of_something_nowhere(tmp_path, rate, status):
    """An integrator of a constant acts on nothing and its own rate does not depend on it: with input 0 it
    rests wherever it starts (held at the guess, status 0); with input 1 it has no rest point (status 4)."""
    c = series_circuit(tmp_path)
    netlist = yaml.safe_load((tmp_path / "series.yaml").read_text())
    netlist["components"]["u"] = {"type": "constant", "params": {"value": rate}}
    netlist["components"]["int"] = {"type": "integrator", "initial": {"x": 7.0}}
    netlist["nets"]["s"] = ["u.y", "int.u"]
    netlist["outputs"]["i"] = {"of": "int.y"}
    (tmp_path / "int.yaml").write_text(yaml.safe_dump(netlist))
    c = Circuit.from_file(tmp_path / "int.yaml")
    eq = c.equilibrium()
    assert eq.status == status
    if status == 0:
        assert eq["i"] == 7.0 and eq["pB"] == pytest.approx(Q / G2, rel=1e-9) and eq.stable


@pytest.mark.parametrize("order", ["a first", "b first"])
def test_a_coupling_that_is_zero_only_at_the_guess_does_not_fool_the_solver(tmp_path, order):
    """a' = 1 - a, b' = 2 - b - a*b from a = b = 0: there the product couples nothing (d b'/d a = -b = 0),
    so both states look as if they act on nothing. Whichever is solved first, the result must be the
    equilibrium a = b = 1, with eigenvalues -1 and -2 (J = [[-1, 0], [-b, -1 - a]])."""
    components = {
        "int_a": {"type": "integrator"}, "int_b": {"type": "integrator"},
        "one": {"type": "constant", "params": {"value": 1.0}}, "two": {"type": "constant", "params": {"value": 2.0}},
        "rate_a": {"type": "sum", "params": {"k1": 1.0, "k2": -1.0}},
        "rate_b": {"type": "sum", "params": {"k1": 1.0, "k2": -1.0, "k3": -1.0}},
        "ab": {"type": "product"},
    }
    if order == "b first":
        components = dict(reversed(list(components.items())))
    netlist = {
        "components": components,
        "nets": {"a": ["int_a.y", "rate_a.u2", "ab.u1"], "b": ["int_b.y", "rate_b.u2", "ab.u2"],
                 "p": ["ab.y", "rate_b.u3"], "c1": ["one.y", "rate_a.u1"], "c2": ["two.y", "rate_b.u1"],
                 "da": ["rate_a.y", "int_a.u"], "db": ["rate_b.y", "int_b.u"]},
        "outputs": {"a": {"of": "int_a.y"}, "b": {"of": "int_b.y"}},
        "simulation": {"t_end": "1 s", "dt_out": "10 ms"},
    }
    (tmp_path / "ab.yaml").write_text(yaml.safe_dump(netlist, sort_keys=False))
    eq = Circuit.from_file(tmp_path / "ab.yaml").equilibrium()
    assert eq.status == 0 and eq["a"] == pytest.approx(1.0, rel=1e-9) and eq["b"] == pytest.approx(1.0, rel=1e-9)
    assert eq.stable and eq.growth == pytest.approx(-1.0, rel=1e-5)
