"""Unit parsing (tribobem.units): numbers are SI, strings carry units, dimensions are checked."""

import math

import pytest

from tribobem.errors import InputError
from tribobem.units import display_unit, format_quantity, to_si


@pytest.mark.parametrize(
    "value, dimension, expected",
    [
        ("10 uN", "force", 1e-5),
        ("10 µN", "force", 1e-5),
        ("0.2 nm", "length", 2e-10),
        ("2 Å", "length", 2e-10),
        ("1 micron", "length", 1e-6),
        ("130 GPa", "pressure", 130e9),
        ("130 GPa", "modulus", 130e9),
        ("50 mJ/m^2", "surface_energy", 0.05),
        ("0.05 N/m", "surface_energy", 0.05),  # same dimension as J/m^2
        ("0.0725 N/m", "surface_tension", 0.0725),
        ("18.05e-6 m^3/mol", "molar_volume", 18.05e-6),
        ("295 K", "temperature", 295.0),
        ("30 %", "dimensionless", 0.3),
        ("1e-9", "length", 1e-9),  # a number in a string: SI
        (3, "force", 3.0),  # numbers are SI
        (2.5e-9, "length", 2.5e-9),
    ],
)
def test_to_si_converts(value, dimension, expected):
    assert to_si(value, dimension) == pytest.approx(expected, rel=1e-12)


def test_prefix_conversion_has_no_binary_noise():
    assert to_si("10 uN", "force") == 1e-5
    assert to_si("0.2 nm", "length") == 2e-10


def test_inf_is_accepted_for_a_rigid_modulus():
    assert math.isinf(to_si("inf", "modulus"))


def test_wrong_dimension_names_the_key():
    with pytest.raises(InputError) as exc:
        to_si("3 nm", "force", field="load.force")
    assert str(exc.value) == "load.force: expected a force (N), got '3 nm'"
    assert exc.value.field == "load.force"


@pytest.mark.parametrize("value", ["10 foo", "abc", "", True, [1.0], None])
def test_unparseable_values_are_input_errors(value):
    with pytest.raises(InputError, match="body1.E"):
        to_si(value, "pressure", field="body1.E")


def test_unknown_dimension_is_a_programming_error():
    with pytest.raises(ValueError):
        to_si(1.0, "banana")


def test_display_units_are_chosen_from_the_data():
    assert display_unit([1e-9, 3e-9], "length") == (1e-9, "nm")
    assert display_unit([2e-6], "length", ascii_only=True) == (1e-6, "um")
    assert display_unit([2e8], "pressure") == (1e6, "MPa")
    assert display_unit([3e9], "pressure") == (1e9, "GPa")
    assert display_unit([3e-7], "force") == (1e-9, "nN")
    assert display_unit([3e-14], "area", ascii_only=True) == (1e-18, "nm^2")
    assert format_quantity(1.2e-6, "force") == "1.2 \u00b5N"
    assert format_quantity(3120e-18, "area", 3, ascii_only=True) == "3120 nm^2"
    assert format_quantity(None, "force") == "n/a"


# ----------------------------------------------------------------------------- dimension-free parsing
def test_si_value_and_si_unit_without_an_expected_dimension():
    from tribobem.units import parse_quantity, si_unit, si_value

    assert si_value("100 um") == 1e-4 and si_value("10 µN") == 1e-5 and si_value("2 Å") == 2e-10
    assert si_value("30 mJ/m^2") == pytest.approx(0.03)
    assert si_value(3) == 3 and isinstance(si_value(3), int) and si_value("3") == 3.0
    for other in (True, None, "abc", [1, 2], {"a": 1}):
        assert si_value(other) == other
    assert si_unit("130 GPa") == "kilogram / meter / second ** 2" and si_unit("1 micron") == "meter"
    assert si_unit("3") == si_unit(3.0) == si_unit("abc") == ""
    assert parse_quantity("5 µm").to("m").magnitude == pytest.approx(5e-6)
    assert parse_quantity("not a unit") is None
