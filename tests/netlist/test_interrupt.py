"""Ctrl-C during compiled code is an interrupt, whatever numba makes of it (blocks/interrupt.py). Found by a
review of `vphs calibrate`: 3 of 30 Ctrl-Cs ended in "internal error: SystemError: CPUDispatcher(...)
returned a result with an exception set", and 1, landing in a ctypes callback during compilation, was
printed as "Exception ignored" and the run went on to exit 0."""

from __future__ import annotations

import os
import signal
from pathlib import Path

import pytest

import cli
from blocks import interrupt
from blocks.circuit import Circuit

STEP = Path(__file__).resolve().parents[1] / "circuits" / "netlists" / "second_order_step.yaml"


def swallowed_sigint():
    """What a ctypes callback does with a KeyboardInterrupt: print it and carry on."""
    try:
        os.kill(os.getpid(), signal.SIGINT)
    except KeyboardInterrupt:
        pass


def test_a_swallowed_interrupt_is_raised_at_the_next_check():
    with interrupt.handling():
        swallowed_sigint()
        with pytest.raises(KeyboardInterrupt):
            interrupt.check()
    interrupt.check()  # outside: nothing noted any more


def test_a_system_error_from_an_interrupted_call_is_told_from_a_bug():
    try:
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as inner:
            raise SystemError("CPUDispatcher(<function integrate>) returned a result with an exception set") from inner
    except SystemError as exc:
        assert interrupt.caused_by_interrupt(exc)
    assert not interrupt.caused_by_interrupt(SystemError("a bug"))


def test_vphs_run_interrupted_during_compilation_stops(tmp_path, capsys, monkeypatch):
    real_compile = Circuit.compile

    def compile_and_swallow(self, quiet=True):
        swallowed_sigint()
        real_compile(self, quiet)

    monkeypatch.setattr(Circuit, "compile", compile_and_swallow)
    code = cli.main(["run", str(STEP), "-q", "-o", str(tmp_path / "r.csv")])
    assert code == 130 and "interrupted" in capsys.readouterr().err
    assert not (tmp_path / "r.csv").exists()


def test_vphs_run_whose_compiled_call_raises_system_error_is_interrupted(tmp_path, capsys, monkeypatch):
    import blocks.solve.run as run

    def interrupted_call(*args, **kwargs):
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as inner:
            raise SystemError("returned a result with an exception set") from inner

    monkeypatch.setattr(run, "_solve_compiled", interrupted_call)
    code = cli.main(["run", str(STEP), "-q", "-o", str(tmp_path / "r.csv")])
    assert code == 130 and "interrupted" in capsys.readouterr().err


def test_an_interrupt_dropped_in_a_callback_then_an_error_is_an_interrupt_and_prints_no_traceback(
        tmp_path, capsys, monkeypatch):
    """Found by a fuzzer (5 of 45 Ctrl-Cs in a 0.1 s window of a first compilation): the KeyboardInterrupt
    raised in llvmlite's object-cache callback was printed as "Exception ignored ... Traceback" and the
    compilation, cut short, failed later with "RuntimeError: no compiled object yet": exit 1, internal
    error. Both now end in the one line of an interrupt."""
    import sys

    def compile_cut_short(self, quiet=True):
        sys.unraisablehook(type("U", (), {"exc_type": KeyboardInterrupt, "exc_value": KeyboardInterrupt(),
                                          "exc_traceback": None, "err_msg": "on calling ctypes callback",
                                          "object": None})())
        raise RuntimeError("no compiled object yet for <Library 'rhs_c'>")

    monkeypatch.setattr(Circuit, "compile", compile_cut_short)
    code = cli.main(["run", str(STEP), "-q", "-o", str(tmp_path / "r.csv")])
    err = capsys.readouterr().err
    assert code == 130 and err == "vphs: interrupted; nothing half-written was left behind\n"
    assert not (tmp_path / "r.csv").exists()
