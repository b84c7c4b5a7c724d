"""The paper's equations by name: each LaTeX label of Xu, Scheibert, Gadegaard & Mulvihill
(docs/paper.md, "Equation numbers") with its printed number and a readable name, so that text
a user reads (the report, the terminal summary) never shows a bare label as the name of an
equation: ``E:Ar_Greenwood`` is written ``preload real contact area (Eq. 16,
E:Ar_Greenwood)``. Docstrings keep the bare labels (they cite the source).
"""

from __future__ import annotations

import re

__all__ = ["EQUATIONS", "equation_name", "name_equations"]

#: Label -> (printed equation number, readable name).
EQUATIONS: dict[str, tuple[str, str]] = {
    "E:JKR_indent": ("1", "JKR indentation"),
    "E:JKR_load": ("2", "JKR load"),
    "E:JKR_delta_min_loading": ("3", "JKR jump-in distance"),
    "E:JKR_delta_min_unloading": ("4", "JKR jump-off distance"),
    "E:failure_locus": ("5", "mixed-mode failure locus"),
    "E:PC_indent": ("6", "PC indentation under shear"),
    "E:PC_P": ("7", "PC normal load"),
    "E:PC_T": ("8", "PC tangential load of a sticking junction"),
    "E:PC_a_min_1": ("9", "fold radius at fixed indentation"),
    "E:max_disp_PC": ("10", "largest sticking displacement"),
    "E:Instable_boundary": ("11", "unstable boundary"),
    "E:Hertz_theory": ("14", "Hertz laws of a sliding junction"),
    "E:Fy_Greenwood": ("15", "preload normal force"),
    "E:Ar_Greenwood": ("16", "preload real contact area"),
    "E:NewFormulation_Fy": ("17", "normal force under shear"),
    "E:NewFormulation_Fx": ("18", "tangential force under shear"),
    "E:NewFormulation_Ar": ("19", "real contact area under shear"),
    "E:delta_2": ("20", "lower limit of the sticking population"),
    "E:delta_1": ("21", "lower limit of the sliding population"),
    "E:BEM_eq1": ("B.1", "BEM gap"),
    "E:BEM_eq2": ("B.2", "BEM contact condition"),
    "E:BEM_eq3": ("B.3", "BEM separation condition"),
    "E:BEM_eq4": ("B.4", "BEM load balance"),
    "eq:PohrtPopov_G": ("B.5", "Pohrt-Popov energy release rate"),
    "eq:max_sigma": ("B.6", "Pohrt-Popov critical tension"),
}

_LABEL = re.compile(r"(?<![\w:])(?:E|eq):[A-Za-z][A-Za-z0-9_]*")
#: A label already named: "(Eq. 16, E:Ar_Greenwood" or "Eqs. 17-19: E:...".
_NAMED = re.compile(r"Eqs?\. [A-Z]?[\d.\-]+[,:] ?`?$")


def equation_name(label: str) -> str:
    """The readable name of ``label`` with its number and the label beside it (the label
    itself when the paper has no such label).

    ``equation_name("E:Ar_Greenwood")`` is ``"preload real contact area (Eq. 16,
    E:Ar_Greenwood)"``.
    """
    if label not in EQUATIONS:
        return label
    number, name = EQUATIONS[label]
    return f"{name} (Eq. {number}, {label})"


def name_equations(text: str) -> str:
    """``text`` with each bare paper label written with its name and number
    (:func:`equation_name`); a label already beside its number is left as it is.

    ``"an independent-asperity model (E:Ar_Greenwood) neglects"`` ->
    ``"an independent-asperity model (preload real contact area (Eq. 16, E:Ar_Greenwood))
    neglects"``.
    """

    def named(match: re.Match[str]) -> str:
        label, before = match.group(0), text[max(0, match.start() - 16) : match.start()]
        if label not in EQUATIONS or _NAMED.search(before):
            return label
        return equation_name(label)

    return _LABEL.sub(named, text)
