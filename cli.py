"""The ``vphs`` command.

    vphs validate NETLIST
    vphs run NETLIST [-o results.csv] [--set name=value ...] [--plot out.png [--x SIGNAL] [--y SIGNAL ...]] [--solver S]
                  [--t-end T] [--fixed-step H]
    vphs blocks [TYPE]
    vphs graph NETLIST [-o circuit.png]
    vphs diff SIMULATED REFERENCE.csv [--x COL] [--y COL|SIM=REF ...] [-o table.csv] [--plot overlay.png]
                  [--t-from T] [--t-to T] [--t-end T]
    vphs docs [-o docs/netlist-reference.md]
    vphs optimise JOB [--resume] [--scheduler ADDRESS] [--workers N]
    vphs sweep JOB [--resume] [--scheduler ADDRESS] [--workers N]
    vphs calibrate EXPERIMENT [-o folder]
    vphs linearise NETLIST [--at TIME] [--equilibrium] [--input PARAM ...] [--output SIGNAL ...] [-o modes.csv]

Exit codes: 0 success, 1 the simulation failed (the solver's message says when and where), 2 bad input
(a netlist, a data file, an argument). Errors are one line, never a traceback.
"""

from __future__ import annotations

import argparse
import os
import signal
import sys
import tempfile
import threading
from contextlib import contextmanager
from pathlib import Path

EXIT_FAILED, EXIT_BAD_INPUT = 1, 2


class ArgumentError(Exception):
    pass


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit 2, as for any bad input
        raise ArgumentError(f"vphs: {message} (see 'vphs --help')")


SET_EXPRESSIONS = ("; or an expression over the netlist's parameters, evaluated once with the plain --set values: "
                   "--set Kvp=Kv/4 (repeatable)")
"""What every command's --set help says of expressions (:func:`parse_overrides`)."""


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="vphs", description="Simulate hydraulic machinery described by YAML netlists.")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    p = sub.add_parser("validate", help="check a netlist without running it")
    p.add_argument("netlist")

    p = sub.add_parser("run", help="simulate a netlist")
    p.add_argument("netlist")
    p.add_argument("-o", "--output", help="CSV file for the logged signals (header: name [unit])")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="override a parameter, e.g. --set ctrl.Kp=4 --set 'm_load=15 t'" + SET_EXPRESSIONS)
    p.add_argument("--plot", help="PNG file: the logged signals on a shared time axis")
    p.add_argument("--x", metavar="SIGNAL", help="the plot's abscissa: a logged signal instead of t (p against Q)")
    p.add_argument("--y", action="append", default=[], metavar="SIGNAL",
                   help="a logged signal to plot (repeat for more; default: every one)")
    p.add_argument("--solver", choices=["rodas", "fixed", "lsoda", "bdf", "radau"], help="override the netlist's solver")
    p.add_argument("--t-end", help="override simulation.t_end, e.g. '5 s'")
    p.add_argument("--fixed-step", help="override simulation.fixed_step (the fixed solver's step), e.g. '0.1 ms'")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress or summary on stderr")

    p = sub.add_parser("blocks", help="the block catalogue, or one type in full")
    p.add_argument("type", nargs="?")

    p = sub.add_parser("graph", help="draw the circuit: components and the nets joining them")
    p.add_argument("netlist")
    p.add_argument("-o", "--output", help="PNG file (default: NETLIST with .png)")

    p = sub.add_parser("diff", help="compare simulated curves with data-sheet or measured points")
    p.add_argument("simulated", help="results CSV (as written by 'vphs run -o') or a netlist (.yaml) to run first")
    p.add_argument("reference", help="CSV of reference points, header 'name [unit]', '#' comment lines allowed")
    p.add_argument("--x", default="t", metavar="COL", help="the abscissa (default t); SIM=REF if the names differ")
    p.add_argument("--y", action="append", default=[], metavar="COL",
                   help="a curve to compare, SIM=REF if the names differ (repeatable; default: every reference "
                        "column the simulation also has)")
    p.add_argument("-o", "--output", help="CSV file for the table of errors")
    p.add_argument("--plot", help="PNG file: simulated lines, reference points and the error beneath")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="override a parameter when SIMULATED is a netlist" + SET_EXPRESSIONS)
    p.add_argument("--t-from", metavar="T", help="compare only from this time of the run on, e.g. '2.5 s' (the "
                   "simulated curve, and the reference points too when --x is t)")
    p.add_argument("--t-to", metavar="T", help="compare only up to this time of the run, e.g. '2.5 s' (as --t-from)")
    p.add_argument("--t-end", metavar="T", help="override simulation.t_end when SIMULATED is a netlist, e.g. '5 s'")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress or notes on stderr")

    for name, what in (("optimise", "run a job's optimisation (the Complex method, Nelder-Mead, differential evolution)"),
                       ("sweep", "evaluate a job's parameter sweep (grid or list, one or two parameters)")):
        p = sub.add_parser(name, help=what)
        p.add_argument("job", help="job file (YAML): netlist, parameters, cost, algorithm: / sweep:")
        p.add_argument("--resume", action="store_true", help="continue the job from its evaluation log")
        p.add_argument("--scheduler", metavar="ADDRESS", help="evaluate on a Dask cluster (tcp://host:8786)")
        p.add_argument("--workers", type=int, metavar="N", help="local worker processes (default: every core)")
        p.add_argument("-q", "--quiet", action="store_true", help="no progress on stderr")

    p = sub.add_parser("calibrate", help="fit an experiment's free parameters to measured data, trace the residual "
                                         "to candidate effects and write the augmented netlist")
    p.add_argument("experiment", help="experiment file (YAML, netlists/experiments/): netlist, data, inputs, outputs, free")
    p.add_argument("-o", "--output", help="folder for the report and the netlists (default out/calibrate/<experiment>)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress on stderr")

    p = sub.add_parser("linearise", aliases=["linearize"],
                       help="the circuit linearised about an operating point: modes, state space, frequency response")
    p.add_argument("netlist")
    p.add_argument("--at", metavar="TIME", help="the operating point is the state at this time of the run "
                   "(default: simulation.t_end; the start time: the initial state), e.g. '2 s'")
    p.add_argument("--equilibrium", action="store_true",
                   help="the equilibrium found from there instead, the inputs held at their values at that time")
    p.add_argument("--input", action="append", default=[], metavar="PARAM",
                   help="a parameter taken as an input (a constant command's value, a load); 'PARAM [unit]' for "
                        "the unit the response is given per")
    p.add_argument("--output", action="append", default=[], metavar="SIGNAL",
                   help="a logged signal taken as an output (default: every logged signal)")
    p.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="override a parameter (SI, or with a unit: --set 'm_load=15 t')" + SET_EXPRESSIONS)
    p.add_argument("-o", "--modes", help="CSV file for the modes (eigenvalues, natural frequency, damping, states)")
    p.add_argument("--state-space", metavar="FILE", help="CSV file for the system matrix [[A, B], [C, D]] (SI)")
    p.add_argument("--response", metavar="FILE", help="CSV file for the frequency response (needs --input)")
    p.add_argument("--plot", help="Bode plot of the frequency response (needs --input)")
    p.add_argument("--f-min", default="0.1", metavar="F", help="lowest frequency of the response, Hz (default 0.1)")
    p.add_argument("--f-max", default="1000", metavar="F", help="highest frequency of the response, Hz (default 1000)")
    p.add_argument("--points", type=int, default=400, help="frequencies of the response, log-spaced (default 400)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress or summary on stderr")

    p = sub.add_parser("docs", help="write the netlist reference generated from the block registry")
    p.add_argument("-o", "--output", default="docs/netlist-reference.md")
    return parser


