"""`--help` without Python types: typer prints a type column (`<bool>`, `<list[Path]>`,
`<str>`) beside every argument and option. Here an argument is named by its metavar alone
(FILE, DIR), an option by its metavar (`-o DIR`, `--jobs N`), and a flag by nothing."""

from __future__ import annotations

from typing import Any

import typer.core

__all__ = ["use_domain_names"]


def _argument_type(self: typer.core.TyperArgument, ctx: Any) -> str | None:
    """No type column for an argument: its name column shows its metavar."""
    return None


def _option_type(self: typer.core.TyperOption, ctx: Any) -> str | None:
    """An option's metavar; nothing for a flag (it takes no value)."""
    if self.is_flag:
        return None
    return self.metavar if self.metavar is not None else self.display_type(ctx)


def use_domain_names() -> None:
    """Make typer's help show domain names instead of Python types (once per process;
    typer offers no setting for it)."""
    setattr(typer.core.TyperArgument, "display_type_rich", _argument_type)  # noqa: B010
    setattr(typer.core.TyperOption, "display_type_rich", _option_type)  # noqa: B010
