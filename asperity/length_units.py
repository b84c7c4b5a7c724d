"""Length units found in instrument files and given by users, and their value in metres.

No numerical library is imported here: the job-file validation reads the same table
(:data:`UNIT_SPELLINGS`) as the readers and the command line."""

from __future__ import annotations

_METRES_PER_UNIT = {
    "m": 1.0,
    "cm": 1e-2,
    "mm": 1e-3,
    "um": 1e-6,
    "µm": 1e-6,  # micro sign U+00B5
    "μm": 1e-6,  # greek mu U+03BC
    "~m": 1e-6,  # Nanoscope writes the micro sign as '~'
    "micrometer": 1e-6,
    "micrometre": 1e-6,
    "micron": 1e-6,
    "nm": 1e-9,
    "pm": 1e-12,
    "a": 1e-10,
    "å": 1e-10,
    "angstrom": 1e-10,
    # long names (Zygo DATX writes e.g. 'MicroMeters'); matched case-insensitively,
    # singular or plural, 'meter' or 'metre'
    "meter": 1.0,
    "millimeter": 1e-3,
    "nanometer": 1e-9,
    "picometer": 1e-12,
}


#: The one table of the length-unit spellings a user may give (``--unit`` on the command line,
#: ``[surface] unit`` in a job file): each unit and its accepted spellings. Long names are also
#: accepted in any case, singular or plural, "meter" or "metre" (:func:`length_unit_in_metres`).
UNIT_SPELLINGS: dict[str, tuple[str, ...]] = {
    "m": ("m", "meter", "metre"),
    "cm": ("cm",),
    "mm": ("mm", "millimeter", "millimetre"),
    "um": ("um", "µm", "μm", "micrometer", "micrometre", "micron"),
    "nm": ("nm", "nanometer", "nanometre"),
    "pm": ("pm", "picometer", "picometre"),
    "Å": ("Å", "angstrom"),
}

#: :data:`UNIT_SPELLINGS` as one line of help text.
UNIT_HELP = "; ".join(
    f"{unit} ({', '.join(spelling for spelling in spellings if spelling != unit)})"
    if len(spellings) > 1
    else unit
    for unit, spellings in UNIT_SPELLINGS.items()
)


def length_unit_in_metres(unit: str) -> float | None:
    """Metres per ``unit`` (e.g. ``"um"`` -> 1e-6), or None if ``unit`` is not a length.

    Accepts the spellings seen in instrument files: ``µm``/``μm``/``um``/``~m``, latin-1
    decoded micro signs (``\\xb5m``), ``Å``, and long names such as ``MicroMeters`` or
    ``nanometre`` (case-insensitive, singular or plural).

    Parameters
    ----------
    unit : str
        The unit as written in the file.

    Returns
    -------
    float or None
        Metres per unit, or None for a non-length unit (e.g. ``"V"``, ``"deg"``).
    """
    key = unit.strip().replace("\x00", "").strip()
    if key in _METRES_PER_UNIT:
        return _METRES_PER_UNIT[key]
    lower = key.lower()
    if lower in _METRES_PER_UNIT and lower not in ("mm", "m"):  # 'Mm' is not millimetre
        return _METRES_PER_UNIT[lower]
    long_name = lower.replace("metre", "meter")
    if len(long_name) > 2 and long_name.endswith("s"):
        long_name = long_name[:-1]
    if long_name in _METRES_PER_UNIT and len(long_name) > 2:
        return _METRES_PER_UNIT[long_name]
    return None
