"""asperity: adhesive friction of rough elastic contacts.

After Y. Xu, J. Scheibert, N. Gadegaard and D. M. Mulvihill, "An asperity-based statistical model
for the adhesive friction of elastic nominally flat rough contact interfaces", Journal of the
Mechanics and Physics of Solids (2022); preprint arXiv:2207.12735 (doi:10.48550/arXiv.2207.12735).
See docs/paper.md for the BibTeX entry and the equation labels. SI units throughout (m, Pa, N,
J/m^2).

Import the four sub-packages by name (``import asperity.topo``, ``from asperity import bem``);
``import asperity`` alone loads none of them, so it stays cheap:

- :mod:`asperity.topo`: height maps, their preparation and asperity statistics (Appendix A);
- :mod:`asperity.bem`: FFT boundary elements, Polonsky-Keer and Pohrt-Popov (Appendix B);
- :mod:`asperity.statmodel`: the single-asperity laws and the statistical model (Sections 2-4);
- :mod:`asperity.pipelines`: the main job, from a measured map to a calibrated prediction.

``asperity.open_results(path)`` reopens a run's ``results.h5`` as typed stage results
(:mod:`asperity.pipelines.results`). Shared by the packages: :mod:`asperity.errors` (input errors,
exit statuses), :mod:`asperity.fields` (the unit, dims and description of every result field),
:mod:`asperity.h5` (every HDF5 file written), :mod:`asperity.schema` (TOML schemas) and
:mod:`asperity.plotting` (figures).
"""

from __future__ import annotations

import os
from importlib.metadata import PackageNotFoundError, version
from os import PathLike
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from asperity.pipelines.results import Results

#: OpenMP's wait policy for the threads of FFTW (pyFFTW's bundled OpenMP runtime) and of numba's
#: parallel kernels, unless the user set one. Two runtimes share the cores in one solve, each
#: with its own pool; with the default (active) policy an idle pool spins on the cores the
#: other one needs, and every hand-off between a transform and a multiplier waits for a
#: scheduler slice: a 64^2 free-boundary JKR cycle (48 solves) took 37 s on a busy 2-core machine
#: and 0.6 s with passive threads (``benchmarks/omp_wait_policy.py`` measures it). Read by each
#: OpenMP runtime when it loads, so it is set here, before any sub-package imports one.
OMP_WAIT_POLICY = "PASSIVE"
os.environ.setdefault("OMP_WAIT_POLICY", OMP_WAIT_POLICY)

try:
    __version__ = version("asperity")
except PackageNotFoundError:  # a source tree that is not installed
    __version__ = "0.0.0+unknown"

__all__ = ["__version__", "open_results"]


def open_results(path: str | PathLike[str]) -> Results:
    """Read every stored stage of an asperity run (nothing is recomputed).

    The same as :func:`asperity.pipelines.results.open_results`.

    Parameters
    ----------
    path : str or PathLike
        ``results.h5`` or the output folder holding it.

    Returns
    -------
    Results
        One attribute per stage (its typed result, None where not stored), the provenance
        and ``to_xarray()``.

    Raises
    ------
    InputError
        No such file, not HDF5, or a stored stage that does not read back.
    """
    # deferred: asperity.pipelines.results loads h5py and every stage; `import asperity` stays light
    from asperity.pipelines.results import open_results as open_stored

    return open_stored(os.fspath(path))
