"""Profile file readers: SIMPACK ``.prr``/``.prw``, MiniProf ``.ban``/``.whl`` and plain
two-column text, from a file or from bytes (an upload: data, never a server path).

Every reader returns a :class:`~flexride.contact.profiles.profile.Profile` in flexride's
convention (m; y toward the field side, z up; wheel origin at the taping line). Problems raise
:class:`~flexride.errors.ScenarioError` naming the file name (never its directory) and, where
it applies, the line.

Formats and their conventions
-----------------------------
SIMPACK (``.prr`` rail, ``.prw`` wheel)
    Text blocks ``header.begin … header.end`` (``type = 0`` rail, ``1`` wheel) and
    ``spline.begin … spline.end`` with processing keys and a ``point.begin … point.end`` block
    of ``y z [weight]`` rows; ``!`` (and ``%``) start comments. The points are processed in the
    order SIMPACK defines: ``point.dist.min`` (drop points closer than this to the previous one),
    ``shift.y``/``shift.z``, ``rotate`` (about x, angle unit ``units.ang.f`` per rad; y' = y cos α
    − z sin α, z' = y sin α + z cos α), ``bound.y.min/max`` (drop points outside, when
    min < max), ``bound.z.min/max`` (clip, when min < max), ``mirror.y``/``mirror.z`` (negate),
    ``units.len.f`` (file length unit per m, 1000 for mm). After processing, a profile is the
    right-hand one in SIMPACK's frame (y toward the field side, z **down**); flexride keeps y and
    negates z. ``inversion`` only reverses the point order, which does not matter here (points
    are ordered by y; a fold is an error). ``approx.smooth`` and the weights are not used.
MiniProf (``.ban`` rail, ``.whl`` wheel)
    ``key=value`` header lines, ``ColumnDef=X,Y[,…]`` naming the columns, a blank line, then
    rows of tab- (or space-) separated numbers, some starting with a ``"`` row flag that is
    ignored. Header lines without ``=`` (old-style files) and lines starting with ``#`` are
    skipped. ``XOffset``/``YOffset`` are added to X/Y; ``XYPoints``, when given, must equal the
    number of rows. Units mm. Rails: X toward the gauge side, Y down (y = −X, z = −Y). Wheels: X
    from the flange back (inner face) toward the field side, Y the radius increase
    (y = X − ``taping_line_offset``, z = −Y).
Plain text (any other extension, e.g. ``.txt``, ``.csv``, ``.dat``)
    Two columns y z in mm per row, separated by white space, comma or semicolon, already in
    flexride's convention (y toward the field side, z up; wheel: y from the taping line,
    z = −radius increase), as the EN 15302 reference profiles are. Blank lines and lines
    starting with ``#``, ``!`` or ``%`` are skipped; the first other line may be a header
    (e.g. ``y_mm,z_mm``). The kind (wheel or rail) must be given.

For all formats ``mirror_y`` negates y after the conversion (a profile of the other side) and
``shift_y`` is then added to y (m).
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

import numpy as np

from flexride.contact.profiles.profile import MAX_POINTS, MIN_SPACING, Profile, ProfileKind
from flexride.errors import ScenarioError

__all__ = [
    "MAX_PROFILE_BYTES",
    "ProfileFormat",
    "profile_format",
    "read_profile",
    "read_profile_bytes",
]

ProfileFormat = Literal["simpack", "miniprof", "text"]

#: Largest profile file accepted (bytes).
MAX_PROFILE_BYTES = 8 * 1024 * 1024

_EXT_FORMAT: dict[str, tuple[ProfileFormat, ProfileKind | None]] = {
    ".prr": ("simpack", "rail"),
    ".prw": ("simpack", "wheel"),
    ".ban": ("miniprof", "rail"),
    ".whl": ("miniprof", "wheel"),
}
_FLOAT = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)([eEdD][+-]?\d+)?$")


def profile_format(name: str) -> tuple[ProfileFormat, ProfileKind | None]:
    """Format and kind implied by a file name's extension (text and no kind when unknown)."""
    return _EXT_FORMAT.get(Path(name).suffix.lower(), ("text", None))


@dataclass
class _Points:
    """Raw points in file units with their 1-based source lines."""

    y: list[float]
    z: list[float]
    lines: list[int]

    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return (np.array(self.y, dtype=np.float64), np.array(self.z, dtype=np.float64),
                np.array(self.lines, dtype=np.int64))


