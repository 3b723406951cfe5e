"""Writing an edited YAML file as its author wrote it: only the edited entries change in the text.

A calibration writes new netlists and experiments that differ from the user's file by a few entries (an
added component, a port moved onto a new net, fitted values). Dumped afresh, such a file would lose every
comment, its quotes and its alignment, and ``diff original.yaml augmented.yaml`` would show everything.
Instead the edited document is laid over the original text, entry by entry, by the positions PyYAML's
composer gives each node:

- an entry whose value did not change keeps its text (and the comments around it) byte for byte;
- a changed value is replaced where it stands by the new value in flow style (``[a.b, c.d]``,
  ``{type: orifice, params: {A: "1 mm^2"}}``, ``"59.1 bar"``); a mapping edited inside is edited entry by
  entry, so a changed component parameter changes only that parameter;
- a new entry goes after the last line of its mapping, at its indentation (in a flow mapping: after its
  last entry), in flow style; a new top-level section likewise, after the document's last entry (before
  any comment lines that end the file). New lines take the file's line ending (CRLF or LF).

An edit this cannot place (an entry removed, a document that is not a mapping, one with anchors and
aliases, whose nodes stand in two places) gives None, and so does a text that the project's own reader
(:func:`blocks.netlist.yaml_source.parse_yaml_text`) does not read back as exactly the edited document,
keys in the same order: the caller then writes the document afresh.
"""

from __future__ import annotations

import yaml

from blocks.errors import NetlistError
from blocks.netlist.yaml_source import parse_yaml_text


class _Unplaceable(Exception):
    """An edit this module does not place in the text."""


def dump_over(original_text: str, data: dict) -> str | None:
    """``data`` written over ``original_text`` (see the module's docstring), or None if that cannot be done
    faithfully."""
    try:
        root = yaml.compose(original_text, Loader=yaml.SafeLoader)
    except yaml.YAMLError:
        return None
    if not isinstance(root, yaml.MappingNode) or root.flow_style or not isinstance(data, dict) or _aliased(root):
        return None
    edits: list[tuple[int, int, str]] = []
    try:
        _lay_mapping(root, data, original_text, edits, top=True)
    except _Unplaceable:
        return None
    newline = "\r\n" if "\r\n" in original_text else "\n"
    text = original_text
    # from the end of the text back; of edits at one place the last made first, so that they stand in the
    # order they were made (an entry of a mapping before a section that follows it)
    for _, (start, end, new) in sorted(enumerate(edits), key=lambda e: (e[1][0], e[0]), reverse=True):
        text = text[:start] + new.replace("\n", newline) + text[end:]
    try:
        read = parse_yaml_text(text, "<written>").data
    except NetlistError:
        return None
    return text if read == data and _same_order(read, data) else None


def _aliased(root) -> bool:
    """Whether a node stands in two places (an anchor and its aliases): its position is one of them only."""
    seen: set[int] = set()
    stack = [root]
    while stack:
        node = stack.pop()
        if id(node) in seen:
            return True
        seen.add(id(node))
        if isinstance(node, yaml.MappingNode):
            stack.extend(part for pair in node.value for part in pair)
        elif isinstance(node, yaml.SequenceNode):
            stack.extend(node.value)
    return False


def _same_order(a, b) -> bool:
    """Whether two equal documents have their mappings' keys in the same order."""
    if isinstance(a, dict):
        return list(a) == list(b) and all(_same_order(a[k], b[k]) for k in a)
    if isinstance(a, list):
        return all(_same_order(x, y) for x, y in zip(a, b))
    return True


_CONSTRUCTOR = yaml.SafeLoader("")


def _read(node):
    """The value the project's reader gives a node (keys of mappings as strings)."""
    if isinstance(node, yaml.MappingNode):
        return {_key(k): _read(v) for k, v in node.value}
    if isinstance(node, yaml.SequenceNode):
        return [_read(item) for item in node.value]
    return _CONSTRUCTOR.construct_object(node, deep=True)


def _key(node) -> str:
    if not isinstance(node, yaml.ScalarNode):
        raise _Unplaceable
    return str(_CONSTRUCTOR.construct_object(node, deep=True))


def _same(old, new) -> bool:
    """Equal as read, and of the same type (1 is not 1.0, nor True)."""
    if type(old) is not type(new):
        return False
    if isinstance(new, dict):
        return old.keys() == new.keys() and all(_same(old[k], new[k]) for k in new)
    if isinstance(new, list):
        return len(old) == len(new) and all(_same(a, b) for a, b in zip(old, new))
    return old == new


def _content_end(node) -> int:
    """Where a node's own text ends (a block collection's trailing blank lines and comments excluded)."""
    if isinstance(node, yaml.MappingNode) and not node.flow_style and node.value:
        return _content_end(node.value[-1][1])
    if isinstance(node, yaml.SequenceNode) and not node.flow_style and node.value:
        return _content_end(node.value[-1])
    return node.end_mark.index


def _lay_mapping(node: yaml.MappingNode, new: dict, text: str, edits: list, top: bool = False) -> None:
    entries = {_key(k): (k, v) for k, v in node.value}
    if any(key not in new for key in entries):
        raise _Unplaceable  # an entry removed
    for key, value in new.items():
        if key in entries:
            _lay_value(*entries[key], value, text, edits)
    added = [(key, value) for key, value in new.items() if key not in entries]
    if not added:
        return
    if node.flow_style:
        at = _content_end(node.value[-1][1]) if node.value else node.end_mark.index - 1
        sep = ", " if node.value else ""
        edits.append((at, at, sep + ", ".join(f"{_flow(k)}: {_flow(v)}" for k, v in added)))
        return
    at = text.find("\n", _content_end(node))
    before, at = ("", at + 1) if at >= 0 else ("\n", len(text))
    indent = " " * node.value[0][0].start_mark.column
    lines = [_block_section(k, v) if top and isinstance(v, dict) and v else f"{indent}{_flow(k)}: {_flow(v)}\n"
             for k, v in added]
    edits.append((at, at, before + "".join(lines)))


def _lay_value(key_node, node, new, text: str, edits: list) -> None:
    if isinstance(node, yaml.MappingNode) and isinstance(new, dict):
        _lay_mapping(node, new, text, edits)
        return
    if _same(_read(node), new):
        return
    if isinstance(node, (yaml.MappingNode, yaml.SequenceNode)) and not node.flow_style:
        # a block collection becomes a flow one on the key's line (comments inside it go with it)
        edits.append((key_node.end_mark.index, _content_end(node), f": {_flow(new)}"))
    else:
        edits.append((node.start_mark.index, node.end_mark.index, _flow(new)))


def _block_section(key: str, value: dict) -> str:
    """A new top-level section: a block mapping of flow values."""
    return f"{_flow(key)}:\n" + "".join(f"  {_flow(k)}: {_flow(v)}\n" for k, v in value.items())


class _FlowDumper(yaml.SafeDumper):
    """Flow style throughout; a string with a space in double quotes, as netlists write values with units."""


def _represent_str(dumper, value: str):
    return dumper.represent_scalar("tag:yaml.org,2002:str", value, style='"' if " " in value else None)


_FlowDumper.add_representer(str, _represent_str)


def _flow(value) -> str:
    """One value in flow style on one line, as PyYAML writes it inside a flow collection (so that it reads
    back the same there and in a block): dumped as the one item of a list, whose brackets are then dropped."""
    text = yaml.dump([value], Dumper=_FlowDumper, default_flow_style=True, width=float("inf"), allow_unicode=True,
                     sort_keys=False).rstrip("\n")
    return text[1:-1]
