"""A strict PLY reader: exactly what the header declares, or an error saying what differs.

trimesh's reader measured a file cut short on the part it could read, took
header counts that disagreed with the body at their word, and read ASCII
values past the end of a row.  This reader checks every promise of the header:

* **Header**: ``ply``, one ``format`` line (``ascii``, ``binary_little_endian``
  or ``binary_big_endian``), ``element`` lines with a whole count, ``property``
  lines of any PLY scalar type (``char`` ... ``double`` and the sized names
  ``int8`` ... ``float64``), list properties with an integer count type,
  ``comment`` and ``obj_info`` lines, ``end_header``.  Anything else is an error.
* **Body**: every element in turn, row by row.  Binary rows are read with one
  ``numpy.frombuffer`` per element (a structured type); lists of varying length
  (polygons of several sizes) are located by a compiled scan.  ASCII rows are
  one per line, parsed with one ``numpy.fromstring``; a row whose numbers do not
  fit the header is an error naming its line.
* **Counts**: a file that ends early is *truncated* (the message says what the
  header declares and what the data holds up to where it ends); data left over
  after the declared elements, or rows of the wrong shape, mean the header's
  counts do not match the data (the message says both, when the rows can be
  counted).  An ASCII file whose last line has no line end is treated as cut
  short: its last number may be incomplete.
* **Values**: integer properties must hold whole numbers of their declared
  type; a face needs at least 3 indices.

Only the ``vertex`` element's ``x``, ``y``, ``z`` and the ``face`` element's
index list (``vertex_indices``, ``vertex_index``, or its only list) are kept;
every other property and element is skipped.  Polygons are cut into triangles
as trimesh does (so results do not change): triangles in file order, then each
quad ``(a, b, c, d)`` as ``(a, b, c)`` for every quad followed by ``(c, d, a)``
for every quad, then larger polygons as fans ``(p0, pi, pi+1)``.
"""

from __future__ import annotations

import os
import stat
from dataclasses import dataclass

import numpy as np

from .._jit import njit
from ._validate import check_finite, check_indices, index_message, plural

#: PLY scalar type names: the specification's and their sized spellings (and three more
#: that trimesh accepts).
TYPES = {
    "char": "i1",
    "uchar": "u1",
    "short": "i2",
    "ushort": "u2",
    "int": "i4",
    "uint": "u4",
    "float": "f4",
    "double": "f8",
    "int8": "i1",
    "uint8": "u1",
    "int16": "i2",
    "uint16": "u2",
    "int32": "i4",
    "uint32": "u4",
    "float32": "f4",
    "float64": "f8",
    "int64": "i8",
    "uint64": "u8",
    "float16": "f2",
}

_ORDERS = {"ascii": "=", "binary_little_endian": "<", "binary_big_endian": ">"}
_NOUNS = {"vertex": ("vertex", "vertices"), "face": ("face", "faces")}
_INDEX_NAMES = ("vertex_indices", "vertex_index")


@dataclass(frozen=True)
class _Property:
    name: str
    type_name: str  # the PLY type name (of a list's items)
    type: np.dtype  # with the file's byte order
    count_type: np.dtype | None = None  # a list's count type; None for a scalar

    @property
    def is_list(self) -> bool:
        return self.count_type is not None


@dataclass(frozen=True)
class _Element:
    name: str
    count: int
    properties: tuple[_Property, ...]

    def noun(self, count: int) -> str:
        singular, many = _NOUNS.get(self.name, (f"{self.name!r} row", f"{self.name!r} rows"))
        return plural(count, singular, many)

    def find(self, name: str) -> _Property | None:
        return next((p for p in self.properties if p.name == name), None)


def _describe(elements, counts=None) -> str:
    """``"331 vertices and 600 faces"``: the elements with the given (or declared) counts."""
    counts = [e.count for e in elements] if counts is None else counts
    parts = [e.noun(n) for e, n in zip(elements, counts, strict=True)]
    if not parts:
        return "no elements"
    return parts[0] if len(parts) == 1 else ", ".join(parts[:-1]) + " and " + parts[-1]


# --- header ---------------------------------------------------------------------------------


