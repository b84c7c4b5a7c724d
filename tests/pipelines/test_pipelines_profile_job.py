"""A line profile as the job's input (tests/data/dektak-1.csv, a real stylus scan; licence in
tests/data): the Nayak scan, the maps synthesised from its spectrum, the realisations' spread
of the BEM's A_r, the isotropy warning, and the [surface] profile keys."""

from __future__ import annotations

import copy
import math
from pathlib import Path

import numpy as np
import pytest

from asperity import topo
from asperity.pipelines.config import ConfigError, config_from_dict
from asperity.pipelines.engine.stage import DISABLED, hash_document, key_document
from asperity.pipelines.job import run_job
from asperity.pipelines.report.profile import profile_section
from asperity.pipelines.stages import STAGES
from asperity.pipelines.stages.realisations import REALISATIONS
from asperity.pipelines.stages.verdict import verdict_markdown
from asperity.statmodel import StatmodelWarning, TaborWarning

DATA = Path(__file__).resolve().parents[1] / "data"
PROFILE = DATA / "dektak-1.csv"
#: A stiff polymer on the stylus-measured surface: A_r/A_n of a few percent at 1-3 N on 1e-5 m^2.
MATERIAL = {"E_star": 2e9, "work_of_adhesion": 0.005}
LOADING = {"nominal_area": 1e-5, "normal_loads": [1.0, 2.0, 3.0], "steps": 21}


def _data(tmp_path: Path, **surface) -> dict:
    """A small profile job: 1500 points of the scan, strides 1-2, 64^2 synthesised maps."""
    keys = {"file": str(PROFILE), "crop": [0, 1500, 0, 1], "max_stride": 2}
    keys.update(profile_synthesis_n=64, **surface)
    return {
        "surface": keys,
        "material": dict(MATERIAL),
        "loading": dict(LOADING),
        "bem": {"max_stride": 1},
    }


def _measured_csv(tmp_path: Path) -> Path:
    path = tmp_path / "area.csv"
    path.write_text("normal_load,real_area\n1.0,2.0e-7\n2.0,3.6e-7\n3.0,5.0e-7\n")
    return path


@pytest.fixture(scope="module")
def measured_run(tmp_path_factory):
    """BEM disabled, calibrated on a measured A_r(F_z): (config, out_dir, JobResult)."""
    out = tmp_path_factory.mktemp("profile_job")
    data = _data(out, profile_seed=7)
    data["bem"] = {"enabled": False}
    data["measured"] = {"normal_area": str(_measured_csv(out))}
    config = config_from_dict(data, source="profile.toml", base_dir=out)
    # the profile's summits give mu < 5 (the verdict's "tabor") and A_r/A_n > 0.1: said by
    # the model itself, as StatmodelWarnings
    with pytest.warns(StatmodelWarning) as caught:
        result = run_job(config, out)
    assert any(issubclass(w.category, TaborWarning) for w in caught)
    return config, out, result


@pytest.fixture(scope="module")
def synthesis_run(measured_run):
    """BEM on 64^2 maps synthesised from the profile, three realisations, in the same folder
    (the read-and-level and scan stages are reused from the measured run, which this job
    replaces on purpose: ``replace_run``)."""
    _, out, _ = measured_run
    data = _data(out, profile_realisations=3, profile_seed=7)
    config = config_from_dict(data, source="profile.toml", base_dir=out)
    with pytest.warns(StatmodelWarning) as caught:
        result = run_job(config, out, replace_run=True)
    assert any(issubclass(w.category, TaborWarning) for w in caught)
    return config, out, result


def _prepared_profile(result) -> topo.LineProfile:
    profile = result.surface.line_profile()
    assert profile is not None
    return profile


def test_measured_profile_job_ends_with_the_isotropy_warning(measured_run):
    _, out, result = measured_run
    verdict = result.verdict
    assert "profile_isotropy" in verdict.codes
    i = verdict.codes.index("profile_isotropy")
    assert verdict.severities[i] == "warning"
    assert "isotropic" in verdict.reasons[i] and "1500 points" in verdict.reasons[i]
    assert result.bem_reference is None and result.realisations is None
    assert any("profile_isotropy" in line for line in verdict_markdown(verdict))


def test_profile_scan_is_nayaks_density_from_the_profile_moments(measured_run):
    """eta = m4 / (6 pi sqrt(3) m2) (Nayak 1971) with the moments written out here from finite
    differences of the stored profile at sampling interval k dx."""
    _, _, result = measured_run
    scan, profile = result.resolution_scan, _prepared_profile(result)
    assert scan.method == "nayak-profile"
    z = np.asarray(profile.heights)
    for i, k in enumerate(scan.stride):
        h = k * profile.dx
        m2 = np.mean(((z[k:] - z[:-k]) / h) ** 2)
        m4 = np.mean(((z[2 * k :] - 2 * z[k:-k] + z[: -2 * k]) / h**2) ** 2)
        eta = m4 / (6 * math.pi * math.sqrt(3) * m2)
        assert scan.asperity_density[i] == pytest.approx(eta, rel=1e-6)
        assert scan.resolution[i] == pytest.approx(h)
    # the statistical model ran on those statistics, against the measurement, at one of the
    # scan's strides (no resampling of the synthesised map between strides: another statistic)
    res = result.statistical_model
    assert res.basis == "measured"
    assert np.all(np.isfinite(res.real_area[res.index]))
    assert res.roughness.asperity_density == pytest.approx(scan.asperity_density[res.index])
    assert res.roughness.summit_height_rms == pytest.approx(scan.summit_height_rms[res.index])
    assert getattr(res, "optimum_status", None) is None


