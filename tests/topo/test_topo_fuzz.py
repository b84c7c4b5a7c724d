"""A seeded fuzz corpus of hostile variants of every sample file.

Every case is a sample file (the real instrument files of tests/data and small files written
here for the formats without one: project HDF5, NPY, NPZ, Gwyddion, X3P with a valid-points
mask, text matrix and x y z) with one mutation: a truncation, byte flips in the header or
the data, a size or scale field set to zero / negative / huge / tiny / NaN, a numeric header
token replaced, or (for zip archives) an archive trick: encrypted-member flags, an unknown
compression method, a declared size of a zip bomb, a CRC mismatch, a damaged deflate stream.

Each case must end in a :class:`TopographyFileError` or a result whose heights are finite or
NaN and whose pixel sizes are within the documented bounds; never another exception, never
more than the time (2 s) or memory budget (64 MiB + 8 x the file size, traced by tracemalloc).
The default suite runs a fixed sample of the corpus; ``-m slow`` runs all of it and prints
the table (format, cases, typed errors, results, other exceptions, over budget).
"""

from __future__ import annotations

import hashlib
import io
import re
import struct
import time
import tracemalloc
import zipfile
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from asperity import topo
from asperity.topo.errors import TopographyFileError
from asperity.topo.io.limits import MAX_ABS_HEIGHT_M, PIXEL_SIZE_BOUNDS_M

DATA = Path(__file__).resolve().parents[1] / "data"
REAL_SAMPLES = [
    "x3p-2.x3p", "sur-3.sur", "metropro-1.dat", "plu-1.plu", "opd-1.opd",
    "di-3.di", "mi-1.mi", "dektak-1.csv",
]  # fmt: skip
TIME_BUDGET_S = 2.0
MEMORY_BASE_BYTES = 64 * 2**20
MEMORY_PER_FILE_BYTE = 8

INT_VALUES = (0, -1, 2**31 - 1, 2**30, 65535)
FLOAT_VALUES = (0.0, -1.0, 1e30, 1e21, 1e-39, float("nan"), float("inf"))
TOKEN_VALUES = ("0", "-1", "1e300", "99999999999", "1e-39", "1e21", "nan", "1_000", "2,5")

# Size and scale fields of the binary formats: (offset, struct format, name).
FIELDS = {
    "sur-3.sur": [
        (98, "<H", "bits"), (100, "<i", "zmin"), (104, "<i", "zmax"), (108, "<i", "nx"),
        (112, "<i", "ny"), (116, "<I", "n_points"), (120, "<f", "step_x"),
        (124, "<f", "step_y"), (128, "<f", "step_z"), (334, "<H", "comment"),
        (336, "<H", "private"), (86, "<H", "special_points"),
    ],
    "metropro-1.dat": [
        (6, ">I", "header_size"), (52, ">H", "ac_w"), (54, ">H", "ac_h"),
        (56, ">H", "ac_buckets"), (60, ">I", "ac_bytes"), (68, ">H", "cn_w"),
        (70, ">H", "cn_h"), (72, ">I", "cn_bytes"), (164, ">f", "scale"),
        (168, ">f", "wavelength"), (176, ">f", "obliquity"), (184, ">f", "lateral"),
        (218, ">h", "phase_res"), (232, ">h", "sign"),
    ],
    "plu-1.plu": [
        (388, "<I", "ny"), (392, "<I", "nx"), (404, "<f", "um_x"), (408, "<f", "um_y"),
        (428, "<I", "type"), (489, "<B", "layers"), (500, "<I", "layer ny"),
        (504, "<I", "layer nx"),
    ],
}  # fmt: skip


# --- the samples --------------------------------------------------------------------------


def _gwy_object(name: str, components: list[tuple[str, str, object]]) -> bytes:
    body = b""
    for key, kind, value in components:
        body += key.encode() + b"\0" + kind.encode()
        if kind in "id":
            body += struct.pack("<" + kind, value)
        elif kind == "s":
            body += value.encode() + b"\0"
        elif kind == "o":
            body += value
        else:  # "D"
            body += struct.pack("<I", value.size) + value.astype("<f8").tobytes()
    return name.encode() + b"\0" + struct.pack("<I", len(body)) + body


