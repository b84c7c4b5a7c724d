"""Every measured column's magnitude is checked: a tangential force in mN under an SI header
is refused with the unit that would make it plausible, as a load in mN is."""

from __future__ import annotations

import pytest

from asperity.errors import InputError
from asperity.pipelines.measured import MAX_FRICTION_COEFFICIENT, read_shear_area


def _curve(path, forces, header="tangential_force,real_area"):
    rows = "".join(f"{f},{1e-7 * (i + 1)}\n" for i, f in enumerate(forces))
    path.write_text(header + "\n" + rows, encoding="utf-8")
    return path


def test_millinewtons_under_an_si_header_are_refused_with_the_unit(tmp_path):
    # F_z = 0.5 N, a friction force peaking at 400 mN written as 400 (N)
    path = _curve(tmp_path / "fx.csv", [0, 120, 400, 310])
    with pytest.raises(InputError) as caught:
        read_shear_area(path, normal_load=0.5)
    text = str(caught.value)
    assert "line 4, column 'tangential_force'" in text and "[mN]" in text
    assert "0.8" in text  # |F_x|/F_z once read in mN
    (curve,) = read_shear_area(
        _curve(tmp_path / "mn.csv", [0, 120, 400, 310], "tangential_force [mN],real_area"),
        normal_load=0.5,
    )
    assert curve.tangential_force.max() == pytest.approx(0.4)


def test_plausible_and_tensile_curves_pass(tmp_path):
    fine = read_shear_area(_curve(tmp_path / "a.csv", [0, 0.3, 0.9]), normal_load=0.5)
    assert fine[0].tangential_force.max() / 0.5 < MAX_FRICTION_COEFFICIENT
    # under tension (F_z < 0, adhesion) any ratio is possible: not checked
    assert read_shear_area(_curve(tmp_path / "b.csv", [0, 0.3]), normal_load=-0.01)
