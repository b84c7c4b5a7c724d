"""Length units found in instrument files, and their value in metres.

The table and its reader live in :mod:`asperity.length_units` (no numerical library, so the
job-file validation reads the same table); re-exported here for the readers.
"""

from __future__ import annotations

from asperity.length_units import UNIT_HELP, UNIT_SPELLINGS, length_unit_in_metres

__all__ = ["UNIT_HELP", "UNIT_SPELLINGS", "length_unit_in_metres"]
