"""A netlist file's shape, validated by the pydantic models of :mod:`blocks.netlist.spec`, and what is wrong
with it said in words at its place (one line, file:line:col): a misspelt key named with its nearest
allowed ones, a value of the wrong shape described (a number, a '<number> <unit>' string, an expression,
a list, {csv: FILE, column: NAME}), a name with spaces around it refused. No meaning yet: the parameters,
subsystems and nets are :mod:`blocks.netlist.flatten`'s.
"""

from __future__ import annotations

from pathlib import Path

from pydantic import ValidationError

from blocks.netlist import spec
from blocks.netlist.yaml_source import Located, document_path, in_words, read_yaml, shown_key, unknown_key, wrong_kind


def load_netlist(file: str | Path) -> spec.Netlist:
    """Parse and validate the shape of one netlist file (no subsystems, no meaning)."""
    return load_spec(read_yaml(file))


def load_spec(located: Located) -> spec.Netlist:
    """The netlist model of a parsed file; its first error said at its place, in words."""
    if not isinstance(located.data, dict):
        raise located.error((), "a netlist must be a mapping with components:, nets:, ...")
    try:
        netlist = spec.Netlist.model_validate(located.data)
    except ValidationError as exc:
        if (other := wrong_kind(located, "a netlist")) is not None:
            raise other from None
        _refuse_padded_names(located)
        errors = exc.errors()  # a boolean read as a value is named as such, whatever else a union tried
        first = next((e for e in errors if e["type"] == spec.NOT_A_NUMBER), errors[0])
        if first["type"] == "missing":  # a misspelt key ('netlst:') is missing and unknown at once: say the latter
            first = next((e for e in errors if e["type"] == "extra_forbidden" and e["loc"][:-1] == first["loc"][:-1]),
                         first)
        path = document_path(located.data, first["loc"])
        where = ".".join(shown_key(p) for p in path) or "netlist"
        message = in_words(first)
        if first["type"] != spec.NOT_A_NUMBER and _is_value_error(first):
            path, message = _value_problem(located.data, document_path(located.data, first["loc"][:-1]), errors)
            where = ".".join(shown_key(p) for p in path)
        elif first["type"] == "extra_forbidden":
            parent = _parent_model(path)
            message = (unknown_key(path[-1], parent.model_fields) if parent is not None
                       else f"unknown key '{shown_key(path[-1])}'" if path else "unknown key")
        elif first["type"] == "missing":
            message = f"missing '{first['loc'][-1]}'"
        elif path[:1] == ("nets",) and len(path) <= 3 and first["type"] != spec.NOT_A_NUMBER:
            message = ("a net is a list of '<component>.<port>' strings, or {ports: [...], volume:, initial:, "
                       "bulk_modulus:}")
        elif first["type"] in ("float_parsing", "int_parsing"):
            message = f"{_shown_value(_at(located.data, path))} is not a number"
        elif path == ("fluid", "cavitation"):
            message = f"{_shown_value(_at(located.data, path))} is not a boolean: write true or false, unquoted"
        raise located.error(path, f"{where}: {message}") from None
    _refuse_padded_names(located)
    return netlist


# the mappings whose keys are names the file chooses (pydantic would strip the spaces around them)
_NAMED = (("parameters",), ("components",), ("subsystems",), ("nets",), ("ports",), ("outputs",))
_NAMED_INSIDE = (("components", "params"), ("components", "initial"), ("subsystems", "parameters"))


def _refuse_padded_names(located: Located) -> None:
    """A name with spaces (or a tab) around it, or an empty one, is refused where written: the schema strips
    the spaces of names, so outputs "x" and "x " became one (the CSV showing the second's values as the
    first's), and a component, net or parameter so written would silently replace another."""
    data = located.data
    places = [path for path in _NAMED if isinstance(_at(data, path), dict)]
    for section, inner in _NAMED_INSIDE:
        named = _at(data, (section,))
        if isinstance(named, dict):
            places += [(section, name, inner) for name, item in named.items()
                       if isinstance(item, dict) and isinstance(item.get(inner), dict)]
    for path in places:
        for key in _at(data, path):
            if not isinstance(key, str) or (key and key == key.strip()):
                continue
            where = ".".join(shown_key(p) for p in path)
            problem = ("a name cannot be empty" if not key.strip() else
                       f"a name may not have spaces around it (it would be read as '{shown_key(key.strip())}')")
            raise located.error(path + (key,), f"{where}: '{shown_key(key)}': {problem}")


