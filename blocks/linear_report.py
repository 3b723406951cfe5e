"""What `vphs linearise` shows and writes: the modes as a table, the state-space model and the frequency
response as CSV (header ``name [unit]``, as every vphs CSV), and a Bode plot.

Units: the state-space CSV is in SI, as the model is; the frequency response is in each output's display
unit (the netlist's ``outputs:`` unit, bar for a pressure) per the unit each input was asked in (its SI unit
unless given as ``--input "name [unit]"``).
"""

from __future__ import annotations

import csv
import io
import math

import numpy as np

from blocks.linearise import GAIN_DEFECTIVE, GAIN_INTEGRATES, GAIN_UNCOUPLED, LinearModel, Mode
from blocks.units import parse_unit

SHOWN_SHARE = 0.05  # a state taking part in a mode is named when its share is at least this
SHOWN_STATES = 4


def ratio_unit(out_unit: str, in_unit: str) -> str:
    """'bar/1' reads badly: a per-unit of a plain number is left out."""
    return out_unit if in_unit == "1" else f"{out_unit}/({in_unit})" if "/" in in_unit or "*" in in_unit \
        else f"{out_unit}/{in_unit}"


def eigenvalue_text(value: complex) -> str:
    if value.imag == 0.0:
        return f"{value.real:.4g}"
    return f"{value.real:.4g} ± {value.imag:.4g}j"


def taking_part(mode: Mode) -> str:
    named = [(s, share) for s, share in mode.participation if share >= SHOWN_SHARE][:SHOWN_STATES]
    return ", ".join(f"{s} {100 * share:.0f} %" for s, share in named)


def modes_table(found: list[Mode]) -> str:
    """The modes as aligned text, lowest |eigenvalue| first."""
    rows = [("#", "f_n [Hz]", "zeta", "tau [s]", "eigenvalue [1/s]", "states (share)")]
    for k, mode in enumerate(found, 1):
        if mode.eigenvalue == 0:
            rows.append((str(k), "-", "-", "inf", "0 (integrator)", taking_part(mode)))
            continue
        rows.append((str(k), f"{mode.natural_frequency:.4g}" if mode.oscillating else "-",
                     f"{mode.damping:.3g}", f"{mode.time_constant:.3g}", eigenvalue_text(mode.eigenvalue),
                     taking_part(mode)))
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]) - 1)]
    return "\n".join("  ".join(cell.ljust(w) for cell, w in zip(r[:-1], widths)) + "  " + r[-1] for r in rows)


def modes_csv(found: list[Mode], notes: list[str] | tuple = ()) -> str:
    """The modes as CSV, one row each, after ``notes`` as comment lines ('# ...', as the data files' and the
    state-space CSV's): the point and what is printed of it (a growing mode, a smoothing band), so the file
    says what the console said."""
    buffer = io.StringIO()
    buffer.writelines(f"# {note}\n" for note in notes)
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(["mode", "real [1/s]", "imag [1/s]", "f_n [Hz]", "zeta [1]", "tau [s]", "states"])
    for k, mode in enumerate(found, 1):
        # blank where the console writes '-': a real mode has no natural frequency, an integrator no zeta
        writer.writerow([k, f"{mode.eigenvalue.real:.10g}", f"{mode.eigenvalue.imag:.10g}",
                         f"{mode.natural_frequency:.10g}" if mode.oscillating else "",
                         "" if mode.eigenvalue == 0 else f"{mode.damping:.6g}", f"{mode.time_constant:.10g}",
                         "; ".join(f"{s} {share:.4f}" for s, share in mode.participation if share >= 1e-4)])
    return buffer.getvalue()


def state_space_csv(model: LinearModel) -> str:
    """The system matrix [[A, B], [C, D]] with named rows and columns, SI."""
    buffer = io.StringIO()
    buffer.write(f"# linearised about {model.point.how}\n"
                 "# rows: d(state)/dt, then the outputs; columns: the states, then the inputs (SI units)\n"
                 "# d(x)/dt = A dx + B du, dy = C dx + D du\n")
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(["row"] + [f"{n} [{u}]" for n, u in zip(model.state_names, model.state_units)]
                    + [f"{n} [{u}]" for n, u in zip(model.input_names, model.input_units)])
    for i, (name, unit) in enumerate(zip(model.state_names, model.state_units)):
        writer.writerow([f"d({name})/dt [{unit}/s]"] + [f"{v:.10g}" for v in model.A[i]]
                        + [f"{v:.10g}" for v in model.B[i]])
    for i, (name, unit) in enumerate(zip(model.output_names, model.output_units)):
        writer.writerow([f"{name} [{unit}]"] + [f"{v:.10g}" for v in model.C[i]] + [f"{v:.10g}" for v in model.D[i]])
    return buffer.getvalue()


