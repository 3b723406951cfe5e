"""A safe evaluator for the arithmetic in netlists: ``"0.085 + m_load*r_p**2/n_g**2"``.

Only numbers, parameter names, + - * / ** %, unary signs, parentheses, comparisons inside ``min``/``max``
style calls and a fixed table of math functions are accepted. A name may be dotted, ``supply.p``: a
parameter of a component (or a net's written ``initial``) of the same netlist, read as one name. The
text is parsed with :mod:`ast` and walked by hand; ``eval`` is never called, subscripts, lambdas and
everything else are refused, so a netlist can run no code. All numbers are floats, so ``9**9**9``
overflows at once instead of hanging.
"""

from __future__ import annotations

import ast
import math
import operator
from dataclasses import dataclass

FUNCTIONS = {
    "sqrt": math.sqrt, "exp": math.exp, "log": math.log, "log10": math.log10, "abs": abs,
    "sin": math.sin, "cos": math.cos, "tan": math.tan, "asin": math.asin, "acos": math.acos,
    "atan": math.atan, "atan2": math.atan2, "tanh": math.tanh, "hypot": math.hypot,
    "min": min, "max": max, "floor": math.floor, "ceil": math.ceil,
    "radians": math.radians, "degrees": math.degrees,
}
CONSTANTS = {"pi": math.pi, "e": math.e}

_BINARY = {
    ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
    ast.Pow: operator.pow, ast.Mod: operator.mod,
}
_UNARY = {ast.UAdd: operator.pos, ast.USub: operator.neg}
_MAX_LENGTH = 2000


class ExpressionError(ValueError):
    """An expression that cannot be parsed or evaluated."""


@dataclass(frozen=True)
class Expression:
    """A parsed expression; :attr:`names` are the parameter names it reads."""

    text: str
    tree: ast.AST
    names: frozenset[str]

    def evaluate(self, values: dict[str, float]) -> float:
        try:
            result = _walk(self.tree, values)
            if isinstance(result, complex):
                raise ExpressionError(f"'{self.text}' has no real value")
            if not math.isfinite(result):
                raise ExpressionError(f"'{self.text}' evaluates to {result}")
            return float(result)
        except ExpressionError as exc:
            if self.text in str(exc):
                raise
            raise ExpressionError(f"'{self.text}': {exc}") from None
        except OverflowError:  # its own text is "(34, 'Numerical result out of range')" or "math range error"
            raise ExpressionError(f"'{self.text}' overflows: its value is too large for a number (the largest "
                                  f"is about 1.8e308)") from None
        except (ZeroDivisionError, ValueError, TypeError) as exc:
            raise ExpressionError(f"cannot evaluate '{self.text}': {exc}") from None


def parse_expression(text: str) -> Expression:
    """Parse ``text``; raise :class:`ExpressionError` for anything outside the safe subset."""
    if len(text) > _MAX_LENGTH:
        raise ExpressionError(f"expression longer than {_MAX_LENGTH} characters")
    try:
        tree = ast.parse(text.strip(), mode="eval").body
    except SyntaxError as exc:  # Python's own reason ("'(' was never closed") says what to mend
        why = f" ({exc.msg})" if exc.msg and exc.msg != "invalid syntax" else ""
        raise ExpressionError(f"'{text}' is neither a '<number> <unit>' value nor a valid expression{why}") from None
    except (ValueError, RecursionError, MemoryError):
        raise ExpressionError(f"'{text}' is neither a '<number> <unit>' value nor a valid expression") from None
    names: set[str] = set()
    _check(tree, text, names)
    return Expression(text, tree, frozenset(names))


def _check(node: ast.AST, text: str, names: set[str], depth: int = 0) -> None:
    if depth > 100:
        raise ExpressionError(f"expression '{text[:40]}...' is nested too deeply")
    if isinstance(node, ast.Constant):
        if isinstance(node.value, bool) or not isinstance(node.value, (int, float)):
            raise ExpressionError(f"only numbers are allowed in '{text}', not {node.value!r}")
    elif isinstance(node, ast.Attribute):
        names.add(dotted_name(node, text))
    elif isinstance(node, ast.Name):
        if node.id not in CONSTANTS and node.id not in FUNCTIONS:
            names.add(node.id)
        elif node.id in FUNCTIONS:
            raise ExpressionError(f"'{node.id}' is a function; call it, as in {node.id}(x), in '{text}'")
    elif isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
        _check(node.left, text, names, depth + 1)
        _check(node.right, text, names, depth + 1)
    elif isinstance(node, ast.UnaryOp) and type(node.op) in _UNARY:
        _check(node.operand, text, names, depth + 1)
    elif isinstance(node, ast.Call):
        if not isinstance(node.func, ast.Name) or node.func.id not in FUNCTIONS:
            what = node.func.id if isinstance(node.func, ast.Name) else "this call"
            raise ExpressionError(f"unknown function '{what}' in '{text}' (allowed: {', '.join(sorted(FUNCTIONS))})")
        if node.keywords:
            raise ExpressionError(f"keyword arguments are not allowed in '{text}'")
        for arg in node.args:
            _check(arg, text, names, depth + 1)
    else:
        raise ExpressionError(f"'{type(node).__name__}' is not allowed in expression '{text}'")


def dotted_name(node: ast.Attribute, text: str) -> str:
    """``supply.p`` (an attribute chain on a name) as the one name "supply.p"; anything else is refused."""
    parts = []
    while isinstance(node, ast.Attribute):
        parts.append(node.attr)
        node = node.value
    if not isinstance(node, ast.Name) or any(part.startswith("_") for part in parts):
        raise ExpressionError(f"attribute access is not allowed in expression '{text}' (a dotted name reads a "
                              f"component's parameter of the same netlist, as in supply.p)")
    return ".".join([node.id] + parts[::-1])


def _walk(node: ast.AST, values: dict[str, float]) -> float:
    if isinstance(node, ast.Constant):
        return float(node.value)
    if isinstance(node, ast.Attribute):
        name = dotted_name(node, "")
        try:
            return values[name]
        except KeyError:
            raise ExpressionError(f"unknown parameter '{name}'") from None
    if isinstance(node, ast.Name):
        if node.id in CONSTANTS:
            return CONSTANTS[node.id]
        try:
            return values[node.id]
        except KeyError:
            raise ExpressionError(f"unknown parameter '{node.id}'") from None
    if isinstance(node, ast.BinOp):
        left, right = _walk(node.left, values), _walk(node.right, values)
        if isinstance(node.op, ast.Pow):
            if abs(right) > 1e4:
                raise ExpressionError(f"exponent {right:g} is too large")
            if left < 0 and not float(right).is_integer():
                raise ExpressionError(f"a negative number ({left:g}) to a fractional power has no real value")
        return _BINARY[type(node.op)](left, right)
    if isinstance(node, ast.UnaryOp):
        return _UNARY[type(node.op)](_walk(node.operand, values))
    if isinstance(node, ast.Call):
        return float(FUNCTIONS[node.func.id](*(_walk(a, values) for a in node.args)))
    raise ExpressionError(f"cannot evaluate {type(node).__name__}")