def _at(data, path: tuple):
    """The document's value at ``path`` (None where there is none)."""
    for key in path:
        if isinstance(data, dict) and key in data:
            data = data[key]
        elif isinstance(data, list) and isinstance(key, int) and 0 <= key < len(data):
            data = data[key]
        else:
            return None
    return data


_VALUE_TAGS = ("float", "int", "constrained-str")  # the last item of an error location inside a spec.Value


def _is_value_error(error) -> bool:
    """Whether a pydantic error says that something is not a spec.Value (a number, a string); the last item
    of its location is then the type tried, not a key of the document (``{float: 1}`` has one)."""
    return error["type"] in ("float_type", "int_type", "string_type") and bool(error["loc"]) \
        and error["loc"][-1] in _VALUE_TAGS


def _value_problem(data, path: tuple, errors) -> tuple[tuple, str]:
    """(where, what is wrong) for a value of the wrong shape (a mapping, a list, nothing), in words.

    A component parameter may also be a list or ``{csv: FILE, column: NAME}``; a mapping with ``csv:`` or
    ``column:`` is taken as the latter and its missing or unknown key named. ``path``: where the value is."""
    value = _at(data, path)
    if isinstance(value, list):  # a list where one is allowed: the element that is not a value
        inner = [document_path(data, e["loc"][:-1]) for e in errors if _is_value_error(e)]
        element = next((p for p in inner if len(p) > len(path) and p[:len(path)] == path), None)
        if element is not None:
            path, value = element[:len(path) + 1], _at(data, element[:len(path) + 1])
    parameter = len(path) >= 4 and path[0] == "components" and path[2] == "params"
    if parameter and len(path) == 4 and isinstance(value, dict) and {"csv", "column"} & set(value):
        csv = [e for e in errors if "CsvColumn" in e["loc"] and document_path(data, e["loc"][:e["loc"].index(
            "CsvColumn")]) == path]
        for error in csv:
            key = error["loc"][-1]
            if error["type"] == "missing":
                return path, f"missing '{key}' ({{csv: FILE, column: NAME}} reads a column of a data file)"
            if error["type"] == "extra_forbidden":
                return path + (key,), (f"{unknown_key(key, ['csv', 'column'])} in {{csv: FILE, column: NAME}}")
            what = "a file name" if key == "csv" else "a column name"
            return path + (key,), f"must be {what}, not {_kind_of_value(value.get(key))}"
    if parameter and len(path) == 4:
        return path, (f"a parameter value must be a number, a '<number> <unit>' string, an expression, a list "
                      f"of these, or {{csv: FILE, column: NAME}}, not {_kind_of_value(value)}")
    return path, (f"a value must be a number, a '<number> <unit>' string or an expression, not "
                  f"{_kind_of_value(value)}")


def _kind_of_value(value) -> str:
    if isinstance(value, dict):
        keys = ", ".join(f"'{shown_key(k)}'" for k in list(value)[:3]) + (", ..." if len(value) > 3 else "")
        return f"a mapping (with {keys})" if value else "an empty mapping"
    if isinstance(value, list):
        return "a list"
    if value is None:
        return "an empty value"
    return _shown_value(value)


def _shown_value(value) -> str:
    """A document value as a message quotes it."""
    if isinstance(value, bool):
        return str(value).lower()
    return repr(value) if isinstance(value, str) else str(value)


def _parent_model(path: tuple):
    models = {(): spec.Netlist, ("fluid",): spec.Fluid, ("defaults",): spec.Defaults,
              ("simulation",): spec.Simulation}
    if path[:-1] in models:
        return models[path[:-1]]
    if len(path) == 3 and path[0] == "components":
        return spec.Component
    if len(path) == 3 and path[0] == "subsystems":
        return spec.Subsystem
    if len(path) == 3 and path[0] == "nets":
        return spec.Net
    if len(path) == 3 and path[0] == "outputs":
        return spec.Output
    return None
