"""NumPy ``.npy`` / ``.npz`` height arrays (never unpickled: ``allow_pickle=False``).

The arrays carry no pixel size: the caller gives ``pixel_size`` (m), unless an ``.npz``
holds scalar ``dx`` and ``dy`` entries beside ``heights``. Heights are taken as metres.
"""

from __future__ import annotations

import zipfile
from pathlib import Path

import numpy as np

from topo.errors import TopographyFileError
from topo.heightmap import HeightMap, LineProfile
from topo.io._common import make_provenance


def _load(path: Path) -> object:
    try:
        return np.load(path, allow_pickle=False)
    except ValueError as exc:
        raise TopographyFileError(
            path, "array data", f"cannot be loaded without pickling or is truncated ({exc})"
        ) from None
    except (EOFError, OSError, zipfile.BadZipFile) as exc:
        raise TopographyFileError(path, "array data", f"is truncated or corrupt ({exc})") from None


def read_numpy(
    path: str | Path, *, pixel_size: float | tuple[float, float] | None = None
) -> HeightMap | LineProfile:
    """Read heights (m) from ``.npy`` or ``.npz`` (key ``heights``, or the only array).

    Parameters
    ----------
    pixel_size : float or (float, float), optional
        Pixel size in m (``dx`` or ``(dx, dy)``); required unless the ``.npz`` has ``dx``/``dy``.

    Raises
    ------
    TopographyFileError
        Truncated/corrupt files, object arrays, more than 2 dimensions, missing key.
    ValueError
        No pixel size available.
    """
    path = Path(path)
    loaded = _load(path)
    dx = dy = None
    if isinstance(loaded, np.lib.npyio.NpzFile):
        with loaded:
            keys = list(loaded.keys())
            if "heights" in keys:
                key = "heights"
            elif len(keys) == 1:
                key = keys[0]
            else:
                raise TopographyFileError(
                    path, "arrays", f"are {keys}; expected a 'heights' array (or a single array)"
                )
            try:
                heights = np.array(loaded[key])
                if "dx" in keys:
                    dx = float(loaded["dx"])
                    dy = float(loaded["dy"]) if "dy" in keys else dx
            except (ValueError, OSError, EOFError, zipfile.BadZipFile) as exc:
                raise TopographyFileError(path, f"array {key!r}", f"is corrupt ({exc})") from None
    else:
        heights = np.asarray(loaded)
    if heights.dtype.kind not in "fiu":
        raise TopographyFileError(path, "dtype", f"is {heights.dtype}; expected real numbers")
    if heights.ndim not in (1, 2):
        raise TopographyFileError(path, "shape", f"is {heights.shape}; expected 1D or 2D")
    if pixel_size is not None:
        dx, dy = (pixel_size, pixel_size) if np.ndim(pixel_size) == 0 else tuple(pixel_size)
    if dx is None:
        raise ValueError(
            f"{path}: a NumPy array carries no pixel size; give pixel_size= "
            "(or --pixel-size DX on the command line), in metres"
        )
    provenance = make_provenance(
        path, path.suffix.lstrip(".").lower(), units={"all": "m (assumed)"}
    )
    if heights.ndim == 1:
        return LineProfile(heights, float(dx), provenance)
    return HeightMap(heights, float(dx), float(dy), False, provenance)
