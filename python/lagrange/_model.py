"""The :class:`Model` and what it returns: :class:`Solution`, :class:`EquationsOfMotion`,
:class:`Linearization` and :class:`Run`.

Everything here is glue: the mechanics is the Rust library's (``lagrange._native``). NumPy is
imported when an array is made, SymPy when the equations are asked for as SymPy matrices and
pandas when a table is made, so that ``import lagrange`` stays quick.
"""

from __future__ import annotations

import os

from . import _native

TYPE_CHECKING = False  # typing and json are imported when needed: `import lagrange` stays quick
if TYPE_CHECKING:
    from typing import Any, Dict, Iterator, List, Optional, Sequence, Tuple, Union

    Value = Union[float, int, str]

__all__ = ["Model", "Solution", "Section", "EquationsOfMotion", "Linearization", "Run"]


class Model:
    """A mechanical system read from a ``.lag`` model (docs/language.md) and its analysis.

    Make one with :meth:`Model.from_file` or :meth:`Model.from_text`; a model is immutable:
    :meth:`with_values` returns a copy with parameters, inputs or initial values changed (the
    equations, derived once, are shared). Each result is computed when first asked for.

    >>> model = Model.from_text('''
    ... coordinates theta
    ... parameters m = 1, l = 2, g = 9.81
    ... frame N
    ... point P = l*sin(theta)*N.x - l*cos(theta)*N.y
    ... particle P mass m
    ... gravity -g*N.y
    ... ''')
    >>> model.coordinates
    ['theta']
    """

    __slots__ = ("_native", "_values", "_rhs", "__weakref__")

    def __init__(self, native: Any, values: Sequence[Tuple[str, Value]] = ()) -> None:
        # Private: use Model.from_file / Model.from_text.
        self._native = native
        self._values = tuple(values)
        self._rhs: Any = None

    @classmethod
    def from_file(cls, path: Union[str, "os.PathLike[str]"]) -> "Model":
        """Reads, checks and lowers a model file.

        Raises :class:`lagrange.ModelError` (message: the located diagnostic; ``line``,
        ``column``) when the model has mistakes.
        """
        return cls(_native.load_file(os.fspath(path)))

    @classmethod
    def from_text(cls, text: str) -> "Model":
        """Reads, checks and lowers model text (errors as :meth:`from_file`)."""
        return cls(_native.load_text(text))

    def with_values(self, **values: Value) -> "Model":
        """A copy with values set, as the command line's ``--set``: parameters, inputs and
        initial values by name, e.g. ``model.with_values(g=1.62, theta=0.3, theta_d=-1)``.
        A value is a number or a string: a constant expression (``"pi/4"``, ``"2*g"``) or,
        for an input, a function of ``t`` (``F="sin(2*t)"``).

        Raises :class:`lagrange.ModelError` for an unknown name or a refused value.
        """
        items = list(values.items())
        return Model(self._native.with_values(items), self._values + tuple(items))

    @property
    def title(self) -> str:
        """The report's title: the first sentence of the model's opening comment."""
        return self._native.title()

    @property
    def coordinates(self) -> List[str]:
        """The generalized coordinates, in the order of every vector and matrix."""
        return self._native.coordinates()

    @property
    def values(self) -> Dict[str, float]:
        """The parameters and inputs by name, after the sets (initial values: :meth:`initial_state`)."""
        return dict(self._native.values())

    def solve(self) -> "Solution":
        """The step-by-step solution, as ``lagrange solve`` writes it: displays in Jupyter as
        the course solution (Markdown with the math); its sections are :attr:`Solution.sections`."""
        return Solution(*self._native.solution())

    def equations_of_motion(self) -> "EquationsOfMotion":
        """Lagrange's equations ``M(q, t) q̈ = f(q, q̇, t)`` as SymPy matrices:
        ``M, f = model.equations_of_motion()``. Coordinates, rates (``theta_d``) and
        parameters are plain SymPy symbols of the same names. Imports SymPy."""
        data = _json(self._native.equations_json())
        return EquationsOfMotion._from_json(data, self._names())

    def equations_json(self) -> Dict[str, Any]:
        """The equations of motion as ``lagrange eom --format json`` prints them
        (docs/json.md): expressions as SymPy-readable strings."""
        return _json(self._native.equations_json())

    def equilibria(self) -> "Any":
        """The equilibria as a NumPy array, one row per equilibrium, one column per
        coordinate (their stability: :meth:`linearize`, or :meth:`equilibria_json`)."""
        import numpy as np

        data = self.equilibria_json()
        names = data["coordinates"]
        rows = [[e["values"][q] for q in names] for e in data["equilibria"]]
        return np.array(rows, dtype=float).reshape(len(rows), len(names))

    def equilibria_json(self) -> Dict[str, Any]:
        """The equilibria as ``lagrange equilibria --format json`` prints them."""
        return _json(self._native.equilibria_json())

    def linearize(self) -> List["Linearization"]:
        """The linearized dynamics about each equilibrium, in the order of
        :meth:`equilibria`: NumPy arrays ``M0, C0, K0, B0, A, B``, the eigenvalues, natural
        frequencies and modes."""
        data = _json(self._native.linearized_json())
        return [Linearization._from_json(item) for item in data["linearized"]]

    def simulate(self, t_end: Optional[float] = None, *, as_frame: Optional[bool] = None, **options: Any):
        """Integrates the equations of motion from the initial state.

        ``t_end`` defaults to the model's ``simulate to T``. Options, as the command line's:
        ``method`` (``"dopri5"``, ``"dop853"``, ``"gauss"``, ``"sdirk"``; default: by the tolerance), ``t_start``, ``rtol``, ``atol``,
        ``output_step``, ``step``, ``stop_when`` (an expression whose zero ends the run),
        ``through_contact_loss``, ``max_steps``, ``max_rows``.

        Returns a pandas ``DataFrame`` when pandas is installed (``as_frame=None``; force with
        ``as_frame=True`` or ``False``), else a :class:`Run`: columns ``t``, the coordinates,
        their rates ``q_d``, ``energy_error`` and ``constraint_drift``. How the run ended is in
        ``run.ending`` (``frame.attrs["ending"]``).
        """
        columns, rows, ending, sentence, reached, steps = self._native.simulate(t_end, **options)
        run = Run(columns, rows, ending, sentence, reached, steps)
        return run.to_frame() if _want_frame(as_frame) else run

    @property
    def rhs(self) -> Any:
        """The right-hand side ``dy/dt = rhs(t, y)``, ``y = (q, q̇)``, for
        ``scipy.integrate.solve_ivp(model.rhs, (0, 10), y0)``: the compiled tape the library
        integrates with, at this model's values. ``y`` is a float64 array of length ``2n``;
        each call returns a new array. Compiled on first use."""
        if self._rhs is None:
            self._rhs = self._native.rhs()
        return self._rhs

    def rhs_batch(self, ys: Any, t: float = 0.0) -> Any:
        """``dy/dt`` at time ``t`` for every row of ``ys`` (``k × 2n``), as a ``k × 2n`` array."""
        import numpy as np

        return self.rhs.batch(np.ascontiguousarray(ys, dtype=float), t)

    def initial_state(self) -> Any:
        """The initial state ``(q, q̇)`` as a NumPy array (the model's ``initial`` values)."""
        import numpy as np

        return np.array(self._native.initial_state(), dtype=float)

    def _names(self) -> List[str]:
        names = list(self.coordinates)
        names += [q + "_d" for q in self.coordinates]
        names += [name for name, _ in self._native.values()]
        return names

    def __reduce__(self):
        # A model travels to another process (a Dask worker) as its text and its sets.
        text = self._native.source_text()
        if text is None:
            raise TypeError("a model without model text cannot be pickled")
        return (_rebuild, (text, self._native.file(), self._values))

    def __repr__(self) -> str:
        return f"<lagrange.Model {self.title!r}: coordinates {', '.join(self.coordinates)}>"