def main(argv: list[str] | None = None, process: bool = False) -> int:
    """Run one `vphs` command; its exit code. ``process``: the command is the whole process (:func:`entry`), so
    a Ctrl-C after its output is complete stays ignored through the interpreter's exit
    (:func:`blocks.interrupt.handling`); a caller in the same process gets its signal handlers back."""
    from blocks.errors import VphsError, SimulationError

    from blocks import interrupt

    try:
        args = build_parser().parse_args(argv)
        with interrupt.handling(process), _standard_output():
            try:
                code = COMMANDS[args.command](args)
            except Exception:
                interrupt.check()  # an error an interrupt caused (a compilation cut short fails later)
                raise
            interrupt.check()  # an interrupt a compiled call swallowed: not a success
            return code
    except ArgumentError as exc:
        _say(exc)
        return EXIT_BAD_INPUT
    except SimulationError as exc:
        _say(f"vphs: {exc}")
        return EXIT_FAILED
    except VphsError as exc:
        _say(f"vphs: {exc}")
        return EXIT_BAD_INPUT
    except KeyboardInterrupt as exc:  # Ctrl-C, or SIGTERM (interrupt.Terminated): stopped alike
        return _interrupted(exc)
    except BrokenPipeError:  # `vphs blocks | head`: the reader left; not an error of ours
        _silence_stdout()  # a pipe named by -o (a FIFO, /dev/stdout) may have been the one
        return 0
    except Exception as exc:  # a bug in vphs, not in the input: still one line unless asked for more
        stop = interrupt.interrupt_of(exc)
        if stop is not None:  # Ctrl-C inside a compiled call comes out as a SystemError
            return _interrupted(stop)
        if os.environ.get("VPHS_DEBUG"):
            raise
        if isinstance(exc, OSError) and exc.filename is not None:  # the file system refused: a full disk, a
            _say(f"vphs: {exc.filename}: {exc.strerror or exc}")  # folder gone mid-run
            return EXIT_FAILED
        _say(f"vphs: internal error: {type(exc).__name__}: {exc} (set VPHS_DEBUG=1 for the traceback)")
        return EXIT_FAILED


class _NamedStdout:
    """Standard output while a command runs: a write or flush the system refuses (``> /dev/full``: a full
    device) is an OSError naming 'standard output', reported as a failed write to a file named by ``-o``
    is (one line, exit 1), not as an internal error; a reader that left stays a BrokenPipeError. Either
    way the output is silenced (:func:`_silence_stdout`): what is left buffered cannot fail again on exit."""

    def __init__(self, stream):
        self._stream = stream

    def __getattr__(self, name):
        return getattr(self._stream, name)

    def write(self, text):
        return self._named(self._stream.write, text)

    def flush(self):
        return self._named(self._stream.flush)

    @staticmethod
    def _named(call, *args):
        try:
            return call(*args)
        except OSError as exc:
            if exc.errno is None:
                raise
            _silence_stdout()
            if isinstance(exc, BrokenPipeError):
                raise
            raise OSError(exc.errno, exc.strerror, "standard output") from None


@contextmanager
def _standard_output():
    """Within: ``sys.stdout`` names itself in its errors (:class:`_NamedStdout`); a command that ends
    normally has what it left buffered written here, so that a reader that left before it
    (`vphs validate | head -c 0`) or a full device is handled as any output's failure, not by the
    interpreter on its way out ("Exception ignored ... BrokenPipeError", exit 120)."""
    original = sys.stdout
    if original is None:
        yield
        return
    sys.stdout = _NamedStdout(original)
    try:
        yield
        sys.stdout.flush()
    finally:
        sys.stdout = original


def _silence_stdout() -> None:
    """Standard output's file descriptor pointed at /dev/null once its reader left (as Python's documentation
    advises for a broken pipe): what is still buffered for it goes nowhere when the interpreter flushes it on
    exit, rather than failing there. A stream without a descriptor (a test's captured output) is left."""
    try:
        fd = sys.stdout.fileno()
    except (AttributeError, ValueError, OSError):
        return
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, fd)
    finally:
        os.close(devnull)


def _interrupted(exc: KeyboardInterrupt) -> int:
    """The one line of a Ctrl-C (exit 130) or a SIGTERM (exit 143)."""
    from blocks import interrupt

    _say(f"vphs: {interrupt.stopped(exc)}; nothing half-written was left behind")
    return interrupt.exit_code(exc)


def entry() -> None:
    """The `vphs` command: :func:`main`, and its exit code. After a Ctrl-C, what an interrupted compilation
    left half-built (llvmlite's objects) may fail to finalise as the interpreter exits: that is not printed
    after the one line."""
    code = main(process=True)
    if code in (130, 143):
        sys.unraisablehook = lambda unraisable: None
    sys.exit(code)


def cmd_validate(args) -> int:
    """Everything `vphs run` checks before simulating: structure, outputs, settings, every value."""
    from blocks.circuit import Circuit

    circuit = Circuit.from_file(args.netlist, compile=False)
    circuit.check_inertia()
    st = circuit.structure
    print(f"{args.netlist}: ok: {len(circuit.flat.components)} components, {len(circuit.flat.nets)} nets, "
          f"{st.n_states} states, {st.theta_size} parameters")
    return 0


