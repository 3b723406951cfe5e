"""A safe evaluator for the arithmetic in netlists: ``"0.085 + m_load*r_p**2/n_g**2"``.

Only numbers, parameter names, + - * / ** %, unary signs, parentheses and calls of a fixed table of math
functions (with their number of arguments) are accepted. A name may be dotted, ``supply.p``: a
parameter of a component (or a net's written ``initial``) of the same netlist, read as one name. The
text is parsed with :mod:`ast` and walked by hand; ``eval`` is never called, subscripts, lambdas and
everything else are refused, so a netlist can run no code. A refused construct is named as written (a comma,
"[ ]", "^"), never by the parser's node type, which the writer of a netlist has no reason to know. All
numbers are floats, so ``9**9**9`` overflows at once instead of hanging.
"""

from __future__ import annotations

import ast
import math
import operator
import warnings
from dataclasses import dataclass

FUNCTIONS = {
    "sqrt": math.sqrt, "exp": math.exp, "log": math.log, "log10": math.log10, "abs": abs,
    "sin": math.sin, "cos": math.cos, "tan": math.tan, "asin": math.asin, "acos": math.acos,
    "atan": math.atan, "atan2": math.atan2, "tanh": math.tanh, "hypot": math.hypot,
    "min": min, "max": max, "floor": math.floor, "ceil": math.ceil,
    "radians": math.radians, "degrees": math.degrees,
}
CONSTANTS = {"pi": math.pi, "e": math.e}
ARGUMENTS = {"atan2": (2, 2), "hypot": (1, None), "min": (2, None), "max": (2, None), "log": (1, 2)}
"""How many arguments a function takes, (fewest, most; None: any number), where it is not exactly one."""

_BINARY = {
    ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
    ast.Pow: operator.pow, ast.Mod: operator.mod,
}
_UNARY = {ast.UAdd: operator.pos, ast.USub: operator.neg}
_MAX_LENGTH = 2000

# a refused construct in the words of its writer (by node type, or operator type for an operation): what it
# is, and what to write instead where that is plain
_REFUSED = {
    ast.Tuple: ("a comma outside a function's parentheses", "a value is one number; a comma only separates a "
                                                              "function's arguments"),
    ast.Subscript: ("indexing with '[ ]'", ""), ast.List: ("a list in '[ ]'", ""), ast.Dict: ("'{ }'", ""),
    ast.Set: ("'{ }'", ""), ast.Compare: ("a comparison", ""), ast.And: ("'and'", ""),
    ast.Or: ("'or'", ""), ast.Not: ("'not'", ""), ast.Invert: ("'~'", ""), ast.IfExp: ("'if ... else'", ""),
    ast.Lambda: ("'lambda'", ""), ast.NamedExpr: ("':='", ""), ast.Starred: ("'*' before an argument", ""),
    ast.ListComp: ("a 'for' loop", ""), ast.SetComp: ("a 'for' loop", ""), ast.DictComp: ("a 'for' loop", ""),
    ast.GeneratorExp: ("a 'for' loop", ""), ast.JoinedStr: ("text", ""),
    ast.BitXor: ("'^'", "write ** for a power, as in x**2"), ast.FloorDiv: ("'//'", "write floor(a/b)"),
    ast.MatMult: ("'@'", ""), ast.BitOr: ("'|'", ""), ast.BitAnd: ("'&'", ""), ast.LShift: ("'<<'", ""),
    ast.RShift: ("'>>'", ""),
}


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
        with warnings.catch_warnings():  # '1if x else y' warns on stderr, outside every message: refused here
            warnings.simplefilter("error", SyntaxWarning)
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
            written = ast.get_source_segment(text.strip(), node) or repr(node.value)
            raise ExpressionError(f"only real numbers are allowed in '{text}', not {written}")
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
        for arg in node.args:
            _check(arg, text, names, depth + 1)
        _check_call(node, text)
    else:
        raise _refused(node, text)


def _check_call(node: ast.Call, text: str) -> None:
    """A call names a function of :data:`FUNCTIONS` and passes it plain arguments (how many: :func:`_arguments`,
    when it is evaluated, so that ``max(ref.times)`` is first said to read a list)."""
    if not isinstance(node.func, ast.Name) or node.func.id not in FUNCTIONS:
        what = node.func.id if isinstance(node.func, ast.Name) else ast.get_source_segment(text.strip(), node.func)
        raise ExpressionError(f"unknown function '{what}' in '{text}' (allowed: {', '.join(sorted(FUNCTIONS))})")
    if node.keywords:
        raise ExpressionError(f"keyword arguments are not allowed in '{text}'")


def _arguments(node: ast.Call) -> None:
    """A call passes its function as many arguments as it takes (Python's own words would be "'float' object
    is not iterable" for max(3))."""
    name, count = node.func.id, len(node.args)
    fewest, most = ARGUMENTS.get(name, (1, 1))
    if count < fewest or (most is not None and count > most):
        takes = f"{fewest}" if fewest == most else f"{fewest} or more" if most is None else f"{fewest} or {most}"
        raise ExpressionError(f"{name}() takes {takes} argument{'s' if takes != '1' else ''}, not {count}")


def _refused(node: ast.AST, text: str) -> ExpressionError:
    """The error for a construct outside the arithmetic subset, naming it as written."""
    kind = type(node.op) if isinstance(node, (ast.BinOp, ast.UnaryOp, ast.BoolOp)) else type(node)
    if kind not in _REFUSED:  # a construct with no words of its own: what is allowed instead
        return ExpressionError(f"'{text}' is not arithmetic: only numbers, parameter names, + - * / ** %, "
                               f"parentheses and function calls are allowed")
    what, instead = _REFUSED[kind]
    return ExpressionError(f"{what} is not allowed in expression '{text}'" + (f" ({instead})" if instead else ""))


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
        _arguments(node)
        return float(FUNCTIONS[node.func.id](*(_walk(a, values) for a in node.args)))
    raise ExpressionError("cannot evaluate it")  # not reached: _check refused everything else
