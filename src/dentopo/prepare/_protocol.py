"""A preparation protocol: the parameters of every step, checked, hashed, read and written as TOML.

A protocol file says what differs from the defaults (clean keeping the largest
piece, orient occlusal side up, no crop, no decimation, no smoothing); one
written by :meth:`Protocol.to_toml` states every step, so that it reads the
same whatever later versions change.  Its layout, a table per step::

    name = "crown-10k"
    description = "..."
    [clean]
    keep = "largest"          # or "all"; enabled = false skips the step
    [orient]
    mode = "occlusal"         # or "none"
    up = [0.0, 0.0, 1.0]      # optional: the occlusal direction, by hand
    spin = "none"             # or "footprint"
    [crop]
    below = 1.5               # or fraction = 0.6, or plane = [px, py, pz, nx, ny, nz]
    [decimate]
    faces = 10000
    method = "quadric"        # or "meshlab" (pymeshlab, an optional GPL extra)
    [smooth]
    method = "implicit"       # laplacian, taubin, hc or implicit
    iterations = 3            # at most 10,000
    step = 0.1                # (0, 1] for laplacian, taubin and hc; (0, 1e6] for implicit
    pin_boundary = true       # the open base's vertices stay put (false: the filter as published)

A name holds no control character, lone surrogate or line separator (it is
shown on one line, in tables and records); the description and the source
may hold tabs and line breaks.  What :meth:`Protocol.to_toml` writes reads
back the same; a file may start with a byte-order mark.

The :attr:`Protocol.digest` is the SHA-256 of the steps' parameters in a
canonical form (the name and description left out): two protocols that do the
same steps have the same digest, whatever they are called.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import unicodedata
from dataclasses import asdict, dataclass, fields, replace
from importlib import resources
from numbers import Integral, Real
from pathlib import Path

try:  # Python 3.11+
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

#: ``keep`` of the clean step.
KEEP = ("largest", "all")

#: ``orient`` modes.
ORIENT = ("occlusal", "none")

#: ``spin`` after orienting.
SPINS = ("none", "footprint")

#: ``decimate`` methods: quadric edge collapse by fast-simplification, or MeshLab's (pymeshlab).
DECIMATORS = ("quadric", "meshlab")

#: ``smooth`` methods, and their default parameters (iterations, step, mu).
SMOOTHERS = {
    # trimesh.smoothing.filter_laplacian's defaults (lamb); run without its volume constraint
    "laplacian": {"iterations": 10, "step": 0.5, "mu": None},
    # trimesh.smoothing.filter_taubin's defaults (lamb, nu)
    "taubin": {"iterations": 10, "step": 0.5, "mu": 0.5},
    # trimesh.smoothing.filter_humphrey's defaults (alpha, beta)
    "hc": {"iterations": 10, "step": 0.1, "mu": 0.5},
    # implicit fairing (Desbrun et al. 1999) as MorphoTester applies it (its defaults)
    "implicit": {"iterations": 3, "step": 0.1, "mu": None},
}

#: The most smoothing iterations a protocol may ask for (a hundred times the most published,
#: MorphoTester's 100): more is a typing slip, and would run for hours on a raw scan.
MAX_SMOOTH_ITERATIONS = 10_000

#: The largest ``step`` and ``mu`` of each smoothing method.  The explicit filters
#: (laplacian, taubin, hc) take them in (0, 1], trimesh's documented ranges: at most 1, a
#: Laplacian pass moves each vertex to a convex combination of itself and its neighbours,
#: so that it can never diverge; beyond, it does (on the sample tooth, step 1.5 grows the
#: mesh 1e5-fold in 100 passes).  Implicit fairing is stable at any step in exact
#: arithmetic; beyond 1e6 (MorphoTester uses 0.1) the identity in ``I - step L`` is lost to
#: rounding and the result is noise (1e16 grows the sample tooth 170-fold).
SMOOTH_LIMITS = {
    "laplacian": {"step": 1.0},
    "taubin": {"step": 1.0, "mu": 1.0},
    "hc": {"step": 1.0, "mu": 1.0},
    "implicit": {"step": 1e6},
}

#: The step tables of a protocol file, and the keys each may hold (file key -> field).
_TABLES = {
    "clean": {"enabled": "clean", "keep": "keep"},
    "orient": {"mode": "orient", "up": "up", "spin": "spin"},
    "crop": {"below": "crop_below", "fraction": "crop_fraction", "plane": "crop_plane"},
    "decimate": {"faces": "faces", "method": "decimate"},
    "smooth": {
        "method": "smooth",
        "iterations": "smooth_iterations",
        "step": "smooth_step",
        "mu": "smooth_mu",
        "pin_boundary": "smooth_pin_boundary",
    },
}

#: The comment under a step's table in a written protocol when the step does not run.
_NOT_DONE = {
    "crop": "no crop (below = H, fraction = F or plane = [px, py, pz, nx, ny, nz])",
    "decimate": "no decimation (faces = N)",
    "smooth": "no smoothing (method = laplacian, taubin, hc or implicit)",
}

#: The fields that describe a protocol and are left out of its digest.
_DESCRIPTIVE = ("name", "description", "source")


class ProtocolError(ValueError):
    """A protocol's parameter or file is wrong (the message names it)."""


