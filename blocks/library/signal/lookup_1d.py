"""One-dimensional lookup table."""

from blocks.block import Block, Param, ValidRange, signal_in, signal_out
from blocks.library.signal.tables import check_breakpoints, check_length, interp1
from blocks.registry import register


@register("lookup_1d")
class Lookup1D(Block):
    """One-dimensional lookup table: y = f(u) interpolated linearly in (x_table, y_table).

    y = y_table[i] + (y_table[i+1] - y_table[i])*(u - x_table[i])/(x_table[i+1] - x_table[i])
    Outside [x_table[0], x_table[-1]]: extrapolate = 0 holds the end value, extrapolate = 1 extends the
    end segment linearly. (The tables are named x_table/y_table because the output port is y.)

    x_table must be strictly increasing and as long as y_table (checked by ``check_values``).
    Units: u and x_table in one (SI) unit, y and y_table in another.
    Checked after a run: an input u outside [x_table[0], x_table[-1]] at an output sample is warned of
    (when it went there, how far, and what the table did there); warn_outside = 0 says nothing (a table
    meant to be held or extended).
    """

    ports = (signal_in("u", "table input (abscissa)"), signal_out("y", "interpolated table value"))
    signal_dimensions = {"u": ("x_table",), "y": ("y_table",)}
    params = (
        Param("x_table", "SI", None, None, None, "breakpoints, strictly increasing (SI)", array=True),
        Param("y_table", "SI", None, None, None, "table values at the breakpoints (SI)", array=True),
        Param("extrapolate", "1", 0.0, 0.0, 1.0, "outside the table: 0 hold end value, 1 linear", integer=True),
        Param("warn_outside", "1", 1.0, 0.0, 1.0, "1: a run whose input leaves the table warns; 0: it does not",
              integer=True),
    )
    checked = ("u",)

    @staticmethod
    def outputs(u, x_table, y_table, extrapolate):
        return (interp1(u, x_table, y_table, extrapolate > 0.5),)

    @classmethod
    def valid_ranges(cls, values: dict) -> tuple[ValidRange, ...]:
        x = values["x_table"]
        if values["warn_outside"] < 0.5 or len(x) < 2:
            return ()
        there = ("the table's end segment is extended" if values["extrapolate"] > 0.5
                 else "the table's end value is held")
        return (ValidRange("u", float(x[0]), float(x[-1]), there),)

    @classmethod
    def check_values(cls, values: dict) -> str | None:
        """None if the parameter values fit together, else what is wrong (build time, not in the hot path)."""
        return check_breakpoints("x_table", values["x_table"]) or check_length(
            "y_table", values["y_table"], len(values["x_table"]), "one per entry of x_table"
        )