class _Fail:
    """Error factory bound to a file name; ``quote`` says whether messages may quote the
    file's text (files a user read themselves) or not (uploads: an answer never quotes data
    that were sent to the service).
    """

    def __init__(self, name: str, quote: bool = True) -> None:
        self.name = name
        self.quote = quote

    def show(self, text: str) -> str:
        """``text`` of the file as a message may show it."""
        if not self.quote:
            return "(a value not shown)"
        return repr(text if len(text) <= 40 else text[:40] + "…")

    def __call__(self, msg: str, line: int | None = None) -> ScenarioError:
        where = self.name if line is None else f"{self.name}, line {line}"
        return ScenarioError(f"{where}: {msg}")


def _number(token: str, fail: _Fail, line: int) -> float:
    t = token.strip()
    if not _FLOAT.match(t) and t.lower() not in ("nan", "inf", "-inf", "+inf"):
        raise fail(f"not a number: {fail.show(t)}", line)
    value = float(t.replace("d", "e").replace("D", "e"))
    if not math.isfinite(value):
        raise fail(f"coordinate is NaN or inf ({fail.show(t)})", line)
    return value


def _decode(data: bytes, fail: _Fail) -> list[str]:
    if len(data) > MAX_PROFILE_BYTES:
        raise fail(f"file too large ({len(data)} bytes > {MAX_PROFILE_BYTES})")
    if b"\x00" in data[:4096]:
        raise fail("unreadable: binary data, not a text profile")
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError:
        text = data.decode("latin-1")
    return text.splitlines()


# --- SIMPACK ---------------------------------------------------------------------------------

_SPCK_REAL_KEYS = {
    "approx.smooth", "point.dist.min", "shift.y", "shift.z", "rotate", "bound.y.min",
    "bound.y.max", "bound.z.min", "bound.z.max", "units.len.f", "units.ang.f",
}
_SPCK_INT_KEYS = {"mirror.y", "mirror.z", "inversion"}


def _strip_comment(line: str, chars: str) -> str:
    cut = len(line)
    in_quote = False
    for i, ch in enumerate(line):
        if ch == "'":
            in_quote = not in_quote
        elif ch in chars and not in_quote:
            cut = i
            break
    return line[:cut].strip()


def _parse_simpack(lines: list[str], fail: _Fail) -> tuple[_Points, int | None, dict[str, float]]:
    section: list[str] = []
    opts: dict[str, float] = {}
    kind_code: int | None = None
    pts = _Points([], [], [])
    seen_points = False
    for no, raw in enumerate(lines, start=1):
        text = _strip_comment(raw, "!%")
        if not text:
            continue
        low = text.lower()
        if low in ("header.begin", "spline.begin", "point.begin"):
            want = {"header.begin": [], "spline.begin": [], "point.begin": ["spline"]}[low]
            if section != want:
                raise fail(f"misplaced {low!r} (sections must nest header, spline > point)", no)
            section.append(low.split(".")[0])
            if low == "point.begin":
                seen_points = True
            continue
        if low in ("header.end", "spline.end", "point.end"):
            name = low.split(".")[0]
            if not section or section[-1] != name:
                raise fail(f"{low!r} without a matching {name}.begin", no)
            section.pop()
            continue
        if section == ["spline", "point"]:
            tokens = text.replace(",", " ").split()
            if not 2 <= len(tokens) <= 3:
                raise fail(f"a point row needs 'y z [weight]', got {len(tokens)} value(s)", no)
            pts.y.append(_number(tokens[0], fail, no))
            pts.z.append(_number(tokens[1], fail, no))
            pts.lines.append(no)
            if len(pts.y) > MAX_POINTS:
                raise fail(f"too many points (> {MAX_POINTS})", no)
            continue
        if "=" not in text:
            if not section:
                continue  # free text outside the blocks
            raise fail(f"expected 'key = value', got {fail.show(text)}", no)
        key, value = (part.strip() for part in text.split("=", 1))
        key = key.lower()
        if section == ["header"]:
            if key == "type":
                code = _number(value, fail, no)
                if code not in (0.0, 1.0):
                    raise fail(f"header type must be 0 (rail) or 1 (wheel), got {fail.show(value)}",
                               no)
                kind_code = int(code)
        elif section == ["spline"]:
            if key in _SPCK_REAL_KEYS or key in _SPCK_INT_KEYS:
                opts[key] = _number(value, fail, no)
    if section:
        raise fail(f"unexpected end of file inside the {section[-1]} section")
    if not seen_points:
        raise fail("no point.begin … point.end block")
    return pts, kind_code, opts


