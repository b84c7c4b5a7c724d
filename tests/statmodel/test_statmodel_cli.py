"""The ``asperity friction`` / ``asperity figures`` command-line contract."""

import json
import warnings
from pathlib import Path

import h5py
import numpy as np
import pytest

from asperity.pipelines.cli import main
from asperity.statmodel import Material, Roughness, shear_curve
from tests._helpers import adhesive_in_tension_toml

EXAMPLE = Path(__file__).resolve().parents[2] / "statmodel" / "examples" / "fig4.toml"


def run(capsys, *argv):
    status = main(list(argv))
    out, err = capsys.readouterr()
    return status, out, err


def test_friction_json_contract(capsys):
    status, out, _ = run(capsys, "friction", str(EXAMPLE), "--json")
    assert status == 0
    data = json.loads(out)
    arrays = [
        "tangential_displacement",
        "tangential_force",
        "normal_force",
        "real_area",
        "n_contact",
        "n_stick",
        "n_slip",
    ]
    scalars = ["tabor_parameter", "separation_preload", "static_friction", "sliding_friction"]
    for key in arrays:
        assert len(data[key]) == 281, key
    for key in scalars:
        assert isinstance(data[key], float), key
    assert data["tangential_displacement"][0] == 0.0
    assert data["tangential_displacement"][-1] == pytest.approx(14e-6)
    np.testing.assert_allclose(data["normal_force"], 3.1, rtol=1e-9)
    # the numbers are those of the Python API
    c = shear_curve(
        Material(2.133e6, 0.040, 0.2, 0.13e6),
        Roughness(652.1e6, 0.041e-3, 0.032e-3),
        700e-6,
        3.1,
        np.linspace(0, 14e-6, 281),
    )
    assert data["static_friction"] == c.static_friction
    assert data["sliding_friction"] == c.sliding_friction
    assert data["tabor_parameter"] == pytest.approx(1217, rel=1e-3)


def test_friction_hdf5_has_units_everywhere(tmp_path, capsys):
    out = tmp_path / "res.h5"
    status, text, _ = run(capsys, "friction", str(EXAMPLE), "--out", str(out))
    assert status == 0 and "static friction" in text
    with h5py.File(out) as fh:
        names = []
        fh.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) else None)
        assert {"tangential_force", "real_area", "n_stick", "sliding_friction"} <= set(names)
        for n in names:
            assert "units" in fh[n].attrs, n
        assert fh["tangential_force"].attrs["units"] == "N"
        assert fh["tangential_force"].shape == (281,)


def _write(tmp_path, text):
    p = tmp_path / "p.toml"
    p.write_text(text)
    return p


@pytest.mark.parametrize(
    "old, new, key",
    [
        ("E_star = 2.133e6", "E_star = -2.133e6", "E_star"),
        ("steps = 281", "steps = 281\ncolour = 3", "colour"),
        ("summit_radius = 0.041e-3    # R, m\n", "", "summit_radius"),
        ("mode_mixity = 0.2", "mode_mixity = 1.2", "mode_mixity"),
        ("steps = 281", "steps = 2.5", "steps"),
        ("nominal_area = 700e-6", "nominal_area = 1e-12", "loading.nominal_area: expected an area"),
        ("steps = 281", "steps = 0", "loading.steps: expected an integer in [1, 100000]"),
        ("steps = 281", "steps = true", "loading.steps: expected an integer"),
        ("E_star = 2.133e6", 'E_star = "2.133e6"', "material.E_star: expected a number"),
        ("E_star = 2.133e6", "E_star = [2.133e6]", "material.E_star: expected a number"),
        ("work_of_adhesion = 0.040", "work_of_adhesion = -0.040", "material.work_of_adhesion"),
        ("shear_strength = 0.13e6", "shear_strength = -1.0", "material.shear_strength"),
        ("equilibrium_distance = 0.2e-9", "equilibrium_distance = 0.0", "equilibrium_distance"),
        ("asperity_density = 652.1e6", "asperity_density = 0", "roughness.asperity_density"),
        ("summit_radius = 0.041e-3", "summit_radius = -0.041e-3", "roughness.summit_radius"),
        ("summit_height_rms = 0.032e-3", "summit_height_rms = nan", "summit_height_rms"),
        (
            "max_tangential_displacement = 14e-6",
            "max_tangential_displacement = -1e-6",
            "loading.max_tangential_displacement: expected a number in (0, 1] m",
        ),
        ("normal_load = 3.1           # N\n", "", "loading.normal_load: expected a value"),
        # absurd values refused at validation, with the reason
        (
            "E_star = 2.133e6",
            "E_star = 1e308",
            "material.E_star: expected a number in [100, 1e+13]",
        ),
        ("steps = 281", "steps = 9223372036854775807", "loading.steps: expected an integer"),
        ("steps = 281", "steps = 281\n[accuracy]\nnodes = 1e6", "accuracy.nodes: expected"),
        ("steps = 281", "steps = 281\n[accuracy]\nnodes = 1000000", "accuracy.nodes"),
        ("steps = 281", "steps = 281\n[accuracy]\ncutoff_sigma = 1e300", "underflows"),
        ("steps = 281", "steps = 281\n[accuracy]\nload_rtol = 1", "accuracy.load_rtol"),
        ("[loading]", "[load]", "'load'"),
        ("normal_load = 3.1", "normal_load = -1.0", "pull-off force"),
        ("normal_load = 3.1", 'normal_load = "3.1"', "normal_load"),
    ],
)
def test_friction_bad_input_exits_2_naming_the_key(tmp_path, capsys, old, new, key):
    text = EXAMPLE.read_text()
    assert old in text
    p = _write(tmp_path, text.replace(old, new))
    status, _, err = run(capsys, "friction", str(p), "--json")
    assert status == 2
    assert key in err and "error" in err


