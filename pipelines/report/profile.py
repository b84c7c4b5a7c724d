"""The report's lines for a line profile as the job's input: the profile, the isotropic maps
synthesised from its spectrum, and the spread of the BEM's A_r over those realisations.

Empty for a map input. Lengths are shown in um, A_r/A_n as fractions; ``results.h5`` keeps SI
(groups ``surface``: ``profile_heights``, ``profile_dx``; ``realisations``).
"""

from __future__ import annotations

from asperity.pipelines.report._run import Run
from asperity.pipelines.stages.realisations import RealisationSpread
from asperity.pipelines.stages.surface import LevelledSurface, ScanResult


def surface_title(surface: LevelledSurface) -> str:
    """The surface figure's title: the levelled map, or the map synthesised from a profile."""
    if getattr(surface, "profile_heights", None) is None:
        return "levelled surface"
    seed = ((surface.provenance or {}).get("profile_synthesis") or {}).get("seed", "?")
    return f"map from the profile's PSD, seed {seed}"


def scan_label(scan: ScanResult) -> str:
    """The legend of the scan's points (Fig 12a-c): the map's summits or the profile's Nayak
    statistics."""
    return "profile (Nayak)" if getattr(scan, "method", None) == "nayak-profile" else "map"


def _synthesis(result: Run) -> dict | None:
    """The synthesis record of a profile input (None for a map)."""
    surface = result.surface
    if getattr(surface, "profile_heights", None) is None:
        return None
    return (surface.provenance or {}).get("profile_synthesis") or {}


def _spread_text(result: Run) -> str:
    """The realisations' spread in one phrase, or why there is none."""
    spread = getattr(result, "realisations", None)
    if spread is None:
        if result.bem_reference is None:
            return "no BEM ([bem] enabled = false): no realisations solved"
        return "1 realisation (surface.profile_realisations = 1): spread not known"
    return (
        f"{spread.realisations} realisations ({spread.mode}): A_r/A_n spread up to "
        f"{spread.max_relative_spread:.1%} (std/mean over the loads)"
    )


def profile_key_numbers(result: Run) -> list[tuple[str, str]]:
    """Key-number rows of a profile input: what the map is, and the realisations' spread."""
    record = _synthesis(result)
    if record is None:
        return []
    return [
        (
            "input line profile",
            f"{record['profile_points']} points at {record['profile_dx'] * 1e6:.4g} um "
            f"({record['profile_length'] * 1e3:.4g} mm); statistics by Nayak's theory, "
            "isotropy assumed",
        ),
        (
            "map synthesised from the profile",
            f"{record['n']} x {record['n']} px at {record['pixel_size'] * 1e6:.4g} um "
            f"({record['map_size'] * 1e6:.4g} um square), random phases, seed {record['seed']}",
        ),
        ("profile realisations", _spread_text(result)),
    ]


def _spread_rows(spread: RealisationSpread) -> list[str]:
    """One table row per load: every realisation's A_r/A_n, the mean, std and relative spread."""
    rows = []
    for j, load in enumerate(spread.normal_load):
        values = ", ".join(f"{v:.4g}" for v in spread.contact_fraction[:, j])
        rows.append(
            f"| {load:.4g} | {values} | {spread.mean_fraction[j]:.4g} | "
            f"{spread.std_fraction[j]:.3g} | {spread.relative_spread[j]:.1%} |"
        )
    return rows


def profile_section(result: Run) -> list[str]:
    """Markdown lines of the report's "Line profile input" section ([] for a map input)."""
    record = _synthesis(result)
    if record is None:
        return []
    lines = [
        "## Line profile input",
        "",
        f"- Profile: {record['profile_points']} points at {record['profile_dx'] * 1e6:.4g} um, "
        f"{record['profile_length'] * 1e3:.4g} mm long. The resolution scan is the profile's "
        "(Nayak's random-process theory: eta, R, sigma_s from its spectral moments m0, m2, m4; "
        "the scan's N column counts the profile's peaks). An isotropic Gaussian surface is "
        "assumed (a verdict warning).",
        f"- Maps for the BEM and Persson's theory: {record['n']} x {record['n']} px at the "
        f"profile's {record['pixel_size'] * 1e6:.4g} um ({record['map_size'] * 1e6:.4g} um "
        f"square, periodic), {record['method']}; seed {record['seed']} for the BEM's map. "
        f"Wavelengths beyond {record['map_size'] * 1e6:.4g} um (the map's size) are not in it.",
        f"- Realisations: {_spread_text(result)}.",
        "",
    ]
    spread = getattr(result, "realisations", None)
    if spread is None:
        return lines
    header = "| F_z (N) | A_r/A_n per realisation (seed " + ", ".join(
        str(int(s)) for s in spread.seed
    )
    lines += [
        header + ") | mean | std | std/mean |",
        "|---|---|---|---|---|",
        *_spread_rows(spread),
        "",
    ]
    if spread.messages:
        lines += [f"- **Not converged:** {m}" for m in spread.messages] + [""]
    return lines