def _json(text: str) -> Any:
    import json

    return json.loads(text)


def _rebuild(text: str, file: str, values: Sequence[Tuple[str, Value]]) -> Model:
    model = Model(_native.load_text(text, file))
    return model.with_values(**dict(values)) if values else model


def _want_frame(as_frame: Optional[bool]) -> bool:
    if as_frame is not None:
        return as_frame
    try:
        import pandas  # noqa: F401
    except ImportError:
        return False
    return True


class Section:
    """One section of a :class:`Solution`: ``title``, ``level`` (2 for a section, 3 for a
    subsection) and ``markdown`` (MyST, math in ``$…$`` and ``$$…$$``)."""

    __slots__ = ("title", "level", "markdown")

    def __init__(self, title: str, level: int, markdown: str) -> None:
        self.title = title
        self.level = level
        self.markdown = markdown

    def __repr__(self) -> str:
        return f"<lagrange.Section {self.title!r}>"

    def _repr_markdown_(self) -> str:
        return self.markdown


class Solution:
    """A model's step-by-step solution (``lagrange solve``).

    In Jupyter it displays as the course solution (:meth:`_repr_markdown_`); ``str()`` gives
    the terminal text, :attr:`latex` a standalone LaTeX document, :attr:`sections` the parts
    and :attr:`document` the structured document (blocks of paragraphs, equations, tables).
    """

    def __init__(
        self,
        title: str,
        markdown: str,
        latex: str,
        text: str,
        document: str,
        sections: Sequence[Tuple[str, int, str]],
    ) -> None:
        self.title = title
        """The title."""
        self.markdown = markdown
        """The whole solution as Markdown (MyST)."""
        self.latex = latex
        """A standalone LaTeX document (``pdflatex`` compiles it)."""
        self.text = text
        """The solution as the terminal shows it."""
        self.document: Dict[str, Any] = _json(document)
        """The structured document, as under ``report`` in ``lagrange solve --format json``."""
        self.sections = [Section(t, lvl, _strip_title(md)) for t, lvl, md in sections]
        """The sections, in order."""

    def section(self, title: str) -> Section:
        """The section whose title is ``title`` (or starts with it)."""
        for section in self.sections:
            if section.title == title:
                return section
        for section in self.sections:
            if section.title.startswith(title):
                return section
        raise KeyError(f"no section {title!r}; the sections: {[s.title for s in self.sections]}")

    def _repr_markdown_(self) -> str:
        return self.markdown

    def _repr_latex_(self) -> str:
        # The body of the document: a notebook exported to LaTeX includes it as it is.
        body = self.latex.split("\\begin{document}", 1)[-1].split("\\end{document}", 1)[0]
        return body.replace("\\maketitle", "\\section*{" + _latex_text(self.title) + "}").strip()

    def __str__(self) -> str:
        return self.text

    def __repr__(self) -> str:
        return f"<lagrange.Solution {self.title!r}: {len(self.sections)} sections>"


