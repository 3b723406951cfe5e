"""Which arguments each value a block's equation function returns may read, from its source (Python's ast).

    derivative_reads(Servo4WRLE.derivatives, 6)
    -> [{P, T, A, B, x, ...params}, ... , {dx}, {u, x, dx, ...params}]

A conservative data-flow over the function's statements: a value reads every name its expression reads,
every name that decides whether its statement runs (an ``if`` or a loop around it, and an ``if`` before it
that may return), and everything a called function was given (a call may also write into any array it is
passed). Inside a branch or a loop an assignment adds to what a name reads (the other path may keep the old
value); only at the top level does it replace it. A statement the analysis does not know (``try``, ``with``,
a bare call, a nested function) gives None: every output then reads every argument, as before.
The Jacobian's sparsity pattern (:func:`blocks.compiler.structure.jacobian_pattern`) uses it to tell the
flows of a valve (its pressures and spool) from the spool's own equation (its command).
"""

from __future__ import annotations

import ast
import inspect
import textwrap
from functools import lru_cache


class _Unknown(Exception):
    pass


_KNOWN_EXPRESSION_STATEMENTS = (ast.Constant,)  # a docstring


def derivative_reads(function, n_outputs: int) -> list[frozenset[str]] | None:
    """For each of the ``n_outputs`` values ``function`` returns, the argument names it may read; None if the
    source cannot be analysed."""
    try:
        return _reads(function, n_outputs)
    except (_Unknown, OSError, TypeError, SyntaxError, IndentationError):
        return None


@lru_cache(maxsize=None)
def _reads(function, n_outputs: int) -> list[frozenset[str]]:
    tree = ast.parse(textwrap.dedent(inspect.getsource(function)))
    fn = next((node for node in tree.body if isinstance(node, (ast.FunctionDef,))), None)
    if fn is None:
        raise _Unknown
    a = fn.args
    if a.vararg or a.kwarg:
        raise _Unknown
    args = [x.arg for x in a.posonlyargs + a.args + a.kwonlyargs]
    env = {name: frozenset([name]) for name in args}
    outputs = [frozenset() for _ in range(n_outputs)]
    returned = [False]

    def reads(node) -> frozenset:
        found = set()
        for sub in ast.walk(node):
            if isinstance(sub, ast.Name) and isinstance(sub.ctx, ast.Load):
                found |= env.get(sub.id, frozenset())
            elif isinstance(sub, (ast.Lambda, ast.NamedExpr, ast.Yield, ast.YieldFrom, ast.Await)):
                raise _Unknown
        return frozenset(found)

    def passed(node, value: frozenset, branch: bool) -> None:
        """Names given to a call in ``node`` may be written by it: they read what the call read."""
        for sub in ast.walk(node):
            if isinstance(sub, ast.Call):
                for arg in list(sub.args) + [k.value for k in sub.keywords]:
                    base = arg
                    while isinstance(base, (ast.Subscript, ast.Attribute, ast.Starred)):
                        base = base.value
                    if isinstance(base, ast.Name) and base.id in env:
                        env[base.id] = env[base.id] | value

    def assign(target, value: frozenset, branch: bool) -> None:
        if isinstance(target, ast.Name):
            env[target.id] = (env.get(target.id, frozenset()) | value) if branch else value
        elif isinstance(target, (ast.Tuple, ast.List)):
            for element in target.elts:
                assign(element, value, branch)
        elif isinstance(target, ast.Starred):
            assign(target.value, value, branch)
        elif isinstance(target, (ast.Subscript, ast.Attribute)):
            base = target
            extra = set()
            while isinstance(base, (ast.Subscript, ast.Attribute)):
                if isinstance(base, ast.Subscript):
                    extra |= reads(base.slice)
                base = base.value
            if not isinstance(base, ast.Name):
                raise _Unknown
            env[base.id] = env.get(base.id, frozenset()) | value | frozenset(extra)
        else:
            raise _Unknown

    def exits(statements) -> bool:
        return any(isinstance(sub, (ast.Return, ast.Raise, ast.Break, ast.Continue))
                   for statement in statements for sub in ast.walk(statement))

    def block(statements, control: frozenset, branch: bool) -> None:
        for statement in statements:
            control = run(statement, control, branch)

    def run(statement, control: frozenset, branch: bool) -> frozenset:
        """Analyse one statement; returns the control set for the statements after it."""
        if isinstance(statement, ast.Assign):
            value = reads(statement.value) | control
            passed(statement.value, value, branch)
            for target in statement.targets:
                assign(target, value, branch)
        elif isinstance(statement, ast.AnnAssign):
            if statement.value is not None:
                value = reads(statement.value) | control
                passed(statement.value, value, branch)
                assign(statement.target, value, branch)
        elif isinstance(statement, ast.AugAssign):
            value = reads(statement.value) | reads(statement.target) | control
            passed(statement.value, value, branch)
            assign(statement.target, value, True)
        elif isinstance(statement, ast.If):
            test = reads(statement.test) | control
            block(statement.body, test, True)
            block(statement.orelse, test, True)
            if exits(statement.body) or exits(statement.orelse):
                return control | test
        elif isinstance(statement, (ast.For, ast.While)):
            head = reads(statement.iter if isinstance(statement, ast.For) else statement.test) | control
            for _ in range(100):  # to a fixed point: a loop may carry a name's reads to the next pass
                before = dict(env)
                if isinstance(statement, ast.For):
                    assign(statement.target, head, True)
                block(statement.body, head, True)
                block(statement.orelse, head, True)
                head = head | (reads(statement.test) if isinstance(statement, ast.While) else frozenset())
                if env == before:
                    break
            else:
                raise _Unknown
            if exits(statement.body) or exits(statement.orelse):
                return control | head
        elif isinstance(statement, ast.Return):
            returned[0] = True
            value = statement.value
            if isinstance(value, ast.Tuple) and len(value.elts) == n_outputs \
                    and not any(isinstance(e, ast.Starred) for e in value.elts):
                for k, element in enumerate(value.elts):
                    outputs[k] = outputs[k] | reads(element) | control
            else:
                every = (reads(value) if value is not None else frozenset()) | control
                for k in range(n_outputs):
                    outputs[k] = outputs[k] | every
        elif isinstance(statement, (ast.Assert, ast.Raise)):
            pass  # no value comes out of it (what follows depends on its test: exits() above)
        elif isinstance(statement, ast.Pass):
            pass
        elif isinstance(statement, ast.Expr) and isinstance(statement.value, _KNOWN_EXPRESSION_STATEMENTS):
            pass
        else:
            raise _Unknown  # try, with, a bare call, raise, nested def, global, del, ...
        return control

    block(fn.body, frozenset(), False)
    if not returned[0]:
        raise _Unknown
    return [frozenset(o) for o in outputs]