def parse_overrides(pairs: list[str], circuit, setting_options: dict[str, str] | None = None,
                    changed: dict[str, str] | None = None) -> dict[str, float]:
    """``name=value`` pairs in SI. A value is a number (SI), ``"<number> <unit>"`` (its unit checked against the
    dimension the netlist gives the parameter) or an expression over the netlist's parameters by their
    qualified names, written as the netlist writes one (``Kv/4``, ``"p_c + 10 bar"``): evaluated once, here,
    with the netlist's values and the plain (number or quantity) ``--set`` values in their place, whatever
    their order on the command line. An expression that reads, itself or through the netlist's expressions,
    another ``--set`` expression, or a parameter in ``changed`` (-> what the command does to it: linearise's
    --input), is refused (it would not follow; the netlist is where such an expression belongs); its own
    name it reads at the netlist's value (``--set 'p_set=p_set + 10 bar'``). Every value is checked against
    the parameter's bounds, and together with the others by :func:`_check_values_with`.

    ``setting_options`` maps a simulation setting to the command's option that sets it (run: t_end to
    --t-end), for the hint when such a setting is given to --set as if it were a parameter."""
    table = circuit.flat.parameters
    plain, expressions, written = {}, {}, {}
    for pair in pairs:
        name, raw = _override_pair(pair, written, circuit, setting_options or {})
        entry = _given_expression(table, name, raw, pair)
        if entry is None:
            plain[name] = _override_value(table, name, raw, pair)
        else:
            expressions[name] = entry
    computed = {}
    if expressions:
        with _set_errors():
            values = _values_with(plain, written, circuit)
            computed = table.given_values(expressions, values, plain, changed or {}, "--set")
        for name, value in computed.items():
            _check_bounds(table, name, value, f"{name}={written[name]}")
    overrides = {name: plain[name] if name in plain else computed[name] for name in written}
    _check_values_with(overrides, written, circuit)
    return overrides


def _values_with(plain: dict[str, float], written: dict[str, str], circuit) -> dict:
    """The netlist's values with the plain ``--set`` values, for its expressions to read. Those the netlist's
    expressions cannot take (a 0 it divides by) are said as :func:`_check_values_with` says them; the blocks'
    checks of their values together wait for the expressions' values (``--set 'p_open=p_set + 10 bar'`` may
    be what makes a higher p_set right)."""
    from blocks.errors import NetlistError

    try:
        return circuit.flat.parameters.evaluate(plain)
    except NetlistError:
        _check_values_with(plain, written, circuit)
        raise


def _override_pair(pair: str, written: dict[str, str], circuit, setting_options: dict[str, str]) -> tuple[str, str]:
    """The name and value text of one ``--set`` pair, the name a parameter that can be set, given once
    (``written``: the values given so far by name, this one added)."""
    from blocks.units import UnitError

    name, sep, raw = pair.partition("=")
    name, raw = name.strip(), raw.strip()
    if not sep or not name or not raw:
        raise ArgumentError(f"vphs: --set '{pair}': expected NAME=VALUE")
    if name in written:
        raise ArgumentError(f"vphs: --set: '{name}' is set twice ({written[name]}, then {raw})")
    written[name] = raw
    table = circuit.flat.parameters
    if name not in table.entries:
        raise ArgumentError(f"vphs: --set '{pair}': unknown parameter '{name}'"
                            + _unknown_parameter_hint(name, table.entries, setting_options, table.derived))
    if name in table.derived:
        raise ArgumentError(f"vphs: --set '{pair}': {name} is derived from {table.derived[name]}: set that instead")
    try:
        table.check_single(name)
    except UnitError as exc:
        raise ArgumentError(f"vphs: --set '{pair}': {exc}") from None
    return name, raw


SET_SOURCE = "--set"
"""The file named by the errors of a ``--set`` expression (:func:`_set_errors` turns them into its own)."""


@contextmanager
def _set_errors():
    """Within: an error located in a ``--set`` value (by :func:`_given_expression`) is said as the command's
    own, one line naming the option; the netlist's own errors stay as they are."""
    from blocks.errors import NetlistError

    try:
        yield
    except NetlistError as exc:
        if exc.file != SET_SOURCE:
            raise
        raise ArgumentError(f"vphs: {exc.message}") from None


def _given_expression(table, name: str, raw: str, pair: str):
    """The expression ``raw`` given by ``--set pair`` for ``name`` (its names and dimension checked), or None
    for a number or a quantity (:func:`_override_value` reads those)."""
    from blocks.netlist.yaml_source import Located

    with _set_errors():
        return table.given_expression(name, raw, Located(SET_SOURCE, None), (), f"--set '{pair}'")


def _override_value(table, name: str, raw: str, pair: str) -> float:
    """A number or ``"<number> <unit>"`` given by ``--set pair`` for ``name``, in SI, inside its bounds."""
    from blocks.units import UnitError

    try:  # value_si refuses a unit the netlist contradicts and a value that is not finite
        value = table.value_si(name, raw)
    except UnitError as exc:
        raise ArgumentError(f"vphs: --set '{pair}': {exc}") from None
    _check_bounds(table, name, value, pair)
    return value


def _check_bounds(table, name: str, value: float, pair: str) -> None:
    """``value`` (SI), given by ``--set pair`` for ``name``, inside the bounds the netlist's block gives it."""
    bounds = table.entries[name].bounds
    problem = bounds.check(value) if bounds is not None else None
    if problem:
        raise ArgumentError(f"vphs: --set '{pair}': {problem}")


def _check_values_with(overrides: dict[str, float], written: dict[str, str], circuit) -> None:
    """The blocks' checks of their values together (p_open above p_set, a start inside the stroke) with the
    --set values. One that fails only with them is the command's error, said with the --set values that
    take part in it: each whose removal makes that failure go (p_set and p_open both set, crossed), not one
    that fails elsewhere too or not at all; all of them if no single one does. The netlist's place alone
    would point at a line that is right as written."""
    from blocks.errors import NetlistError

    def failure(values: dict[str, float]) -> NetlistError | None:
        try:
            circuit.vectors(values)
        except NetlistError as exc:
            return exc
        return None

    with_all = failure(overrides) if overrides else None
    if with_all is None or failure({}) is not None:
        return  # fine, or the netlist's own error: said where it is, when the command evaluates it
    def takes_part(name: str) -> bool:
        without = failure({k: v for k, v in overrides.items() if k != name})
        return without is None or without.message != with_all.message

    culprits = [name for name in overrides if takes_part(name)] or list(overrides)
    sets = ", ".join(f"--set '{name}={written[name]}'" for name in culprits)
    where = str(NetlistError(with_all.file, "", with_all.line, with_all.column)).removesuffix(": ")
    raise ArgumentError(f"vphs: {sets}: {with_all.message} (checked at {where}, right as written there)")


