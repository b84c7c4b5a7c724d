"""The elastic half-space: FFT transforms, influence coefficients (normal and tangential), the
operators the solvers apply, and the Pohrt-Popov element energy (paper Appendix B,
eq:PohrtPopov_G).

The public names are those of :mod:`asperity.bem` (its ``__init__.pyi``).
"""
