"""Gas-loaded hydraulic accumulator (bladder or piston), polytropic gas."""

from blocks.block import Block, Param, State, hydraulic
from blocks.library.hydraulic.flow import smooth_step
from blocks.registry import register

EMPTY_FRACTION = 1e-3
"""Oil volume, as a fraction of V0, over which the outflow of an emptying accumulator fades to nothing."""


@register("accumulator")
class Accumulator(Block):
    """Gas-loaded accumulator: oil volume V_oil against a gas precharged to p0 in the volume V0.

    V_g  = V0 - max(V_oil, 0)                                gas volume [m^3]
    p_g  = (p0 + p_atm)*(V0/V_g)^kappa - p_atm               gas (= oil) pressure, gauge [Pa]
    q    = G_in*(p - p_g)                     p >= p_g       flow into the accumulator [m^3/s]
    q    = G_in*(p - p_g)*s(V_oil)            p <  p_g       out of it: s = smooth_step(V_oil, 0, 0.1 % of V0)
    dV_oil/dt = q

    The gas follows the polytropic law in absolute pressures (kappa = 1 isothermal, slow cycles; 1.4
    adiabatic, fast ones). Below its precharge the accumulator is empty: the gas holds the bladder on its
    stop and no oil comes out (the outflow fades to zero over the last 0.1 % of V0, a continuous law rather
    than a switch the solver would have to find), so an empty accumulator on a net below p0 leaves it alone.
    G_in is the port's conductance (its inlet valve and neck): small enough to be the accumulator's own lag,
    large enough that the oil pressure follows the gas. The accumulator adds no capacity to its net: the
    net's own volume (a line) is still needed. It starts empty (V_oil = 0, at rest on a net at or below
    p0); one charged to pressure p >= p0 is given its oil volume, ``initial: {V_oil: ...}`` with
    V_oil = V0*(1 - ((p0 + p_atm)/(p + p_atm))^(1/kappa)), in 0 <= V_oil < V0 (checked).

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
        start = values.get("initial.V_oil", 0.0)
        if not 0.0 <= start < values["V0"]:
            return (f"initial V_oil = {start * 1e3:g} l must be in [0, V0 = {values['V0'] * 1e3:g} l): 0 is empty "
                    f"(any pressure up to p0), a charged one holds less oil than its gas volume")
        return None

    @staticmethod
    def derivatives(port, V_oil, V0, p0, kappa, G_in, p_atm):
        V_g = max(V0 - max(V_oil, 0.0), 1e-9 * V0)
        p_g = (p0 + p_atm) * (V0 / V_g) ** kappa - p_atm
        q = G_in * (port - p_g)
        if q < 0.0:
            q *= smooth_step(V_oil, 0.0, EMPTY_FRACTION * V0)
        return -q, q