def _header(data: bytes, where: str) -> tuple[str, list[_Element], int, int]:
    """The format, the elements, the offset of the body and its first line number."""
    first_end = data.find(b"\n")
    if data[: first_end if first_end >= 0 else 8].strip() != b"ply":
        raise ValueError(f"{where}not a PLY file (its first line is not 'ply')")
    fmt = None
    elements: list[tuple[str, int, list[_Property]]] = []
    position, line_number = first_end + 1, 1
    while True:
        end = data.find(b"\n", position)
        if end < 0:
            raise ValueError(f"{where}the PLY header has no end_header line")
        line = data[position:end].decode("latin-1").strip()
        position, line_number = end + 1, line_number + 1
        words = line.split()
        if not words or words[0] in ("comment", "obj_info"):
            continue
        keyword = words[0]
        if keyword == "end_header" and len(words) == 1:
            break
        if keyword == "format":
            if fmt is not None:
                raise ValueError(f"{where}the PLY header has two format lines")
            if len(words) != 3 or words[1] not in _ORDERS:
                raise ValueError(
                    f"{where}unsupported PLY format line {line!r} (expected 'format ascii 1.0', "
                    "'format binary_little_endian 1.0' or 'format binary_big_endian 1.0')"
                )
            if words[2] not in ("1.0", "1"):
                raise ValueError(f"{where}unsupported PLY version {words[2]!r} (expected 1.0)")
            fmt = words[1]
        elif keyword == "element":
            if len(words) != 3 or not words[2].isdigit():
                raise ValueError(
                    f"{where}header line {line!r}: an element needs a name and a whole, "
                    "non-negative count"
                )
            elements.append((words[1], int(words[2]), []))
        elif keyword == "property":
            if not elements:
                raise ValueError(f"{where}header line {line!r} comes before any element")
            elements[-1][2].append(_property(words, line, fmt, where))
        elif keyword[0] in "0123456789+-.":
            raise ValueError(
                f"{where}the PLY header has no end_header line: line {line_number} "
                f"({line[:40]!r}) holds data"
            )
        else:
            raise ValueError(f"{where}unknown PLY header line {line!r}")
    if fmt is None:
        raise ValueError(f"{where}the PLY header has no format line")
    order = _ORDERS[fmt]
    parsed = []
    for name, count, properties in elements:
        names = [p.name for p in properties]
        if len(set(names)) != len(names):
            raise ValueError(f"{where}the {name!r} element declares a property twice")
        # the byte order is only known once the format line is read
        properties = [
            _Property(
                p.name,
                p.type_name,
                p.type.newbyteorder(order),
                None if p.count_type is None else p.count_type.newbyteorder(order),
            )
            for p in properties
        ]
        parsed.append(_Element(name, count, tuple(properties)))
    return fmt, parsed, position, line_number + 1


def _property(words: list[str], line: str, fmt, where: str) -> _Property:
    def known(name):
        if name not in TYPES:
            raise ValueError(f"{where}header line {line!r}: unknown PLY type {name!r}")
        return np.dtype(TYPES[name])

    if len(words) == 5 and words[1] == "list":
        count_type = known(words[2])
        if count_type.kind not in "iu":
            raise ValueError(f"{where}header line {line!r}: a list count must be an integer type")
        return _Property(words[4], words[3], known(words[3]), count_type)
    if len(words) == 3 and words[1] != "list":
        return _Property(words[2], words[1], known(words[1]))
    raise ValueError(f"{where}malformed PLY property line {line!r}")


# --- values ---------------------------------------------------------------------------------


def _typed(values: np.ndarray, prop: _Property, what, where: str) -> np.ndarray:
    """ASCII `values` as the property's declared type; whole numbers in range for integers."""
    if prop.type.kind in "iu":
        info = np.iinfo(prop.type)
        bad = ~((values == np.floor(values)) & (values >= info.min) & (values <= info.max))
        if bad.any():
            first = int(np.flatnonzero(bad)[0])
            raise ValueError(
                f"{where}{what(first)}: {prop.name} = {values[first]!r} is not a whole number "
                f"of the declared type {prop.type_name}"
            )
    return values.astype(prop.type.newbyteorder("="))