def _shown(value, limit: int = 60) -> str:
    """``repr(value)``, cut to `limit` characters (a message stays one short line)."""
    try:
        text = repr(value)
    except RecursionError:  # pragma: no cover - nested deeper than repr goes
        return f"a nested {type(value).__name__}"
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _choice(name: str, value, choices) -> str:
    if not isinstance(value, str) or value not in choices:
        raise ProtocolError(
            f"{name} must be one of {', '.join(map(repr, choices))}; got {_shown(value)}"
        )
    return value


def _number(name: str, value, *, low=None, high=None, open_low=False) -> float:
    if isinstance(value, bool) or not isinstance(value, Real) or not math.isfinite(value):
        raise ProtocolError(f"{name} must be a finite number; got {_shown(value)}")
    value = float(value)
    if low is not None and (value < low or (open_low and value == low)):
        bound = f"above {low:g}" if open_low else f"at least {low:g}"
        raise ProtocolError(f"{name} must be {bound}; got {value:g}")
    if high is not None and value > high:
        raise ProtocolError(f"{name} must be at most {high:g}; got {value:g}")
    return value


def _count(name: str, value, *, low: int, high: int | None = None) -> int:
    if isinstance(value, bool) or not isinstance(value, Integral):
        raise ProtocolError(f"{name} must be a whole number; got {_shown(value)}")
    if value < low:
        raise ProtocolError(f"{name} must be at least {low}; got {value}")
    if high is not None and value > high:
        raise ProtocolError(f"{name} must be at most {high:,}; got {_shown(int(value))}")
    return int(value)


def _vector(name: str, value, size: int) -> tuple[float, ...]:
    if isinstance(value, str):
        value = [part.strip() for part in value.split(",")]
        try:
            value = [float(part) for part in value]
        except ValueError:
            raise ProtocolError(f"{name} must be {size} numbers separated by commas") from None
    try:
        items = tuple(value)
    except TypeError:
        raise ProtocolError(f"{name} must be {size} numbers; got {_shown(value)}") from None
    if len(items) != size:
        raise ProtocolError(f"{name} must be {size} numbers; got {len(items)}")
    return tuple(_number(name, item) for item in items)


def scaled_direction(name: str, values) -> tuple[float, ...]:
    """`values` (finite numbers) times a power of two, their largest magnitude in [0.5, 1).

    The same direction exactly (a power of two scales without rounding), whose
    length can be computed: ``1e308`` components overflow and subnormal ones
    underflow when squared, so that the length is infinite or 0 and the unit
    vector NaN or zero.  The steps normalise this (``up``, the crop plane's
    normal), and the protocol checks with it: every direction the check
    passes gives a finite unit vector.

    Raises
    ------
    ProtocolError
        If every component is 0 (no direction) or one is not finite (named `name`).
    """
    items = [float(x) for x in values]
    if not all(math.isfinite(x) for x in items):
        raise ProtocolError(f"{name} must be finite numbers; got {_shown(tuple(values))}")
    largest = max((abs(x) for x in items), default=0.0)
    if not largest > 0:
        raise ProtocolError(f"{name} must not be the zero vector")
    exponent = math.frexp(largest)[1]
    return tuple(math.ldexp(x, -exponent) for x in items)


#: Unicode categories a protocol's name may not hold: control characters (they end
#: lines, move the cursor, are refused raw by TOML), lone surrogates (no UTF-8 can hold
#: them) and line and paragraph separators.  The description and the source may hold
#: tabs and line breaks, but no other of these.
_NOT_IN_NAME = {
    "Cc": "a control character",
    "Cs": "a lone surrogate",
    "Zl": "a line separator",
    "Zp": "a paragraph separator",
}
_TEXT_CONTROLS = frozenset("\t\n\r")


