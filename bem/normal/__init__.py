"""The normal contact problem: Polonsky-Keer constrained conjugate gradients, the Pohrt-Popov and
Maugis-Dugdale adhesion laws, load sweeps, periodic arrays and the validity of a normal solve
(paper Appendix B, E:BEM_eq1..E:BEM_eq4).

The public names are those of :mod:`asperity.bem` (its ``__init__.pyi``).
"""