# --- ASCII ----------------------------------------------------------------------------------


@dataclass
class _Lines:
    """The non-empty lines of an ASCII body: token counts, first tokens, file line numbers."""

    values: np.ndarray  # every number of the body, in order
    tokens: np.ndarray  # numbers on each non-empty line
    first: np.ndarray  # index in `values` of each line's first number
    number: np.ndarray  # line number in the file
    unterminated: bool  # the last line has no line end


def _lines(body: bytes, first_line: int, where: str) -> _Lines:
    raw = np.frombuffer(body, dtype=np.uint8)
    space = (raw == 32) | ((raw >= 9) & (raw <= 13))
    starts = ~space
    starts[1:] &= space[:-1]
    newline = np.flatnonzero(raw == 10)
    line_start = np.concatenate([[0], newline + 1])
    line_start = line_start[line_start < len(raw)]
    if len(line_start):
        per_line = np.add.reduceat(starts, line_start, dtype=np.int64)
    else:
        per_line = np.zeros(0, dtype=np.int64)
    del space, starts
    unterminated = _ends_without_newline(body)
    kept = np.flatnonzero(per_line)
    tokens = per_line[kept]
    total = int(tokens.sum())
    values = np.zeros(0)
    if total:
        try:
            values = np.fromstring(body, sep=" ")
        except ValueError:
            values = None
    if values is None or len(values) != total:
        _not_a_number(body, first_line, where)
    return _Lines(values, tokens, np.cumsum(tokens) - tokens, kept + first_line, unterminated)


def _ends_without_newline(body: bytes) -> bool:
    """Whether the last number of `body` has no line end after it (a cut may have shortened it)."""
    end = len(body)
    while end > 0 and body[end - 1] in b" \t\r\x0b\x0c\n":
        if body[end - 1] == 10:
            return False
        end -= 1
    return end > 0


def _not_a_number(body: bytes, first_line: int, where: str):
    for number, line in enumerate(body.split(b"\n"), start=first_line):
        for word in line.split():
            try:
                float(word)
            except ValueError:
                text = word.decode("latin-1")
                raise ValueError(f"{where}line {number}: {text!r} is not a number") from None
    raise ValueError(f"{where}the data holds text that is not a number")


def _ascii_layout(element: _Element, lines: _Lines, start: int, stop: int):
    """For the lines ``start:stop`` read as rows of `element`.

    Returns whether each line fits the element, whether it ends too early (a
    row cut short), and per property the offset of its first number in the row
    and, for lists, each row's count.
    """
    tokens = lines.tokens[start:stop]
    first = lines.first[start:stop]
    if not any(p.is_list for p in element.properties):
        width = len(element.properties)
        offsets = {p.name: j for j, p in enumerate(element.properties)}
        return tokens == width, tokens < width, offsets, {}
    position = np.zeros(len(tokens), dtype=np.int64)
    fits = np.ones(len(tokens), dtype=bool)
    short = np.zeros(len(tokens), dtype=bool)
    offsets, counts = {}, {}
    for prop in element.properties:
        offsets[prop.name] = position.copy()
        if not prop.is_list:
            position += 1
            continue
        inside = position < tokens
        short |= ~inside
        count = lines.values[first + np.where(inside, position, 0)] if len(tokens) else tokens
        info = np.iinfo(prop.count_type)
        valid = inside & (count == np.floor(count)) & (count >= max(info.min, 0))
        valid &= count <= info.max
        fits &= valid
        count = np.where(valid, count, 0).astype(np.int64)
        counts[prop.name] = count
        position += 1 + count
    short |= position > tokens
    fits &= position == tokens
    return fits, short, offsets, counts


def _census(elements, lines: _Lines) -> list[int] | None:
    """How many rows of each element the lines hold, read greedily; None if they do not fit."""
    found, row = [], 0
    for element in elements:
        fits = _ascii_layout(element, lines, row, len(lines.tokens))[0]
        run = int(np.argmin(fits)) if not fits.all() else len(fits)
        found.append(run)
        row += run
    return found if row == len(lines.tokens) else None