def _unknown_parameter_hint(name: str, entries, setting_options: dict[str, str], derived=()) -> str:
    """' (did you mean ...?)', or for a simulation setting where it is set instead; '' if nothing fits."""
    from blocks.netlist.spec import Simulation
    from blocks.units import nearest

    setting = name.removeprefix("simulation.")
    if setting in Simulation.model_fields:
        option = setting_options.get(setting)
        return (f" (the simulation's {setting} is set with {option})" if option else
                f" ({setting} is a simulation setting: change it in the netlist's simulation: section)")
    if name == "fluid.cavitation":
        return " (fluid cavitation is a switch of the netlist's fluid: section, not a parameter)"
    hint = [n for n in nearest(name, entries) if n not in derived]  # a derived entry is not set
    return f" (did you mean {', '.join(hint)}?)" if hint else ""


PLOT_SUFFIXES = (".png", ".pdf", ".svg")


def check_output_paths(csv_path: str | None, plot_path: str | None, plot_option: str = "--plot",
                       inputs: tuple = ()) -> None:
    """Before any work: each output names a file in a folder that exists (or can be made), plots a format;
    the outputs are two files, and none of them is one of the ``inputs`` (the netlist, the data read).

    The folder is tried with a nameless temporary file: a folder that looks writable may still refuse
    new files (/proc, a read-only mount as root). ``plot_option`` is the option the plot was given with."""
    from blocks.result import special_target

    for target in (csv_path, plot_path):
        if target and os.path.islink(os.path.realpath(target)):
            raise ArgumentError(f"vphs: output '{target}' is a symbolic link that leads back to itself")
    if csv_path and plot_path and _real(csv_path) == _real(plot_path):
        raise ArgumentError(f"vphs: -o and {plot_option} name one file, '{csv_path}': the plot would replace the CSV")
    for target in (csv_path, plot_path):
        if target and any(_real(target) == _real(source) for source in inputs if source):
            raise ArgumentError(f"vphs: output '{target}' is an input of this command; writing it would destroy it")
    for target in (csv_path, plot_path):
        if not target or special_target(target):  # a pipe, a device, a stream: written into, as it is
            continue
        path = _real(target)  # a symbolic link is written through: the folder that counts is its target's
        if path.is_dir():
            raise ArgumentError(f"vphs: output '{target}' is a folder; give a file name")
        parent = next((p for p in [path.parent, *path.parent.parents] if p.exists()), Path("."))
        if not parent.is_dir() or not os.access(parent, os.W_OK):
            raise ArgumentError(f"vphs: cannot write '{target}': {parent} is not a writable folder")
        try:
            with tempfile.TemporaryFile(dir=parent):
                pass
        except OSError as exc:
            raise ArgumentError(f"vphs: cannot write '{target}': {parent} takes no new files "
                                f"({exc.strerror or exc})") from None
    if plot_path and Path(plot_path).suffix.lower() not in PLOT_SUFFIXES:
        raise ArgumentError(f"vphs: {plot_option} '{plot_path}': give a file ending in {', '.join(PLOT_SUFFIXES)}")


def _real(path) -> Path:
    """The file a path names, its symbolic links followed (a loop left as it is, never an exception)."""
    return Path(os.path.realpath(path))


def _is_number(text: str) -> bool:
    try:
        float(text)
        return True
    except ValueError:
        return False


RUN_SETTING_OPTIONS = {"t_end": "--t-end", "solver": "--solver", "fixed_step": "--fixed-step"}
"""The simulation settings vphs run overrides, by the option that does it."""


def _seconds_option(option: str, text: str) -> float:
    """A time given on the command line ('5 s', '0.1 ms', or a number of seconds), finite, in s."""
    import math

    from blocks.units import UnitError, quantity

    try:
        seconds = quantity(float(text) if _is_number(text) else text, "s")
    except UnitError as exc:
        raise ArgumentError(f"vphs: {option} '{text}': {exc}") from None
    if not math.isfinite(seconds):
        raise ArgumentError(f"vphs: {option} '{text}': not a finite time")
    return seconds


def cmd_run(args) -> int:
    from blocks.circuit import Circuit

    for option, given in (("-o", args.output), ("--plot", args.plot)):
        if given is not None and not given.strip():
            raise ArgumentError(f"vphs: {option} '{given}': name a file (without -o the CSV goes to standard output)")
    check_output_paths(args.output, args.plot, inputs=(args.netlist,))
    circuit = Circuit.from_file(args.netlist, quiet=args.quiet, compile=False)
    _check_plot_signals(args, [o.name for o in circuit.outputs])
    overrides = parse_overrides(args.set, circuit, RUN_SETTING_OPTIONS)  # before the (possibly slow) compilation
    circuit.check_inertia(overrides)
    settings = circuit.settings
    if args.solver:
        settings = settings.with_(solver=args.solver)
    if args.t_end is not None:
        settings = settings.with_(t_end=_seconds_option("--t-end", args.t_end))
    if args.fixed_step is not None:
        if settings.solver != "fixed":
            raise ArgumentError(f"vphs: --fixed-step '{args.fixed_step}': the step of the fixed solver, and this run's "
                                f"solver is {settings.solver} (add --solver fixed)")
        settings = settings.with_(fixed_step=_seconds_option("--fixed-step", args.fixed_step))
    problem = settings.problem()
    if problem:
        raise ArgumentError(f"vphs: simulation.{problem[0]} (with --solver/--t-end/--fixed-step): {problem[1]}")
    circuit.compile(quiet=args.quiet)
    try:
        # always in slices (results do not depend on -q); progress shows only for runs longer than 1 s
        result = circuit.simulate(overrides, settings, progress=_progress_printer(silent=args.quiet))
    except KeyError as exc:
        raise ArgumentError(f"vphs: {exc.args[0]}") from None
    for warning in result.warnings:
        print(f"vphs: warning: {warning}", file=sys.stderr)
    if not args.output:
        result.write_csv_into(sys.stdout)
    if args.output and args.plot:  # both or neither: never a CSV of this run beside a plot of the last
        from blocks.result import write_together

        write_together((Path(args.output), result.write_csv_file),
                       (Path(args.plot), lambda tmp: result.plot(tmp, x=args.x, y=args.y)))
    elif args.output:
        result.write_csv(args.output)
    elif args.plot:
        result.plot(args.plot, x=args.x, y=args.y)
    if not args.quiet:
        stats = ", ".join(f"{k} {v}" for k, v in result.stats.items())
        compiled = (f", after {result.compile_seconds:.1f} s compiling (or loading from the cache) the integrator"
                    if result.compile_seconds >= 0.5 else "")
        print(f"vphs: {args.netlist}: {settings.t_end - settings.t_start:g} s simulated in {result.seconds * 1e3:.1f} ms "
              f"({settings.solver}; {stats}{compiled})" + (f"; wrote {args.output}" if args.output else "")
              + (f", {args.plot}" if args.plot else ""), file=sys.stderr)
    return 0


