"""The netlist schema as pydantic models: the shape of a file, before any meaning is given to it.

A netlist describes a circuit as its drawing sheet does::

    fluid:      {rho: "850 kg/m^3", nu: "1.8e-5 m^2/s", beta: "8e8 Pa", vapour_pressure: "-1 bar"}
    defaults:   {volume: "0.1 l"}               # optional: the volume of a hydraulic net that names none
    parameters: {m_load: "7500 kg", J: "0.085 + m_load*0.075**2/39**2"}
    components:
      valve: {type: valve_4_3, params: {A_max: "125 mm^2"}, initial: {}}
      mcv:   {type: mcv_vaa, preset: VF250, params: {alpha: 2.8, p_crack: "230 bar"}}   # a data-sheet preset, overridden
    subsystems:
      left: {netlist: drive_line.yaml, parameters: {m_load: "15 t"}}
    nets:
      A: {ports: [valve.A, motor.a], volume: "1 l", initial: "20 bar"}
      cmd: [ctrl.y, valve.x]                     # short form: just the ports
    ports: {P: P, cmd: valve.x}                  # what a file used as a subsystem exposes
    outputs: {pA: {of: A, unit: bar}, x: sensor.y}
    simulation: {t_end: "3 s", dt_out: "1 ms", solver: rodas, rtol: 1e-6}

Values are numbers in SI or strings: "<number> <unit>", or an expression over parameter names (in SI).
What the names and values mean is checked later (:mod:`blocks.netlist.flatten`); here only the shape.
"""

from __future__ import annotations

from typing import Annotated, Literal, Union

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, StrictBool
from pydantic_core import PydanticCustomError

NOT_A_NUMBER = "not_a_number"
"""The pydantic error type of a YAML boolean where a number is expected (its message is the one to show)."""


def _no_boolean(value):
    """Refuse a YAML boolean (``true``, ``false``, ``yes``, ``no``, ``on``, ``off``) where a number is expected.

    pydantic would take it as 1.0 or 0.0, so ``Cd: true`` (a slip for a number) would simulate Cd = 1 and
    ``max_steps: yes`` one step; the error says what was read."""
    if isinstance(value, bool):
        raise PydanticCustomError(NOT_A_NUMBER, "{text} is not a number", {"text": str(value).lower()})
    return value


Value = Annotated[Union[float, int, str], BeforeValidator(_no_boolean)]
"""A number in SI, a '<number> <unit>' string or an expression; never a boolean."""
Number = Annotated[float, BeforeValidator(_no_boolean)]
Count = Annotated[int, BeforeValidator(_no_boolean)]


class Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", str_strip_whitespace=True)


class CsvColumn(Strict):
    """An array parameter read from a column of a CSV file (relative to the netlist's folder)."""

    csv: str
    column: str


class Fluid(Strict):
    rho: Value = "850 kg/m^3"
    nu: Value = "1.8e-5 m^2/s"
    beta: Value = "8e8 Pa"
    vapour_pressure: Value = Field("-1 bar", description="gauge; a node below it is reported as cavitating")
    cavitation: StrictBool = Field(True, description="a net drawn below the vapour pressure holds a vapour cavity")
    air: Value | None = Field(None, description="free air entrained in the oil, volume fraction at atmospheric "
                                                "pressure (absent: the pure liquid)")
    air_index: Value = Field(1.0, description="polytropic index of the entrained air: 1 isothermal, 1.4 adiabatic")


class Defaults(Strict):
    volume: Value | None = None


class Component(Strict):
    type: str
    preset: str | None = None
    params: dict[str, Union[Value, list[Value], CsvColumn]] = Field(default_factory=dict)
    initial: dict[str, Union[Value, list[Value]]] = Field(default_factory=dict)


class Subsystem(Strict):
    netlist: str
    parameters: dict[str, Value] = Field(default_factory=dict)


class Net(Strict):
    ports: list[str]
    volume: Value | None = None
    bulk_modulus: Value | None = None
    initial: Value | None = None


class Output(Strict):
    of: str
    unit: str | None = None


class Simulation(Strict):
    t_start: Value = 0.0
    t_end: Value = 1.0
    dt_out: Value = "1 ms"
    solver: Literal["rodas", "fixed", "lsoda", "bdf", "radau"] = "rodas"
    rtol: Number = Field(1e-6, gt=0, lt=1)
    atol: Number = Field(1e-6, gt=0, lt=1, description="absolute tolerance relative to each state's nominal size")
    fixed_step: Value | None = None
    max_step: Value | None = None
    max_steps: Count = Field(2_000_000, gt=0)
    fixed_step_check: bool = True


class Netlist(Strict):
    description: str = ""
    fluid: Fluid = Field(default_factory=Fluid)
    defaults: Defaults = Field(default_factory=Defaults)
    parameters: dict[str, Value] = Field(default_factory=dict)
    components: dict[str, Component] = Field(default_factory=dict)
    subsystems: dict[str, Subsystem] = Field(default_factory=dict)
    nets: dict[str, Union[Net, list[str]]] = Field(default_factory=dict)
    ports: dict[str, str] = Field(default_factory=dict)
    outputs: dict[str, Union[Output, str]] = Field(default_factory=dict)
    simulation: Simulation = Field(default_factory=Simulation)

    def net(self, name: str) -> Net:
        value = self.nets[name]
        return Net(ports=value) if isinstance(value, list) else value