def _gwy(heights: np.ndarray) -> bytes:
    unit = _gwy_object("GwySIUnit", [("unitstr", "s", "m")])
    field = _gwy_object(
        "GwyDataField",
        [("xres", "i", heights.shape[0]), ("yres", "i", heights.shape[1]),
         ("xreal", "d", 8e-6), ("yreal", "d", 6e-6), ("si_unit_xy", "o", unit),
         ("si_unit_z", "o", unit), ("data", "D", heights.T.ravel())],
    )  # fmt: skip
    return b"GWYP" + _gwy_object(
        "GwyContainer", [("/0/data", "o", field), ("/0/data/title", "s", "Topography")]
    )


def _x3p(raw: np.ndarray) -> bytes:
    nx, ny = raw.shape
    point = raw.T.astype("<u2").tobytes()
    valid = np.ones(raw.shape, bool)
    valid[1, 2] = False
    mask = np.packbits(valid.T.ravel(), bitorder="little").tobytes()
    xml = f"""<?xml version="1.0" encoding="UTF-8"?>
<p:ISO5436_2 xmlns:p="http://www.opengps.eu/2008/ISO5436_2">
<Record1><Revision>ISO5436 - 2000</Revision><FeatureType>SUR</FeatureType><Axes>
<CX><AxisType>I</AxisType><DataType>D</DataType><Increment>1e-06</Increment></CX>
<CY><AxisType>I</AxisType><DataType>D</DataType><Increment>2e-06</Increment></CY>
<CZ><AxisType>A</AxisType><DataType>I</DataType><Increment>1e-09</Increment>
<Offset>0.0</Offset></CZ></Axes></Record1>
<Record3><MatrixDimension><SizeX>{nx}</SizeX><SizeY>{ny}</SizeY><SizeZ>1</SizeZ>
</MatrixDimension><DataLink><PointDataLink>bindata/data.bin</PointDataLink>
<MD5ChecksumPointData>{hashlib.md5(point).hexdigest()}</MD5ChecksumPointData>
<ValidPointsLink>bindata/valid.bin</ValidPointsLink></DataLink></Record3></p:ISO5436_2>"""
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as archive:
        archive.writestr("main.xml", xml)
        archive.writestr("bindata/data.bin", point)
        archive.writestr("bindata/valid.bin", mask)
    return buffer.getvalue()


def _generated_samples(folder: Path) -> dict[str, bytes]:
    rng = np.random.default_rng(12)
    heights = rng.normal(scale=1e-6, size=(16, 12))
    topo.write_hdf5(topo.HeightMap(heights, 1e-6, 2e-6), folder / "project.h5")
    np.save(folder / "map.npy", heights)
    buffer = io.BytesIO()
    np.savez_compressed(buffer, heights=heights, dx=1e-6, dy=2e-6)
    x, y = np.meshgrid(np.arange(8) * 2e-6, np.arange(6) * 3e-6, indexing="ij")
    xyz = np.column_stack([x.ravel(), y.ravel(), heights[:8, :6].ravel()])
    return {
        "project.h5": (folder / "project.h5").read_bytes(),
        "map.npy": (folder / "map.npy").read_bytes(),
        "map.npz": buffer.getvalue(),
        "map.gwy": _gwy(heights),
        "mask.x3p": _x3p(rng.integers(0, 60000, size=(9, 7))),
        "matrix.txt": "\n".join(" ".join(f"{v:.6e}" for v in row) for row in heights).encode(),
        "grid.xyz": "\n".join(f"{a:.6e} {b:.6e} {c:.6e}" for a, b, c in xyz).encode(),
    }


@pytest.fixture(scope="module")
def samples(tmp_path_factory) -> dict[str, bytes]:
    found = {name: (DATA / name).read_bytes() for name in REAL_SAMPLES}
    found.update(_generated_samples(tmp_path_factory.mktemp("fuzz-samples")))
    return found


NEEDS_PIXEL_SIZE = {"map.npy", "matrix.txt"}


# --- the mutations ------------------------------------------------------------------------


@dataclass(frozen=True)
class Case:
    """One mutated file: ``kind`` of mutation and its ``detail`` (offsets, values)."""

    sample: str
    kind: str
    detail: tuple

    @property
    def label(self) -> str:
        return f"{self.sample}:{self.kind}:{self.detail}"


def _seed(*parts: object) -> int:
    return int.from_bytes(hashlib.sha256(repr(parts).encode()).digest()[:8], "little")