def test_friction_file_accepts_the_lower_case_modulus(tmp_path, capsys):
    p = _write(tmp_path, EXAMPLE.read_text().replace("E_star =", "e_star ="))
    status, out, _ = run(capsys, "friction", str(p), "--json")
    assert status == 0
    assert json.loads(out)["tabor_parameter"] == pytest.approx(1217, rel=1e-3)


def test_friction_unknown_table_and_missing_file(tmp_path, capsys):
    p = _write(tmp_path, EXAMPLE.read_text() + "\n[extra]\nx = 1\n")
    status, _, err = run(capsys, "friction", str(p))
    assert status == 2 and "extra" in err
    status, _, err = run(capsys, "friction", str(tmp_path / "missing.toml"))
    assert status == 2 and "missing.toml" in err


ADHESIVE_TOML = adhesive_in_tension_toml(51)


def test_friction_pull_off_under_shear_exits_1_with_results(tmp_path, capsys):
    # a smooth adhesive surface held in tension: shear peels the junctions until the tensile
    # load can no longer be carried; the solve fails, exit status 1, partial results printed
    p = _write(tmp_path, ADHESIVE_TOML)
    status, out, err = run(capsys, "friction", str(p), "--json")
    assert status == 1
    assert "cannot be carried" in err
    data = json.loads(out)
    assert data["converged"] is False
    fz = data["normal_force"]
    assert fz[0] == pytest.approx(-1.0, rel=1e-9)
    assert fz[-1] is None  # steps after the failure are NaN -> null
    # the same file under compression converges; this smooth surface is then in contact over
    # more than 15 % of A_n, beyond independent asperities: computed, exit 3, said on stderr
    p = _write(tmp_path, ADHESIVE_TOML.replace("normal_load = -1.0", "normal_load = 1.0"))
    status, out, err = run(capsys, "friction", str(p), "--json")
    assert json.loads(out)["converged"] is True
    assert status == 3 and "A_r/A_n reaches" in err


def test_friction_single_step_is_the_preload_state(tmp_path, capsys):
    p = _write(tmp_path, EXAMPLE.read_text().replace("steps = 281", "steps = 1"))
    status, out, _ = run(capsys, "friction", str(p), "--json")
    assert status == 0
    data = json.loads(out)
    assert data["tangential_displacement"] == [0.0]
    assert data["tangential_force"] == [0.0]
    assert len(data["real_area"]) == len(data["n_stick"]) == 1
    assert data["normal_force"][0] == pytest.approx(3.1, rel=1e-9)