def _raise_if_counts_differ(elements, lines: _Lines, where: str, declared: str) -> None:
    """Raise naming declared and found counts if the lines fit the elements in other counts."""
    census = _census(elements, lines)
    if census is not None:
        raise ValueError(
            f"{where}the header declares {declared}, but the data holds "
            f"{_describe(elements, census)}"
        )


def _read_ascii(
    body: bytes, elements, first_line: int, wanted: dict, where: str, exact: tuple = ()
) -> dict:
    """The wanted properties of every element; floating properties named ``(element, name)``
    in `exact` are kept as parsed from the text (float64), not rounded to their declared type.
    """
    lines = _lines(body, first_line, where)
    n_lines = len(lines.tokens)
    declared = _describe(elements)
    out, row = {}, 0
    for index, element in enumerate(elements):
        stop = min(row + element.count, n_lines)
        fits, short, offsets, counts = _ascii_layout(element, lines, row, stop)
        unended = lines.unterminated and stop == n_lines and stop > row and bool(fits[-1])
        if unended:
            fits[-1] = False  # the last number may be cut short
            short[-1] = True
        bad = np.flatnonzero(~fits)
        if len(bad) or stop - row < element.count:
            failed = int(bad[0]) if len(bad) else stop - row
            at_end = row + failed >= n_lines - 1 and (failed == stop - row or short[failed])
            if at_end:
                found = [e.count for e in elements[:index]] + [failed]
                found += [0] * (len(elements) - index - 1)
                why = ""
                if unended and failed == stop - row - 1:
                    why = " (its last line has no line end: its last number may be cut short)"
                raise ValueError(
                    f"{where}truncated: the header declares {declared}; the data ends after "
                    f"{_describe(elements, found)}{why}"
                )
            _raise_if_counts_differ(elements, lines, where, declared)
            raise ValueError(
                f"{where}line {lines.number[row + failed]} (row {failed + 1} of the "
                f"{element.noun(element.count)}) holds {lines.tokens[row + failed]} numbers, "
                f"which do not make a {element.name} as the header describes it (the header "
                f"declares {declared})"
            )
        first = lines.first[row:stop]
        out[element.name] = {}
        for name in wanted.get(element.name, ()):
            prop = element.find(name)
            offset = first + offsets[name]

            def what(i, element=element, row=row):
                return f"line {lines.number[row + i]} ({element.name} {i}, counting from 0)"

            if not prop.is_list:
                values = lines.values[offset]
                if (element.name, name) in exact and prop.type.kind == "f":
                    out[element.name][name] = values  # float64 from the decimal text
                else:
                    out[element.name][name] = _typed(values, prop, what, where)
                continue
            count = counts[name]
            flat_start = np.cumsum(count) - count
            within = np.arange(int(count.sum())) - np.repeat(flat_start, count)
            flat = lines.values[np.repeat(offset + 1, count) + within]
            face_of = np.repeat(np.arange(len(count)), count)
            out[element.name][name] = (
                count,
                _typed(flat, prop, lambda i, f=face_of, w=what: w(int(f[i])), where),
            )
        row = stop
    if row < n_lines:
        _raise_if_counts_differ(elements, lines, where, declared)
        raise ValueError(
            f"{where}the header declares {declared}, but {plural(n_lines - row, 'more line')} "
            f"of data {'follows' if n_lines - row == 1 else 'follow'} them (from line "
            f"{lines.number[row]})"
        )
    return out


# --- binary ---------------------------------------------------------------------------------


@njit(cache=True)
def _row_starts(buf, position, rows, is_list, size, item, signed, big, starts):  # pragma: no cover
    """Byte offset of each row (and of the end) of an element with lists of any length.

    The offsets go to ``starts`` (``rows + 1`` zeros, from the caller: a
    returned array would be boxed with a little Python code, where a Ctrl-C
    that arrived meanwhile would be raised and crash the caller).  Returns a
    status: ``rows`` when every row is there; ``0 <= status < rows`` when the
    data ends inside row ``status``; ``-1 - r`` when row ``r`` has a negative
    list count.
    """
    end = len(buf)
    for r in range(rows):
        starts[r] = position
        for p in range(len(is_list)):
            if not is_list[p]:
                position += size[p]
                continue
            width = size[p]
            if position + width > end:
                return r
            count = np.int64(0)
            for k in range(width):
                byte = np.int64(buf[position + (k if big else width - 1 - k)])
                count = count * 256 + byte
            if signed[p] and width < 8 and count >= (np.int64(1) << (8 * width - 1)):
                count -= np.int64(1) << (8 * width)
            if count < 0:
                return -1 - r
            position += width + count * item[p]
        if position > end:
            return r
    starts[rows] = position
    return rows