def _header_length(name: str, data: bytes) -> int:
    if name.endswith((".di",)):
        return data.find(b"\\*File list end") + 16
    if name.endswith((".mi", ".csv")):
        return min(len(data), data.find(b"data ") + 20 if b"data " in data else 4096)
    return min(len(data) // 2, {"sur-3.sur": 512, "metropro-1.dat": 834}.get(name, 600))


def _cases_for(name: str, data: bytes) -> list[Case]:
    rng = np.random.default_rng(_seed("cases", name))
    size, header = len(data), _header_length(name, data)
    cases = [Case(name, "truncate", (int(n),)) for n in sorted({1, 2, 8, 64, header - 1})]
    cases += [Case(name, "truncate", (int(n),)) for n in rng.integers(1, size, 20)]
    cases += [
        Case(name, "flip", tuple(int(p) for p in rng.integers(0, header, 1 + k % 3)))
        for k in range(24)
    ]
    cases += [
        Case(name, "flip", tuple(int(p) for p in rng.integers(header, size, 1 + k % 4)))
        for k in range(8)
    ]
    cases += [Case(name, "zero-run", (int(p), 64)) for p in rng.integers(0, size, 4)]
    for offset, fmt, field in FIELDS.get(name, []):
        values = FLOAT_VALUES if fmt[-1] == "f" else INT_VALUES
        cases += [Case(name, "field", (offset, fmt, field, v)) for v in values]
    if name.endswith((".di", ".mi", ".csv", ".txt", ".xyz", ".npy")):
        tokens = [m.span() for m in re.finditer(rb"[-+]?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?", data)]
        tokens = [span for span in tokens if span[1] <= header or name.endswith((".txt", ".xyz"))]
        picks = rng.choice(len(tokens), size=min(len(tokens), 40), replace=False)
        for k, pick in enumerate(sorted(picks)):
            cases.append(Case(name, "token", (*tokens[pick], TOKEN_VALUES[k % len(TOKEN_VALUES)])))
    else:  # binary: aligned words of the header set to hostile values
        for k, offset in enumerate(rng.integers(0, max(1, header - 8), 24)):
            value = (FLOAT_VALUES + INT_VALUES)[k % 12]
            fmt = "<f" if isinstance(value, float) else "<i"
            cases.append(Case(name, "word", (int(offset) & ~3, fmt, "word", value)))
    if name.endswith((".x3p", ".npz")):
        cases += _archive_cases(name, data)
    return cases


def _archive_cases(name: str, data: bytes) -> list[Case]:
    with zipfile.ZipFile(io.BytesIO(data)) as archive:
        members = [info.filename for info in archive.infolist()]
    cases = []
    for member in members:
        cases += [
            Case(name, "zip-encrypted", (member,)),
            Case(name, "zip-method", (member, 12)),
            Case(name, "zip-method", (member, 99)),
            Case(name, "zip-bomb", (member, 2**40)),
            Case(name, "zip-bomb", (member, 2**31)),
            Case(name, "zip-crc", (member,)),
            Case(name, "zip-deflate", (member,)),
        ]
    if name.endswith(".x3p"):
        xml = _member(data, "main.xml").decode()
        numbers = list(re.finditer(r">([-+]?[0-9][^<]*)<", xml))
        for k, match in enumerate(numbers):
            for value in ("0", "-1", "1e21", "1e-39", "nan", "4294967296")[k % 3 :: 3]:
                cases.append(Case(name, "xml", (match.start(1), match.end(1), value)))
    return cases


def _member(data: bytes, name: str) -> bytes:
    with zipfile.ZipFile(io.BytesIO(data)) as archive:
        return archive.read(name)


def _zip_headers(data: bytes, member: str) -> list[tuple[int, bool]]:
    """Offsets of the local (False) and central (True) headers of ``member``."""
    found = []
    encoded = member.encode()
    for signature, central, name_at in ((b"PK\x03\x04", False, 30), (b"PK\x01\x02", True, 46)):
        for match in re.finditer(re.escape(signature), data):
            start = match.start()
            length = struct.unpack_from("<H", data, start + (28 if central else 26))[0]
            if data[start + name_at : start + name_at + length] == encoded:
                found.append((start, central))
    return found


def mutate(case: Case, data: bytes) -> bytes:
    """The bytes of ``case``: ``data`` with the mutation applied (deterministic)."""
    out = bytearray(data)
    kind, detail = case.kind, case.detail
    if kind == "truncate":
        return bytes(out[: detail[0]])
    if kind == "flip":
        for position in detail:
            out[position] ^= 1 << (_seed(case.label, position) % 8)
    elif kind == "zero-run":
        start, length = detail
        out[start : start + length] = bytes(len(out[start : start + length]))
    elif kind in ("field", "word"):
        offset, fmt, _field, value = detail
        if fmt[-1] in "f":
            packed = struct.pack(fmt, value)
        else:
            bits = 8 * struct.calcsize(fmt)
            packed = struct.pack(fmt[0] + {8: "B", 16: "H", 32: "I"}[bits], value % 2**bits)
        out[offset : offset + len(packed)] = packed
    elif kind == "token":
        start, end, value = detail
        out[start:end] = value.encode()
    elif kind == "xml":
        start, end, value = detail
        xml = _member(data, "main.xml").decode()
        return _replace_member(data, "main.xml", (xml[:start] + value + xml[end:]).encode())
    else:
        _zip_trick(out, kind, detail)
    return bytes(out)


def _zip_trick(out: bytearray, kind: str, detail: tuple) -> None:
    member = detail[0]
    for start, central in _zip_headers(bytes(out), member):
        flags, method = start + (8 if central else 6), start + (10 if central else 8)
        crc, usize = start + (16 if central else 14), start + (24 if central else 22)
        if kind == "zip-encrypted":
            struct.pack_into("<H", out, flags, struct.unpack_from("<H", out, flags)[0] | 1)
        elif kind == "zip-method":
            struct.pack_into("<H", out, method, detail[1])
        elif kind == "zip-bomb":
            struct.pack_into("<I", out, usize, min(detail[1], 2**32 - 1))
        elif kind == "zip-crc":
            struct.pack_into("<I", out, crc, struct.unpack_from("<I", out, crc)[0] ^ 0x5A5A)
    if kind == "zip-deflate":
        with zipfile.ZipFile(io.BytesIO(bytes(out))) as archive:
            info = archive.getinfo(member)
        name_length, extra = struct.unpack_from("<HH", out, info.header_offset + 26)
        body = info.header_offset + 30 + name_length + extra
        for k in range(0, info.compress_size, max(1, info.compress_size // 7)):
            out[body + k] ^= 0xFF


def _replace_member(data: bytes, name: str, content: bytes) -> bytes:
    buffer = io.BytesIO()
    with zipfile.ZipFile(io.BytesIO(data)) as source:
        with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as target:
            for info in source.infolist():
                body = content if info.filename == name else source.read(info)
                target.writestr(info.filename, body)
    return buffer.getvalue()


# --- running a case -----------------------------------------------------------------------


def check_result(surface: object) -> str | None:
    """Why ``surface`` is not an acceptable result, or None."""
    if not isinstance(surface, topo.HeightMap | topo.LineProfile):
        return f"returned {type(surface).__name__}"
    low, high = PIXEL_SIZE_BOUNDS_M
    sizes = (surface.dx,) if isinstance(surface, topo.LineProfile) else (surface.dx, surface.dy)
    if not all(low <= size <= high for size in sizes):
        return f"pixel sizes {sizes} outside {PIXEL_SIZE_BOUNDS_M}"
    heights = np.asarray(surface.heights)
    if np.isinf(heights).any():
        return "infinite heights"
    if np.nanmax(np.abs(heights), initial=0.0) > MAX_ABS_HEIGHT_M:
        return "heights beyond the bound"
    return None


def run_case(case: Case, data: bytes, folder: Path) -> tuple[str, str]:
    """Read the mutated file; ('error'|'result'|'other'|'budget', detail)."""
    path = folder / case.sample
    content = mutate(case, data)
    path.write_bytes(content)
    pixel_size = 1e-6 if case.sample in NEEDS_PIXEL_SIZE else None
    tracemalloc.reset_peak()
    start = time.perf_counter()
    try:
        surface = topo.read_surface(path, pixel_size=pixel_size)
    except TopographyFileError as exc:
        outcome = ("error", type(exc).__name__)
    except Exception as exc:  # noqa: BLE001 - the point of the test is to see any other
        outcome = ("other", f"{type(exc).__name__}: {exc}")
    else:
        problem = check_result(surface)
        outcome = ("other", problem) if problem else ("result", "")
    elapsed = time.perf_counter() - start
    peak = tracemalloc.get_traced_memory()[1]
    if elapsed > TIME_BUDGET_S:
        return "budget", f"{elapsed:.2f} s"
    if peak > MEMORY_BASE_BYTES + MEMORY_PER_FILE_BYTE * len(content):
        return "budget", f"peak {peak} bytes"
    return outcome


def run_corpus(samples: dict[str, bytes], folder: Path, every: int, timing: bool = False) -> dict:
    """Run every ``every``-th case of the corpus; per-format outcome counts and failures."""
    table: dict[str, Counter] = {}
    failures = []
    tracemalloc.start()
    try:
        for name, data in samples.items():
            counts = table.setdefault(name, Counter())
            began = time.perf_counter()
            for case in _cases_for(name, data)[::every]:
                outcome, detail = run_case(case, data, folder)
                counts[outcome] += 1
                if outcome in ("other", "budget"):
                    failures.append(f"{case.label}: {outcome}: {detail}")
            if timing:
                print(name, sum(counts.values()), f"{time.perf_counter() - began:.1f} s")
    finally:
        tracemalloc.stop()
    return {"table": table, "failures": failures}


def format_table(table: dict[str, Counter]) -> str:
    lines = [
        "| sample | mutated files | typed errors | results | other exceptions | over budget |",
        "|---|---|---|---|---|---|",
    ]
    total: Counter = Counter()
    for name, counts in table.items():
        total.update(counts)
        lines.append(
            f"| {name} | {sum(counts.values())} | {counts['error']} | {counts['result']} "
            f"| {counts['other']} | {counts['budget']} |"
        )
    lines.append(
        f"| all | {sum(total.values())} | {total['error']} | {total['result']} "
        f"| {total['other']} | {total['budget']} |"
    )
    return "\n".join(lines)


@pytest.mark.slow  # several seconds: the default run stays under 3 min on 2 cores
def test_fuzz_corpus_sample_ends_in_typed_errors_or_valid_results(samples, tmp_path):
    report = run_corpus(samples, tmp_path, every=7)
    cases = sum(sum(c.values()) for c in report["table"].values())
    assert cases >= 200
    assert not report["failures"], "\n".join(report["failures"][:20])
    # the corpus is hostile: most cases must be refused, and some must still read
    errors = sum(c["error"] for c in report["table"].values())
    assert errors > cases // 2


@pytest.mark.slow
def test_full_fuzz_corpus_ends_in_typed_errors_or_valid_results(samples, tmp_path):
    report = run_corpus(samples, tmp_path, every=1, timing=True)
    print("\n" + format_table(report["table"]))
    assert not report["failures"], "\n".join(report["failures"][:40])


def test_corpus_is_deterministic(samples):
    first = [case.label for case in _cases_for("sur-3.sur", samples["sur-3.sur"])]
    again = [case.label for case in _cases_for("sur-3.sur", samples["sur-3.sur"])]
    assert first == again and len(first) > 100
    case = first and _cases_for("sur-3.sur", samples["sur-3.sur"])[30]
    assert mutate(case, samples["sur-3.sur"]) == mutate(case, samples["sur-3.sur"])


# --- headers that lie: mutations that once read without a word, each refused or warned ----


def _replace_once(data: bytes, old: bytes, new: bytes, after: bytes = b"") -> bytes:
    start = data.index(after) if after else 0
    at = data.index(old, start)
    return data[:at] + new + data[at + len(old) :]


def _pack(data: bytes, offset: int, fmt: str, value) -> bytes:
    out = bytearray(data)
    struct.pack_into(fmt, out, offset, value)
    return bytes(out)


def _scaled_float(data: bytes, offset: int, fmt: str, factor: float) -> bytes:
    return _pack(data, offset, fmt, struct.unpack_from(fmt, data, offset)[0] * factor)


def _sur_grid(data: bytes) -> bytes:
    return _pack(_pack(data, 108, "<i", 256), 112, "<i", 1024)  # 512 x 512 as 256 x 1024


def _plu_infinite(data: bytes) -> bytes:
    return _pack(data, 508 + 4 * 1000, "<f", float("inf"))  # one height of layer 0


# (sample, mutation, refused: error message pattern | warned: preparation warning pattern)
LYING_HEADERS = [
    ("mi-1.mi", lambda d: _replace_once(d, b"BINARY_32", b"BINARY   "),
     "refused", r"data: .*exactly twice: the values look like int32"),
    ("di-3.di", lambda d: _replace_once(d, b"Data offset: 434176", b"Data offset: 303104"),
     "refused", r"image 3 'Data offset': is 303104, inside the data of image 2"),
    ("di-3.di", lambda d: _replace_once(d, b"Samps/line: 256", b"Samps/line: 128",
                                        after=b"Ciao image list"),
     "refused", r"image 0 'Data length': is 131072; expected 'Samps/line'"),
    ("di-3.di", lambda d: _replace_once(d, b"Valid data len X: 256", b"Valid data len X: 128"),
     "refused", r"image 0 'Valid data len x': is 128"),
    ("sur-3.sur", _sur_grid, "warned", r"along y \(between lines\) differ as much as unrelated"),
    ("metropro-1.dat", lambda d: _scaled_float(d, 184, ">f", 0.25),
     "warned", r"lateral_res is 2.746e-07 m .* 0.371 times"),
    ("metropro-1.dat", lambda d: _scaled_float(d, 168, ">f", 1.44),
     "refused", r"wavelength_in: is 8.208e-07 m but wavelength_in_1 is 5.7e-07 m"),
    ("metropro-1.dat", lambda d: _pack(d, 168, ">f", 5.7e-5),
     "refused", r"wavelength_in: is 5.7e-05; expected 1.5e-07 .. 2e-06"),
    ("metropro-1.dat", lambda d: _pack(d, 176, ">f", 3.0),
     "refused", r"obliquity_factor: is 3; expected 0.9 .. 2"),
    ("metropro-1.dat", lambda d: _pack(d, 164, ">f", 4.0),
     "refused", r"intf_scale_factor: is 4; expected 0.001 .. 1"),
    ("plu-1.plu", _plu_infinite, "refused", r"heights: hold 1 infinite values"),
]  # fmt: skip


@pytest.mark.parametrize(("name", "mutate", "outcome", "pattern"), LYING_HEADERS)
def test_a_header_that_lies_is_refused_or_warned_naming_the_field(
    tmp_path, name, mutate, outcome, pattern
):
    path = tmp_path / name
    path.write_bytes(mutate((DATA / name).read_bytes()))
    if outcome == "refused":
        with pytest.raises(TopographyFileError, match=pattern):
            topo.read_surface(path)
        return
    warnings = topo.prepare_surface(topo.read_surface(path)).record.warnings
    assert any(re.search(pattern, w) for w in warnings), warnings
    # the unmutated sample carries no such warning
    clean = topo.prepare_surface(topo.read_surface(DATA / name)).record.warnings
    assert not any(re.search(pattern, w) for w in clean)


def test_heights_below_floating_point_resolution_are_refused(tmp_path):
    from asperity.errors import InputError

    heights = np.random.default_rng(3).normal(size=(32, 32)) * 1e-300
    np.save(tmp_path / "tiny.npy", heights)
    surface = topo.read_surface(tmp_path / "tiny.npy", pixel_size=1e-6)
    with pytest.raises(InputError, match=r"tiny\.npy: heights: vary by only .* 1e-15 m"):
        topo.prepare_surface(surface)
    # the same map in its right unit is prepared
    np.save(tmp_path / "fine.npy", heights * 1e294)
    topo.prepare_surface(topo.read_surface(tmp_path / "fine.npy", pixel_size=1e-6))


def test_an_outlier_rule_that_masks_half_the_map_is_refused(tmp_path):
    from asperity.errors import InputError
    from asperity.topo.cleaning import OutlierRule
    from asperity.topo.preparation import PreparationOptions

    rng = np.random.default_rng(4)
    heights = np.where(np.arange(64)[:, None] < 32, 0.0, 1e-6) + rng.normal(size=(64, 64)) * 1e-9
    np.save(tmp_path / "steps.npy", heights)
    surface = topo.read_surface(tmp_path / "steps.npy", pixel_size=1e-6)
    options = PreparationOptions(form_order=None, outliers=OutlierRule("percentile", 25.0))
    with pytest.raises(InputError, match=r"steps\.npy: outliers: the rule .* more than 25 %"):
        topo.prepare_surface(surface, options)


def test_infinity_is_refused_by_every_reader_that_stores_floats(tmp_path):
    """+inf is never a missing-point marker: plu (above) and opd refuse it as npy does."""
    from asperity.topo.io.opd import _data_block, _directory

    data = bytearray((DATA / "opd-1.opd").read_bytes())
    _name, offset, _nx, _ny, itemsize = _data_block(
        Path("opd-1.opd"), data, _directory(Path("opd-1.opd"), bytes(data))
    )
    assert itemsize == 4
    struct.pack_into("<f", data, offset + 6 + 4 * 100, float("inf"))
    (tmp_path / "inf.opd").write_bytes(bytes(data))
    np.save(tmp_path / "inf.npy", np.array([[0.0, np.inf], [1e-6, 2e-6]]))
    for path, kwargs in ((tmp_path / "inf.opd", {}), (tmp_path / "inf.npy", {"pixel_size": 1e-6})):
        with pytest.raises(TopographyFileError, match="heights: hold 1 infinite values"):
            topo.read_surface(path, **kwargs)