def _check_text(field: str, value) -> str:
    """`value` if it is a text a protocol file can hold (a ProtocolError naming the character)."""
    if not isinstance(value, str):
        raise ProtocolError(f"{field} must be a text; got {_shown(value)}")
    for place, char in enumerate(value):
        kind = unicodedata.category(char)
        if kind not in _NOT_IN_NAME or (field != "name" and char in _TEXT_CONTROLS):
            continue
        if kind == "Cc" and field != "name":
            what = "a control character other than tab and line breaks"
        else:
            what = _NOT_IN_NAME[kind]
        raise ProtocolError(
            f"{field} must not hold {what}: U+{ord(char):04X} at character {place + 1} "
            f"of {_shown(value, 40)}"
        )
    return value


@dataclass(frozen=True)
class Protocol:
    """The parameters of every preparation step (see the module docstring for the file form).

    Attributes
    ----------
    name : str
        What the protocol is called (``"custom"`` unless named).
    description, source : str
        What it is for, and where its parameters come from (a paper, a tool's manual).
    clean : bool
        Whether to clean (merge coincident vertices, drop degenerate and duplicate faces).
    keep : {"largest", "all"}
        After cleaning: keep the largest piece by area (scans carry specks and
        loose shells), or every piece.
    orient : {"occlusal", "none"}
        ``"occlusal"``: turn the crown occlusal side up (+z); ``"none"`` keeps the pose.
    up : (3,) float or None
        The occlusal direction, by hand (turned to +z); None: found.
    spin : {"none", "footprint"}
        ``"footprint"`` also turns the crown about z so that the footprint's
        long axis lies along y (doolkit's mesio-distal convention).
    crop_below : float or None
        After orienting, remove what lies less than this height (mesh units)
        above the lowest point.
    crop_fraction : float or None
        After orienting, keep the top fraction (0, 1] of the crown's height.
    crop_plane : (6,) float or None
        ``(px, py, pz, nx, ny, nz)``: keep the side of the plane through p that n points to.
    faces : int or None
        Decimate to this many faces (None: no decimation).
    decimate : {"quadric", "meshlab"}
        How to decimate.
    smooth : {"laplacian", "taubin", "hc", "implicit"} or None
        How to smooth (None: no smoothing).
    smooth_iterations : int or None
        Smoothing iterations (None: the method's default, ``SMOOTHERS``).
    smooth_step, smooth_mu : float or None
        The method's step (Laplacian's and Taubin's lambda, HC's alpha, implicit
        fairing's time step) and second parameter (Taubin's nu, HC's beta).
    smooth_pin_boundary : bool
        Keep the open boundary's vertices (a crown's base outline) where they
        are while smoothing (default); False runs the filters as published,
        which pull the boundary inwards.
    """

    name: str = "custom"
    description: str = ""
    source: str = ""
    clean: bool = True
    keep: str = "largest"
    orient: str = "occlusal"
    up: tuple[float, float, float] | None = None
    spin: str = "none"
    crop_below: float | None = None
    crop_fraction: float | None = None
    crop_plane: tuple[float, float, float, float, float, float] | None = None
    faces: int | None = None
    decimate: str = "quadric"
    smooth: str | None = None
    smooth_iterations: int | None = None
    smooth_step: float | None = None
    smooth_mu: float | None = None
    smooth_pin_boundary: bool = True

    def __post_init__(self):
        set_ = object.__setattr__
        for text in _DESCRIPTIVE:
            _check_text(text, getattr(self, text))
        if not isinstance(self.clean, bool):
            raise ProtocolError(f"clean must be true or false; got {_shown(self.clean)}")
        _choice("keep", self.keep, KEEP)
        _choice("orient", self.orient, ORIENT)
        _choice("spin", self.spin, SPINS)
        if self.up is not None:
            up = _vector("up", self.up, 3)
            scaled_direction("up", up)  # the step's unit vector is finite (see there)
            set_(self, "up", up)
        if self.orient == "none" and (self.up is not None or self.spin != "none"):
            raise ProtocolError("up and spin need orient='occlusal' (orient='none' keeps the pose)")
        crops = [
            c for c in ("crop_below", "crop_fraction", "crop_plane") if getattr(self, c) is not None
        ]
        if len(crops) > 1:
            raise ProtocolError(f"give one crop, not {' and '.join(crops)}")
        if self.crop_below is not None:
            set_(self, "crop_below", _number("crop_below", self.crop_below, low=0.0))
        if self.crop_fraction is not None:
            set_(
                self,
                "crop_fraction",
                _number("crop_fraction", self.crop_fraction, low=0.0, high=1.0, open_low=True),
            )
        if self.crop_plane is not None:
            plane = _vector("crop_plane", self.crop_plane, 6)
            if not any(plane[3:]):
                raise ProtocolError("crop_plane's normal (its last three numbers) must not be zero")
            _plane_height(plane)
            set_(self, "crop_plane", plane)
        if self.faces is not None:
            set_(self, "faces", _count("faces", self.faces, low=4))
        _choice("decimate", self.decimate, DECIMATORS)
        if self.smooth is not None:
            _choice("smooth", self.smooth, tuple(SMOOTHERS))
        elif any(
            v is not None for v in (self.smooth_iterations, self.smooth_step, self.smooth_mu)
        ) or (self.smooth_pin_boundary is not True):
            raise ProtocolError("smoothing parameters need a smooth method")
        if not isinstance(self.smooth_pin_boundary, bool):
            raise ProtocolError(
                f"smooth_pin_boundary must be true or false; got {_shown(self.smooth_pin_boundary)}"
            )
        if self.smooth_iterations is not None:
            set_(
                self,
                "smooth_iterations",
                _count(
                    "smooth_iterations",
                    self.smooth_iterations,
                    low=0,
                    high=MAX_SMOOTH_ITERATIONS,
                ),
            )
        if self.smooth_step is not None:
            set_(
                self,
                "smooth_step",
                _number("smooth_step", self.smooth_step, low=0.0, open_low=True),
            )
        if self.smooth_mu is not None:
            if self.smooth not in ("taubin", "hc"):
                raise ProtocolError(f"smooth_mu is a parameter of taubin and hc, not {self.smooth}")
            set_(self, "smooth_mu", _number("smooth_mu", self.smooth_mu, low=0.0, open_low=True))
        if self.smooth is not None:
            for key, value in (("step", self.smooth_step), ("mu", self.smooth_mu)):
                high = SMOOTH_LIMITS[self.smooth].get(key)
                if value is not None and high is not None and value > high:
                    why = (
                        "its stability limit: beyond, the filter can diverge"
                        if self.smooth != "implicit"
                        else "beyond, rounding swamps the system solved"
                    )
                    raise ProtocolError(
                        f"smooth_{key} must be at most {high:g} for {self.smooth} smoothing "
                        f"({why}); got {value:g}"
                    )

    # -- derived ------------------------------------------------------------------------------

    def smoothing(self) -> dict | None:
        """The smoothing method and its parameters, defaults filled in (None: no smoothing)."""
        if self.smooth is None:
            return None
        default = SMOOTHERS[self.smooth]
        given = {
            "iterations": self.smooth_iterations,
            "step": self.smooth_step,
            "mu": self.smooth_mu,
        }
        found = {key: default[key] if given[key] is None else given[key] for key in default}
        found = {k: v for k, v in found.items() if v is not None}
        return {"method": self.smooth, **found, "pin_boundary": self.smooth_pin_boundary}

    def steps(self) -> dict[str, dict]:
        """Each step that runs, in order, with its parameters (the protocol's canonical form)."""
        out: dict[str, dict] = {}
        if self.clean:
            out["clean"] = {"keep": self.keep}
        if self.orient != "none":
            out["orient"] = {
                "mode": self.orient,
                "up": None if self.up is None else list(self.up),
                "spin": self.spin,
            }
        if self.crop_below is not None:
            out["crop"] = {"below": self.crop_below}
        elif self.crop_fraction is not None:
            out["crop"] = {"fraction": self.crop_fraction}
        elif self.crop_plane is not None:
            out["crop"] = {"plane": list(self.crop_plane)}
        if self.faces is not None:
            out["decimate"] = {"faces": self.faces, "method": self.decimate}
        smoothing = self.smoothing()
        if smoothing is not None:
            out["smooth"] = smoothing
        return out

    @property
    def digest(self) -> str:
        """SHA-256 (hex) of :meth:`steps` in canonical JSON: the same steps, the same digest."""
        text = json.dumps(self.steps(), sort_keys=True, separators=(",", ":"), allow_nan=False)
        return hashlib.sha256(text.encode("utf-8")).hexdigest()

    @property
    def label(self) -> str:
        """The name and a short digest, ``"crown-10k 3f2a9c1e0b7d"`` (the ``protocol`` cell)."""
        return f"{self.name} {self.digest[:12]}"

    def __str__(self) -> str:
        return self.label

    def _repr_html_(self) -> str:
        from .._html_repr import result_html

        return result_html(self)

    def to_dict(self) -> dict:
        """Every field (JSON-ready: tuples as lists)."""
        return {k: list(v) if isinstance(v, tuple) else v for k, v in asdict(self).items()}

    # -- TOML ---------------------------------------------------------------------------------

    def to_toml(self) -> str:
        """The protocol as a TOML file stating every step (read back by :func:`read_protocol`)."""
        lines = ["# dentopo preparation protocol", f"name = {_toml(self.name)}"]
        if self.description:
            lines.append(f"description = {_toml(self.description)}")
        if self.source:
            lines.append(f"source = {_toml(self.source)}")
        tables = {
            "clean": {"enabled": self.clean, "keep": self.keep},
            "orient": {"mode": self.orient, "up": self.up, "spin": self.spin},
            "crop": {
                "below": self.crop_below,
                "fraction": self.crop_fraction,
                "plane": self.crop_plane,
            },
            "decimate": {"faces": self.faces, "method": self.decimate},
            "smooth": self.smoothing() or {},
        }
        for table, values in tables.items():
            lines.append("")
            lines.append(f"[{table}]")
            given = [(key, value) for key, value in values.items() if value is not None]
            given = [
                (k, v)
                for k, v in given
                # the method alone, at its default, says nothing: no decimation
                if not (table == "decimate" and k == "method" and v == DECIMATORS[0])
                or values["faces"] is not None
            ]
            lines += [f"{key} = {_toml(value)}" for key, value in given]
            if not given:
                lines.append(f"# {_NOT_DONE[table]}")
        return "\n".join(lines) + "\n"

    @classmethod
    def from_mapping(cls, data: dict, *, where: str = "the protocol") -> Protocol:
        """A protocol from a parsed TOML document (tables per step), checking every key."""
        if not isinstance(data, dict):
            raise ProtocolError(f"{where}: not a table of steps")
        values: dict = {}
        for key, value in data.items():
            if key in _DESCRIPTIVE:
                values[key] = value
            elif key in _TABLES:
                if not isinstance(value, dict):
                    raise ProtocolError(f"{where}: [{key}] must be a table")
                for inner, item in value.items():
                    if inner not in _TABLES[key]:
                        known = ", ".join(_TABLES[key])
                        raise ProtocolError(
                            f"{where}: [{key}] has no key {_shown(inner)} (known: {known})"
                        )
                    values[_TABLES[key][inner]] = item
            else:
                known = ", ".join([*_DESCRIPTIVE, *_TABLES])
                raise ProtocolError(f"{where}: unknown key {_shown(key)} (known: {known})")
        if values.get("faces") is not None and isinstance(values["faces"], float):
            if values["faces"].is_integer():
                values["faces"] = int(values["faces"])
        try:
            return cls(**values)
        except ProtocolError as exc:
            raise ProtocolError(f"{where}: {exc}") from None

    def replace(self, **changes) -> Protocol:
        """A copy with `changes` (checked); the name becomes ``"custom"`` unless given."""
        unknown = set(changes) - {f.name for f in fields(self)}
        if unknown:
            raise ProtocolError(f"unknown protocol parameter {sorted(unknown)[0]!r}")
        if changes and "name" not in changes and self.name != "custom":
            changes = {"name": f"{self.name}+", **changes}
        return replace(self, **changes)


