"""The exceptions of lagrange.

Every error of the library arrives as a :class:`LagrangeError` with its ``kind`` (whose
mistake it is); the user's own mistakes — a model that does not read, an unknown name, a value
that is refused — are :class:`ModelError`, whose message is the located diagnostic the
command line prints and which carries the ``line`` and ``column`` it points at.
"""

from __future__ import annotations

TYPE_CHECKING = False  # typing is not imported at run time: `import lagrange` stays quick
if TYPE_CHECKING:
    from typing import Optional

__all__ = ["LagrangeError", "ModelError", "MechanicsError"]


class LagrangeError(Exception):
    """An error of lagrange.

    ``kind`` says whose mistake it is: ``"input"`` (the model or a value: mend it),
    ``"mechanics"`` (a degenerate system: a singular mass matrix, conflicting constraints),
    ``"internal"`` (lagrange disagrees with itself: a bug) or ``"output"``.
    """

    def __init__(
        self,
        message: str,
        line: Optional[int] = None,
        column: Optional[int] = None,
        kind: str = "internal",
    ) -> None:
        super().__init__(message)
        self.message = message
        self.line = line
        self.column = column
        self.kind = kind

    def __reduce__(self):  # pickles across processes (a Dask worker's error)
        return (type(self), (self.message, self.line, self.column, self.kind))

    def __str__(self) -> str:
        return self.message


class ModelError(LagrangeError, ValueError):
    """The model or a value given for it is wrong.

    ``str(error)`` is the diagnostic drawn under the offending source line, with how to mend
    it; ``line`` and ``column`` (1-based) say where, or are ``None`` when the mistake has no
    place in the text (an unknown name given to :meth:`lagrange.Model.with_values`).
    """


class MechanicsError(LagrangeError):
    """The model reads but its mechanics is degenerate or not supported."""


def from_native(kind: str, message: str, line: Optional[int], column: Optional[int]):
    """The exception for an error of the native module (called from Rust)."""
    if kind == "input":
        cls = ModelError
    elif kind == "mechanics":
        cls = MechanicsError
    else:
        cls = LagrangeError
    return cls(message, line, column, kind)