def test_friction_warns_on_stderr_when_tabor_is_below_5(tmp_path, capsys):
    # E* 1e4 times stiffer: mu = 1217 / 1e4^(2/3) = 2.6 < 5; the warning reaches stderr even
    # when the user's warning filters would silence it
    p = _write(tmp_path, EXAMPLE.read_text().replace("E_star = 2.133e6", "E_star = 2.133e10"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        status, out, err = run(capsys, "friction", str(p), "--json")
    assert status == 3  # computed, outside the model's validity (ExitStatus.INVALID_RESULT)
    assert "asperity friction: warning: Tabor parameter mu = 2.62 < 5" in err
    assert json.loads(out)["tabor_parameter"] == pytest.approx(2.62, rel=1e-2)
    status, _, err = run(capsys, "friction", str(EXAMPLE), "--json")
    assert status == 0 and "warning" not in err


# ------------------------------------------------------------------ Fig. 4 and the figures


@pytest.fixture(scope="module")
def fig4_curve():
    return shear_curve(
        Material(2.133e6, 0.040, 0.2, 0.13e6),
        Roughness(652.1e6, 0.041e-3, 0.032e-3),
        700e-6,
        3.1,
        np.linspace(0, 14e-6, 57),
    )


def test_draw_shear_curve_draws_fig4_in_readable_units(fig4_curve):
    """Fig. 4's four panels in um, N, mm^2 and mN; each total is its stick plus sliding part
    (the two integrals of E:NewFormulation_Fy/Fx/Ar) and F_z stays at the imposed 3.1 N."""
    from asperity.plotting import layout_problems, new_figure
    from asperity.statmodel import draw_shear_curve

    fig = draw_shear_curve(new_figure(10, 8), fig4_curve, title="Fig. 4")
    axes = fig.get_axes()
    assert [ax.get_title() for ax in axes] == ["(a)", "(b)", "(c)", "(d)"]
    assert all(ax.get_xlabel().endswith("(\u00b5m)") for ax in axes)
    units = [ax.get_ylabel().rsplit("(", 1)[-1] for ax in axes]
    assert units == ["N)", "contacting asperities", "mm$^{2}$)", "mN)"]
    for ax in axes:
        x, total, stick, slip = (ax.lines[0].get_xdata(), *(ln.get_ydata() for ln in ax.lines))
        np.testing.assert_allclose(x[-1], 14.0)  # um
        np.testing.assert_allclose(total, stick + slip, rtol=1e-9, atol=1e-9 * np.max(total))
    np.testing.assert_allclose(axes[0].lines[0].get_ydata(), 3.1, rtol=1e-9)
    # the paper's Fig. 4(c): about 6 mm^2 at preload; (d) the static peak, in mN
    assert axes[2].lines[0].get_ydata()[0] == pytest.approx(fig4_curve.real_area[0] * 1e6)
    assert 5.0 < axes[2].lines[0].get_ydata()[0] < 7.0
    # the static friction is the continuous peak: no plotted grid point above it, the grid's
    # maximum within 1 % of it on 57 steps
    plotted_peak = max(axes[3].lines[0].get_ydata())
    assert plotted_peak <= fig4_curve.static_friction * 1e3 * (1 + 1e-12)
    assert plotted_peak >= fig4_curve.static_friction * 1e3 * 0.99
    assert [t.get_text() for t in axes[0].get_legend().get_texts()] == [
        "total",
        "stick",
        "sliding",
    ]
    assert layout_problems(fig) == []


def test_draw_shear_curve_accepts_a_user_figure(fig4_curve):
    """Any blank Figure will do (a notebook's, sized by the user), and it is returned."""
    from matplotlib.figure import Figure

    from asperity.statmodel import draw_shear_curve

    fig = Figure(figsize=(6, 5))
    assert draw_shear_curve(fig, fig4_curve) is fig
    assert len(fig.get_axes()) == 4 and fig._suptitle is None


@pytest.mark.slow  # ~0.6-1 s each; Fig. 4 (the shared plotter) is checked by default
@pytest.mark.parametrize(
    "name", ["fig1_pc_single_asperity", "fig2_status_map", "fig5_parameter_study"]
)
def test_every_paper_figure_has_a_clean_layout(tmp_path, name):
    """No overlapping or clipped text in Figs. 1, 2, 5 (Fig. 4: the test above)."""
    from asperity.plotting import layout_problems
    from asperity.statmodel.figures import FIGURES

    with h5py.File(tmp_path / "data.h5", "w") as h5:
        assert layout_problems(FIGURES[name](h5)) == []