def _plane_height(plane) -> float:
    """The crop plane's height along its unit normal (``p . n``); a ProtocolError if it overflows.

    The crop step measures every vertex's height along the normal from this;
    a point so far out that it overflows (``1e308`` in two coordinates along
    a slanted normal) would give infinite heights.
    """
    normal = scaled_direction("crop_plane's normal", plane[3:])
    length = math.sqrt(sum(x * x for x in normal))
    height = sum(p * n / length for p, n in zip(plane[:3], normal, strict=True))
    if not math.isfinite(height):
        raise ProtocolError(
            f"crop_plane's point {_shown(tuple(plane[:3]))} is too far from the origin: its "
            "distance along the normal overflows"
        )
    return height


#: The escapes of a TOML basic string (the control characters without one: ``\uXXXX``).
_ESCAPES = {'"': '\\"', "\\": "\\\\", "\b": "\\b", "\t": "\\t", "\n": "\\n"}
_ESCAPES.update({"\f": "\\f", "\r": "\\r"})


def _toml_string(text: str) -> str:
    """`text` as a TOML basic string: quotes, backslashes and every control character escaped.

    TOML refuses raw control characters (U+0000 to U+001F but tab, and U+007F)
    in a string, and lone surrogates anywhere (they are no Unicode scalar
    values): the first are escaped, the second refused (the protocol's texts
    are checked for them before).
    """
    out = []
    for char in text:
        code = ord(char)
        if char in _ESCAPES:
            out.append(_ESCAPES[char])
        elif code < 0x20 or code == 0x7F:
            out.append(f"\\u{code:04X}")
        elif 0xD800 <= code <= 0xDFFF:
            raise ProtocolError(f"a lone surrogate (U+{code:04X}) cannot be written to TOML")
        else:
            out.append(char)
    return '"' + "".join(out) + '"'