def _check_plot_signals(args, logged: list[str]) -> None:
    """--x and --y choose what --plot draws: logged signals, each once, and only with --plot (--x t: time,
    the default)."""
    if args.x == "t" and "t" not in logged:
        args.x = None if args.plot else args.x
    chosen = ([args.x] if args.x else []) + args.y
    if chosen and not args.plot:
        raise ArgumentError(f"vphs: {'--x' if args.x else '--y'} chooses what --plot draws: give --plot FILE too")
    _check_signals("--x", [args.x] if args.x else [], logged, args.netlist)
    _check_signals("--y", args.y, logged, args.netlist)
    if args.x and args.y == [args.x]:
        raise ArgumentError(f"vphs: --x and --y name only '{args.x}': nothing to plot against it")


_PROGRESS_LINE = {"open": False}  # a progress line on stderr not yet ended by a newline


def _progress_printer(silent: bool):
    """Progress on stderr for runs that take more than a second (nothing for quick ones)."""
    state = {"shown": False}

    def show(fraction: float, seconds: float) -> None:
        if silent or (seconds < 1.0 and not state["shown"]):
            return
        state["shown"] = True
        eta = seconds / fraction - seconds if fraction > 0 else float("nan")
        end = "\n" if fraction >= 1.0 else ""
        print(f"\rvphs: {100 * fraction:5.1f} % simulated, {seconds:6.1f} s elapsed, ~{eta:5.1f} s left",
              end=end, file=sys.stderr, flush=True)
        _PROGRESS_LINE["open"] = not end

    return show


def _say(message) -> None:
    """An error on stderr, on a line of its own (after a progress line the failure interrupted); a long
    value it quotes is cut short (:func:`blocks.errors.shorten_values`: an --set value, an argument)."""
    from blocks.errors import shorten_values

    if _PROGRESS_LINE["open"]:
        print(file=sys.stderr)
        _PROGRESS_LINE["open"] = False
    print(shorten_values(str(message)), file=sys.stderr)


def cmd_blocks(args) -> int:
    from blocks import registry
    from blocks.docs import block_reference

    if args.type:
        try:
            cls = registry.get(args.type)
        except KeyError as exc:
            raise ArgumentError(f"vphs: {exc.args[0]}") from None
        print(block_reference(cls))
        return 0
    for name, cls in registry.all_types().items():
        print(f"{name:24s} {cls.summary()}")
    return 0


def cmd_graph(args) -> int:
    from blocks.graph import draw_circuit
    from blocks.netlist.flatten import flatten

    output = args.output or str(Path(args.netlist).with_suffix(".png"))
    check_output_paths(None, output, plot_option="-o", inputs=(args.netlist,))
    flat = flatten(args.netlist)
    draw_circuit(flat, output)
    print(f"vphs: wrote {output}", file=sys.stderr)
    return 0


def cmd_diff(args) -> int:
    from blocks.compare import (apply_window, check_reference_columns, compare, is_netlist, planned_table, resolve,
                                table_from_result, window_problem)
    from blocks.datafile import read_table

    check_output_paths(args.output, args.plot, inputs=(args.simulated, args.reference))
    netlist = is_netlist(args.simulated)
    for option, given in (("--set", args.set), ("--t-end", args.t_end)):
        if given and not netlist:
            raise ArgumentError(f"vphs: {option} applies only when SIMULATED is a netlist")
    t_from = None if args.t_from is None else _seconds_option("--t-from", args.t_from)
    t_to = None if args.t_to is None else _seconds_option("--t-to", args.t_to)
    problem = window_problem(t_from, t_to)  # an empty window, before reading any file
    if problem:
        raise ArgumentError(f"vphs: {problem}")
    reference = read_table(args.reference)  # a bad reference fails before a long run
    check_reference_columns(reference, args.x, args.y)
    if netlist:
        from blocks.circuit import Circuit

        circuit = Circuit.from_file(args.simulated, quiet=args.quiet, compile=False)
        resolve(planned_table(circuit), reference, args.x, args.y)  # names and units, before the run
        overrides = parse_overrides(args.set, circuit, {"t_end": "--t-end"})  # before the (slow) compilation
        circuit.check_inertia(overrides)
        settings = circuit.settings
        if args.t_end is not None:
            settings = settings.with_(t_end=_seconds_option("--t-end", args.t_end))
            problem = settings.problem()
            if problem:
                raise ArgumentError(f"vphs: simulation.{problem[0]} (with --t-end): {problem[1]}")
        what = f"the run of {args.simulated}" + (" with --t-end" if args.t_end is not None else "")
        problem = window_problem(t_from, t_to, settings.t_start, settings.t_end, what)
        if problem:  # before the run, not after it
            raise ArgumentError(f"vphs: {problem}")
        circuit.compile(quiet=args.quiet)
        result = circuit.simulate(overrides, settings, progress=_progress_printer(silent=args.quiet))
        for warning in result.warnings:
            print(f"vphs: warning: {warning}", file=sys.stderr)
        simulated = table_from_result(result)
    else:
        simulated = read_table(args.simulated)
    window, outside = "", 0
    if t_from is not None or t_to is not None:
        try:
            simulated, reference, window, outside = apply_window(simulated, reference, args.x, t_from, t_to)
        except ValueError as exc:
            raise ArgumentError(f"vphs: {exc}") from None
    comparison = compare(simulated, reference, x=args.x, ys=args.y, window=window, outside=outside)
    if comparison.skipped and not args.quiet:
        print(f"vphs: not compared (not simulated): {', '.join(comparison.skipped)}", file=sys.stderr)
    sys.stdout.write(comparison.format())
    if args.output:
        from blocks.result import atomic_write_text

        atomic_write_text(Path(args.output), comparison.to_csv_text())
    if args.plot:
        comparison.plot(args.plot)
    if not args.quiet and (args.output or args.plot):
        print("vphs: wrote " + ", ".join(f for f in (args.output, args.plot) if f), file=sys.stderr)
    return 0