def _gather(raw: np.ndarray, offsets: np.ndarray, dtype: np.dtype) -> np.ndarray:
    """Values of `dtype` at the byte `offsets` of `raw`."""
    index = offsets[:, None] + np.arange(dtype.itemsize)
    return np.ascontiguousarray(raw[index]).view(dtype).reshape(len(offsets))


def _read_binary(body: bytes, elements, big: bool, wanted: dict, where: str) -> dict:
    raw = np.frombuffer(body, dtype=np.uint8)
    declared = _describe(elements)
    out, position = {}, 0

    def truncated(index, rows):
        found = [e.count for e in elements[:index]] + [rows] + [0] * (len(elements) - index - 1)
        return ValueError(
            f"{where}truncated: the header declares {declared}; the data ends after "
            f"{_describe(elements, found)} ({len(body)} bytes of data)"
        )

    for index, element in enumerate(elements):
        names = wanted.get(element.name, ())
        out[element.name] = {}
        if not element.properties or element.count == 0:
            continue
        if not any(p.is_list for p in element.properties):
            dtype = np.dtype([(p.name, p.type) for p in element.properties])
            if len(body) - position < element.count * dtype.itemsize:
                raise truncated(index, (len(body) - position) // dtype.itemsize)
            table = np.frombuffer(body, dtype=dtype, count=element.count, offset=position)
            position += element.count * dtype.itemsize
            for name in names:
                out[element.name][name] = table[name]
            continue
        data, position = _binary_lists(body, raw, element, position, big, names, index, truncated)
        if isinstance(data, str):
            raise ValueError(f"{where}{data} (the header declares {declared})")
        out[element.name] = data
    if position != len(body):
        raise ValueError(
            f"{where}the header declares {declared}, but {plural(len(body) - position, 'byte')} "
            f"of data {'follows' if len(body) - position == 1 else 'follow'} them: the counts "
            "do not match the data"
        )
    return out


def _binary_lists(body, raw, element, position, big, names, index, truncated):
    """Read an element with list properties: one frombuffer if every row is alike."""
    # the first row decides the list lengths; every row is checked against them
    fields, cursor, lengths = [], position, {}
    for j, prop in enumerate(element.properties):
        if prop.is_list:
            if cursor + prop.count_type.itemsize > len(body):
                raise truncated(index, 0)
            count = int(np.frombuffer(body, prop.count_type, 1, cursor)[0])
            if count < 0:
                return f"{element.name} 0 has a list of {count} {prop.name}", position
            lengths[prop.name] = count
            fields += [(f"n{j}", prop.count_type), (f"v{j}", prop.type, (count,))]
            cursor += prop.count_type.itemsize + count * prop.type.itemsize
        else:
            fields.append((f"v{j}", prop.type))
            cursor += prop.type.itemsize
    dtype = np.dtype(fields)
    rows = min(element.count, (len(body) - position) // dtype.itemsize)
    table = np.frombuffer(body, dtype=dtype, count=rows, offset=position)
    alike = np.ones(rows, dtype=bool)
    for j, prop in enumerate(element.properties):
        if prop.is_list:
            alike &= table[f"n{j}"] == lengths[prop.name]
    if rows == element.count and alike.all():
        data = {}
        for j, prop in enumerate(element.properties):
            if prop.name in names:
                column = table[f"v{j}"]
                if prop.is_list:
                    count = np.full(rows, lengths[prop.name], dtype=np.int64)
                    kind = np.int64 if column.dtype.kind in "iu" else column.dtype
                    data[prop.name] = (count, column.astype(kind).reshape(-1))  # one copy
                else:
                    data[prop.name] = column
        return data, position + rows * dtype.itemsize
    # rows of different lengths: find where each row starts, then gather
    is_list = np.array([p.is_list for p in element.properties])
    size = np.array([(p.count_type if p.is_list else p.type).itemsize for p in element.properties])
    item = np.array([p.type.itemsize for p in element.properties])
    signed = np.array([p.is_list and p.count_type.kind == "i" for p in element.properties])
    starts = np.zeros(element.count + 1, dtype=np.int64)
    status = _row_starts(raw, position, element.count, is_list, size, item, signed, big, starts)
    if 0 <= status < element.count:
        raise truncated(index, int(status))
    if status < 0:
        return f"{element.name} {-1 - status} has a negative list count", position
    offset = starts[:-1].copy()
    data = {}
    for prop in element.properties:
        if not prop.is_list:
            if prop.name in names:
                data[prop.name] = _gather(raw, offset, prop.type)
            offset += prop.type.itemsize
            continue
        count = _gather(raw, offset, prop.count_type).astype(np.int64)
        offset += prop.count_type.itemsize
        if prop.name in names:
            flat_start = np.cumsum(count) - count
            within = np.arange(int(count.sum())) - np.repeat(flat_start, count)
            at = np.repeat(offset, count) + within * prop.type.itemsize
            data[prop.name] = (count, _gather(raw, at, prop.type))
        offset += count * prop.type.itemsize
    return data, int(starts[-1])


# --- the mesh -------------------------------------------------------------------------------


def _triangles(count: np.ndarray, flat: np.ndarray) -> np.ndarray:
    """Polygons (``count[i]`` indices each, concatenated in `flat`) as triangles, trimesh's way."""
    if len(count) and (count == count[0]).all():
        rows = flat.reshape(len(count), int(count[0]))
        if count[0] == 3:
            return rows
        if count[0] == 4:
            return np.vstack([rows[:, [0, 1, 2]], rows[:, [2, 3, 0]]])
    start = np.cumsum(count) - count
    tri = flat[start[count == 3, None] + np.arange(3)]
    quad = flat[start[count == 4, None] + np.arange(4)]
    big = count >= 5
    fan_count = count[big] - 2
    corner = np.repeat(start[big], fan_count)
    step = np.arange(int(fan_count.sum())) - np.repeat(np.cumsum(fan_count) - fan_count, fan_count)
    fans = np.column_stack([flat[corner], flat[corner + step + 1], flat[corner + step + 2]])
    return np.vstack([tri, quad[:, [0, 1, 2]], quad[:, [2, 3, 0]], fans]).reshape(-1, 3)


_NOT_REGULAR = (
    (stat.S_ISFIFO, "a FIFO"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
    (stat.S_ISDIR, "a directory"),
)


def check_regular(status: os.stat_result, path: str) -> None:
    """Raise ``ValueError`` unless `status` (of `path`) is a regular file's.

    A FIFO blocks its reader until something writes to it, and a device such
    as ``/dev/zero`` never ends; both have a size of 0, and were called empty.
    """
    if stat.S_ISREG(status.st_mode):
        return
    kind = next((name for test, name in _NOT_REGULAR if test(status.st_mode)), "not a file")
    raise ValueError(f"{path!r} is not a regular file ({kind}): give a mesh file")


def open_regular(path: str):
    """Open `path` for reading in binary, refusing what is not a regular file; never blocks.

    Opened without blocking (a FIFO with no writer would wait for one), then
    checked on the open file itself (so a file swapped for a FIFO in between is
    refused too).

    Raises
    ------
    ValueError
        If it is a FIFO, a device, a socket or a directory.
    """
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0)
    descriptor = os.open(path, flags)
    try:
        check_regular(os.fstat(descriptor), path)
        if hasattr(os, "set_blocking"):
            os.set_blocking(descriptor, True)
        return os.fdopen(descriptor, "rb")
    except BaseException:
        os.close(descriptor)
        raise


def read_ply(path: str | os.PathLike, *, exact_text: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Read the vertices and triangles of a PLY file, strictly (see the module's notes).

    Parameters
    ----------
    path : str or path-like
    exact_text : bool, default False
        In an ASCII file, keep the vertex coordinates x, y, z as float64 parsed from their
        decimal text, as MorphoTester reads them, instead of rounding them to their declared
        type (``float`` is float32: ``40.711`` is read as ``40.71099853515625``).  Binary
        files are unaffected (their float32 values are widened exactly).  MorphoTester's
        DNE, RFI and outline area match its printed digits only when read this way.

    Returns
    -------
    vertices : (n, 3) float64
        Finite coordinates, as stored (no vertex merged or dropped).
    faces : (m, 3) int64
        Indices in ``[0, n)``; polygons cut into triangles as trimesh does.
        Empty when the file has no faces.

    Raises
    ------
    ValueError
        One line naming the file and the problem: not a PLY file, a malformed
        header, truncated data, counts that do not match the data, a value that
        is not a number, a face of fewer than 3 vertices, non-finite coordinates,
        or face indices outside the vertices.
    """
    path = os.fspath(path)
    with open_regular(path) as handle:
        data = handle.read()
    where = f"could not read mesh file {path!r}: "
    fmt, elements, offset, first_line = _header(data, where)
    vertex = next((e for e in elements if e.name == "vertex"), None)
    if vertex is None:
        raise ValueError(f"{where}the PLY header declares no vertex element")
    for axis in "xyz":
        prop = vertex.find(axis)
        if prop is None or prop.is_list:
            raise ValueError(f"{where}the vertex element has no property {axis} (a number)")
    wanted = {"vertex": ("x", "y", "z")}
    face = next((e for e in elements if e.name == "face"), None)
    if face is not None:
        lists = [p for p in face.properties if p.is_list]
        chosen = next((p for p in lists if p.name in _INDEX_NAMES), None)
        if chosen is None and len(lists) == 1:
            chosen = lists[0]
        if chosen is None:
            raise ValueError(f"{where}the face element has no vertex_indices list")
        if chosen.type.kind not in "iuf":
            raise ValueError(f"{where}the face indices are not numbers")
        wanted["face"] = (chosen.name,)
    body = memoryview(data)[offset:]
    if fmt == "ascii":
        exact = tuple(("vertex", axis) for axis in "xyz") if exact_text else ()
        read = _read_ascii(bytes(body), elements, first_line, wanted, where, exact)
    else:
        read = _read_binary(body, elements, fmt == "binary_big_endian", wanted, where)
    columns = read["vertex"]
    vertices = np.empty((len(columns["x"]), 3))
    for axis, name in enumerate("xyz"):
        vertices[:, axis] = columns[name]
    if face is None or face.count == 0:
        return vertices, np.zeros((0, 3), dtype=np.int64)
    if len(vertices) == 0:
        raise ValueError(f"{where}the file has {face.noun(face.count)} but no vertices")
    count, flat = read["face"][wanted["face"][0]]
    if flat.dtype.kind == "f":
        whole = np.isfinite(flat) & (flat == np.floor(flat))
        if not whole.all():
            first = int(np.repeat(np.arange(len(count)), count)[np.flatnonzero(~whole)[0]])
            raise ValueError(f"{where}face {first} has an index that is not a whole number")
    flat = flat.astype(np.int64, copy=False)
    few = np.flatnonzero(count < 3)
    if len(few):
        indices = plural(int(count[few[0]]), "vertex index", "vertex indices")
        raise ValueError(
            f"{where}face {few[0]} has {indices}; a face needs at least 3 "
            f"({plural(len(few), 'face')} like this; the header declares {_describe(elements)})"
        )
    where = f"{path!r}: "
    check_finite(vertices, where=where)
    if (count == 3).all():
        check_indices(flat.reshape(-1, 3), len(vertices), where=where)
    else:  # check the polygons as the file numbers them
        outside = (flat < 0) | (flat >= len(vertices))
        if outside.any():
            bad = np.unique(np.repeat(np.arange(len(count)), count)[outside])
            start = int(count[: bad[0]].sum())
            indices = flat[start : start + count[bad[0]]]
            raise ValueError(
                index_message(len(bad), int(bad[0]), indices, len(vertices), where=where)
            )
    return vertices, _triangles(count, flat)
