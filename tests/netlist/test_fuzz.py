"""Mutated and truncated netlists fed to the loader (hypothesis).

Start from the text of valid netlists (the drive-line example, the three-axes example with its subsystem,
the small base circuit of the error tests and a circuit with subsystems), apply random mutations (truncate
at a byte; delete, duplicate or swap lines; replace a token by one from a pool of names, numbers, units,
YAML punctuation and hostile strings; change indentation; insert random unicode) and load the result as
far as a circuit: ``flatten`` + ``Circuit(...)`` (its generated source checked to be valid Python, not
compiled: see :mod:`netlist_helpers`) + ``circuit.vectors()``.

Every example must end in a valid circuit or a :class:`blocks.errors.VphsError` whose text is ONE line
starting with the name of a netlist file (the mutant, or a file it includes). Anything else -- another
exception, a multi-line message, an example slower than the deadline -- fails the test, and the failure
prints the mutant's text for reproduction.
"""

from __future__ import annotations

import re
import shutil
import signal
from pathlib import Path
from unittest import mock

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from blocks import registry
from blocks.errors import VphsError
from netlist_helpers import CASES, EXAMPLES, load, split_message

BASES = {
    "drive_line": EXAMPLES / "drive_line.yaml",
    "three_axes": EXAMPLES / "three_axes.yaml",
    "base": CASES / "base.yaml",
    "with_subsystem": CASES / "with_subsystem.yaml",
}
TEXTS = {name: path.read_bytes() for name, path in BASES.items()}

_TOKEN = re.compile(rb"[A-Za-z_][A-Za-z0-9_.]*|\d+(?:\.\d+)?(?:[eE][-+]?\d+)?|[^\sA-Za-z0-9_]")

POOL = sorted({t.decode() for text in TEXTS.values() for t in _TOKEN.findall(text)}) + sorted(registry.all_types()) + [
    # numbers
    "0", "-1", "1e400", "-1e400", "1e-320", "nan", ".nan", ".inf", "-.inf", "0x10", "1_000", "3.5", "1e5",
    "99999999999999999999999999", "-0",
    # units and quantities
    '"207 bar"', '"1 l"', '"30 cm^3/rev"', '"12 Hz"', '"207 m^2"', '"1 km^400"', '"1 s^-1"', '"5 barr"', "rpm",
    "m^3/(s*Pa)", "%", '"50 %"', '"1e400 bar"', '"-0.5 l"',
    # expressions
    '"(-8)**(1/3)"', '"9**9**9"', '"1/0"', '"sqrt(-1)"', '"m_load*2"', '"x.y"', '"__import__(\'os\')"',
    '"(lambda: 1)()"', '"[1][0]"', '"a if b else c"',
    # YAML punctuation and structure
    "{", "}", "[", "]", ":", "-", ",", "?", "|", ">", "'", '"', "#", "~", "null", "true", "no", "<<", "&a", "*a",
    "!!python/object/apply:os.system", "!!binary", "!!str", "!!float", "!!map", "!!set", "!custom", "---", "...",
    "%YAML 1.1", "{a: 1}", "[1, 2]", "{csv: missing.csv, column: t}", "''", '""',
    # names that mean something to the loader
    "components", "nets", "subsystems", "ports", "outputs", "parameters", "simulation", "defaults", "fluid",
    "netlist", "mutant.yaml", "restrictor.yaml", "parts/axis.yaml", "type", "params", "initial", "volume",
    "ports", "of", "unit", "t_end", "t_start", "dt_out", "solver", "fixed_step", "rtol",
]

truncate = st.tuples(st.just("truncate"), st.integers(0, 1 << 20))
line_op = st.tuples(st.sampled_from(["delete", "duplicate"]), st.integers(0, 1 << 20))
swap = st.tuples(st.just("swap"), st.integers(0, 1 << 20), st.integers(0, 1 << 20))
token = st.tuples(st.just("token"), st.integers(0, 1 << 20), st.integers(0, 1 << 20), st.sampled_from(POOL))
indent = st.tuples(st.just("indent"), st.integers(0, 1 << 20), st.sampled_from([-4, -2, -1, 1, 2, 4, "\t"]))
insert = st.tuples(st.just("insert"), st.integers(0, 1 << 20), st.text(min_size=1, max_size=8))
MUTATION = st.one_of(token, token, line_op, swap, indent, insert, truncate)


