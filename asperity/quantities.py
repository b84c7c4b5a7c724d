"""One bound per quantity: the range, SI unit and reason of every bounded input, in one table.

Each :class:`Quantity` of :data:`QUANTITIES` is used by every place that takes the value:

* the dataclasses' ``__post_init__`` (``statmodel.Material``, ``statmodel.Roughness``,
  ``statmodel.QuadratureOptions``, ``bem.SolverOptions``) through :meth:`Quantity.check`;
* the TOML schemas (the job file of ``asperity run``, the ``asperity friction`` parameter
  file) through :attr:`Quantity.kind`;
* the command-line options through :meth:`Quantity.option` (an argparse ``type=``);
* the bounds tables of the docs (:func:`markdown_table`, tested against docs/statmodel.md).

Every refusal is one line naming the key, the bound with its reason, and the value, whatever
the route::

    job.toml: accuracy.cutoff_sigma: expected a number in [8, 40] (...), got 5
    QuadratureOptions.cutoff_sigma: expected a number in [8, 40] (...), got 5
    asperity bem: --e-star: expected a number in [100, 1e+13] Pa (...), got 1e+300

Pure Python (no numerical library is loaded): a configuration is checked in milliseconds.
"""

from __future__ import annotations

import argparse
import math
import numbers
import sys
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from asperity.errors import InputError, error_line
from asperity.schema import Integer, Invalid, Real, interval_text, tiny_text


@dataclass(frozen=True)
class Quantity:
    """One bounded input quantity.

    Attributes
    ----------
    key : str
        Where it is documented: ``table.key`` of the job or friction file, or the option.
    unit : str
        SI unit ("" for a dimensionless number or a count).
    low, high : float
        The bounds.
    why : str
        Why these bounds (shown in every refusal).
    open_low, open_high : bool
        The end is excluded.
    integer : bool
        A count: an integer in [low, high].
    """

    key: str
    unit: str
    low: float
    high: float
    why: str
    open_low: bool = False
    open_high: bool = False
    integer: bool = False
    tiny: float = 0.0

    @property
    def kind(self) -> Real | Integer:
        """The schema :class:`~asperity.schema.Kind` that converts and bounds a TOML value."""
        if self.integer:
            return Integer(int(self.low), int(self.high), why=self.why)
        return Real(
            self.unit,
            self.low,
            self.high,
            self.open_low,
            self.open_high,
            why=self.why,
            tiny=self.tiny,
        )

    @property
    def interval(self) -> str:
        """The range as ``[low, high]`` with open ends as parentheses (and the floor of nonzero
        magnitudes, when there is one)."""
        return interval_text(self.low, self.high, self.open_low, self.open_high) + tiny_text(
            self.tiny
        )

    def expected(self) -> str:
        """What a valid value is, in words, with the reason."""
        return self.kind.expected()

    def check(self, value: Any, name: str, error: type[InputError] = InputError) -> Any:
        """``value`` as a float (an int for a count) within the bounds, else ``error``.

        Numbers of any numeric type are accepted (numpy scalars included, an integral float
        for a count); bools, strings, NaN and infinities are refused. The message is
        ``name: expected <bound> (<why>), got <value>``.
        """
        plain = _plain_number(value, self.integer)
        try:
            return self.kind.convert(plain, None)  # type: ignore[arg-type]
        except Invalid as exc:
            raise error(f"{name}: expected {exc.expected}, got {value!r}") from None

    def parse(self, text: str, option: str) -> Any:
        """A command-line value of ``option`` (a string) checked against the bounds.

        Raises
        ------
        InputError
            ``option: expected <bound> (<why>), got <text>``.
        """
        try:
            value: Any = int(text) if self.integer else float(text)
        except (TypeError, ValueError):
            raise InputError(f"{option}: expected {self.expected()}, got {text!r}") from None
        return self.check(value, option)

    def option(self, option: str) -> Callable[[str], Any]:
        """An argparse ``type=`` for ``option``: parses and bounds, one error line."""

        def parse(text: str) -> Any:
            try:
                return self.parse(text, option)
            except InputError as exc:  # argparse prefixes "argument OPTION: " itself
                raise argparse.ArgumentTypeError(str(exc).removeprefix(f"{option}: ")) from None

        parse.__name__ = option.lstrip("-").replace("-", "_")
        return parse