def cmd_docs(args) -> int:
    from blocks.docs import write_reference

    check_output_paths(args.output, None)
    write_reference(args.output)
    print(f"vphs: wrote {args.output}", file=sys.stderr)
    return 0


def cmd_optimise(args, sweep: bool = False) -> int:
    """vphs optimise|sweep JOB: evaluations logged as they finish; a report at the end (blocks.optimise)."""
    from blocks.optimise.executors import EvaluationLost, terminate_as_interrupt
    from blocks.optimise.job import load_job
    from blocks.optimise.runner import Interrupted, run_optimise, run_sweep

    if args.workers is not None and args.workers < 1:
        raise ArgumentError("vphs: --workers must be at least 1")
    if args.scheduler:
        from blocks.optimise.executors import scheduler_problem

        problem = scheduler_problem(args.scheduler)
        if problem:
            raise ArgumentError(f"vphs: --scheduler '{args.scheduler}': {problem}")
    job = load_job(args.job)
    for warning in job.warnings:  # before the run: what its count of failures would say only at the end
        print(f"vphs: warning: {warning}", file=sys.stderr)
    main_thread = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGTERM, terminate_as_interrupt) if main_thread else None
    try:
        summary = (run_sweep if sweep else run_optimise)(job, resume=args.resume, workers=args.workers,
                                                         scheduler=args.scheduler, quiet=args.quiet)
    except Interrupted as stop:  # Ctrl-C, or SIGTERM (kill, a batch system's time limit)
        _say(f"vphs: {stop.summary.reason}; {_resume_hint(args, stop.summary)}")
        return 128 + signal.SIGTERM if stop.summary.reason == "terminated" else 130
    except EvaluationLost as lost:  # the cluster's fault, not the design's: nothing was logged as failed
        _say(f"vphs: {lost}; {_resume_hint(args, lost.summary)}")
        return EXIT_FAILED
    finally:
        if main_thread:
            signal.signal(signal.SIGTERM, previous)
    from blocks.optimise.display import shown
    from blocks.optimise.report import netlist_comparison, warnings

    for warning in warnings(summary):
        print(f"vphs: warning: {warning}", file=sys.stderr)
    if not sweep and summary.best is not None:  # as report.md says them: a limit the best design breaks
        for warning in summary.best.get("warnings") or []:
            print(f"vphs: warning: the best design: {warning}", file=sys.stderr)
    comparison, warn = netlist_comparison(summary)
    if summary.best is None:
        print(f"vphs: every evaluation failed; see {summary.report}", file=sys.stderr)
        return EXIT_FAILED
    if not args.quiet:
        best = ", ".join(f"{k} = {shown(v, summary.job.units.get(k, ''))}" for k, v in summary.best["parameters"].items())
        ahead = f", {len(summary.discarded)} more evaluated ahead and discarded" if summary.discarded else ""
        repeats = f", {summary.path_repeats} repeats not simulated again" if summary.path_repeats else ""
        print(f"vphs: {summary.reason}: {len(summary.records)} evaluations ({summary.failed} failed{repeats}{ahead}) in "
              f"{summary.seconds:.1f} s; best cost {summary.best['cost']:.6g} at {best}; report {summary.report}",
              file=sys.stderr)
    if comparison and not warn and not args.quiet:
        print(f"vphs: {comparison}", file=sys.stderr)
    return 0


def _resume_hint(args, summary) -> str:
    return (f"{summary.total} evaluations are in {summary.folder}; continue with: "
            f"vphs {args.command} {args.job} --resume")


def cmd_calibrate(args) -> int:
    """vphs calibrate EXPERIMENT: declared fit, residual trace, augmented netlist, report (blocks.calibrate)."""
    from blocks.calibrate.output import check_creatable, replacing
    from blocks.calibrate.report import write
    from blocks.calibrate.experiment import load_experiment
    from blocks.calibrate.run import calibrate, refuse_to_overwrite_inputs

    out = Path(args.output or Path("out") / "calibrate" / Path(args.experiment).stem)
    if out.exists() and not out.is_dir():
        raise ArgumentError(f"vphs: output '{out}' is a file; give a folder")
    check_creatable(out)  # before any work: a folder that cannot be made (-o /proc/x) is the argument's error

    def say(message: str) -> None:
        if not args.quiet:
            print(f"vphs: {message}", file=sys.stderr, flush=True)

    def warn(message: str) -> None:  # what changes how the results read: said even with -q
        print(f"vphs: warning: {message}", file=sys.stderr, flush=True)

    exp = load_experiment(args.experiment)
    refuse_to_overwrite_inputs(exp, out)  # before the previous run's files are moved aside: they may be inputs
    with replacing(out):  # the previous run's files are put back if this one fails or is interrupted
        cal = calibrate(exp, out, progress=say, warn=warn)
        paths = write(cal, out)
    for line in cal.verdict:
        print(line)
    written = list(paths.values()) + [p for p in (cal.calibrated, out / "experiment_augmented.yaml") if p and p.exists()]
    say("wrote " + ", ".join(str(p) for p in written) + f" and the rounds' netlists under {out}")
    return 0


