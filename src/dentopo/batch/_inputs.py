"""Finding mesh files: explicit files, directories (recursively) and glob patterns.

Turns what a user types (``scans/``, ``"scans/**/*.ply"``, ``tooth.obj``) into
a sorted list of mesh files, each once.  Directories are searched recursively
for the mesh formats trimesh reads; hidden files and folders and this tool's
own outputs are skipped there.  A file named explicitly is always kept (if it
turns out not to be a mesh, its row in the batch says so).
"""

from __future__ import annotations

import glob
import os
import warnings
from collections.abc import Iterable
from dataclasses import dataclass, field

from ..formats import OUTPUT_SUFFIX

#: Mesh formats searched for in directories (when trimesh can read them).
MESH_EXTENSIONS = ("ply", "obj", "stl", "off", "glb", "gltf", "3mf", "dae")
#: The formats trimesh reads only with a package that dentopo does not install.
FORMAT_PACKAGES = {"dae": "pycollada"}

_GLOB_CHARACTERS = frozenset("*?[")


@dataclass
class FoundInputs:
    """The outcome of :func:`find_mesh_files`.

    Attributes
    ----------
    files : list of str
        Mesh files, sorted, each once (paths as the user wrote them, or joined
        onto the directory the user gave).
    unmatched : list of str
        Patterns or directories that yielded no mesh file (for a message).
    """

    files: list[str] = field(default_factory=list)
    unmatched: list[str] = field(default_factory=list)


def mesh_extensions() -> tuple[str, ...]:
    """Extensions (lower case, no dot) of the mesh formats searched for in directories."""
    import trimesh  # only here: files named one by one are not asked of trimesh (0.5 s)

    readable = set(trimesh.available_formats())
    return tuple(ext for ext in MESH_EXTENSIONS if ext in readable)


def is_own_output(path: str) -> bool:
    """True for a per-vertex file written by this tool (``*.dentopo.ply`` / ``.csv``)."""
    stem = os.path.splitext(os.path.basename(path))[0]
    return stem.endswith(OUTPUT_SUFFIX)


#: A file that marks a folder as this tool's own output (``dentopo app``'s): folders searched
#: for meshes skip a subfolder holding it, so that prepared copies are not measured as scans.
OUTPUT_FOLDER_MARK = ".dentopo-output"


def is_own_output_folder(path: str) -> bool:
    """True for a folder this tool writes its outputs into (it holds :data:`OUTPUT_FOLDER_MARK`)."""
    return os.path.isfile(os.path.join(path, OUTPUT_FOLDER_MARK))


def _is_hidden(name: str) -> bool:
    return name.startswith(".")


def _search_directory(
    directory: str, extensions: tuple[str, ...], skipped: dict[str, set[str]] | None = None
) -> list[str]:
    """Mesh files below `directory`; `skipped` collects the files of unreadable formats."""
    found = []
    for root, dirnames, filenames in os.walk(directory, followlinks=False):
        dirnames[:] = sorted(
            d
            for d in dirnames
            if not _is_hidden(d) and not is_own_output_folder(os.path.join(root, d))
        )
        for name in filenames:
            ext = os.path.splitext(name)[1][1:].lower()
            if _is_hidden(name) or ext not in extensions:
                if skipped is not None and not _is_hidden(name) and ext in FORMAT_PACKAGES:
                    skipped.setdefault(ext, set()).add(_key(os.path.join(root, name)))
                continue
            path = os.path.join(root, name)
            if not is_own_output(path):
                found.append(path)
    return found


def _key(path: str) -> str:
    """Identity of a file for de-duplication (symlinks and ``..`` resolved)."""
    return os.path.normcase(os.path.realpath(path))


def find_mesh_files(inputs: Iterable[str | os.PathLike]) -> FoundInputs:
    """Expand files, directories and glob patterns into a sorted list of mesh files.

    Parameters
    ----------
    inputs : iterable of str or path-like
        Each is a file (kept whatever its extension), a directory (searched
        recursively for the formats in :func:`mesh_extensions`, skipping
        hidden entries, ``*.dentopo.*`` outputs and the subfolders
        ``dentopo app`` writes into) or, if no such path
        exists, a shell-style glob pattern (``**`` matches nested folders).
        A path that exists neither as a file nor as a pattern is kept as a
        file, so that the batch reports it as not found.

    Returns
    -------
    FoundInputs
        ``files`` sorted and free of duplicates (the same file reached twice,
        also through a symbolic link, is listed once), and ``unmatched``.

    Warns
    -----
    UserWarning
        Once per format, when a directory holds files of a format searched for
        that trimesh cannot read here (``.dae`` without pycollada): they are
        skipped, and the warning names the package that reads them.
    """
    extensions: tuple[str, ...] | None = None  # asked of trimesh for the first folder searched
    skipped: dict[str, set[str]] = {}  # files of a format trimesh cannot read, by extension
    candidates: list[str] = []
    unmatched: list[str] = []
    for item in inputs:
        path = os.fspath(item)
        if os.path.isdir(path):
            extensions = mesh_extensions() if extensions is None else extensions
            files = _search_directory(path, extensions, skipped)
            if not files:
                unmatched.append(path)
            candidates.extend(files)
        elif os.path.lexists(path) or not (_GLOB_CHARACTERS & set(path)):
            candidates.append(path)
        else:
            files = []
            for match in sorted(glob.glob(path, recursive=True)):
                if os.path.isdir(match):
                    extensions = mesh_extensions() if extensions is None else extensions
                    files.extend(_search_directory(match, extensions, skipped))
                elif not _is_hidden(os.path.basename(match)) and not is_own_output(match):
                    files.append(match)
            if not files:
                unmatched.append(path)
            candidates.extend(files)
    for ext, paths in skipped.items():  # once per format, not once per file or folder
        count = len(paths)
        files = "a .{0} file" if count == 1 else f"{count} .{{0}} files"
        warnings.warn(
            f"{files.format(ext)} skipped in the folders searched: reading .{ext} needs "
            f"{FORMAT_PACKAGES[ext]} (pip install {FORMAT_PACKAGES[ext]})",
            UserWarning,
            stacklevel=2,
        )
    chosen: dict[str, str] = {}  # one spelling per file: the shortest ("a.ply", not "./a.ply")
    for path in sorted(candidates, key=lambda p: (len(p), p)):
        chosen.setdefault(_key(path), path)
    return FoundInputs(files=sorted(chosen.values()), unmatched=unmatched)