def add_bounded_option(
    parser: argparse.ArgumentParser | argparse._MutuallyExclusiveGroup,
    option: str,
    key: str,
    **keywords: Any,
) -> argparse.Action:
    """``parser.add_argument(option, ...)`` parsed and bounded by the quantity ``key``."""
    return parser.add_argument(option, type=quantity(key).option(option), **keywords)


class OneLineErrorParser(argparse.ArgumentParser):
    """An argparse parser whose usage error is one line, ``PROG: error: OPTION: ...`` (exit 2).

    The usage block argparse prints first would push the one line that matters off the
    terminal; ``--help`` still shows it. Sub-command parsers inherit the class.
    """

    def error(self, message: str):  # noqa: ANN201 (NoReturn: argparse's signature)
        """Print ``message`` as one line naming the option (no usage block), exit with 2."""
        line = error_line(f"{self.prog}: error: ", message.removeprefix("argument "))
        self.exit(2, f"{line}\n")


def _plain_number(value: Any, integer: bool) -> Any:
    """A Python int or float for the schema kinds, or the value itself (then refused)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        return value
    if integer:
        if isinstance(value, numbers.Integral):
            return int(value)
        number = float(value)
        return int(number) if math.isfinite(number) and number.is_integer() else value
    return float(value)


def _q(key: str, unit: str, low: float, high: float, why: str, **ends: Any) -> Quantity:
    return Quantity(key, unit, low, high, why, **ends)


def _count(key: str, low: int, high: int, why: str) -> Quantity:
    return Quantity(key, "", low, high, why, integer=True)


#: The largest finite double: a bound that only refuses infinities and NaN.
_LARGEST = sys.float_info.max

_ENTRIES = (
    # material (statmodel.Material; [material] of the job and friction files; bem --e-star)
    _q(
        "material.E_star",
        "Pa",
        1e2,
        1e13,
        "from the softest gels (~1 kPa) to diamond (~1.2e12 Pa)",
    ),
    _q("material.work_of_adhesion", "J/m^2", 0, 10, "solid surface energies are < ~5 J/m^2"),
    _q("material.mode_mixity", "", 0, 1, "lambda: 0 pure JKR, 1 Savkoor-Briggs (E:failure_locus)"),
    _q(
        "material.shear_strength",
        "Pa",
        0,
        1e11,
        "no solid shears above its theoretical strength, < 1e11 Pa",
    ),
    _q(
        "material.friction_coefficient",
        "",
        0,
        10,
        "Coulomb mu; measured values are below ~5, and mu = 0 leaves no stick to solve for "
        "(the shear solve cannot converge: F_x = 0 at once)",
        open_low=True,
    ),
    _q("material.equilibrium_distance", "m", 1e-11, 1e-8, "interatomic distances are 0.1-1 nm"),
    _q(
        "material.hardness",
        "Pa",
        1e4,
        2e11,
        "indentation hardness, from soft gels (~10 kPa) to diamond (~1e11 Pa); job only",
    ),
    # roughness (statmodel.Roughness; [roughness] of the friction file)
    _q(
        "roughness.asperity_density",
        "1/m^2",
        1e-6,
        1e20,
        "from one summit per km^2 to one per (0.1 nm)^2",
    ),
    _q(
        "roughness.summit_radius",
        "m",
        1e-10,
        1e2,
        "from an atom (0.1 nm) to 100 m, the curvature of the smoothest polished summits",
    ),
    _q("roughness.summit_height_rms", "m", 1e-12, 1, "from 1 pm to 1 m"),
    # accuracy knobs of the statistical model (statmodel.QuadratureOptions; [accuracy])
    _count(
        "accuracy.nodes",
        1,
        128,
        "more than 128 Gauss-Legendre nodes per panel gain nothing in double precision",
    ),
    _count(
        "accuracy.panels",
        1,
        64,
        "more than 64 panels per population gain nothing in double precision",
    ),
    _q(
        "accuracy.cutoff_sigma",
        "",
        8,
        40,
        "below 8 sigma_s the truncated Gaussian tail exceeds the model's 1e-6 accuracy; beyond "
        "40 it underflows and the quadrature panels spread over empty heights (wrong friction)",
    ),
    _q(
        "accuracy.load_rtol",
        "",
        1e-14,
        1e-6,
        "looser than 1e-6 the normal load is not resolved to the model's accuracy; tighter than "
        "1e-14 is below the round-off of the load integral",
    ),
    _count("accuracy.max_iter", 1, 10_000, "a separation solve needs about 10-40 Brent iterations"),
    # loading ([loading] of the job and friction files; bem --load, --mean-pressure)
    _q(
        "loading.normal_load",
        "N",
        -1e6,
        1e6,
        "a laboratory or machine contact; a nonzero force under 1 pN is below any instrument "
        "and underflows the solvers' residuals",
        tiny=1e-12,
    ),
    _q("loading.nominal_area", "m^2", 0, 100, "up to 10 m x 10 m", open_low=True),
    _q(
        "loading.max_tangential_displacement",
        "m",
        0,
        1,
        "a shear path up to 1 m",
        open_low=True,
    ),
    _q("loading.tangential_displacement", "m", 0, 1, "a shear path up to 1 m"),
    _q(
        "loading.drive_stiffness",
        "N/m",
        0,
        1e12,
        "the tangential loading system in series with the contact, from a soft wire (the "
        "paper's 9200 N/m) to a stiff frame; absent: rigid",
        open_low=True,
    ),
    _count(
        "loading.steps",
        3,
        100_000,
        "the job finds full sliding on at least 3 steps; each step stores 17 float64 values "
        "per load: 100000 steps x 100 loads take 1.4 GB",
    ),
    _count(
        "friction.loading.steps",
        1,
        100_000,
        "one separation solve and 17 stored values per step (1: the preload state only)",
    ),
    _q(
        "loading.mean_pressure",
        "Pa",
        -1e11,
        1e11,
        "no contact carries a mean pressure above the theoretical strength of solids, 1e11 Pa; "
        "a nonzero one under 1e-14 Pa (1 pN on 100 m^2) underflows the solver's residual",
        tiny=1e-14,
    ),
    # surface preparation ([surface] of the job; topo and bem options)
    _q(
        "surface.pixel_size",
        "m",
        1e-10,
        1e-2,
        "from an atomic-resolution map to a 1 cm pixel",
    ),
    _count("surface.max_stride", 1, 1000, "strides 1..max_stride of the resolution scan"),
    _q(
        "surface.outlier_threshold",
        "",
        0,
        1000,
        "k of the k x MAD rule, or a percentile p < 50",
        open_low=True,
    ),
    _count("surface.form_order", 0, 8, "polynomial order of the form"),
    _count(
        "surface.synthetic.n",
        8,
        17500,
        "an n x n map takes 8 n^2 bytes and the BEM ~30 times that; 17,500 is the paper's "
        "35 mm at 2 um (the nominal preset)",
    ),
    _count(
        "surface.synthetic.ny",
        8,
        17500,
        "pixels along y of a non-square map: an n x ny map takes 8 n ny bytes and the BEM ~30 "
        "times that",
    ),
    _count("surface.synthetic.seed", 0, 2**32 - 1, "a numpy random seed"),
    _count(
        "surface.profile_synthesis_n",
        32,
        4096,
        "pixels per side of the map synthesised from a line profile: fewer than 32 hold no "
        "summit statistics, and an n x n map takes 8 n^2 bytes and the BEM ~30 times that",
    ),
    _count("surface.profile_seed", 0, 2**32 - 1, "a numpy random seed"),
    _count(
        "surface.profile_realisations",
        1,
        20,
        "maps synthesised from a line profile (each one more BEM sweep at the job's loads)",
    ),
    _q(
        "surface.synthetic.rms_height",
        "m",
        1e-12,
        0.1,
        "from atomic flatness to 0.1 m: the readers refuse heights beyond 1 m and a Gaussian "
        "map's extremes reach about 6 rms",
    ),
    _q(
        "surface.synthetic.wavelength",
        "m",
        1e-10,
        1,
        "a roll-off or cut-off wavelength, from an atom to 1 m",
    ),
    _q("surface.synthetic.hurst", "", 0, 2, "the spectral exponent H", open_low=True),
    # BEM ([bem] of the job; bem.SolverOptions; bem options)
    _q(
        "bem.tol",
        "",
        1e-14,
        1e-2,
        "relative rms pressure residual: below 1e-14 it is under the round-off of double "
        "precision, above 1e-2 a 'converged' pressure may be wrong by more than a per cent",
    ),
    _count(
        "bem.max_iter",
        1,
        1_000_000,
        "solver iterations: at least one, bounded so that a typo cannot run for days",
    ),
    _count(
        "bem.stall_window",
        1,
        1_000_000,
        "iterations without a 0.1 % decrease that declare a stall",
    ),
    _count("bem.refresh", 1, 1_000_000, "iterations between exact recomputations of u = K * p"),
    _count("bem.threads", 1, 1024, "FFT threads of one machine"),
    _q("bem.area_tolerance", "", 0, 1, "a relative change of A_r", open_low=True),
    _count("bem.max_stride", 1, 64, "coarsest decimation of the grid check"),
    _count(
        "bem.max_refinement",
        1,
        4,
        "largest Fourier-interpolation factor of the discretisation check (1: none, 2, 4)",
    ),
    _count(
        "bem.refinement_pixels",
        64,
        100_000_000,
        "pixels of the largest refinement grid: the BEM takes ~240 bytes a pixel",
    ),
    _q(
        "bem.adhesion_range",
        "m",
        1e-10,
        1e-3,
        "the Maugis-Dugdale range h_0: from an atomic distance to a coarse-grained range of "
        "a millimetre",
    ),
    # the shear BEM stage ([bem_shear] of the job)
    _count("bem_shear.stride", 1, 64, "decimation of the map for the shear solves"),
    _count("bem_shear.steps", 3, 10_000, "delta_T values per curve, each a mixed-mode solve"),
    _count(
        "bem_shear.check_grids",
        0,
        3,
        "coarser grids (strides x2, x4, x8) solved for the grid error: three grids give the "
        "observed order",
    ),
    _q(
        "bem_shear.path_extension",
        "",
        1,
        100,
        "the path may continue past its planned end up to this multiple of it (1: not at all)",
    ),
    _q("bem_shear.max_displacement", "m", 0, 1, "a shear path up to 1 m", open_low=True),
    _q(
        "bem_shear.tol",
        "",
        1e-14,
        1e-2,
        "relative rms traction residual of the shear solves (bem.ShearOptions's bounds)",
    ),
    # bem.solve_contact's arguments: the solver is scale-free (linear in E*, in any consistent
    # units), so the library takes any finite positive value; the job and the CLI bound the SI
    # values by material.E_star, surface.pixel_size and material.work_of_adhesion
    _q(
        "solve_contact.dx",
        "m",
        0,
        _LARGEST,
        "a pixel size; the solver is scale-free, any finite length > 0",
        open_low=True,
    ),
    _q(
        "solve_contact.e_star",
        "Pa",
        0,
        _LARGEST,
        "the solver is linear in E*: any finite modulus > 0",
        open_low=True,
    ),
    _q(
        "solve_contact.work_of_adhesion",
        "J/m^2",
        0,
        _LARGEST,
        "0: no adhesion; the solver is scale-free, any finite value",
    ),
    # the rest of the job
    _q(
        "statmodel.area_tolerance",
        "",
        1e-10,
        0.5,
        "relative change between quadrature settings: no setting reaches less than 1e-10",
    ),
    _q("fit.mode_mixity_bounds", "", 0, 1, "lambda", open_low=True),
    _count("run.workers", 1, 256, "worker processes on this machine"),
    _count("report.dpi", 30, 2400, "dots per inch of PNG figures"),
)

#: Every bounded quantity by key (``table.key``).
QUANTITIES: dict[str, Quantity] = {q.key: q for q in _ENTRIES}


def quantity(key: str) -> Quantity:
    """The :class:`Quantity` of ``key`` (a KeyError names the known keys)."""
    try:
        return QUANTITIES[key]
    except KeyError:
        raise KeyError(f"no bounded quantity {key!r}; known: {', '.join(QUANTITIES)}") from None


#: The keys of the ``asperity friction`` parameter file, in the order of its docs table.
FRICTION_FILE_KEYS: tuple[str, ...] = (
    "material.E_star",
    "material.work_of_adhesion",
    "material.mode_mixity",
    "material.shear_strength",
    "material.equilibrium_distance",
    "roughness.",
    "loading.normal_load",
    "loading.nominal_area",
    "loading.max_tangential_displacement",
    "friction.loading.steps",
    "accuracy.",
)


def markdown_table(keys: tuple[str, ...]) -> str:
    """The docs' bounds table of ``keys`` (a key, or a prefix ending in "." for a table).

    docs/statmodel.md holds ``markdown_table(FRICTION_FILE_KEYS)`` between the lines
    ``<!-- bounds: asperity.quantities -->`` and ``<!-- end bounds -->`` (tested).
    """
    rows = ["| key | range | unit | why |", "|---|---|---|---|"]
    for q in _ENTRIES:
        if q.key in keys or any(k.endswith(".") and q.key.startswith(k) for k in keys):
            kind = "integer in " if q.integer else ""
            rows.append(f"| `{q.key}` | {kind}{q.interval} | {q.unit or '-'} | {q.why} |")
    return "\n".join(rows)