def mutate(doc: bytes, mutations) -> bytes:
    for m in mutations:
        kind = m[0]
        lines = doc.split(b"\n")
        if kind == "truncate":
            doc = doc[: m[1] % (len(doc) + 1)]
        elif kind == "delete":
            del lines[m[1] % len(lines)]
            doc = b"\n".join(lines)
        elif kind == "duplicate":
            i = m[1] % len(lines)
            lines.insert(i, lines[i])
            doc = b"\n".join(lines)
        elif kind == "swap":
            i, j = m[1] % len(lines), m[2] % len(lines)
            lines[i], lines[j] = lines[j], lines[i]
            doc = b"\n".join(lines)
        elif kind == "token":
            i = m[1] % len(lines)
            found = list(_TOKEN.finditer(lines[i]))
            if found:
                t = found[m[2] % len(found)]
                lines[i] = lines[i][: t.start()] + m[3].encode() + lines[i][t.end():]
            doc = b"\n".join(lines)
        elif kind == "indent":
            i = m[1] % len(lines)
            body = lines[i].lstrip(b" ")
            width = len(lines[i]) - len(body)
            lines[i] = b"\t" + lines[i] if m[2] == "\t" else b" " * max(0, width + m[2]) + body
            doc = b"\n".join(lines)
        elif kind == "insert":
            at = m[1] % (len(doc) + 1)
            doc = doc[:at] + m[2].encode("utf-8", "surrogatepass") + doc[at:]
    return doc


@pytest.fixture(scope="module")
def workdir(tmp_path_factory) -> Path:
    """A folder holding the mutant and the unmodified files the bases include."""
    folder = tmp_path_factory.mktemp("fuzz")
    shutil.copy(CASES / "restrictor.yaml", folder / "restrictor.yaml")
    (folder / "parts").mkdir()
    shutil.copy(EXAMPLES / "parts" / "axis.yaml", folder / "parts" / "axis.yaml")
    return folder


def _hang_guard(signum, frame):
    raise TimeoutError("the loader ran for more than 20 s on one example")


def check_mutant(folder: Path, doc: bytes) -> str:
    """Load ``doc`` as ``folder/mutant.yaml``; return 'ok' or the error text; fail on anything else."""
    path = folder / "mutant.yaml"
    path.write_bytes(doc)
    old = signal.signal(signal.SIGALRM, _hang_guard)
    signal.alarm(20)  # a hang becomes a failure even past hypothesis' deadline
    try:
        with mock.patch("os.system") as system:
            try:
                load(path)
                outcome = "ok"
            except VphsError as exc:
                outcome = str(exc)
            except AssertionError as exc:  # load_error's or the helper's own check
                raise AssertionError(f"{exc}\nmutant text: {doc!r}") from None
            except Exception as exc:  # noqa: BLE001  (anything but a VphsError is a bug)
                raise AssertionError(f"{type(exc).__name__}: {exc}\nmutant text: {doc!r}") from None
        assert not system.called, f"a netlist ran os.system\nmutant text: {doc!r}"
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)
    if outcome != "ok":
        try:
            file, _, _, what = split_message(outcome)
        except AssertionError as exc:
            raise AssertionError(f"{exc}\nmutant text: {doc!r}") from None
        named = Path(file)
        assert named == path or (named.is_file() and folder in named.resolve().parents), \
            f"message does not start with a netlist file name: {outcome!r}\nmutant text: {doc!r}"
        assert what.strip(), outcome
    return outcome


FUZZ = settings(max_examples=800, deadline=2000, suppress_health_check=[HealthCheck.too_slow,
                                                                         HealthCheck.function_scoped_fixture])


# ENGINE BUG (reported): these fuzz tests and test_arbitrary_bytes_fail_cleanly currently fail on the
# two-line "unacceptable character" message (see test_control_character_gives_one_line); they are left
# as they are so that, once it is fixed, they go on looking for other faults.
@pytest.mark.parametrize("base", sorted(BASES))
@FUZZ
@given(mutations=st.lists(MUTATION, min_size=1, max_size=4))
def test_mutated_netlists_fail_cleanly(workdir, base, mutations):
    check_mutant(workdir, mutate(TEXTS[base], mutations))


