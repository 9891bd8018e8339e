"""A Pratt parser from tokens to expression trees, with our own error messages.

Precedence, lowest first: `or`, `and`, `not`, comparisons (not chained), `+ -`, `* /`,
unary `- +`, `**` / `^` (right-associative, so -2**2 == -4 and 2**-1 == 0.5).

Bounded (`loadcases.foundation.limits`): a text of at most MAX_EXPRESSION_CHARS characters,
nested at most MAX_EXPRESSION_DEPTH levels, counted both as the parser descends
(parentheses, calls, unary operators, the right side of `**`) and as the tree grows (each
operator of a chain such as `a + b + c` is a level): the passes over a tree (names, folding,
derivatives) recurse once per level, well inside Python's recursion limit.
"""

from __future__ import annotations

import difflib
import functools
import keyword
import math

from ..foundation.limits import MAX_EXPRESSION_CHARS, MAX_EXPRESSION_DEPTH
from .errors import ExpressionError
from .functions import FUNCTIONS, MEASURES
from .lexer import Token, tokenize
from .nodes import COMPARISONS, Call, Measure, Name, Node, Num, Op, Table, children

__all__ = ["TOO_DEEP", "parse_tree"]

TOO_DEEP = f"nested more than {MAX_EXPRESSION_DEPTH} levels deep"

_INFIX = {"or": 10, "and": 20, "+": 50, "-": 50, "*": 60, "/": 60, "**": 80, "^": 80}
_INFIX.update(dict.fromkeys(COMPARISONS, 40))
_NOT_OPERAND = 30
_UNARY_OPERAND = 70
_RIGHT_ASSOCIATIVE = {"**", "^"}
_TERMINATORS = {")", ","}
_FORBIDDEN_CALLS = frozenset(
    {
        "eval",
        "exec",
        "compile",
        "open",
        "getattr",
        "setattr",
        "delattr",
        "globals",
        "locals",
        "vars",
        "input",
        "breakpoint",
        "import",
    }
)
_CALLABLE = sorted({*FUNCTIONS, *MEASURES, "table"})


@functools.lru_cache(maxsize=4096)  # the trees are frozen; a set's cases repeat their texts
def parse_tree(text: str) -> Node:
    """The tree of `text`; raises ExpressionError (message, offset) on the first problem."""
    if not text.strip():
        raise ExpressionError("empty expression", 0, text)
    if len(text) > MAX_EXPRESSION_CHARS:
        raise ExpressionError(
            f"longer than {MAX_EXPRESSION_CHARS:,} characters ({len(text):,})", 0, text
        )
    try:
        return _Parser(text).parse()
    except ExpressionError as error:
        raise error.with_text(text) from None
    except RecursionError:
        raise ExpressionError(TOO_DEEP, 0, text) from None


def _check_name(token: Token) -> None:
    word = token.text
    if word.startswith("__") or (keyword.iskeyword(word) and word not in ("and", "or", "not")):
        raise ExpressionError(f"{word!r} is not allowed", token.offset)


def _suggest(word: str, choices: list[str]) -> str | None:
    close = difflib.get_close_matches(word, choices, n=1)
    return f"did you mean {close[0]!r}?" if close else None


