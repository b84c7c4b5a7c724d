"""asperity: adhesive friction of rough elastic contacts.

After Y. Xu, J. Scheibert, N. Gadegaard and D. M. Mulvihill, "An asperity-based statistical model
for the adhesive friction of elastic nominally flat rough contact interfaces", Journal of the
Mechanics and Physics of Solids (2022); preprint arXiv:2207.12735 (doi:10.48550/arXiv.2207.12735).
See docs/paper.md for the BibTeX entry and the equation labels. SI units throughout (m, Pa, N,
J/m^2).

The four sub-packages load on first use, so ``import asperity`` is cheap:

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

import importlib
from importlib.metadata import PackageNotFoundError, version
from typing import Any

try:
    __version__ = version("asperity")
except PackageNotFoundError:  # a source tree that is not installed
    __version__ = "0.0.0+unknown"

_SUBPACKAGES = ("topo", "bem", "statmodel", "pipelines")

#: Public functions by name -> the module that defines them (imported on first use).
_EXPORTS: dict[str, str] = {"open_results": "asperity.pipelines.results"}

__all__ = ["__version__", *_SUBPACKAGES, *_EXPORTS]


def __getattr__(name: str) -> Any:
    if name in _EXPORTS:
        value = getattr(importlib.import_module(_EXPORTS[name]), name)
        globals()[name] = value
        return value
    if name not in _SUBPACKAGES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    module = importlib.import_module(f"{__name__}.{name}")
    globals()[name] = module
    return module


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
