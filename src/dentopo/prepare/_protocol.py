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
    iterations = 3
    step = 0.1
    pin_boundary = true       # the open base's vertices stay put (false: the filter as published)

The :attr:`Protocol.digest` is the SHA-256 of the steps' parameters in a
canonical form (the name and description left out): two protocols that do the
same steps have the same digest, whatever they are called.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
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


def _choice(name: str, value, choices) -> str:
    if not isinstance(value, str) or value not in choices:
        raise ProtocolError(f"{name} must be one of {', '.join(map(repr, choices))}; got {value!r}")
    return value


def _number(name: str, value, *, low=None, high=None, open_low=False) -> float:
    if isinstance(value, bool) or not isinstance(value, Real) or not math.isfinite(value):
        raise ProtocolError(f"{name} must be a finite number; got {value!r}")
    value = float(value)
    if low is not None and (value < low or (open_low and value == low)):
        bound = f"above {low:g}" if open_low else f"at least {low:g}"
        raise ProtocolError(f"{name} must be {bound}; got {value:g}")
    if high is not None and value > high:
        raise ProtocolError(f"{name} must be at most {high:g}; got {value:g}")
    return value


def _count(name: str, value, *, low: int) -> int:
    if isinstance(value, bool) or not isinstance(value, Integral):
        raise ProtocolError(f"{name} must be a whole number; got {value!r}")
    if value < low:
        raise ProtocolError(f"{name} must be at least {low}; got {value}")
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
        raise ProtocolError(f"{name} must be {size} numbers; got {value!r}") from None
    if len(items) != size:
        raise ProtocolError(f"{name} must be {size} numbers; got {len(items)}")
    return tuple(_number(name, item) for item in items)


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
            if not isinstance(getattr(self, text), str):
                raise ProtocolError(f"{text} must be a text; got {getattr(self, text)!r}")
        if not isinstance(self.clean, bool):
            raise ProtocolError(f"clean must be true or false; got {self.clean!r}")
        _choice("keep", self.keep, KEEP)
        _choice("orient", self.orient, ORIENT)
        _choice("spin", self.spin, SPINS)
        if self.up is not None:
            up = _vector("up", self.up, 3)
            if not math.hypot(*up) > 0:
                raise ProtocolError("up must not be the zero vector")
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
            if not math.hypot(*plane[3:]) > 0:
                raise ProtocolError("crop_plane's normal (its last three numbers) must not be zero")
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
                f"smooth_pin_boundary must be true or false; got {self.smooth_pin_boundary!r}"
            )
        if self.smooth_iterations is not None:
            set_(
                self,
                "smooth_iterations",
                _count("smooth_iterations", self.smooth_iterations, low=0),
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
                            f"{where}: [{key}] has no key {inner!r} (known: {known})"
                        )
                    values[_TABLES[key][inner]] = item
            else:
                known = ", ".join([*_DESCRIPTIVE, *_TABLES])
                raise ProtocolError(f"{where}: unknown key {key!r} (known: {known})")
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


def _toml(value) -> str:
    """One TOML value (text, bool, number or array)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)  # a JSON string is a TOML basic string
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
            protocol = _parse(entry.read_text(encoding="utf-8"), f"protocol {entry.name}")
            found[protocol.name] = protocol
    return found


def _parse(text: str, where: str) -> Protocol:
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ProtocolError(f"{where} is not valid TOML: {exc}") from None
    return Protocol.from_mapping(data, where=where)


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
    return _parse(text, f"protocol {path}")


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
