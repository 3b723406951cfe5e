"""The block registry: YAML ``type`` name -> block class, filled by an explicit decorator.

Nothing is discovered by scanning folders: a block is known because its module was imported and its class
carries ``@register("type_name")``. :mod:`blocks.library` imports the generic library, and
:mod:`vphs_blocks` the crane's components; :func:`load_all` imports both.
"""

from __future__ import annotations

from typing import Callable, TypeVar

from blocks.block import Block, check_declarations
from blocks.units import nearest

B = TypeVar("B", bound=type[Block])

_REGISTRY: dict[str, type[Block]] = {}


def register(type_name: str) -> Callable[[B], B]:
    """Class decorator: check the block's declarations and register it under ``type_name``."""

    def decorate(cls: B) -> B:
        if type_name in _REGISTRY and _REGISTRY[type_name] is not cls:
            raise TypeError(f"block type '{type_name}' registered twice ({_REGISTRY[type_name].__name__}, {cls.__name__})")
        check_declarations(cls)
        cls.type_name = type_name
        _REGISTRY[type_name] = cls
        return cls

    return decorate


def load_all() -> dict[str, type[Block]]:
    """Import the generic library and the crane's blocks; return the registry."""
    import blocks.library  # noqa: F401  (imports register the generic blocks)
    import vphs_blocks  # noqa: F401  (the crane's own components)

    return _REGISTRY


def get(type_name: str) -> type[Block]:
    """The block class for ``type_name``; KeyError with the nearest names if unknown."""
    load_all()
    try:
        return _REGISTRY[type_name]
    except KeyError:
        near = nearest(type_name, _REGISTRY)
        hint = f" (did you mean {', '.join(near)}?)" if near else ""
        raise KeyError(f"unknown block type '{type_name}'{hint}") from None


def all_types() -> dict[str, type[Block]]:
    return dict(sorted(load_all().items()))