class _Parser:
    def __init__(self, text: str) -> None:
        self.tokens = tokenize(text)
        self.next: Token | None = None
        self.level = 0  # expression() calls under way
        self.depths: dict[int, int] = {}  # id of each node made -> levels of its tree

    def made(self, node: Node) -> Node:
        """`node`, its depth recorded; ExpressionError at it if that is too deep."""
        depth = 1 + max((self.depths.get(id(c), 1) for c in children(node)), default=0)
        if depth > MAX_EXPRESSION_DEPTH:
            raise ExpressionError(TOO_DEEP, node.offset)
        self.depths[id(node)] = depth
        return node

    def peek(self) -> Token:
        if self.next is None:
            self.next = next(self.tokens)
        return self.next

    def advance(self) -> Token:
        token = self.peek()
        self.next = None
        return token

    def expect_close(self) -> None:
        token = self.advance()
        if token.text != ")":
            raise ExpressionError("expected ')'", token.offset)

    def parse(self) -> Node:
        node = self.expression(0)
        token = self.peek()
        if token.kind != "end":
            raise ExpressionError(f"unexpected {token.text!r}", token.offset)
        return node

    def expression(self, min_bp: int) -> Node:
        self.level += 1
        try:
            if self.level > MAX_EXPRESSION_DEPTH:
                raise ExpressionError(TOO_DEEP, self.peek().offset)
            return self.operations(min_bp)
        finally:
            self.level -= 1

    def operations(self, min_bp: int) -> Node:
        left = self.prefix(self.advance())
        compared = False
        while True:
            token = self.peek()
            if token.kind == "end" or token.text in _TERMINATORS:
                return left
            if token.kind != "op" or token.text == "(":
                if token.kind == "name":
                    _check_name(token)
                raise ExpressionError(f"missing operator before {token.text!r}", token.offset)
            bp = _INFIX.get(token.text)
            if bp is None:
                raise ExpressionError(f"unexpected {token.text!r}", token.offset)
            if bp <= min_bp:
                return left
            if token.text in COMPARISONS:
                if compared:
                    raise ExpressionError(
                        "chained comparisons are not allowed; use 'and'", token.offset
                    )
                compared = True
            self.advance()
            right = self.expression(bp - 1 if token.text in _RIGHT_ASSOCIATIVE else bp)
            op = "**" if token.text == "^" else token.text
            left = self.made(Op(op, (left, right), token.offset))

    def prefix(self, token: Token) -> Node:
        if token.kind == "num":
            value = float(token.text)
            if not math.isfinite(value):
                raise ExpressionError("number out of range (not finite)", token.offset)
            return Num(value, token.offset)
        if token.kind == "name":
            _check_name(token)
            if self.peek().text == "(":
                return self.call(token)
            return Name(token.text, token.offset)
        if token.text == "(":
            node = self.expression(0)
            self.expect_close()
            return node
        if token.text == "-":
            return self.made(Op("neg", (self.expression(_UNARY_OPERAND),), token.offset))
        if token.text == "+":
            return self.expression(_UNARY_OPERAND)
        if token.text == "not":
            return self.made(Op("not", (self.expression(_NOT_OPERAND),), token.offset))
        raise ExpressionError("expected an expression", token.offset)

    def arguments(self) -> list[tuple[int, Node]]:
        """Arguments after '(' up to and including ')', each with its start offset."""
        self.advance()
        args: list[tuple[int, Node]] = []
        if self.peek().text == ")":
            self.advance()
            return args
        while True:
            start = self.peek().offset
            args.append((start, self.expression(0)))
            token = self.advance()
            if token.text == ")":
                return args
            if token.text != ",":
                raise ExpressionError("expected ')'", token.offset)

    def call(self, name: Token) -> Node:
        func = name.text
        if func in _FORBIDDEN_CALLS:
            raise ExpressionError(f"{func!r} is not allowed", name.offset)
        if func not in FUNCTIONS and func not in MEASURES and func != "table":
            raise ExpressionError(
                f"unknown function {func!r}", name.offset, hint=_suggest(func, _CALLABLE)
            )
        args = self.arguments()
        if func in MEASURES:
            count, what = MEASURES[func]
            _check_count(func, count, False, len(args), name.offset)
            names = tuple(_bare(func, a, f"a {what} name") for a in args)
            return self.made(Measure(func, names, name.offset))
        if func == "table":
            _check_count(func, 2, False, len(args), name.offset)
            table = _bare(func, args[0], "a table name", "first ")
            return self.made(Table(table, (args[1][1],), name.offset))
        spec = FUNCTIONS[func]
        _check_count(func, spec.arity, spec.variadic, len(args), name.offset)
        return self.made(Call(func, tuple(node for _, node in args), name.offset))


def _check_count(func: str, arity: int, variadic: bool, got: int, offset: int) -> None:
    if got == arity or (variadic and got > arity):
        return
    least = "at least " if variadic else ""
    plural = "" if arity == 1 else "s"
    raise ExpressionError(f"{func!r} takes {least}{arity} argument{plural}, got {got}", offset)


def _bare(func: str, arg: tuple[int, Node], what: str, which: str = "") -> str:
    start, node = arg
    if not isinstance(node, Name):
        raise ExpressionError(f"{which}argument of {func!r} must be {what}", start)
    return node.id
