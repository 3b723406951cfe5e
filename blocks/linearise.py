"""A circuit linearised about an operating point: its state-space model, its modes, its frequency response.

About the operating point (t*, x*, p*) the circuit dx/dt = f(t, x, p), y = g(t, x, p) is, to first order,

    d(dx)/dt = A dx + B du,    dy = C dx + D du
    A = df/dx,  B = df/du,  C = dg/dx,  D = dg/du          (SI units throughout)

where x is the flat state vector (the nets' pressures, the rigid bodies' speeds, the blocks' own states), y
the logged signals and u the parameters named as inputs (the value of a ``constant`` command, a load mass, a
valve's setting). An input is a parameter like any other: it is changed the way an optimiser changes one,
by evaluating the netlist's parameter table with it overridden, so an expression that reads it (a load
``m_L`` in an inertia ``J0 + m_L*r^2``) follows.

Derivatives are central differences: state j is moved by h_j = 1e-6 * max(|x_j|, s_j), s_j its nominal
magnitude (1 bar for a pressure); an input by 1e-6 * |u|, or at u = 0 by 1e-6 of the larger magnitude of
its declared bounds (1e-6 in SI when it has none), one-sided where a step would leave its bounds. An entry
of [A, B] (or [C, D]) within 100 times the rounding of its difference, eps times its row's terms over its
step, is set to 0 (:func:`_drop_round_off`). The model holds t fixed at t*: the inputs that are
functions of time (steps, profiles) are held at their values there.

Modes. The eigenvalues lambda_k of A (computed on A scaled by the states' nominal magnitudes,
S^-1 A S, which has the same eigenvalues and is better conditioned: a circuit's rates span from a spool's
1e3/s to a line's 1e9/s). A complex pair is reported once: its undamped natural frequency
f_n = |lambda|/(2*pi) [Hz], its damping ratio zeta = -Re(lambda)/|lambda| and its time constant
tau = -1/Re(lambda) [s] (the envelope's decay; negative: it grows). A real eigenvalue is shown with no
f_n, its tau likewise, and zeta = +1 (decays) or -1 (grows); one at 0 (|lambda| <= 1e-9 times the
largest) is an integrator (a position, an angle, a quantity the circuit conserves: the oil shut in two
chambers that one piston joins). The states a mode lives in are its
participation factors, p_jk = |l_kj * r_jk| / sum_j |l_kj * r_jk| (r_k, l_k the right and left
eigenvectors): the share of state j in mode k, independent of the states' units.

Frequency response: G(j*w) = C (j*w*I - A)^-1 B + D for each pair of an input and an output, in SI
(e.g. Pa per unit of command); :func:`frequency_response` returns it complex, the reports convert it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg

from blocks.errors import SimulationError, VphsError

STATE_STEP = 1e-6  # relative central-difference step (the optimum for central differences is ~eps^(1/3))
PERTURBATION = 1e-10  # relative change of the linear model's entries that a response must survive (_through_states)
ROUND_OFF = 100 * np.finfo(float).eps  # an entry times its step under this times its row's terms is rounding
INTEGRATOR = 1e-12  # an eigenvalue below this fraction of the largest is taken as 0 (eig's rounding: ~1e-14)
SPLIT = 1e-6
"""A repeated real eigenvalue (a critically damped spool filter's -wn, twice) is found split by eig into a
pair about sqrt(rounding) ~ 1e-8 of its size apart (-75.4 +- 1.6e-6j): an imaginary part under this
fraction of the eigenvalue's size is rounding, and the two are real modes. A pair of zeta above
1 - 5e-13 is no oscillation one could see either."""


@dataclass
class OperatingPoint:
    """Where the circuit is linearised: the time, the state, and how it was found."""

    t: float
    x: np.ndarray
    overrides: dict[str, float]
    how: str  # "the state at t = 2 s of the run", "the equilibrium with the inputs at t = 2 s"
    rates: np.ndarray = field(default_factory=lambda: np.zeros(0))  # f(t, x): zero at an equilibrium
    moving: tuple[str, ...] = ()  # positions held in a steady motion (blocks.steady_motion): not at rest
    warnings: tuple[str, ...] = ()  # the run's to the point (a cavity, a fixed step too long), as vphs run says them


@dataclass
class LinearModel:
    """dx' = A dx + B du, dy = C dx + D du about ``point`` (SI); names and SI units of x, u and y."""

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    state_names: list[str]
    state_units: list[str]
    state_nominal: np.ndarray
    input_names: list[str]
    input_units: list[str]
    output_names: list[str]
    output_units: list[str]
    point: OperatingPoint


@dataclass
class Mode:
    """One eigenvalue of A (a complex pair once, its positive-imaginary member) and where it lives."""

    eigenvalue: complex  # 1/s
    participation: list[tuple[str, float]]  # (state, share), largest first, shares summing to 1

    @property
    def oscillating(self) -> bool:
        return self.eigenvalue.imag > 0.0

    @property
    def natural_frequency(self) -> float:
        """Undamped natural frequency [Hz] of an oscillating pair; 0 for a real eigenvalue."""
        return abs(self.eigenvalue) / (2.0 * math.pi) if self.oscillating else 0.0

    @property
    def damping(self) -> float:
        """Damping ratio: -Re/|lambda| for a pair; +1 (decays) or -1 (grows) for a real eigenvalue; nan at 0."""
        magnitude = abs(self.eigenvalue)
        if magnitude == 0.0:
            return float("nan")
        if not self.oscillating:
            return math.copysign(1.0, -self.eigenvalue.real)
        return -self.eigenvalue.real / magnitude + 0.0  # + 0.0: an undamped pair's zeta is 0, not -0

    @property
    def time_constant(self) -> float:
        """-1/Re(lambda) [s]: the decay of the mode (its envelope for a pair); inf for an integrator."""
        return math.inf if self.eigenvalue.real == 0.0 else -1.0 / self.eigenvalue.real


def operating_point(circuit, overrides: dict[str, float], settings, at: float | None = None,
                    equilibrium: bool = False) -> OperatingPoint:
    """The state the circuit is in at ``at`` (default: the end of its simulation) when run with
    ``settings``; with ``equilibrium``, the equilibrium that Newton's method finds from there with the
    inputs held at their values at that time (a state that only integrates, a position or an angle, may
    keep moving: the steady motion of a machine at a constant speed)."""
    t = settings.t_end if at is None else float(at)
    if t < settings.t_start:
        raise VphsError(f"the operating point's time {t:g} s is before the simulation's start {settings.t_start:g} s")
    warnings: tuple[str, ...] = ()
    if t == settings.t_start:
        x = circuit.vectors(overrides).x0
        how = f"the initial state (t = {t:g} s)"
    else:
        result = circuit.simulate(overrides, settings.with_(t_end=t))
        x = np.array(result.states[-1], dtype=float)
        how = f"the state at t = {t:g} s of the run"
        warnings = tuple(result.warnings)
    moving: tuple[str, ...] = ()
    if equilibrium:  # status 4: at rest but for states that act on nothing and integrate (see integrating())
        found = circuit.equilibrium(overrides, guess=x, t=t)
        if found.status in (0, 4):
            x = np.array(found.states, dtype=float)
            how = f"the equilibrium with the inputs held at their values at t = {t:g} s, found from {how}"
        else:  # no rest point: a steady motion of positions that act on the circuit (a cylinder's stroke)?
            from blocks.steady_motion import steady_motion

            speeds = np.array([slot.kind == "speed" for slot in circuit.structure.states for _ in range(slot.size)])
            motion = steady_motion(lambda state: _rates(circuit, t, state, overrides), x, _state_nominal(circuit),
                                   speeds)
            if motion is None:
                raise SimulationError(f"{circuit.flat.file}: no equilibrium found from {how}: "
                                      f"{EQUILIBRIUM_FAILURE.get(found.status, 'status ' + str(found.status))}")
            x, held = motion
            names = _state_names(circuit)
            moving = tuple(names[j] for j in held)
            held_at = "its value there" if len(moving) == 1 else "their values there"
            how = (f"the steady motion with the inputs held at their values at t = {t:g} s ({', '.join(moving)} "
                   f"moving, held at {held_at} for the others' rest), found from {how}")
    rates = _rates(circuit, t, x, overrides)
    bad = [name for name, value, rate in zip(_state_names(circuit), x, rates)
           if not (math.isfinite(value) and math.isfinite(rate))]
    if bad:
        raise SimulationError(f"{circuit.flat.file}: at {how}, the value or the rate of {', '.join(bad[:6])} is not "
                              f"finite: nothing to linearise (a non-finite initial value, or a rigid body with no "
                              f"mass or inertia?)")
    return OperatingPoint(t, x, dict(overrides), how, rates, moving, warnings)


EQUILIBRIUM_FAILURE = {
    1: "the Jacobian is singular there (no isolated equilibrium: oil shut in between two chambers, or a "
       "state that rests anywhere; linearise about the state of the run instead, without --equilibrium)",
    2: "Newton's method did not converge (run longer, --at a later time, to start nearer one)",
    3: "a value became infinite or not a number",
}


def linearise(circuit, point: OperatingPoint, inputs: list[str] | tuple = (),
              outputs: list[str] | None = None) -> LinearModel:
    """A, B, C, D about ``point``; ``inputs`` are parameter names, ``outputs`` logged signals (default all)."""
    module = circuit.module
    names = _state_names(circuit)
    out_names = [o.name for o in circuit.outputs]
    chosen = out_names if outputs is None else list(outputs)
    rows = [out_names.index(name) for name in chosen]
    theta = circuit.vectors(point.overrides).theta
    x0, t = point.x, point.t
    n = x0.size

    def f(x, th):
        dx = np.zeros(n)
        module.rhs(t, x, th, dx)
        return dx

    def g(x, th):
        y = np.zeros(circuit.n_observed)
        module.observe(t, x, th, y)
        return y[rows]

    nominal = _state_nominal(circuit)
    state_step = STATE_STEP * np.maximum(np.abs(x0), nominal)
    A = np.zeros((n, n))
    C = np.zeros((len(rows), n))
    for j in range(n):
        h = state_step[j]
        xp, xm = x0.copy(), x0.copy()
        xp[j] += h
        xm[j] -= h
        A[:, j] = (f(xp, theta) - f(xm, theta)) / (2.0 * h)
        C[:, j] = (g(xp, theta) - g(xm, theta)) / (2.0 * h)
    B = np.zeros((n, len(inputs)))
    D = np.zeros((len(rows), len(inputs)))
    input_value, input_step = np.zeros(len(inputs)), np.zeros(len(inputs))
    for k, name in enumerate(inputs):
        value = circuit.flat.parameters.evaluate(point.overrides)[name]
        low, high = _input_span(circuit, name, value)
        input_value[k], input_step[k] = value, (high - low) / 2.0
        up = circuit.vectors({**point.overrides, name: high}).theta
        down = circuit.vectors({**point.overrides, name: low}).theta
        B[:, k] = (f(x0, up) - f(x0, down)) / (high - low)
        D[:, k] = (g(x0, up) - g(x0, down)) / (high - low)
    steps, values = np.concatenate([state_step, input_step]), np.concatenate([x0, input_value])
    _drop_round_off(A, B, steps, values, f(x0, theta))
    _drop_round_off(C, D, steps, values, g(x0, theta))
    units = {o.name: o.unit for o in circuit.outputs}
    return LinearModel(A, B, C, D, names, _state_units(circuit), nominal, list(inputs),
                       [input_unit(circuit, name) for name in inputs], chosen, [units[o] for o in chosen], point)


def modes(model: LinearModel) -> list[Mode]:
    """The eigenvalues of A, each complex pair once, lowest |eigenvalue| first, with the states taking part."""
    values, left, right = _eigen(model)
    found = []
    for k, value in enumerate(values):
        if value.imag < 0.0:
            continue
        weights = np.abs(left[k] * right[:, k])
        total = weights.sum()
        shares = weights / total if total > 0 else weights
        order = np.argsort(-shares)
        found.append(Mode(complex(value), [(model.state_names[j], float(shares[j])) for j in order]))
    found.sort(key=lambda m: (abs(m.eigenvalue), m.eigenvalue.imag))
    return found


def _scaled(model: LinearModel) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A, B, C for the states divided by their nominal magnitudes (x = S z): the same eigenvalues and
    transfer functions, better conditioned (a circuit's rates span from a spool's 1e3/s to a line's 1e9/s)."""
    scale = model.state_nominal
    return model.A * scale[None, :] / scale[:, None], model.B / scale[:, None], model.C * scale[None, :]


def _eigen(model: LinearModel) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`_eig` of the scaled A."""
    return _eig(_scaled(model)[0])


def _eig(A: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Eigenvalues (those under INTEGRATOR times the largest set to 0, an imaginary part under SPLIT times
    the eigenvalue's size to 0), left eigenvectors as rows normalised to l_k r_k = 1, right eigenvectors as
    columns."""
    if A.size == 0:
        return np.zeros(0, dtype=complex), np.zeros((0, 0), dtype=complex), np.zeros((0, 0), dtype=complex)
    values, vl, vr = scipy.linalg.eig(A, left=True, right=True)
    values = np.where(np.abs(values) <= INTEGRATOR * np.max(np.abs(values)), 0.0j, values)
    values = np.where(np.abs(values.imag) <= SPLIT * np.abs(values), values.real + 0.0j, values)
    left = vl.conj().T
    norms = np.einsum("kj,jk->k", left, vr)
    left = left / np.where(norms == 0, 1.0, norms)[:, None]
    return values, left, vr


def frequency_response(model: LinearModel, frequencies_hz: np.ndarray) -> np.ndarray:
    """G(j*2*pi*f) = C (j*w*I - A)^-1 B + D for each frequency [Hz] (:func:`_through_states`: a part the
    model does not determine is 0): an array (frequencies, outputs, inputs), complex, SI."""
    A, B, C = _scaled(model)
    n = A.shape[0]
    response = np.empty((len(frequencies_hz), model.C.shape[0], model.B.shape[1]), dtype=complex)
    through = _through_any_state(A, B, C)  # an input that reaches no state the output reads: 0
    for i, f in enumerate(frequencies_hz):
        response[i] = np.where(through, _through_states(2j * math.pi * f * np.eye(n) - A, B, C), 0.0) + model.D
    return response


GAIN_INTEGRATES, GAIN_UNCOUPLED, GAIN_DEFECTIVE = "integrates", "uncoupled", "defective"


def steady_gain(model: LinearModel) -> tuple[np.ndarray, np.ndarray]:
    """The gain at zero frequency per output and input (SI), and why there is none where there is not.

    For each pair, on the states the input reaches and the output sees (:func:`_reaching`; the rest cannot
    take part), A_r, B_r, C_r: G(0) = D - C_r A_r^-1 B_r, by a solve (:func:`_through_states`: a part the
    model does not determine is 0). Modes at 0 (integrators, |lambda| <= 1e-12 times the largest) are taken out first:
    with P0 the projector onto their eigenvectors along the others, G(0) = D - C_r (A_r + P0)^-1 (I - P0) B_r,
    A_r on the other modes. Returns (gain, why), why per pair "" (a gain), GAIN_INTEGRATES (a mode at 0 that
    the input drives and the output sees: the output integrates the input, gain NaN), GAIN_UNCOUPLED (the
    input does not reach the output: gain 0) or GAIN_DEFECTIVE (the modes at 0 have no full set of
    eigenvectors, a Jordan block such as a free body's speed and position: gain NaN).

    A mode at 0 that the input does not drive, or the output does not see, leaves the gain finite: the
    piston position of a cylinder whose flow is the input integrates, but the pressure behind a relief
    valve does not. (A bare solve would call every such circuit singular.) The other modes are not summed
    one by one: two equal filters in series have nearly parallel eigenvectors, and their modal terms, 1e7
    each, summed to 0.77 for a gain of 1."""
    A, B, C = _scaled(model)
    n_out, n_in = model.D.shape
    gain = np.array(model.D, dtype=float)
    why = np.full((n_out, n_in), "", dtype=object)
    for a in range(n_out):
        for b in range(n_in):
            states = _reaching(A, B[:, b], C[a])
            if not states.any():
                why[a, b] = "" if model.D[a, b] != 0.0 else GAIN_UNCOUPLED
                continue
            A_r, B_r, C_r = A[np.ix_(states, states)], B[states, b:b + 1], C[a:a + 1, states]
            values, left, right = _eig(A_r)
            zero = values == 0
            projector = np.zeros_like(A_r)
            if zero.any():
                R, L = right[:, zero], left[zero]
                if np.linalg.cond(R) > 1e12:
                    gain[a, b], why[a, b] = np.nan, GAIN_DEFECTIVE
                    continue
                projector = (R @ np.linalg.solve(L @ R, L)).real
                # the output integrates what reaches it through the modes at 0, C_r P0 B_r (taken together:
                # two integrators of one input, one subtracted from the other, integrate nothing)
                integrated = abs((C_r @ projector @ B_r)[0, 0])
                if integrated > 1e-8 * np.linalg.norm(C_r) * np.linalg.norm(projector, 2) * np.linalg.norm(B_r):
                    gain[a, b], why[a, b] = np.nan, GAIN_INTEGRATES
                    continue
            rest = np.eye(len(A_r)) - projector
            gain[a, b] = model.D[a, b] + _through_states(-(A_r + projector), rest @ B_r, C_r)[0, 0].real
    return gain, why


def _through_states(M: np.ndarray, B: np.ndarray, C: np.ndarray) -> np.ndarray:
    """C M^-1 B, with each part that the model does not determine set to 0.

    The entries of M and B are differences, good to about 1e-10 of themselves. A part that moves by more
    than a tenth of itself when they move by that much (each entry scaled by 1 +- 1e-10, signs fixed and
    random) is not determined by them: the rounding of a cancellation, not a response: a symmetric piston fed the same
    pressure on both sides read 1e-25 mm/Pa at a random phase. A small part computed accurately stays:
    eight low-passes in series at 100 times their corner give 1e-16 of their input."""
    through = C @ np.linalg.solve(M, B)
    signs = np.random.default_rng(0)
    M2 = M * (1.0 + PERTURBATION * signs.choice((-1.0, 1.0), M.shape))
    B2 = B * (1.0 + PERTURBATION * signs.choice((-1.0, 1.0), B.shape))
    moved = np.abs(C @ np.linalg.solve(M2, B2) - through)
    return np.where(np.abs(through) <= 10.0 * moved, 0.0, through)


def coupled(model: LinearModel) -> np.ndarray:
    """Per output and input: does the input reach the output at all (D, or states the input moves that the
    output reads, through A's couplings)? False is an exact zero transfer function."""
    return (model.D != 0.0) | _through_any_state(*_scaled(model))


def _through_any_state(A: np.ndarray, B: np.ndarray, C: np.ndarray) -> np.ndarray:
    """Per output and input: is there a state the input moves that the output reads (:func:`_reaching`)?"""
    return np.array([[_reaching(A, B[:, b], C[a]).any() for b in range(B.shape[1])] for a in range(C.shape[0])],
                    dtype=bool).reshape(C.shape[0], B.shape[1])


def _reaching(A: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """The states on a path from the input (column b of B) to the output (row c of C) through A's nonzero
    couplings (x_j acts on x_i where A[i, j] != 0): those the input moves and that move the output."""
    def closure(start: np.ndarray, links: np.ndarray) -> np.ndarray:
        found = start.copy()
        while True:
            grown = found | (links @ found > 0)
            if (grown == found).all():
                return found
            found = grown

    links = A != 0.0
    return closure(b != 0.0, links.astype(int)) & closure(c != 0.0, links.T.astype(int))


def input_unit(circuit, name: str) -> str:
    """The SI unit of a parameter: the unit its block declares; for a netlist parameter or a generic one
    ("SI": a constant's value), that of the quantity it was written with; "1" for a bare number, "SI" for a
    generic parameter written as a bare number or an expression."""
    from blocks.units import GENERIC, si_name

    entry = circuit.flat.parameters.entries[name]
    if entry.unit is not None and entry.unit != GENERIC:
        return entry.unit
    if entry.dims is None:  # a bare number (or an expression, whose dimension is not kept)
        return "1" if entry.unit is None else GENERIC
    return si_name(entry.dims)


def _drop_round_off(on_states: np.ndarray, on_inputs: np.ndarray, steps: np.ndarray, values: np.ndarray,
                    at_point: np.ndarray) -> None:
    """Set to 0, in place, the entries of M = [on_states, on_inputs] (A and B, or C and D) that are the
    central differences' rounding, not a coupling.

    Row i's terms are about T_i = max(|f_i|, max_j |M_ij|*(|v_j| + h_j)) in size where the differences
    evaluate it (``at_point`` f_i at the point, v_j each state's and input's value there, h_j its step,
    ``steps``). A difference over h_j rounds by about eps*T_i/h_j; an entry within 100 times that is the
    rounding, and is 0. (A load mass on a body at rest
    with no net force on it read 4.6e-37 (m/s^2)/kg, and a pressure per kg of 2e-37 bar followed; a command
    of 1e-9, or a gain of 1e-9 between two filters, is a coupling of its own size and is kept.)"""
    M = np.hstack([on_states, on_inputs])
    if M.size == 0:
        return
    terms = np.maximum(np.abs(at_point), np.max(np.abs(M) * (np.abs(values) + steps)[None, :], axis=1))
    rounding = np.abs(M) * steps[None, :] <= ROUND_OFF * terms[:, None]
    n = on_states.shape[1]
    on_states[rounding[:, :n]] = 0.0
    on_inputs[rounding[:, n:]] = 0.0


def _input_span(circuit, name: str, value: float) -> tuple[float, float]:
    """The two values of an input the difference is taken between: value -+ h, h = 1e-6 of the value (at 0,
    of the larger magnitude of its declared bounds, else of 1 in SI); one-sided (value itself on one end)
    where a step would leave the declared bounds (an efficiency at 1)."""
    bounds = circuit.flat.parameters.entries[name].bounds
    lower, upper = getattr(bounds, "lower", None), getattr(bounds, "upper", None)
    ends = [abs(b) for b in (lower, upper) if b]
    h = STATE_STEP * (abs(value) if value != 0.0 else max(ends) if ends else 1.0)
    low, high = value - h, value + h
    if upper is not None and high > upper:
        high = value
    if lower is not None and (low < lower or (low <= lower and getattr(bounds, "positive", False))):
        low = value
    return low, high


REST = 1e-6  # a state whose rate would be undone by a step of this fraction of its nominal size is at rest


def integrating(model: LinearModel, point: OperatingPoint) -> list[str]:
    """The states that keep integrating at the point and act on nothing: those whose column of A is zero (no
    state, itself included, depends on them) and whose rate is not (an integrator of a constant command, a
    position sensor's angle; an equilibrium leaves them moving): a steady motion, not a transient."""
    acting = np.any(model.A != 0.0, axis=0)
    return [name for j, name in enumerate(model.state_names) if not acting[j] and point.rates[j] != 0.0]


def at_rest(model: LinearModel, point: OperatingPoint) -> bool:
    """Whether every state is at rest at the point, those that only integrate (:func:`integrating`) and the
    positions of a steady motion (``point.moving``) apart:
    |dx_j/dt| <= REST * s_j * max(1/s, |A_jj|), the rate that an offset of REST * s_j from rest makes (an
    equilibrium found to Newton's tolerance leaves a stiff node, 3e8/s, a rate of a few Pa/s)."""
    moving = set(integrating(model, point)) | set(point.moving)
    resting = [j for j, name in enumerate(model.state_names) if name not in moving]
    if not resting:
        return True
    allowed = REST * model.state_nominal[resting] * np.maximum(1.0, np.abs(np.diag(model.A)[resting]))
    return bool(np.all(np.abs(point.rates[resting]) <= allowed))


def logged_values(circuit, point: OperatingPoint) -> dict[str, float]:
    """The logged signals at the operating point, SI, by name."""
    y = np.zeros(circuit.n_observed)
    circuit.module.observe(point.t, np.asarray(point.x, dtype=float), circuit.vectors(point.overrides).theta, y)
    return {o.name: float(v) for o, v in zip(circuit.outputs, y)}


def _rates(circuit, t, x, overrides) -> np.ndarray:
    dx = np.zeros(x.size)
    circuit.module.rhs(t, np.asarray(x, dtype=float), circuit.vectors(overrides).theta, dx)
    return dx


def _state_names(circuit) -> list[str]:
    return [slot.name if slot.size == 1 else f"{slot.name}[{i}]"
            for slot in circuit.structure.states for i in range(slot.size)]


def _state_units(circuit) -> list[str]:
    return [slot.unit for slot in circuit.structure.states for _ in range(slot.size)]


def _state_nominal(circuit) -> np.ndarray:
    return np.array([slot.nominal for slot in circuit.structure.states for _ in range(slot.size)], dtype=float)