def response_in_units(model: LinearModel, response: np.ndarray, out_units: list[str], in_units: list[str]):
    """The response converted from SI to each output's and input's shown unit (same array shape)."""
    out_factor = np.array([parse_unit(u).factor for u in out_units])
    in_factor = np.array([parse_unit(u).factor for u in in_units])
    return response * in_factor[None, None, :] / out_factor[None, :, None]


def response_csv(frequencies: np.ndarray, shown: np.ndarray, model: LinearModel, out_units, in_units) -> str:
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    header = ["f [Hz]"]
    for out, ou in zip(model.output_names, out_units):
        for inp, iu in zip(model.input_names, in_units):
            header += [f"|{out}/{inp}| [{ratio_unit(ou, iu)}]", f"phase {out}/{inp} [deg]"]
    writer.writerow(header)
    phases = phases_deg(shown)
    for i, f in enumerate(frequencies):
        row = [f"{f:.8g}"]
        for a in range(shown.shape[1]):
            for b in range(shown.shape[2]):
                phase = phases[i, a, b]
                row += [f"{abs(shown[i, a, b]):.10g}", f"{phase:.8g}" if math.isfinite(phase) else ""]
        writer.writerow(row)
    return buffer.getvalue()


def phases_deg(shown: np.ndarray) -> np.ndarray:
    """The phase of each response [deg], unwrapped along the frequencies; NaN where the response is 0 (a
    zero has no phase), the unwrapping carried across it."""
    zero = shown == 0
    angle = np.angle(shown)
    for i in range(1, angle.shape[0]):  # a zero takes the angle before it, so it breaks no unwrapping
        angle[i] = np.where(zero[i], angle[i - 1], angle[i])
    phases = np.degrees(np.unwrap(angle, axis=0))
    phases[zero] = np.nan
    return phases


def steady_gain_lines(model: LinearModel, gain: np.ndarray, why: np.ndarray, out_units, in_units) -> list[str]:
    """One line per output and input: the gain at zero frequency, or why there is none
    (:func:`blocks.linearise.steady_gain`)."""
    shown = gain * np.array([parse_unit(u).factor for u in in_units])[None, :] \
        / np.array([parse_unit(u).factor for u in out_units])[:, None]
    reasons = {GAIN_INTEGRATES: "none (it integrates the input)",
               GAIN_DEFECTIVE: "not computed (the states between them have no full set of eigenvectors: a "
                               "free body's speed and position)"}
    lines = []
    for a, out in enumerate(model.output_names):
        for b, inp in enumerate(model.input_names):
            unit = ratio_unit(out_units[a], in_units[b])
            text = reasons.get(why[a, b]) or (f"{shown[a, b]:.6g} {unit}" + (
                " (the input does not reach it)" if why[a, b] == GAIN_UNCOUPLED else ""))
            lines.append(f"steady-state gain {out}/{inp}: {text}")
    return lines


def bode_plot(path, frequencies, shown, model: LinearModel, out_units, in_units, found: list[Mode],
              reached: np.ndarray) -> None:
    """Write to ``path`` (its suffix gives the format): magnitude (log) and phase against frequency, one
    line per output/input pair that the input reaches (``reached``) and whose response is not 0 throughout;
    dotted lines at the natural frequencies of the lightly damped modes (zeta < 0.7) in range."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (mag, phase) = plt.subplots(2, 1, sharex=True, figsize=(9, 6.5), layout="constrained")
    phases = phases_deg(shown)
    drawn = False
    for a, (out, ou) in enumerate(zip(model.output_names, out_units)):
        for b, (inp, iu) in enumerate(zip(model.input_names, in_units)):
            if not reached[a, b] or not shown[:, a, b].any():
                continue
            drawn = True
            label = f"{out}/{inp} [{ratio_unit(ou, iu)}]"
            magnitude = np.abs(shown[:, a, b])
            mag.loglog(frequencies, np.where(magnitude > 0.0, magnitude, np.nan), label=label)  # 0: no point
            phase.semilogx(frequencies, phases[:, a, b], label=label)
    for mode in found:
        if mode.oscillating and mode.damping < 0.7 and frequencies[0] <= mode.natural_frequency <= frequencies[-1]:
            for ax in (mag, phase):
                ax.axvline(mode.natural_frequency, color="grey", linestyle=":", linewidth=1)
    mag.set_ylabel("|G|")
    phase.set_ylabel("phase [deg]")
    phase.set_xlabel("f [Hz]")
    for ax in (mag, phase):
        ax.grid(True, which="both", alpha=0.3)
    if drawn:
        mag.legend(loc="best", fontsize="small")
    else:
        mag.text(0.5, 0.5, "no input reaches an output here", transform=mag.transAxes, ha="center")
    fig.suptitle(f"{model.point.how}"[:110], fontsize="medium")
    try:
        fig.savefig(path, dpi=110)
    finally:
        plt.close(fig)


def frequencies_hz(f_min: float, f_max: float, points: int) -> np.ndarray:
    return np.logspace(math.log10(f_min), math.log10(f_max), points)
