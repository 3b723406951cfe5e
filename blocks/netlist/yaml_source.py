"""Read YAML safely and remember where every key and value stands (for errors that name line and column).

Only YAML's safe subset is accepted (no tags that build Python objects), duplicate keys are refused, and
the file's size and nesting are bounded so that a hostile or broken file cannot run code or hang the loader.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import yaml

from blocks.errors import NetlistError

MAX_BYTES = 5_000_000
MAX_DEPTH = 50
MAX_NODES = 200_000

Path_ = tuple  # a path into the document: keys and list indices


@dataclass
class Located:
    """A parsed document and the (line, column) of each path in it, 1-based."""

    file: str
    data: object
    positions: dict[tuple, tuple[int, int]] = field(default_factory=dict)

    def where(self, path: tuple) -> tuple[int | None, int | None]:
        """Line and column of ``path``, or of its nearest located ancestor."""
        path = tuple(path)
        while path:
            if path in self.positions:
                return self.positions[path]
            path = path[:-1]
        return self.positions.get((), (None, None))

    def error(self, path: tuple, message: str) -> NetlistError:
        line, col = self.where(path)
        return NetlistError(self.file, message, line, col)


def read_yaml(file: str | Path) -> Located:
    """Parse ``file``; raise :class:`NetlistError` (with line and column) for anything unreadable."""
    name = str(file)
    raw = read_bounded(file, MAX_BYTES)
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise NetlistError(name, f"not UTF-8 text (byte {exc.start})") from None
    return parse_yaml_text(text, name)


def read_bounded(file: str | Path, limit: int) -> bytes:
    """The bytes of a regular file of at most ``limit`` bytes (never an unbounded read of a device)."""
    name = str(file)
    path = Path(file)
    try:
        if not path.exists():
            raise NetlistError(name, "file not found")
        if not path.is_file():
            raise NetlistError(name, "not a regular file" + (" (a folder)" if path.is_dir() else ""))
        with open(path, "rb") as handle:
            raw = handle.read(limit + 1)
    except OSError as exc:
        raise NetlistError(name, f"cannot read file: {exc.strerror}") from None
    if len(raw) > limit:
        raise NetlistError(name, f"file larger than {limit} bytes")
    return raw


def parse_yaml_text(text: str, name: str) -> Located:
    try:
        node = yaml.compose(text, Loader=yaml.SafeLoader)
    except yaml.reader.ReaderError as exc:
        line, col = _line_col(text, exc.position)
        code = exc.character if isinstance(exc.character, int) else ord(exc.character)
        raise NetlistError(name, f"invalid YAML: control character U+{code:04X} is not allowed", line, col) from None
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        problem = (exc.problem or exc.context or "invalid YAML").strip() + _yaml_context(exc)
        line, col = (mark.line + 1, mark.column + 1) if mark else (None, None)
        raise NetlistError(name, f"invalid YAML: {problem}", line, col) from None
    except yaml.YAMLError as exc:
        raise NetlistError(name, f"invalid YAML: {exc}") from None
    except RecursionError:
        raise NetlistError(name, "YAML nested too deeply") from None
    located = Located(name, None)
    if node is None:
        located.data = {}
        return located
    counter = [0]
    located.data = _convert(node, (), located, yaml.SafeLoader(""), counter, 0)
    return located


_UNCLOSED = {"while parsing a flow mapping": "brace", "while parsing a flow sequence": "bracket"}
"""The flow collections whose closing character the hint names: on a later line than the opening one the
parser ran past where it should have closed (an unclosed '{' is noticed at the next key); on the same line
a missing ',' between two entries is as likely ("{type: constant params: ...}")."""


def _yaml_context(exc) -> str:
    """PyYAML's context, said where it starts (" (while parsing a flow mapping that starts at line 19,
    column 12; is its closing brace missing?)"), or "". The hint names the brace in words: quoted, it
    would pair with the problem's quotes where messages are shortened (:func:`blocks.errors.shorten_values`).
    The problem is found where the parser gave up, often the line after the slip (an unclosed '{' is noticed
    at the next key); the context's place is the slip's. A problem on the construct's own line asks whether
    a ',' or the closing brace is missing (see :data:`_UNCLOSED`). A quoted scalar's context comes only with
    the end of the stream or a document separator ('---') reached inside it: its closing quote is missing
    wherever that is (an unknown escape comes with another context, "a double-quoted scalar", and no hint)."""
    context, where = (exc.context or "").strip(), exc.context_mark
    problem = exc.problem_mark
    if not (exc.problem and context and where) or (problem is not None and
                                                    (where.line, where.column) == (problem.line, problem.column)):
        return ""
    hint = None
    if context == "while scanning a quoted scalar":
        hint = "is its closing quote missing?"
    elif context in _UNCLOSED:
        closing = _UNCLOSED[context]
        same_line = problem is not None and problem.line == where.line
        hint = f"is a ',' or its closing {closing} missing?" if same_line else f"is its closing {closing} missing?"
    return f" ({context} that starts at line {where.line + 1}, column {where.column + 1}" + \
        (f"; {hint})" if hint else ")")


def _line_col(text: str, position: int) -> tuple[int, int]:
    before = text[:position]
    return before.count("\n") + 1, position - (before.rfind("\n") + 1) + 1


_PLAIN_TAGS = {"tag:yaml.org,2002:map", "tag:yaml.org,2002:seq"}


def _convert(node, path, located: Located, loader, counter, depth):
    counter[0] += 1
    if counter[0] > MAX_NODES:
        raise NetlistError(located.file, f"more than {MAX_NODES} YAML nodes")
    if depth > MAX_DEPTH:
        raise NetlistError(located.file, "YAML nested too deeply", node.start_mark.line + 1, node.start_mark.column + 1)
    located.positions.setdefault(path, (node.start_mark.line + 1, node.start_mark.column + 1))
    if isinstance(node, (yaml.MappingNode, yaml.SequenceNode)) and node.tag not in _PLAIN_TAGS:
        where = ".".join(str(p) for p in path) or "document"
        raise NetlistError(located.file, f"{where}: YAML tag '{node.tag}' is not allowed (plain data only)",
                           node.start_mark.line + 1, node.start_mark.column + 1)
    if isinstance(node, yaml.MappingNode):
        out = {}
        for key_node, value_node in node.value:
            if not isinstance(key_node, yaml.ScalarNode):
                raise NetlistError(located.file, "mapping keys must be plain names",
                                   key_node.start_mark.line + 1, key_node.start_mark.column + 1)
            key = _scalar(key_node, loader, located)
            if isinstance(key, bool) or key is None:
                key = key_node.value  # a name as written: YAML 1.1 reads `on:`, `off:`, `yes:`, `no:` as booleans
            if key == "<<":
                raise NetlistError(located.file, "YAML merge keys (<<) are not supported",
                                   key_node.start_mark.line + 1, key_node.start_mark.column + 1)
            if not isinstance(key, (str, int, float)) or isinstance(key, bool):
                key = str(key)
            key = str(key)
            if key in out:
                raise NetlistError(located.file, f"duplicate key '{key}'",
                                   key_node.start_mark.line + 1, key_node.start_mark.column + 1)
            located.positions[path + (key,)] = (key_node.start_mark.line + 1, key_node.start_mark.column + 1)
            out[key] = _convert(value_node, path + (key,), located, loader, counter, depth + 1)
        return out
    if isinstance(node, yaml.SequenceNode):
        return [_convert(item, path + (i,), located, loader, counter, depth + 1) for i, item in enumerate(node.value)]
    return _scalar(node, loader, located)


def _scalar(node, loader, located):
    try:
        value = loader.construct_object(node, deep=True)
    except yaml.YAMLError as exc:
        problem = (getattr(exc, "problem", None) or "cannot read this value").splitlines()[0]
        raise NetlistError(located.file, f"invalid value: {problem}", node.start_mark.line + 1,
                           node.start_mark.column + 1) from None
    except (ValueError, IndexError, KeyError, AttributeError):  # PyYAML's own reading of an explicit tag
        # (`!!float` with no value, `!!bool x`, `!!timestamp x`) fails with these rather than a YAMLError
        tag = node.tag.rsplit(":", 1)[-1]
        raise NetlistError(located.file, f"invalid value: {node.value!r} is not a valid !!{tag}",
                           node.start_mark.line + 1, node.start_mark.column + 1) from None
    if isinstance(value, (bytes, bytearray)) or type(value).__module__ == "datetime":
        return str(node.value)
    return value


_PYDANTIC_TAGS = {"str", "float", "int", "list", "dict", "function-after", "function-before", "union"}


def document_path(data, loc, known_fields=None) -> tuple:
    """The part of a pydantic error location that indexes into the document (union tags dropped).

    A last key that is not in the document (missing, or unknown) is kept when it is a field name: one of
    ``known_fields`` if given, else any lower-case identifier that is not a pydantic type tag (not
    ``function-before[_no_boolean(), ...]``)."""
    path, node = [], data
    for item in loc:
        if isinstance(node, dict) and item in node:
            path.append(item)
            node = node[item]
        elif isinstance(node, list) and isinstance(item, int) and 0 <= item < len(node):
            path.append(item)
            node = node[item]
        elif isinstance(node, dict) and isinstance(item, str) and item not in node and (
                item in known_fields if known_fields is not None
                else item[:1].islower() and item.isidentifier() and item not in _PYDANTIC_TAGS):
            path.append(item)  # a key that should be there (missing) or is unknown
            break
    return tuple(path)


def shown_key(key) -> str:
    """A document key as an error message shows it: characters that do not print (a no-break space, a tab)
    escaped, so that a key '\\xa0description' is not read as ' description'."""
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in str(key))


def in_words(error: dict) -> str:
    """A pydantic error's message in the project's own wording, for every file the loaders validate
    (netlists, jobs, experiments): "must be at most 50, got 60", not pydantic's "Input should be less than
    or equal to 50". The one place these are worded; a type not listed here keeps pydantic's message (and
    a custom error, such as a boolean where a number belongs, its own)."""
    kind, ctx, given = error.get("type"), error.get("ctx") or {}, error.get("input")
    got = f", got {_given(given)}" if "input" in error else ""
    if kind in _BOUNDS:
        word, key = _BOUNDS[kind]
        return f"must be {word} {_given(ctx[key])}{got}"
    if kind == "int_from_float":
        return f"must be a whole number{got}"
    if kind in ("int_parsing", "int_type"):
        return f"{_given(given)} is not a whole number"
    if kind in ("float_parsing", "float_type"):
        return f"{_given(given)} is not a number"
    if kind == "finite_number":
        return f"must be a finite number{got}"
    if kind in ("bool_parsing", "bool_type"):
        return f"{_given(given)} is not a boolean: write true or false, unquoted"
    if kind == "literal_error":
        return f"{_given(given)} is not known; allowed: {ctx.get('expected')}"
    if kind in ("string_type", "list_type", "dict_type"):
        wanted = {"string_type": "text", "list_type": "a list", "dict_type": "a mapping"}[kind]
        return f"expected {wanted}, got {_kind(given)}"
    if kind == "model_type":
        return f"expected a mapping, got {_kind(given)}"
    if kind in ("too_short", "too_long"):
        limit = ctx.get("min_length" if kind == "too_short" else "max_length")
        what = "entry" if limit == 1 else "entries"
        side = "at least" if kind == "too_short" else "at most"
        empty = kind == "too_short" and ctx.get("actual_length") == 0
        return (f"empty: give {side} {limit} {what}" if empty
                else f"takes {side} {limit} {what}, got {ctx.get('actual_length')}")
    return error.get("msg", "invalid")


_BOUNDS = {"greater_than": ("greater than", "gt"), "greater_than_equal": ("at least", "ge"),
           "less_than": ("less than", "lt"), "less_than_equal": ("at most", "le")}


def _given(value) -> str:
    """A value from the file as a message quotes it: a number as written, text in quotes."""
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, float) and value.is_integer() and abs(value) < 1e16:
        return f"{value:g}"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, str):
        return f"'{shown_key(value)}'"
    return repr(value)


def _kind(value) -> str:
    """What a value is, for 'expected a list, got ...': "the number 5", "the text 'abc'", "a mapping"."""
    if isinstance(value, bool):
        return f"the boolean {str(value).lower()}"
    if isinstance(value, (int, float)):
        return f"the number {_given(value)}"
    if isinstance(value, str):
        return f"the text {_given(value)}"
    if isinstance(value, dict):
        return "a mapping"
    if isinstance(value, list):
        return "a list"
    return "nothing" if value is None else type(value).__name__


def unknown_key(key, allowed) -> str:
    """'unknown key' with the nearest allowed keys as a question, or, when none is near, all of them."""
    from blocks.units import nearest

    near = nearest(str(key), allowed)
    return f"unknown key '{shown_key(key)}'" + (f" (did you mean {', '.join(near)}?)" if near
                                                else f" (allowed: {', '.join(sorted(allowed))})")


def wrong_kind(located: Located, expected: str) -> NetlistError | None:
    """When the top-level keys clearly mark the file as another kind than ``expected`` (a job given to
    ``vphs run``, a netlist to ``vphs optimise``): an error saying what it is and which command takes it.
    Called once the file has failed to validate, so a file of the right kind is never refused for it."""
    found = _kind_of([str(k) for k in located.data]) if isinstance(located.data, dict) else None
    if found is None or found[0] == expected:
        return None
    kind, keys, command = found
    return NetlistError(located.file, f"this is {kind} (it has {', '.join(k + ':' for k in keys)}), not {expected}; "
                                      f"run it with {command}")


def _kind_of(keys: list[str]) -> tuple[str, list[str], str] | None:
    """(kind, the keys that show it, the command that takes it) from a file's top-level keys, or None."""
    if "netlist" in keys:  # a job or an experiment names the netlist it works on
        for kind, marks, command in (("an optimisation job", ("cost", "algorithm", "sweep"),
                                      "vphs optimise or vphs sweep"),
                                     ("a calibration experiment", ("data",), "vphs calibrate")):
            found = [k for k in keys if k in marks]
            if found:
                return kind, ["netlist", *found], command
        return None
    found = [k for k in keys if k in ("components", "subsystems", "nets")]
    return ("a netlist", found, "vphs run") if found else None
