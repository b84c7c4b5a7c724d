"""asperity.bem: FFT boundary elements for the normal contact of rough elastic surfaces.

Polonsky-Keer constrained conjugate gradients (load or displacement control) with the
Pohrt-Popov mesh-dependent adhesion criterion (paper Appendix B, eqs. E:BEM_eq1..E:BEM_eq4,
eq:PohrtPopov_G, eq:max_sigma). Works on plain arrays of heights (m) with pixel sizes (m).
"""

import lazy_loader

# The public names are the imports in __init__.pyi (also what type checkers read); each is
# imported on first use, so that `asperity --help` and light sub-commands load no numba kernel.
__getattr__, __dir__, __all__ = lazy_loader.attach_stub(__name__, __file__)
