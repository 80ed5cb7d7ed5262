import dataclasses
import math

import pytest

from acoustiviz.core.contact import hertz_stiffness
from acoustiviz.core.materials import catalogue, material, reduced_modulus
from acoustiviz.core.medium import AIR, Medium, air_at
from acoustiviz.errors import ParameterError

REQUIRED = ["steel", "stainless_steel", "aluminium", "brass", "glass", "pmma", "nylon", "rubber"]


def test_catalogue_has_the_required_materials_with_sources():
    cat = catalogue()
    for name in REQUIRED:
        m = cat[name]
        assert m.source, name
        assert 1e5 < m.E < 1e12 and 0 <= m.nu < 0.5 and 500 < m.density < 20000


def test_lookup_is_forgiving_about_spelling():
    assert material("Stainless Steel") is material("stainless-steel")


def test_reduced_modulus_of_identical_bodies():
    s = material("steel")
    assert reduced_modulus(s, s) == pytest.approx(s.E / (2 * (1 - s.nu**2)), rel=1e-12)  # < 10 roundings either way


def test_soft_surface_lowers_stiffness():
    s = material("steel")
    assert hertz_stiffness(0.01, s, material("rubber")) < 1e-3 * hertz_stiffness(0.01, s, s)


def test_air_default_and_ideal_gas():
    assert AIR.c == pytest.approx(air_at(20.0).c, rel=1e-3)
    assert AIR.rho == pytest.approx(air_at(20.0).rho, rel=1e-3)
    # c grows as sqrt(T)
    assert air_at(80.0).c / air_at(0.0).c == pytest.approx(math.sqrt(353.15 / 273.15), rel=1e-12)
    with pytest.raises(ParameterError, match="temperature"):
        air_at(500.0)
    with pytest.raises(ParameterError, match="rho"):
        Medium(c=343.0, rho=0.0)
    with pytest.raises(dataclasses.FrozenInstanceError):  # frozen: no global mutable state
        AIR.c = 300.0  # type: ignore[misc]