@pytest.mark.slow  # several seconds: the default run stays under 3 min on 2 cores
def test_profile_job_stores_the_realisations_spread(synthesis_run):
    config, out, result = synthesis_run
    spread, bem = result.realisations, result.bem_reference
    assert spread.realisations == 3 and list(spread.seed) == [7, 8, 9]
    assert spread.contact_fraction.shape == (3, 3)
    # realisation 0 is the BEM stage's own map
    np.testing.assert_allclose(spread.contact_fraction[0], bem.reference_fraction())
    # independent maps of one spectrum: different areas, but of one size
    assert np.all(np.ptp(spread.contact_fraction, axis=0) > 0)
    assert np.all(spread.relative_spread < 0.5)
    np.testing.assert_allclose(
        spread.std_fraction, np.std(spread.contact_fraction, axis=0, ddof=1), rtol=1e-12
    )
    # A_r grows with the load in every realisation
    assert np.all(np.diff(spread.contact_fraction, axis=1) > 0)
    section = "\n".join(profile_section(result))
    assert "## Line profile input" in section and "3 realisations" in section
    assert "64 x 64 px" in section and "seed 7" in section
    # the scan was taken from the measured run's store: one profile, one scan
    assert [s.status for s in result.stages[:2]] == ["stored", "stored"]
    assert "profile_isotropy" in result.verdict.codes


@pytest.mark.slow  # several seconds: the default run stays under 3 min on 2 cores
def test_synthesised_map_keeps_the_profile_slope(synthesis_run):
    """The map synthesised from the profile's spectrum has the profile's rms slope along x (the
    Abel inversion keeps m2; slopes live at short wavelengths, which the map holds)."""
    _, _, result = synthesis_run
    profile = _prepared_profile(result)
    heights = result.surface.heights
    map_slope = np.sqrt(np.mean((np.diff(heights, axis=0) / result.surface.dx) ** 2))
    profile_slope = np.sqrt(np.mean((np.diff(profile.heights) / profile.dx) ** 2))
    assert map_slope == pytest.approx(profile_slope, rel=0.2)
    assert result.surface.dx == pytest.approx(profile.dx)
    assert result.surface.nx == result.surface.ny == 64


def test_profile_keys_are_validated(tmp_path):
    base = _data(tmp_path)
    for key, value, expected in (
        ("profile_realisations", 0, r"surface\.profile_realisations: expected an integer in"),
        ("profile_realisations", 50, r"surface\.profile_realisations: expected an integer in"),
        ("profile_synthesis_n", 16, r"surface\.profile_synthesis_n: expected an integer in"),
        ("profile_seed", -1, r"surface\.profile_seed: expected an integer in"),
    ):
        data = {**base, "surface": {**base["surface"], key: value}}
        with pytest.raises(ConfigError, match=expected):
            config_from_dict(data, source="p.toml", base_dir=tmp_path)


def test_a_profile_without_a_nominal_area_is_refused(tmp_path):
    data = _data(tmp_path)
    del data["loading"]["nominal_area"]
    config = config_from_dict(data, source="p.toml", base_dir=tmp_path)
    with pytest.raises(ConfigError, match=r"^p\.toml: loading\.nominal_area: .*line profile has"):
        run_job(config, tmp_path / "out")
    assert not (tmp_path / "out" / "results.h5").exists()


def test_a_profile_crop_with_a_y_range_is_refused(tmp_path):
    data = _data(tmp_path)
    data["surface"]["crop"] = [0, 1500, 0, 5]
    config = config_from_dict(data, source="p.toml", base_dir=tmp_path)
    with pytest.raises(ConfigError, match=r"surface\.crop: expected \[x0, x1, 0, 1\]"):
        run_job(config, tmp_path / "out")


def _planned_keys(config, document):
    """Every stage's key for this configuration document, as the job plans them."""
    keys = {}
    for stage in STAGES:
        enabled = stage.enabled(config)
        keys[stage.name] = (
            hash_document(key_document(stage, document, keys, "1.0")) if enabled else DISABLED
        )
    return keys


@pytest.mark.parametrize("key", REALISATIONS.config)
def test_every_key_the_realisations_read_recomputes_them(tmp_path, key):
    """On a profile job the realisations stage is enabled, and each key it declares keys it."""
    config = config_from_dict(_data(tmp_path), source="p.toml", base_dir=tmp_path)
    before = _planned_keys(config, config.key_document())
    document = copy.deepcopy(config.key_document())
    section, name = key.split(".")
    document[section][name] = {"changed": True}
    after = _planned_keys(config, document)
    assert before["realisations"] != DISABLED
    assert after["realisations"] != before["realisations"]


def test_the_realisations_are_off_for_a_map_one_realisation_or_no_bem(tmp_path):
    profile = config_from_dict(_data(tmp_path), source="p.toml", base_dir=tmp_path)
    assert REALISATIONS.enabled(profile)
    one = _data(tmp_path, profile_realisations=1)
    assert not REALISATIONS.enabled(config_from_dict(one, base_dir=tmp_path))
    a_map = _data(tmp_path)
    a_map["surface"] = {"file": str(DATA / "mi-1.mi")}
    assert not REALISATIONS.enabled(config_from_dict(a_map, base_dir=tmp_path))
