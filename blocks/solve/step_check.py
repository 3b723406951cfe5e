"""The ``fixed`` solver's check: a second run at twice the step says how far the outputs move.

Nothing controls the error of a fixed step, and a step too long for a circuit rarely fails: it gives other
numbers. ``netlists/components/power_unit.yaml`` at 1 ms runs to its end with ``q_pump`` 8 % of its range
off a tight reference; the 4WRLE servo's step response at 1 ms has ``q_midA`` 46 % off. The method's own
local error estimate does not say so: Rodas4P2 is L-stable, so both its solutions damp a mode faster than
the step alike, and their difference stays small while the mode's transient is lost (the servo at 1 ms:
4e-3 of the pressure's peak per step); where it is large it is also large for steps that are fine (the
counterbalance lowering at 1 ms: 3e4 times the tolerance, outputs within 2e-5 of their range).

So the run is repeated at 2h on the same output samples, and the largest difference of an output, as a
share of that output's range in the run at h, is what is said:

    d_k = max_t |y_k(t; 2h) - y_k(t; h)| / range_k,    range_k = max_t y_k(t; h) - min_t y_k(t; h)

Once h is small enough for the method's order to show, the run at h is off by much less than d (Richardson:
d/(2^p - 1) for an order p, 4 at the steps' ends, 3 for the dense output between them); a step past a fast
mode, or across a kink no block declares, is not in that regime. The warning therefore gives d itself,
which is measured, not a corrected error.
It costs half a run (half as many steps). An output that does not move (range 0) is compared with its own
magnitude, or not at all when it is 0 throughout.
"""

from __future__ import annotations

import numpy as np

from blocks.solve.run import solve

FIXED_STEP_MOVE = 0.01  # share of an output's range that doubling the step may move it by, unsaid


def doubled_step_warning(circuit, vec, settings, outcome) -> str:
    """'' or a line saying how far the outputs move when ``settings.fixed_step`` is doubled (``outcome``:
    the run at the step itself, finished)."""
    step = settings.fixed_step
    coarse = solve(circuit, vec, settings.with_(fixed_step=2.0 * step))
    head = f"simulation.fixed_step {step:g} s may be too long for this circuit"
    advice = "a fixed step has no error control: shorten it, or compare with solver rodas, which controls its error"
    if coarse.status != 0 or not np.all(np.isfinite(coarse.Y)):
        return (f"{head}: at twice the step ({2 * step:g} s) the run fails at t = {coarse.t_reached:.4g} s; "
                f"{advice}")
    logged = len(circuit.outputs)  # not the checked signals observed after them
    share, k, i = _largest_move(outcome.Y[:, :logged], coarse.Y[:, :logged])
    if not share > FIXED_STEP_MOVE:
        return ""
    name = circuit.outputs[k].name
    moved = f"{100 * share:.3g} % of its range" if share < 10 else f"{share:.3g} times its range"
    return f"{head}: at twice the step '{name}' moves by {moved} (at t = {outcome.t[i]:.4g} s); {advice}"


def _largest_move(fine: np.ndarray, coarse: np.ndarray) -> tuple[float, int, int]:
    """(share, output, sample) of the largest |coarse - fine| over each output's range in ``fine``."""
    if fine.size == 0:
        return 0.0, -1, -1
    scale = np.ptp(fine, axis=0)
    flat = ~(scale > 0)
    scale[flat] = np.max(np.abs(fine[:, flat]), axis=0)
    moved = np.abs(coarse - fine)
    with np.errstate(divide="ignore", invalid="ignore"):
        share = np.where(scale > 0, moved / np.where(scale > 0, scale, 1.0), 0.0)
    i, k = np.unravel_index(int(np.argmax(share)), share.shape)
    return float(share[i, k]), int(k), int(i)