@settings(FUZZ, max_examples=300)
@given(cut=st.integers(0, 1 << 20), base=st.sampled_from(sorted(BASES)))
def test_truncated_netlists_fail_cleanly(workdir, base, cut):
    text = TEXTS[base]
    check_mutant(workdir, text[: cut % (len(text) + 1)])


@settings(max_examples=60, deadline=2000, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(garbage=st.binary(max_size=300) | st.text(max_size=300).map(lambda s: s.encode("utf-8", "surrogatepass")))
def test_arbitrary_bytes_fail_cleanly(workdir, garbage):
    check_mutant(workdir, garbage)


def test_the_bases_are_valid(workdir):
    """The mutations start from valid netlists."""
    for name, text in TEXTS.items():
        assert check_mutant(workdir, text) == "ok", name


def test_billion_laughs_rejected_quickly(workdir):
    """cases/billion_laughs.yaml: nine levels of nine aliases, 9^9 scalars once expanded. The loader must
    refuse it, not expand it (check_mutant's hang guard turns a 20 s run into a failure; it takes well under
    a second)."""
    outcome = check_mutant(workdir, (CASES / "billion_laughs.yaml").read_bytes())
    assert outcome != "ok"
    assert "YAML" in outcome or "alias" in outcome.lower(), outcome


def test_deep_nesting_fails_cleanly(workdir):
    """Deep flow nesting must give a one-line error, not a RecursionError."""
    for depth in (60, 2000):
        outcome = check_mutant(workdir, ("components: " + "[" * depth + "]" * depth + "\n").encode())
        assert outcome != "ok"


def test_control_character_gives_one_line(workdir):
    """A control character is refused by YAML's reader, which PyYAML reports in two lines.

    ENGINE BUG (reported): yaml_source.parse_yaml_text formats a plain yaml.YAMLError (here a ReaderError,
    which has no problem_mark) with str(exc), which spans two lines: 'invalid YAML: unacceptable character
    #x001f: special characters are not allowed\\n  in "<unicode string>", position 0'; and gives no line.
    The fuzz tests above find the same bug through their random insertions.
    """
    doc = TEXTS["base"].replace(b"  tank:   {type: tank}", b"  tank:   {type: \x1ftank}")
    outcome = check_mutant(workdir, doc)
    assert outcome != "ok"
    _, line, col, _ = split_message(outcome)
    text = doc.decode()
    expected_line = text[: text.index("\x1f")].count("\n") + 1
    assert line == expected_line, outcome


def test_a_key_with_an_invisible_character_is_shown_escaped(tmp_path):
    """The fuzzer's find: a no-break space before a top-level key. The message names the file and shows the
    key as \\xa0description, not as ' description'."""
    text = "\xa0description: x\ncomponents: {tank: {type: tank}}\nnets: {T: [tank.port]}\n"
    path = tmp_path / "mutant.yaml"
    path.write_text(text)
    outcome = check_mutant(tmp_path, text.encode())
    assert "unknown key '\\xa0description'" in outcome and outcome.startswith(f"{path}:1:1: \\xa0description:")


@pytest.mark.parametrize("value", ["!!float", "!!float x", "!!int", "!!bool x", "!!timestamp x"])
def test_an_explicit_tag_on_a_value_it_cannot_read_gives_one_line(workdir, value):
    """The fuzzer's find (CI, session 14): `err: !!float` with no value. PyYAML's own reading of an explicit
    tag fails with IndexError, ValueError, KeyError or AttributeError rather than a YAMLError; the loader
    names the file, line and column of the value and the tag."""
    doc = TEXTS["base"].replace(b"  err:   mix.y", f"  err:   {value}".encode())
    assert doc != TEXTS["base"]
    outcome = check_mutant(workdir, doc)
    _, line, col, message = split_message(outcome)
    text = doc.decode()
    assert (line, col) == (text[: text.index(value)].count("\n") + 1, 10), outcome
    assert f"is not a valid !!{value[2:].split()[0]}" in message, outcome
