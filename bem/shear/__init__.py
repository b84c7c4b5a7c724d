"""The tangential problem: stick-slip under a given normal pressure (Cattaneo-Mindlin), the paper's
mode-mixity law at the contact edge (E:failure_locus), and shear curves of rough contacts.

The public names are those of :mod:`asperity.bem` (its ``__init__.pyi``).
"""