def _toml(value) -> str:
    """One TOML value (text, bool, number or array)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return _toml_string(value)
    if isinstance(value, Integral):
        return str(int(value))
    if isinstance(value, Real):
        return repr(float(value))
    return "[" + ", ".join(_toml(item) for item in value) + "]"


#: The package folder of the named protocols.
_NAMED = "protocols"


def named_protocols() -> dict[str, Protocol]:
    """The protocols that ship with dentopo, by name (``dentopo prepare --protocols``)."""
    found = {}
    for entry in sorted(resources.files(__package__).joinpath(_NAMED).iterdir(), key=str):
        if entry.name.endswith(".toml"):
            protocol = parse_protocol(entry.read_text(encoding="utf-8"), f"protocol {entry.name}")
            found[protocol.name] = protocol
    return found


#: The byte-order mark some editors put at the start of a UTF-8 file (TOML has none: it is
#: dropped, the file read).
BOM = "\ufeff"


def parse_protocol(text: str, where: str = "the protocol") -> Protocol:
    """A protocol from the text of a TOML file (a leading byte-order mark is dropped).

    Raises
    ------
    ProtocolError
        One line naming `where` and the problem: not valid TOML (also nested
        deeper than the reader goes), or a step's parameter wrong.
    """
    if text.startswith(BOM):
        text = text[len(BOM) :]
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ProtocolError(f"{where} is not valid TOML: {exc}") from None
    except RecursionError:
        raise ProtocolError(
            f"{where} is not a protocol: its arrays or tables nest too deeply to be read"
        ) from None
    try:
        return Protocol.from_mapping(data, where=where)
    except RecursionError:  # pragma: no cover - the reader refuses such nesting first
        raise ProtocolError(f"{where} is not a protocol: its values nest too deeply") from None


def read_protocol(path: str | os.PathLike) -> Protocol:
    """Read a protocol file (TOML; see the module docstring).

    Raises
    ------
    ProtocolError
        If the file is not valid TOML or a step's parameter is wrong (named).
    OSError
        If it cannot be read.
    """
    path = Path(path)
    try:
        text = path.read_bytes().decode("utf-8")
    except UnicodeDecodeError:
        raise ProtocolError(f"protocol {path} is not UTF-8 text") from None
    return parse_protocol(text, f"protocol {path}")


def load_protocol(protocol) -> Protocol:
    """A protocol from a :class:`Protocol`, a shipped name, a TOML file's path, or None.

    A text is a shipped name if one is called so, else a path.
    """
    if protocol is None:
        return Protocol()
    if isinstance(protocol, Protocol):
        return protocol
    if isinstance(protocol, dict):
        return Protocol.from_mapping(protocol)
    if isinstance(protocol, str):
        named = named_protocols()
        if protocol in named:
            return named[protocol]
        if not Path(protocol).is_file():
            raise ProtocolError(
                f"no protocol {protocol!r}: not a shipped name ({', '.join(sorted(named))}) "
                "and not a file"
            )
        return read_protocol(protocol)
    if isinstance(protocol, os.PathLike):
        return read_protocol(protocol)
    raise ProtocolError(
        f"a protocol is a Protocol, a name or a path; got {type(protocol).__name__}"
    )
