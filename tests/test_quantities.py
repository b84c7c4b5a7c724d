"""One bound per quantity: the dataclasses, both TOML files, the CLIs and the docs agree."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest
import tomllib
from hypothesis import given
from hypothesis import strategies as st

from asperity.errors import InputError
from asperity.quantities import FRICTION_FILE_KEYS, QUANTITIES, markdown_table, quantity
from asperity.schema import ConfigError, Integer, Real, Section

ROOT = Path(__file__).resolve().parents[1]
FIG4 = (ROOT / "statmodel" / "examples" / "fig4.toml").read_text()


def test_every_bound_is_an_ordered_interval_with_a_reason():
    for key, q in QUANTITIES.items():
        assert q.key == key and q.why, key
        assert math.isfinite(q.low) and math.isfinite(q.high) and q.low < q.high, key
        if q.integer:
            assert q.low == int(q.low) and q.high == int(q.high), key


def _schema_kinds(section: Section, prefix: str):
    for key in section.keys:
        kind = getattr(key.kind, "kind", key.kind)  # OrAuto / ListOf hold the bounded kind
        if isinstance(kind, Section):
            yield from _schema_kinds(kind, f"{prefix}{key.name}.")
        elif isinstance(kind, (Real, Integer)):
            yield f"{prefix}{key.name}", kind


#: Schema keys bounded by a quantity of another name (one bound for several keys).
SHARED = {
    ("friction", "loading.steps"): "friction.loading.steps",
    ("job", "surface.synthetic.pixel_size"): "surface.pixel_size",
    ("job", "loading.normal_loads"): "loading.normal_load",
}


@pytest.mark.parametrize("which", ["job", "friction"])
def test_the_toml_schemas_take_their_bounds_from_the_registry(which):
    if which == "job":
        from asperity.pipelines.config import JOB_SCHEMA as schema
    else:
        from asperity.statmodel.config import FRICTION_SCHEMA as schema
    checked = 0
    for section in schema.sections:
        for name, kind in _schema_kinds(section, f"{section.name}."):
            key = SHARED.get((which, name), name)
            assert key in QUANTITIES, f"{which}: {name} is bounded outside asperity.quantities"
            assert kind == QUANTITIES[key].kind, name
            checked += 1
    assert checked >= (20 if which == "job" else 17)


def _friction_error(tmp_path: Path, table: str, line: str) -> str:
    from asperity.statmodel.config import read_friction_parameters

    path = tmp_path / "p.toml"
    path.write_text(FIG4 + f"\n[{table}]\n{line}\n" if table == "accuracy" else FIG4)
    with pytest.raises(ConfigError) as info:
        read_friction_parameters(path)
    return str(info.value)


@pytest.mark.parametrize(
    "knob, value",
    [("cutoff_sigma", 5), ("load_rtol", 1e-3), ("nodes", 200), ("max_iter", 0)],
)
def test_an_accuracy_knob_is_refused_alike_from_toml_and_python(tmp_path, knob, value):
    from asperity.statmodel import QuadratureOptions

    toml = _friction_error(tmp_path, "accuracy", f"{knob} = {value!r}")
    with pytest.raises(InputError) as info:
        QuadratureOptions(**{knob: value})
    python = str(info.value)
    # the TOML line names the file and the key alone (never the whole table)
    assert toml.startswith(f"{tmp_path / 'p.toml'}: accuracy.{knob}: expected "), toml
    assert toml.split(f"accuracy.{knob}: ", 1)[1] == python.split(f"{knob}: ", 1)[1]
    assert toml.endswith(f", got {value!r}")


def test_the_model_knob_range_is_accepted_from_toml(tmp_path):
    from asperity.statmodel.config import read_friction_parameters

    path = tmp_path / "p.toml"
    path.write_text(FIG4 + "\n[accuracy]\nnodes = 100\nmax_iter = 300\n")
    options = read_friction_parameters(path).options
    assert (options.nodes, options.max_iter) == (100, 300)


@pytest.mark.parametrize(
    "table, key, field, value",
    [
        ("material", "E_star", "e_star", 50.0),  # below the softest gel: refused by both
        ("roughness", "summit_radius", "summit_radius", 500.0),  # refused by both
        ("roughness", "summit_radius", "summit_radius", 50.0),  # accepted by both
    ],
)
def test_material_and_roughness_alike_from_toml_and_python(table, key, field, value):
    from asperity.statmodel import Material, Roughness
    from asperity.statmodel.config import parse_friction_parameters

    data = tomllib.loads(FIG4)
    data[table][key] = value
    base = {"e_star": 2e6, "work_of_adhesion": 0.04, "mode_mixity": 0.2, "shear_strength": 1e5}
    if table == "material":
        owner, build = "Material", lambda: Material(**{**base, field: value})
    else:
        owner, build = "Roughness", lambda: Roughness(6e8, value, 3e-5)
    bound = QUANTITIES[f"{table}.{key}"]
    if bound.low <= value <= bound.high:
        build()
        parse_friction_parameters(data, "p.toml")
        return
    with pytest.raises(InputError) as python:
        build()
    with pytest.raises(ConfigError) as toml:
        parse_friction_parameters(data, "p.toml")
    expected = f"expected {bound.expected()}, got {value!r}"
    assert str(python.value) == f"{owner}.{field}: {expected}"
    assert str(toml.value) == f"p.toml: {table}.{key}: {expected}"


def test_the_docs_bounds_table_is_the_registry():
    text = (ROOT / "docs" / "statmodel.md").read_text()
    block = re.search(
        r"<!-- bounds: asperity.quantities -->\n(.*?)\n<!-- end bounds -->", text, re.S
    )
    assert block, "docs/statmodel.md lost its generated bounds table"
    assert block.group(1) == markdown_table(FRICTION_FILE_KEYS), (
        "regenerate the table: python -c 'from asperity.quantities import *; "
        "print(markdown_table(FRICTION_FILE_KEYS))'"
    )


@given(st.floats(allow_nan=True, allow_infinity=True))
def test_a_real_bound_accepts_exactly_its_interval(value):
    for key in ("material.E_star", "loading.nominal_area", "accuracy.cutoff_sigma"):
        q = quantity(key)
        low_ok = value > q.low if q.open_low else value >= q.low
        inside = math.isfinite(value) and low_ok and value <= q.high
        try:
            q.check(value, key)
        except InputError as exc:
            assert not inside and str(exc).startswith(f"{key}: expected a number in ")
        else:
            assert inside


@given(st.one_of(st.integers(-(2**70), 2**70), st.floats(), st.booleans(), st.text(max_size=3)))
def test_a_count_accepts_integers_in_range_only(value):
    q = quantity("accuracy.nodes")
    integral = not isinstance(value, (bool, str)) and (
        isinstance(value, int) or (math.isfinite(value) and float(value).is_integer())
    )
    inside = integral and 1 <= value <= 128
    try:
        assert q.check(value, "nodes") == value and inside
    except InputError as exc:
        assert not inside and "nodes: expected an integer in [1, 128]" in str(exc)


def test_a_command_line_value_is_parsed_then_bounded():
    q = quantity("surface.synthetic.seed")
    assert q.parse("7", "--seed") == 7
    for text, shown in (("-1", "-1"), ("x", "'x'"), ("1.5", "'1.5'")):
        with pytest.raises(
            InputError, match=rf"^--seed: expected an integer in \[0, .*got {shown}$"
        ):
            q.parse(text, "--seed")
