"""Two-dimensional lookup table."""

from blocks.block import Block, Param, ValidRange, signal_in, signal_out
from blocks.library.signal.tables import check_breakpoints, check_length, interp2
from blocks.registry import register


@register("lookup_2d")
class Lookup2D(Block):
    """Two-dimensional lookup table: y = z(u1, u2), bilinear in the grid x_table (nx) by y_table (ny).

    z_table is the nx*ny grid flattened row-major: z(x_table[i], y_table[j]) = z_table[i*ny + j].
    In a cell, with s = (u1 - x[i])/(x[i+1] - x[i]) and r = (u2 - y[j])/(y[j+1] - y[j]):
    y = (1-s)*((1-r)*z[i,j] + r*z[i,j+1]) + s*((1-r)*z[i+1,j] + r*z[i+1,j+1])
    Inputs outside the grid are clamped to its edges (no extrapolation).

    x_table and y_table must be strictly increasing and z_table nx*ny long (checked by ``check_values``).
    Units: u1 and x_table in one (SI) unit, u2 and y_table in a second, y and z_table in a third.
    Checked after a run: an input outside its breakpoints at an output sample is warned of (when, how far);
    warn_outside = 0 says nothing.
    """

    ports = (
        signal_in("u1", "first input, along x_table"),
        signal_in("u2", "second input, along y_table"),
        signal_out("y", "interpolated table value"),
    )
    signal_dimensions = {"u1": ("x_table",), "u2": ("y_table",), "y": ("z_table",)}
    params = (
        Param("x_table", "SI", None, None, None, "breakpoints of u1, strictly increasing (SI)", array=True),
        Param("y_table", "SI", None, None, None, "breakpoints of u2, strictly increasing (SI)", array=True),
        Param("z_table", "SI", None, None, None, "grid values, row-major: z[i*ny + j] at (x[i], y[j]) (SI)", array=True),
        Param("warn_outside", "1", 1.0, 0.0, 1.0, "1: a run whose inputs leave the grid warns; 0: it does not",
              integer=True),
    )
    checked = ("u1", "u2")

    @staticmethod
    def outputs(u1, u2, x_table, y_table, z_table):
        return (interp2(u1, u2, x_table, y_table, z_table),)

    @classmethod
    def valid_ranges(cls, values: dict) -> tuple[ValidRange, ...]:
        if values["warn_outside"] < 0.5:
            return ()
        return tuple(ValidRange(port, float(breaks[0]), float(breaks[-1]), "the grid's edge value is held")
                     for port, breaks in (("u1", values["x_table"]), ("u2", values["y_table"])) if len(breaks) > 1)

    @classmethod
    def check_values(cls, values: dict) -> str | None:
        """None if the parameter values fit together, else what is wrong (build time, not in the hot path)."""
        nx, ny = len(values["x_table"]), len(values["y_table"])
        return (
            check_breakpoints("x_table", values["x_table"])
            or check_breakpoints("y_table", values["y_table"])
            or check_length("z_table", values["z_table"], nx * ny, f"a {nx} x {ny} grid")
        )