def cmd_linearise(args) -> int:
    import math

    from blocks import linear_report as report
    from blocks.circuit import Circuit
    from blocks.linearise import (at_rest, coupled, frequency_response, linearise, logged_values, modes,
                                  operating_point, steady_gain)
    from blocks.units import parse_unit

    files = {"-o": args.modes, "--state-space": args.state_space, "--response": args.response, "--plot": args.plot}
    _check_linearise_files(files, args.netlist)
    if (args.response or args.plot) and not args.input:
        raise ArgumentError("vphs: --response and --plot show the response to an input: name one with --input PARAM")
    f_min, f_max = _frequency(args.f_min, "--f-min"), _frequency(args.f_max, "--f-max")
    if not 0 < f_min < f_max < math.inf:
        raise ArgumentError(f"vphs: --f-min {args.f_min} and --f-max {args.f_max}: need 0 < f-min < f-max, both finite")
    if not 2 <= args.points <= MAX_RESPONSE_POINTS:
        raise ArgumentError(f"vphs: --points {args.points}: need 2 to {MAX_RESPONSE_POINTS}")
    circuit = Circuit.from_file(args.netlist, quiet=args.quiet, compile=False, regularised=True)
    inputs, in_units = _linear_inputs(args.input, circuit)
    perturbed = {name: f"--input {name} perturbs (the response would leave it out)" for name in inputs}
    overrides = parse_overrides(args.set, circuit, {"t_end": "--at"}, perturbed)
    circuit.vectors(overrides)
    logged = {o.name: o for o in circuit.outputs}
    _check_signals("--output", args.output, logged, args.netlist)
    at = None
    if args.at is not None:
        at = _seconds_option("--at", args.at)
        if at < circuit.settings.t_start:
            raise ArgumentError(f"vphs: --at '{args.at}': before the simulation's start, t_start = "
                                f"{circuit.settings.t_start:g} s in {args.netlist}")
        problem = circuit.settings.with_(t_end=at).problem() if at > circuit.settings.t_start else None
        if problem:  # the run to the operating point is a run like `vphs run --t-end`'s
            raise ArgumentError(f"vphs: --at '{args.at}': {problem[1]}")
    circuit.compile(quiet=args.quiet)
    point = operating_point(circuit, overrides, circuit.settings, at, args.equilibrium)
    for warning in point.warnings:
        print(f"vphs: warning: the run to the operating point: {warning}", file=sys.stderr)
    model = linearise(circuit, point, inputs, args.output or None)
    found = modes(model)
    out_units = [logged[name].display_unit for name in model.output_names]
    from blocks.regularisation import band_notes

    notes = [f"{args.netlist} linearised about {point.how}"] \
        + _linear_notes(model, point, found, circuit.settings.t_end - circuit.settings.t_start) \
        + band_notes(circuit, point)
    for note in notes:
        print(f"# {note}")
    shown = [f"{name} = {value / parse_unit(logged[name].display_unit).factor:.6g}"
             + ("" if logged[name].display_unit == "1" else f" {logged[name].display_unit}")
             for name, value in logged_values(circuit, point).items()]
    print(f"# there: {', '.join(shown)}")
    print(report.modes_table(found))
    reached = coupled(model)
    if inputs and not at_rest(model, point):
        print("steady-state gains: not given (the point is not at rest, so there is no steady state about it; "
              "--equilibrium linearises about one)")
    elif inputs:
        for line in report.steady_gain_lines(model, *steady_gain(model), out_units, in_units):
            print(line)
    for name in [n for k, n in enumerate(inputs) if not model.B[:, k].any() and not model.D[:, k].any()]:
        print(f"vphs: warning: --input {name} moves nothing at this operating point (to first order: it sets "
              f"an initial value, acts only elsewhere in time, or is a mass with no net force on it?)",
              file=sys.stderr)
    writes = []
    if args.modes:
        text = report.modes_csv(found, notes)
        writes.append((Path(args.modes), lambda tmp: tmp.write_text(text, encoding="utf-8")))
    if args.state_space:
        matrix = report.state_space_csv(model)
        writes.append((Path(args.state_space), lambda tmp: tmp.write_text(matrix, encoding="utf-8")))
    if args.response or args.plot:
        freqs = report.frequencies_hz(f_min, f_max, args.points)
        shown = report.response_in_units(model, frequency_response(model, freqs), out_units, in_units)
        if args.response:
            table = report.response_csv(freqs, shown, model, out_units, in_units)
            writes.append((Path(args.response), lambda tmp: tmp.write_text(table, encoding="utf-8")))
        if args.plot:
            writes.append((Path(args.plot), lambda tmp: report.bode_plot(tmp, freqs, shown, model, out_units,
                                                                         in_units, found, reached)))
    if writes:
        from blocks.result import write_together

        write_together(*writes)
        if not args.quiet:
            print(f"vphs: wrote {', '.join(str(path) for path, _ in writes)}", file=sys.stderr)
    return 0


def _check_signals(option: str, names: list[str], logged, netlist: str) -> None:
    """Each of ``names`` (given with ``option``) a logged signal of the netlist, and none named twice."""
    seen = set()
    for name in names:
        if name not in logged:
            raise ArgumentError(f"vphs: {option} '{name}': not a logged signal of {netlist} "
                                f"(logged: {', '.join(logged)})")
        if name in seen:
            raise ArgumentError(f"vphs: {option} '{name}': named twice")
        seen.add(name)


MAX_RESPONSE_POINTS = 100_000  # frequencies of a response: a Bode plot needs hundreds; 1e9 would fill the memory


def _check_linearise_files(files: dict[str, str | None], netlist: str) -> None:
    given = {option: path for option, path in files.items() if path is not None}
    for option, path in given.items():
        if not path.strip() or path.endswith(("/", os.sep)):
            raise ArgumentError(f"vphs: {option} '{path}': name a file")
    seen: dict[Path, str] = {}
    for option, path in given.items():
        resolved = _real(path)
        if resolved in seen:
            raise ArgumentError(f"vphs: {seen[resolved]} and {option} name one file, '{path}'")
        seen[resolved] = option
        check_output_paths(None if option == "--plot" else path, path if option == "--plot" else None,
                           inputs=(netlist,))


def _frequency(text: str, option: str) -> float:
    """A frequency in Hz: a bare number is Hz; '2 Hz', '60 rpm' and '100 rad/s' are converted."""
    from blocks.units import UnitError, quantity

    try:
        return float(text) if _is_number(text) else quantity(text, "rad/s") / (2 * 3.141592653589793)
    except UnitError as exc:
        raise ArgumentError(f"vphs: {option} '{text}': {exc}") from None


