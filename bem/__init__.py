"""asperity.bem: FFT boundary elements for the normal contact of rough elastic surfaces.

Polonsky-Keer constrained conjugate gradients (load or displacement control) with the
Pohrt-Popov mesh-dependent adhesion criterion (paper Appendix B, eqs. E:BEM_eq1..E:BEM_eq4,
eq:PohrtPopov_G, eq:max_sigma). Works on plain arrays of heights (m) with pixel sizes (m).
"""

from bem.adhesion import approach_retract, critical_tension, pull_off_force
from bem.fft_backend import crop_to_fast_size, fast_size
from bem.polonsky_keer import solve_contact
from bem.result import ContactResult
from bem.sweep import load_sweep

__all__ = [
    "ContactResult",
    "approach_retract",
    "critical_tension",
    "crop_to_fast_size",
    "fast_size",
    "load_sweep",
    "pull_off_force",
    "solve_contact",
]
