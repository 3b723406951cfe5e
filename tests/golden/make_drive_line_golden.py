"""Write the drive line's golden traces from the independent hand-written model (not from vphs).

The golden file is the reference circuit of issue 2 written out by hand as one function
(`bench/drive_line_reference.py`) and solved with scipy's Radau at rtol 1e-10, so the golden test compares
the netlist + compiler + Rodas path against equations that share no code with them.

    python tests/golden/make_drive_line_golden.py
"""

import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "bench"))

import drive_line_reference as ref  # noqa: E402


def main() -> None:
    for V, tag in ((1e-3, "1l"), (2e-5, "0.02l")):
        t, y = ref.reference(V)
        keep = slice(None, None, 10)  # 10 ms
        table = np.column_stack([t[keep], ref.bridge_position(y)[keep] * 1e3, y[2][keep] / 1e5, y[3][keep] / 1e5,
                                 y[4][keep]])
        path = os.path.join(HERE, f"drive_line_{tag}.csv")
        header = ("# Golden traces of the reference drive line (issue 2), V = %g m^3 per line, from the hand-written\n"
                  "# model bench/drive_line_reference.py solved by scipy Radau rtol 1e-10 (make_drive_line_golden.py).\n"
                  "t [s],x [mm],pA [bar],pB [bar],speed [rad/s]") % V
        np.savetxt(path, table, delimiter=",", header=header, comments="", fmt="%.10g")
        print("wrote", path)


if __name__ == "__main__":
    main()