def _linear_inputs(written: list[str], circuit) -> tuple[list[str], list[str]]:
    """The --input parameters and the unit each is shown per (its SI unit unless 'name [unit]' was given)."""
    import re

    from blocks.linearise import input_unit
    from blocks.units import UnitError, parse_unit

    names, units = [], []
    entries = circuit.flat.parameters.entries
    for text in written:
        match = re.fullmatch(r"\s*(.*?)\s*\[(.+)\]\s*", text)
        name, unit = (match.group(1), match.group(2).strip()) if match else (text.strip(), None)
        if name not in entries:
            raise ArgumentError(f"vphs: --input '{text}': unknown parameter '{name}'"
                                + _unknown_parameter_hint(name, entries, {}, circuit.flat.parameters.derived))
        if name in names:
            raise ArgumentError(f"vphs: --input '{text}': '{name}' is named twice")
        if entries[name].elements is not None or isinstance(entries[name].constant, tuple):
            raise ArgumentError(f"vphs: --input '{text}': '{name}' is an array (a table); name a single value")
        si = input_unit(circuit, name)
        if unit is not None:
            try:
                same = parse_unit(unit).same_dimension(parse_unit(si))
            except UnitError as exc:
                raise ArgumentError(f"vphs: --input '{text}': {exc}") from None
            if not same and si != "SI":  # a generic parameter ("SI") takes the unit it is given
                raise ArgumentError(f"vphs: --input '{text}': {name} is in {si}, not in a unit like {unit}")
        names.append(name)
        units.append(unit or si)
    return names, units


def _linear_notes(model, point, found, run: float) -> list[str]:
    """What to know about the point: the states that only integrate (a steady motion), a mode that grows
    (an unstable point; a slow growth, one that doubles over more than SLOW_GROWTH times the netlist's ``run``
    [s], said apart), and the fastest-changing state when the point is not at rest."""
    import math

    import numpy as np

    from blocks.linearise import REST, at_rest, integrating

    notes, moving = [], integrating(model, point)
    if moving:
        notes.append(f"in steady motion: {', '.join(moving)} keep{'s' if len(moving) == 1 else ''} integrating "
                     f"and act{'s' if len(moving) == 1 else ''} on nothing else")
    if point.moving:
        names = list(model.state_names)
        held = [names.index(name) for name in point.moving]
        rest = [j for j in range(len(names)) if j not in held and names[j] not in moving]
        acting = model.A[np.ix_(rest, held)]
        drift = acting @ point.rates[held]  # how the others' rates change as the positions move (per s)
        terms = np.abs(acting) @ np.abs(point.rates[held])  # what cancels there when they move together
        own = np.abs(np.diag(model.A)[rest])
        # the rate offset the drift builds over the state's own relaxation time 1/|A_ii|, against rest's
        offset = np.abs(drift) / np.where(own > 0.0, own, np.finfo(float).tiny)
        allowed = REST * model.state_nominal[rest] * np.maximum(1.0, own)
        if np.any((offset > allowed) & (np.abs(drift) > 1e-3 * terms)):
            notes.append(f"a snapshot: as {', '.join(point.moving)} move{'s' if len(held) == 1 else ''}, the "
                         f"others' rest changes (a spring, an end stop, a servo's error still settling): the "
                         f"point holds where {'it is' if len(held) == 1 else 'they are'}, not along the motion")
    fastest = max((abs(m.eigenvalue) for m in found), default=0.0)
    growing = [m for m in found if m.eigenvalue.real > UNSTABLE * fastest]
    slow = [m for m in growing if math.log(2) / m.eigenvalue.real > SLOW_GROWTH * run]
    unstable = [m for m in growing if m not in slow]
    still = at_rest(model, point)
    if unstable:
        lam = max(unstable, key=lambda m: m.eigenvalue.real).eigenvalue
        shown = f"{lam.real:.4g}" + (f" ± {abs(lam.imag):.4g}j" if lam.imag else "")
        notes.append(f"UNSTABLE: {len(unstable)} mode{'s grow' if len(unstable) > 1 else ' grows'} (fastest: "
                     f"lambda = {shown}, doubling in {math.log(2) / lam.real:.3g} s): the circuit leaves this "
                     f"point, and its steady-state gains describe a state it does not stay in")
    if slow:
        lam = max(slow, key=lambda m: m.eigenvalue.real)
        doubling = math.log(2) / lam.eigenvalue.real
        shown = f"{lam.eigenvalue.real:.4g}" + (f" ± {lam.eigenvalue.imag:.4g}j" if lam.oscillating else "")
        what = ("about a point not at rest this is likely the drift of the motion under way (the linear model's "
                "terms that carry the point's own rates: a chamber whose volume changes with the stroke while its "
                "pressure falls), not an instability of the motion" if not still else
                "the point is unstable, but the circuit leaves it far more slowly than the run lasts; its steady-state "
                "gains describe what it does on time scales well below the doubling time")
        notes.append(f"SLOW GROWTH: {len(slow)} mode{'s grow' if len(slow) > 1 else ' grows'}, mainly in "
                     f"{lam.participation[0][0]} (fastest: lambda = {shown}, doubling in {doubling:.3g} s, "
                     f"{doubling / run:.2g} x the netlist's run of {run:g} s): {what}")
    if not still:
        resting = [j for j, name in enumerate(model.state_names) if name not in moving]
        scaled = np.abs(point.rates) / model.state_nominal
        j = resting[int(np.argmax(scaled[resting]))]
        rate, unit = (point.rates[j] / 1e5, "bar") if model.state_units[j] == "Pa" else (point.rates[j], model.state_units[j])
        notes.append(f"not at rest: {model.state_names[j]} changes at {rate:.3g} {unit}/s (the modes describe "
                     f"small motions about this point of the run; --equilibrium linearises about a rest point)")
    return notes


UNSTABLE = 1e-9  # a mode grows when Re(lambda) exceeds this fraction of the fastest |lambda| (not round-off)
SLOW_GROWTH = 100.0
"""A growing mode whose doubling time exceeds this many times the netlist's run (t_end - t_start) is said as a
slow growth, not as UNSTABLE: it grows by under 0.7 % over the whole run (2^(1/100)), which no trace of the run
shows, and about a point the run passes through at rates of its own the linear model cannot tell it from the
point's own change: its terms that carry those rates (a chamber's pressure falling at dp/dt, whose volume the
stroke sets, gives d(dp/dt)/dx = -(dV/dx)/V*dp/dt) are of the size of such a growth. About a held boom creeping
through its counterbalance valve's leak (-0.025 mm/s) they turned the stroke's integrator into a mode doubling
in 2.5e4 s, 4000 runs' time; an unstable servo or a load balanced on its valve doubles within the run."""


COMMANDS = {"validate": cmd_validate, "run": cmd_run, "blocks": cmd_blocks, "graph": cmd_graph, "diff": cmd_diff,
            "optimise": cmd_optimise, "sweep": lambda args: cmd_optimise(args, sweep=True),
            "calibrate": cmd_calibrate, "docs": cmd_docs, "linearise": cmd_linearise, "linearize": cmd_linearise}


if __name__ == "__main__":
    entry()