def _simpack_to_profile(pts: _Points, kind: ProfileKind, opts: dict[str, float], fail: _Fail,
                        ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    y, z, ln = pts.arrays()
    dist_min = opts.get("point.dist.min", 0.0)
    if dist_min > 0.0 and y.size > 1:
        keep = [0]
        for i in range(1, y.size):
            if math.hypot(y[i] - y[keep[-1]], z[i] - z[keep[-1]]) >= dist_min:
                keep.append(i)
        y, z, ln = y[keep], z[keep], ln[keep]
    y = y + opts.get("shift.y", 0.0)
    z = z + opts.get("shift.z", 0.0)
    ang_f = opts.get("units.ang.f", 1.0)
    if not (math.isfinite(ang_f) and ang_f > 0.0):
        raise fail(f"units.ang.f must be positive, got {ang_f!r}")
    alpha = opts.get("rotate", 0.0) / ang_f
    if alpha != 0.0:
        c, s = math.cos(alpha), math.sin(alpha)
        y, z = c * y - s * z, s * y + c * z
    ylo, yhi = opts.get("bound.y.min", 1.0), opts.get("bound.y.max", 0.0)
    if ylo < yhi:
        keep_b = (y >= ylo) & (y <= yhi)
        y, z, ln = y[keep_b], z[keep_b], ln[keep_b]
    zlo, zhi = opts.get("bound.z.min", 1.0), opts.get("bound.z.max", 0.0)
    if zlo < zhi:
        z = np.clip(z, zlo, zhi)
    if int(opts.get("mirror.y", 0.0)) == 1:
        y = -y
    if int(opts.get("mirror.z", 0.0)) == 1:
        z = -z
    len_f = opts.get("units.len.f", 1.0)
    if not (math.isfinite(len_f) and len_f > 0.0):
        raise fail(f"units.len.f must be positive (file length unit per m), got {len_f!r}")
    # SIMPACK frame: y toward the field side, z down -> flexride: z up
    return y / len_f, -z / len_f, ln


# --- MiniProf --------------------------------------------------------------------------------

def _parse_miniprof(lines: list[str], fail: _Fail) -> tuple[_Points, dict[str, str]]:
    header: dict[str, str] = {}
    pts = _Points([], [], [])
    in_header = True
    seen_header = False  # any header line, key=value or free text (old-style files)
    ix, iy, ncol = 0, 1, 2
    for no, raw in enumerate(lines, start=1):
        text = raw.strip()
        if in_header:
            if not text:
                in_header = not seen_header  # the blank line after the header
                continue
            if text.startswith("#"):
                continue
            if "=" in text:
                key, value = (p.strip() for p in text.split("=", 1))
                header[key.lower()] = value
                seen_header = True
                if key.lower() == "columndef":
                    cols = [c.strip().upper() for c in value.split(",")]
                    if "X" not in cols or "Y" not in cols:
                        raise fail("ColumnDef must name columns X and Y, got "
                                   f"{fail.show(value)}", no)
                    ix, iy, ncol = cols.index("X"), cols.index("Y"), len(cols)
                continue
            tokens = text.lstrip('"').replace(",", " ").split()
            numeric = len(tokens) >= 2 and all(_FLOAT.match(t) for t in tokens[:2])
            if not (numeric and not seen_header):
                seen_header = True  # free text or numbers inside an old-style header
                continue
            in_header = False  # data without any header
        if not text or text.startswith("#"):
            continue
        if "=" in text:
            raise fail(f"header line {fail.show(text.split('=', 1)[0])} after the data rows", no)
        tokens = text.lstrip('"').replace(",", " ").split()
        if len(tokens) < max(ix, iy) + 1 or (len(tokens) < ncol and "columndef" in header):
            raise fail(f"expected {ncol} columns (ColumnDef), got {len(tokens)}", no)
        pts.y.append(_number(tokens[ix], fail, no))
        pts.z.append(_number(tokens[iy], fail, no))
        pts.lines.append(no)
        if len(pts.y) > MAX_POINTS:
            raise fail(f"too many points (> {MAX_POINTS})", no)
    return pts, header


def _miniprof_to_profile(pts: _Points, header: dict[str, str], kind: ProfileKind,
                         taping_line_offset: float, fail: _Fail,
                         ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    y, z, ln = pts.arrays()
    if "xypoints" in header and header["xypoints"].strip():
        try:
            declared = int(float(header["xypoints"]))
        except ValueError as exc:
            raise fail(f"XYPoints is not a number: {fail.show(header['xypoints'])}") from exc
        if declared != y.size:
            raise fail(f"XYPoints = {declared} but the file has {y.size} data rows "
                       "(truncated or damaged file?)")

    def offset(key: str) -> float:
        text = header.get(key, "").strip()
        if not text:
            return 0.0
        try:
            return float(text.replace(",", "."))
        except ValueError as exc:
            raise fail(f"{key} is not a number: {fail.show(text)}") from exc

    x_mm = y + offset("xoffset")
    y_mm = z + offset("yoffset")
    if kind == "rail":
        return -x_mm * 1e-3, -y_mm * 1e-3, ln
    return x_mm * 1e-3 - taping_line_offset, -y_mm * 1e-3, ln


# --- plain text ------------------------------------------------------------------------------

def _parse_text(lines: list[str], fail: _Fail) -> _Points:
    pts = _Points([], [], [])
    header_allowed = True
    for no, raw in enumerate(lines, start=1):
        text = raw.strip()
        if not text or text[0] in "#!%":
            continue
        tokens = [t for t in re.split(r"[\s,;]+", text) if t]
        numeric = [bool(_FLOAT.match(t)) or t.lower() in ("nan", "inf", "-inf") for t in tokens]
        if header_allowed and not any(numeric):
            header_allowed = False
            continue
        header_allowed = False
        if len(tokens) != 2:
            raise fail(f"expected two columns 'y z' (mm), got {len(tokens)}", no)
        pts.y.append(_number(tokens[0], fail, no))
        pts.z.append(_number(tokens[1], fail, no))
        pts.lines.append(no)
        if len(pts.y) > MAX_POINTS:
            raise fail(f"too many points (> {MAX_POINTS})", no)
    return pts


# --- common ----------------------------------------------------------------------------------

def _finish(y: np.ndarray, z: np.ndarray, ln: np.ndarray, kind: ProfileKind, name: str,
            mirror_y: bool, shift_y: float) -> Profile:
    if mirror_y:
        y = -y
    y = y + shift_y
    if y.size >= 2 and y[0] > y[-1]:  # stored from the field side: order by y
        y, z, ln = y[::-1], z[::-1], ln[::-1]
    if y.size:
        keep = [0]
        for i in range(1, y.size):
            if math.hypot(y[i] - y[keep[-1]], z[i] - z[keep[-1]]) >= MIN_SPACING:
                keep.append(i)
        y, z, ln = y[keep], z[keep], ln[keep]
    return Profile(kind, y, z, name, ln)


def _read(lines_of: Callable[[_Fail], list[str]], name: str, kind: ProfileKind | None,
          fmt: ProfileFormat | None, mirror_y: bool, shift_y: float,
          taping_line_offset: float, quote: bool = True) -> Profile:
    label = Path(name).name or "profile"
    fail = _Fail(label, quote)
    ext_fmt, ext_kind = profile_format(label)
    fmt = fmt or ext_fmt
    if fmt not in ("simpack", "miniprof", "text"):
        raise fail(f"unknown profile format {fmt!r} (simpack, miniprof or text)")
    if kind is not None and kind not in ("wheel", "rail"):
        raise fail(f"profile kind must be 'wheel' or 'rail', got {kind!r}")
    if kind is not None and ext_kind is not None and kind != ext_kind:
        raise fail(f"a {Path(label).suffix} file holds a {ext_kind} profile, expected a {kind}")
    if not (math.isfinite(shift_y) and math.isfinite(taping_line_offset)):
        raise fail("shift_y and taping_line_offset must be finite")
    lines = lines_of(fail)
    if fmt == "simpack":
        pts, code, opts = _parse_simpack(lines, fail)
        file_kind: ProfileKind | None = None if code is None else ("wheel" if code else "rail")
        if file_kind is not None and kind is not None and file_kind != kind:
            raise fail(f"header type = {code} marks a {file_kind} profile, expected a {kind}")
        if file_kind is not None and ext_kind is not None and file_kind != ext_kind:
            raise fail(f"header type = {code} marks a {file_kind} profile, but a "
                       f"{Path(label).suffix} file holds a {ext_kind} profile")
        use = kind or file_kind or ext_kind
        if use is None:
            raise fail("cannot tell wheel from rail: no header type; give the kind")
        y, z, ln = _simpack_to_profile(pts, use, opts, fail)
    elif fmt == "miniprof":
        use = kind or ext_kind
        if use is None:
            raise fail("cannot tell wheel from rail (.ban rail, .whl wheel); give the kind")
        pts_m, header = _parse_miniprof(lines, fail)
        y, z, ln = _miniprof_to_profile(pts_m, header, use, taping_line_offset, fail)
    else:
        if kind is None:
            raise fail("plain-text profile: give the kind (wheel or rail)")
        use = kind
        y_mm, z_mm, ln = _parse_text(lines, fail).arrays()
        y, z = y_mm * 1e-3, z_mm * 1e-3
    return _finish(y, z, ln, use, label, mirror_y, shift_y)


def read_profile(path: str | Path, kind: ProfileKind | None = None, *,
                 fmt: ProfileFormat | None = None, mirror_y: bool = False, shift_y: float = 0.0,
                 taping_line_offset: float = 0.070) -> Profile:
    """Read a wheel or rail profile file.

    Parameters
    ----------
    path : str or pathlib.Path
        The file. Messages name only its file name.
    kind : {"wheel", "rail"}, optional
        Expected kind; required for plain text, checked against the extension and the SIMPACK
        header otherwise.
    fmt : {"simpack", "miniprof", "text"}, optional
        Format; default from the extension (``.prr``/``.prw`` SIMPACK, ``.ban``/``.whl``
        MiniProf, anything else plain text).
    mirror_y : bool
        Negate y after the conversion (a profile drawn for the other side).
    shift_y : float
        Added to y after the conversion, in m.
    taping_line_offset : float
        MiniProf wheels only: distance from the flange back (X = 0) to the taping line in m.

    Returns
    -------
    Profile
        In flexride's convention (see :mod:`flexride.contact.profiles.profile`).

    Raises
    ------
    ScenarioError
        Unreadable or missing file, malformed content, non-monotonic or too few points, NaN,
        wrong orientation or kind — with the file name and line.
    """
    p = Path(path)

    def lines_of(fail: _Fail) -> list[str]:
        try:
            size = p.stat().st_size
            if size > MAX_PROFILE_BYTES:
                raise fail(f"file too large ({size} bytes > {MAX_PROFILE_BYTES})")
            data = p.read_bytes()
        except OSError as exc:
            raise fail(f"cannot read the file ({exc.strerror or exc})") from exc
        return _decode(data, fail)

    return _read(lines_of, p.name, kind, fmt, mirror_y, shift_y, taping_line_offset)


def read_profile_bytes(data: bytes, name: str, kind: ProfileKind | None = None, *,
                       fmt: ProfileFormat | None = None, mirror_y: bool = False,
                       shift_y: float = 0.0, taping_line_offset: float = 0.070) -> Profile:
    """Read a profile from the bytes of an uploaded file. Error messages name the line but
    never quote the file's text (an answer of the service never echoes data sent to it).

    Parameters
    ----------
    data : bytes
        File content (at most :data:`MAX_PROFILE_BYTES`).
    name : str
        The file's name as the client gave it: a label for messages and the extension that
        selects the format; never opened. Directory parts are dropped.
    kind, fmt, mirror_y, shift_y, taping_line_offset
        As for :func:`read_profile`.

    Returns
    -------
    Profile
    """
    if not isinstance(data, (bytes, bytearray, memoryview)):
        raise ScenarioError(f"{Path(str(name)).name}: profile data must be bytes")
    raw = bytes(data)
    return _read(lambda fail: _decode(raw, fail), str(name).replace("\\", "/"), kind, fmt,
                 mirror_y, shift_y, taping_line_offset, quote=False)