def _strip_title(markdown: str) -> str:
    # A section rendered alone opens with the (empty) document title.
    lines = markdown.split("\n")
    while lines and (lines[0].strip() in ("", "#")):
        lines.pop(0)
    return "\n".join(lines)


def _latex_text(text: str) -> str:
    for a, b in (("\\", "\\textbackslash{}"), ("&", "\\&"), ("%", "\\%"), ("$", "\\$"), ("#", "\\#"), ("_", "\\_")):
        text = text.replace(a, b)
    return text


class EquationsOfMotion:
    """``M(q, t) q̈ = f(q, q̇, t)`` as SymPy matrices; unpacks as ``M, f``.

    :attr:`coordinates` and :attr:`rates` are the SymPy symbols of ``q`` and ``q̇`` (named
    ``theta`` and ``theta_d``), :attr:`symbols` every symbol by name.
    """

    def __init__(self, M: Any, f: Any, coordinates: List[Any], rates: List[Any], symbols: Dict[str, Any]) -> None:
        self.M = M
        """The mass matrix ``M(q, t)`` (n × n)."""
        self.f = f
        """The forcing ``f(q, q̇, t)`` (n × 1)."""
        self.coordinates = coordinates
        self.rates = rates
        self.symbols = symbols

    @classmethod
    def _from_json(cls, data: Dict[str, Any], names: List[str]) -> "EquationsOfMotion":
        import sympy

        symbols = {name: sympy.Symbol(name) for name in names}
        symbols.setdefault("t", sympy.Symbol("t"))

        def read(text: str) -> Any:
            return sympy.sympify(text, locals=symbols)

        M = sympy.Matrix([[read(e) for e in row] for row in data["mass_matrix"]])
        f = sympy.Matrix([read(e) for e in data["forcing"]])
        q = [symbols[name] for name in data["coordinates"]]
        qd = [symbols[name + "_d"] for name in data["coordinates"]]
        return cls(M, f, q, qd, symbols)

    def __iter__(self) -> Iterator[Any]:
        return iter((self.M, self.f))

    def __repr__(self) -> str:
        return f"EquationsOfMotion(M={self.M!r}, f={self.f!r})"


