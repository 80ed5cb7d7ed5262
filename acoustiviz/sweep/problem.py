"""What an optimisation searches: its variables, objectives and constraints, and the Pareto filter.

A :class:`Problem` names the design variables (each continuous ``LO:HI``, log-scaled ``log:LO:HI``,
categorical ``A,B,C`` or fixed; a whole number, the number of balls, ``LO:HI`` over the integers), the
objective columns to minimise or maximise and the constraints ``COLUMN<=VALUE`` / ``COLUMN>=VALUE`` on
the columns of one evaluated design. What a design is and
which columns it reports is the business of an evaluation mode (:mod:`acoustiviz.sweep.modes`): a
function design -> row of columns. Everything is checked when the problem is made, before any work.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError

__all__ = ["Variable", "Objective", "Constraint", "Problem", "parse_variable", "parse_constraint", "pareto_mask",
           "feasible_mask", "VARIABLE_FORM"]

#: How a variable is written, as errors state it.
VARIABLE_FORM = "LO:HI (continuous), log:LO:HI (log scale), A,B,C (categorical) or one value (fixed)"
_CONSTRAINT = re.compile(r"\s*([A-Za-z_][A-Za-z0-9_]*)\s*(<=|>=)\s*(\S+)\s*")


@dataclass(frozen=True)
class Variable:
    """One design variable.

    Attributes
    ----------
    name : str
        The API parameter it sets (``"gap"``, ``"m"``, ``"material"``...).
    kind : {"float", "log", "int", "categorical", "fixed"}
        Continuous on ``[low, high]``, continuous on a log scale, a whole number in ``[low, high]`` (every
        integer between, both ends included), one of ``choices``, or ``choices[0]``.
    low, high : float
        Bounds of a continuous or whole-number variable (in the parameter's unit); NaN otherwise.
    choices : tuple
        The values of a categorical variable, or the one value of a fixed one.
    """

    name: str
    kind: str
    low: float = math.nan
    high: float = math.nan
    choices: tuple = ()

    @property
    def searched(self) -> bool:
        """True unless the variable is fixed."""
        return self.kind != "fixed"

    def to_dict(self) -> dict:
        """The variable as plain JSON values."""
        if self.kind in ("float", "log", "int"):
            return {"name": self.name, "kind": self.kind, "low": self.low, "high": self.high}
        return {"name": self.name, "kind": self.kind, "choices": list(self.choices)}


def _number(name: str, text: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise ParameterError(name, f"expected {VARIABLE_FORM}, got a non-number {text!r}") from None
    if not math.isfinite(v):
        raise ParameterError(name, f"bounds must be finite, got {text!r}")
    return v


def parse_variable(name: str, text, kind=float) -> Variable:
    """Parse one variable: ``LO:HI``, ``log:LO:HI``, ``A,B,C`` or one value.

    Parameters
    ----------
    name : str
        The API parameter (errors name it; front ends rename it to the option or scene key).
    text : str or number
        The specification.
    kind : type
        ``float`` for numbers, ``int`` for whole numbers (``LO:HI`` then samples the integers from LO to HI;
        no log scale), ``str`` for names (which are categorical or fixed only).

    Returns
    -------
    Variable

    Examples
    --------
    >>> parse_variable("gap", "0.01:0.06")
    Variable(name='gap', kind='float', low=0.01, high=0.06, choices=())
    >>> parse_variable("m", "log:0.005:0.1").kind, parse_variable("material", "steel,brass", str).choices
    ('log', ('steel', 'brass'))
    >>> parse_variable("balls", "1:5", int)
    Variable(name='balls', kind='int', low=1, high=5, choices=())
    """
    if kind is int:
        return _whole(parse_variable(name, text))
    if isinstance(text, (int, float)) and not isinstance(text, bool) and kind is float:
        return Variable(name, "fixed", choices=(_number(name, repr(float(text))),))
    s = str(text).strip()
    if not s:
        raise ParameterError(name, f"expected {VARIABLE_FORM}")
    if ":" in s:
        if kind is not float:
            raise ParameterError(name, f"expected names separated by commas, got {s!r}")
        parts = s.split(":")
        log = parts[0].strip().lower() == "log"
        if log:
            parts = parts[1:]
        if len(parts) != 2:
            raise ParameterError(name, f"expected {VARIABLE_FORM}, got {s!r}")
        lo, hi = _number(name, parts[0]), _number(name, parts[1])
        if not lo < hi:
            raise ParameterError(name, f"needs LO < HI, got {s!r}")
        if log and lo <= 0:
            raise ParameterError(name, f"a log scale needs LO > 0, got {s!r}")
        return Variable(name, "log" if log else "float", lo, hi)
    items = [p.strip() for p in s.split(",")]
    values = tuple(_number(name, p) for p in items) if kind is float else tuple(items)
    if any(not str(v) for v in values):
        raise ParameterError(name, f"expected {VARIABLE_FORM}, got an empty item in {s!r}")
    if len(set(values)) != len(values):
        raise ParameterError(name, f"values must not repeat, got {s!r}")
    return Variable(name, "categorical" if len(values) > 1 else "fixed", choices=values)


def _whole(var: Variable) -> Variable:
    """``var`` over the integers: its bounds or values whole numbers, a range ``"int"`` (no log scale)."""
    if var.kind == "log":
        raise ParameterError(var.name, "a whole number takes LO:HI, A,B,C or one value, not a log scale")
    values = (var.low, var.high) if var.kind == "float" else var.choices
    if any(v != math.floor(v) for v in values):
        raise ParameterError(var.name, f"must be whole numbers, got {', '.join(f'{v:g}' for v in values)}")
    if var.kind == "float":
        return Variable(var.name, "int", int(var.low), int(var.high))
    return Variable(var.name, var.kind, choices=tuple(int(v) for v in var.choices))


@dataclass(frozen=True)
class Objective:
    """A column to minimise (``sense="min"``) or maximise (``"max"``)."""

    column: str
    sense: str

    def to_dict(self) -> dict:
        """The objective as plain JSON values."""
        return {"column": self.column, "sense": self.sense}


@dataclass(frozen=True)
class Constraint:
    """``column <= value`` (``op="<="``) or ``column >= value``; a design missing the column (NaN) violates it."""

    column: str
    op: str
    value: float

    def violation(self, x: float) -> float:
        """How far ``x`` is from satisfying the constraint, relative to ``|value|`` (or absolute at 0); 0 if it does."""
        if not math.isfinite(x):
            return math.inf
        excess = x - self.value if self.op == "<=" else self.value - x
        return max(0.0, excess) / (abs(self.value) or 1.0)

    def text(self) -> str:
        """``COLUMN<=VALUE`` as typed."""
        return f"{self.column}{self.op}{self.value!r}"


def parse_constraint(name: str, text: str) -> Constraint:
    """Parse ``COLUMN<=VALUE`` or ``COLUMN>=VALUE``.

    Examples
    --------
    >>> parse_constraint("constraints", "inclination_two_maxima_m_s>=0.004")
    Constraint(column='inclination_two_maxima_m_s', op='>=', value=0.004)
    """
    m = _CONSTRAINT.fullmatch(str(text))
    if m is None:
        raise ParameterError(name, f"expected 'COLUMN<=VALUE' or 'COLUMN>=VALUE', got {text!r}")
    value = _number(name, m[3])
    return Constraint(m[1], m[2], value)


@dataclass(frozen=True)
class Problem:
    """The variables, objectives and constraints of an optimisation, and its budget.

    Attributes
    ----------
    variables : tuple of Variable
        Every design variable (fixed ones included).
    objectives : tuple of Objective
        One (the best design) or more (a Pareto front).
    constraints : tuple of Constraint
        Every constraint a feasible design meets.
    evaluations : int
        Number of designs evaluated in all (>= 1).
    seed : int
        Seed of the optimiser (>= 0): the same seed, problem and batch give the same designs.
    batch : int
        Designs asked of the optimiser at a time and evaluated in parallel (>= 1).
    columns : tuple of str
        The columns objectives and constraints may name (those of the evaluation mode).
    """

    variables: tuple
    objectives: tuple
    constraints: tuple
    evaluations: int
    seed: int
    batch: int
    columns: tuple = ()

    def __post_init__(self):
        for name in ("evaluations", "seed", "batch"):  # the front ends check the ranges of their records
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < (0 if name == "seed" else 1):
                raise ParameterError(name, f"must be an integer >= {0 if name == 'seed' else 1}, got {value!r}")
        if not self.objectives:
            raise ParameterError("minimize", "give at least one objective column (--minimize or --maximize)")
        for name, items in (("objectives", self.objectives), ("constraints", self.constraints)):
            for it in items:
                if self.columns and it.column not in self.columns:
                    option = name if name == "constraints" else ("minimize" if it.sense == "min" else "maximize")
                    raise ParameterError(option, f"unknown column {it.column!r}; one of {', '.join(self.columns)}")
        cols = [o.column for o in self.objectives]
        if len(set(cols)) != len(cols):
            raise ParameterError("minimize", f"an objective column appears twice: {cols}")
        names = [v.name for v in self.variables]
        if len(set(names)) != len(names):
            raise ParameterError("variables", f"a variable appears twice: {names}")
        if not any(v.searched for v in self.variables):
            raise ParameterError("variables", f"no variable to search: give at least one as {VARIABLE_FORM}")

    @property
    def searched(self) -> tuple:
        """The variables the optimiser chooses (not fixed)."""
        return tuple(v for v in self.variables if v.searched)

    @property
    def fixed(self) -> dict:
        """``{name: value}`` of the fixed variables."""
        return {v.name: v.choices[0] for v in self.variables if not v.searched}

    def to_dict(self) -> dict:
        """The problem as plain JSON values."""
        return {"variables": [v.to_dict() for v in self.variables],
                "objectives": [o.to_dict() for o in self.objectives],
                "constraints": [c.text() for c in self.constraints],
                "evaluations": self.evaluations, "seed": self.seed, "batch": self.batch}


def objective_matrix(problem: Problem, rows) -> np.ndarray:
    """``(n, k)`` objective values of ``rows`` (dicts of column -> number), each to be minimised (maxima negated)."""
    out = np.full((len(rows), len(problem.objectives)), np.nan)
    for i, row in enumerate(rows):
        for j, o in enumerate(problem.objectives):
            v = float(row[o.column])
            out[i, j] = v if o.sense == "min" else -v
    return out


def feasible_mask(problem: Problem, rows) -> np.ndarray:
    """True for each row that succeeded, has finite objectives and meets every constraint."""
    values = objective_matrix(problem, rows)
    ok = np.all(np.isfinite(values), axis=1)
    for i, row in enumerate(rows):
        if row.get("error"):
            ok[i] = False
        elif ok[i]:
            ok[i] = all(c.violation(float(row[c.column])) == 0.0 for c in problem.constraints)
    return ok


def pareto_mask(values, candidates=None) -> np.ndarray:
    """True for each row of ``values`` (to be minimised) that no other candidate row dominates.

    Row a dominates row b when it is no worse in every column and better in one. Only rows where
    ``candidates`` is True take part (default all); a tie keeps both.

    Examples
    --------
    >>> pareto_mask([[1, 2], [2, 1], [2, 2]]).tolist()
    [True, True, False]
    """
    v = np.asarray(values, dtype=float)
    cand = np.ones(len(v), dtype=bool) if candidates is None else np.asarray(candidates, dtype=bool).copy()
    out = cand.copy()
    idx = np.flatnonzero(cand)
    for i in idx:
        others = v[idx]
        dominated = np.all(others <= v[i], axis=1) & np.any(others < v[i], axis=1)
        out[i] = not dominated.any()
    return out
