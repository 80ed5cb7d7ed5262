"""Elastic materials and the catalogue shipped in ``assets/materials.toml``."""

from __future__ import annotations

import difflib
import functools
import math
from dataclasses import dataclass
from importlib import resources

from .._validate import ParameterError, check_positive, check_range

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

__all__ = ["Material", "catalogue", "material", "reduced_modulus", "sphere_radius"]


@dataclass(frozen=True)
class Material:
    """An isotropic linear-elastic material.

    Parameters
    ----------
    E : float
        Young's modulus in Pa.
    nu : float
        Poisson's ratio, in [-1, 0.5).
    density : float
        Density in kg/m³.
    name : str
        Short name (catalogue key).
    source : str
        Where the values come from.

    Examples
    --------
    A material outside the catalogue; its Hertz stiffness against the catalogue's steel for the
    paper's 19.05 mm radius sphere (paper eq 2):

    >>> from acoustiviz.core.contact import hertz_stiffness
    >>> glass = Material(E=63e9, nu=0.23, density=2500.0, name="soda-lime glass")
    >>> f"{hertz_stiffness(0.01905, glass, material('steel')):.3g}"  # N/m^1.5
    '9.5e+09'
    """

    E: float
    nu: float
    density: float
    name: str = ""
    source: str = ""

    def __post_init__(self):
        check_positive("E", self.E, "Pa")
        check_range("nu", self.nu, -1.0, 0.5, high_open=True)
        check_positive("density", self.density, "kg/m^3")

    @property
    def plane_strain_compliance(self) -> float:
        """(1 - ν²)/E in 1/Pa, one body's share of the Hertz compliance."""
        return (1.0 - self.nu**2) / self.E


def reduced_modulus(a: Material, b: Material) -> float:
    """Hertz reduced modulus E* = 1 / ((1-ν₁²)/E₁ + (1-ν₂²)/E₂) in Pa.

    Notes
    -----
    Johnson, *Contact Mechanics* (1985), eq. 4.22; the paper's eq 2 writes the same
    quantity with the factors of π of Goldsmith's notation.
    """
    return 1.0 / (a.plane_strain_compliance + b.plane_strain_compliance)


@functools.lru_cache(maxsize=1)
def _load() -> dict:
    text = resources.files("acoustiviz").joinpath("assets/materials.toml").read_text("utf-8")
    raw = tomllib.loads(text)
    out = {}
    for key, entry in raw.items():
        out[key] = Material(
            E=float(entry["E"]),
            nu=float(entry["nu"]),
            density=float(entry["density"]),
            name=key,
            source=str(entry.get("source", "")),
        )
    return out


def catalogue() -> dict[str, Material]:
    """Return a copy of the materials catalogue, keyed by name (e.g. ``"steel"``).

    Examples
    --------
    The bar wave speed ``sqrt(E/ρ)`` of a few catalogue materials, in m/s:

    >>> table = catalogue()
    >>> {k: round(math.sqrt(table[k].E / table[k].density)) for k in ("steel", "nylon", "rubber")}
    {'steel': 5172, 'nylon': 1567, 'rubber': 67}
    """
    return dict(_load())


def material(name: str) -> Material:
    """Look up a catalogue material by name (case-insensitive; spaces or dashes allowed).

    Raises
    ------
    ParameterError
        If the name is unknown; the message lists the close matches and all names.

    Examples
    --------
    >>> steel = material("Steel")
    >>> steel.E, steel.nu, steel.density  # Pa, -, kg/m³
    (210000000000.0, 0.3, 7850.0)
    >>> material("stainless-steel").name
    'stainless_steel'
    >>> material("stele")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    acoustiviz.errors.ParameterError: material: unknown material 'stele' (did you mean 'steel'?); known: ...
    """
    key = str(name).strip().lower().replace(" ", "_").replace("-", "_")
    table = _load()
    if key in table:
        return table[key]
    close = difflib.get_close_matches(key, table, n=1)
    hint = f" (did you mean {close[0]!r}?)" if close else ""
    raise ParameterError(
        "material", f"unknown material {name!r}{hint}; known: {', '.join(sorted(table))}"
    )


def sphere_radius(mass: float, density: float) -> float:
    """Radius in m of a solid sphere of ``mass`` kg and ``density`` kg/m³: a = (3 m / (4 π ρ))^(1/3).

    Examples
    --------
    >>> round(sphere_radius(0.0405, 7800.0), 6)  # the Table 1 impact mass as a steel ball
    0.010742
    """
    m = check_positive("mass", mass, "kg")
    rho = check_positive("density", density, "kg/m^3")
    return (3.0 * m / (4.0 * math.pi * rho)) ** (1.0 / 3.0)