class Linearization:
    """The linearized dynamics about one equilibrium:
    ``M0 δq̈ + C0 δq̇ + K0 δq = B0 δu`` and its state-space form ``ẋ = A x + B u``.

    Attributes are NumPy arrays: ``M0``, ``C0``, ``K0``, ``B0``, ``A``, ``B``,
    ``eigenvalues`` (complex), ``frequencies`` (rad/s, of the oscillating modes), ``modes``
    (one row per mode, in the order of ``frequencies``) and ``values`` (the equilibrium's coordinates); ``stable`` and
    ``criterion`` say how stability was decided, ``exact`` holds ``M0 … B0`` as SymPy-readable
    strings, ``data`` everything as ``lagrange linearize --format json`` prints it.
    """

    def __init__(self, data: Dict[str, Any]) -> None:
        import numpy as np

        def matrix(key: str) -> Any:
            return np.array(data.get(key) or [], dtype=float)

        self.data = data
        self.equilibrium: int = data.get("equilibrium", 0)
        self.M0, self.C0, self.K0, self.B0 = (matrix(k) for k in ("M0", "C0", "K0", "B0"))
        self.A, self.B = matrix("A"), matrix("B")
        pairs = data.get("eigenvalues") or []
        self.eigenvalues = np.array([complex(re, im) for re, im in pairs], dtype=complex)
        self.frequencies = np.array(data.get("frequencies") or [], dtype=float)
        self.modes = matrix("modes")
        self.stable: Optional[bool] = data.get("stable")
        self.criterion: Optional[str] = data.get("criterion")
        self.exact: Dict[str, Any] = data.get("exact") or {}
        values = data.get("values") or {}
        self.values = np.array(list(values.values()) if isinstance(values, dict) else values, dtype=float)

    @classmethod
    def _from_json(cls, data: Dict[str, Any]) -> "Linearization":
        return cls(data)

    def __repr__(self) -> str:
        return f"<lagrange.Linearization about equilibrium {self.equilibrium}: stable={self.stable}>"


class Run(dict):
    """A simulation's time history: a ``dict`` of column name → NumPy array, in column
    order, with :attr:`array` (rows × columns), :attr:`ending` (``"finished"``, ``"event"``,
    ``"failed …"``), :attr:`message` (why it stopped early, or ``None``), :attr:`t` (the time
    reached) and :attr:`steps`."""

    def __init__(self, columns: List[str], rows: Any, ending: str, message: Optional[str], t: float, steps: int) -> None:
        super().__init__((name, rows[:, i]) for i, name in enumerate(columns))
        self.columns = columns
        self.array = rows
        self.ending = ending
        self.message = message
        self.t = t
        self.steps = steps

    def to_frame(self) -> Any:
        """A pandas ``DataFrame`` of the columns; ``attrs`` holds the ending, message, time
        reached and steps."""
        import pandas as pd

        frame = pd.DataFrame(self.array, columns=self.columns)
        frame.attrs.update(ending=self.ending, message=self.message, t=self.t, steps=self.steps)
        return frame
