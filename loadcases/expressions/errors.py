"""The one error type of the expression language."""

from __future__ import annotations

__all__ = ["ExpressionError"]


class ExpressionError(ValueError):
    """A problem in an expression: a short `message` and the 0-based character `offset`.

    `text` is the expression text when known and `hint` an optional fix suggestion
    (`did you mean 'crank_speed'?`); the loader turns both into a `Diagnostic`.
    """

    def __init__(
        self, message: str, offset: int, text: str | None = None, hint: str | None = None
    ) -> None:
        super().__init__(message, offset)
        self.message = message
        self.offset = offset
        self.text = text
        self.hint = hint

    def __str__(self) -> str:
        where = f"at offset {self.offset}"
        if self.text is not None:
            where += f" of {self.text!r}"
        tail = f" ({self.hint})" if self.hint else ""
        return f"{self.message} {where}{tail}"

    def with_text(self, text: str) -> ExpressionError:
        """This error with the expression text attached (for messages)."""
        if self.text is None:
            self.text = text
        return self
