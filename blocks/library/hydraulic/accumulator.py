"""Gas-loaded hydraulic accumulator (bladder or piston), polytropic gas."""

from blocks.block import Block, Param, State, hydraulic
from blocks.registry import register

STOP_FRACTION = 1e-3
"""Oil volume below empty, as a fraction of V0, over which the emptied bladder's stop takes the gas pressure
from the precharge down to absolute zero (a stiff, continuous stop instead of a switch)."""


@register("accumulator")
class Accumulator(Block):
    """Gas-loaded accumulator: oil volume V_oil against a gas precharged to p0 in the volume V0.

    V_g  = V0 - V_oil                                        gas volume [m^3]
    p_g  = (p0 + p_atm)*(V0/V_g)^kappa - p_atm               gas (= oil) pressure, gauge [Pa], V_oil >= 0
    p_g  = p0 + (p0 + p_atm)*V_oil/(STOP_FRACTION*V0)         V_oil < 0: the emptied bladder on its stop
    q    = G_in*(p - p_g)                                    flow into the accumulator [m^3/s]
    dV_oil/dt = q

    The gas follows the polytropic law in absolute pressures (kappa = 1 isothermal, slow cycles; 1.4
    adiabatic, fast ones). Below its precharge the accumulator is empty: the gas holds the bladder on
    its stop, and the stop takes the gas pressure from p0 down to absolute zero over 0.1 % of V0 below
    empty, so an empty accumulator gives up at most that much more oil (a stiff stop rather than a switch
    the solver would have to find). G_in is the port's conductance (its inlet valve and neck): small
    enough to be the accumulator's own lag, large enough that the oil pressure follows the gas.
    An accumulator starting charged is given its oil volume: ``initial: {V_oil: ...}``, at pressure p
    V_oil = V0*(1 - ((p0 + p_atm)/(p + p_atm))^(1/kappa)).

    q > 0 flows into the accumulator: the block delivers -q to its net.
    """

    ports = (hydraulic("port", "the oil port"),)
    params = (
        Param("V0", "m^3", None, 1e-9, 10.0, "gas volume at precharge (the accumulator's size)"),
        Param("p0", "Pa", None, 0.0, 1e9, "gas precharge pressure (gauge)"),
        Param("kappa", "1", 1.4, 1.0, 1.67, "polytropic exponent of the gas (1 isothermal, 1.4 adiabatic)"),
        Param("G_in", "m^3/(s*Pa)", 1e-7, 1e-15, 1.0, "conductance of the oil port (inlet and neck)"),
        Param("p_atm", "Pa", 101325.0, 0.0, 1e6, "ambient pressure: gauge to absolute for the gas law"),
    )
    states = (State("V_oil", "m^3", 0.0, 1e-3, "oil volume in the accumulator (0: empty)"),)

    @classmethod
    def check_values(cls, values: dict) -> str | None:
        if values["p0"] + values["p_atm"] <= 0.0:
            return "p0 + p_atm must be positive: the gas law needs an absolute precharge pressure"
        return None

    @staticmethod
    def derivatives(port, V_oil, V0, p0, kappa, G_in, p_atm):
        if V_oil >= 0.0:
            V_g = max(V0 - V_oil, 1e-9 * V0)
            p_g = (p0 + p_atm) * (V0 / V_g) ** kappa - p_atm
        else:
            p_g = p0 + (p0 + p_atm) * V_oil / (STOP_FRACTION * V0)
        q = G_in * (port - p_g)
        return -q, q
