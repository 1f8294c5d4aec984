"""Every example in README.md and docs/**/*.md runs, as a reader would run it.

The gallery's scripts (examples/gallery/plot_*.py, which the docs build runs in
its own process) are run here too, each as ``python FILE`` in an empty folder.

Each fenced block of a page is one test, named ``PAGE:LINE`` (the fence's line):

- ``python`` blocks run as a script in a fresh interpreter (this one, with this
  checkout's ``src`` first on the path);
- ``bash``, ``sh``, ``shell`` and ``console`` blocks (``$ `` prompts in a console
  block) run their commands that start with ``dentopo`` or ``python``, each
  through bash with ``pipefail``: ``dentopo`` is ``python -m dentopo`` with this
  interpreter, ``python``/``python3`` this interpreter, and the interpreter's own
  bin directory (``dentopo`` installed beside it) comes first on the ``PATH`` for
  the rest of a line (after a pipe, say).  Other commands (``ls``, ``dask worker``)
  are not run.  A block that installs (``pip``, ``python3 -m venv``, ``git clone``,
  ``R CMD INSTALL`` ...) is skipped with the reason "installs": the README's first
  two commands, which do, are run by CI itself (tests/test_readme.py);
- ``r`` and ``matlab`` blocks are skipped: the bridges are tested by
  tests/test_bridges.py.  Blocks of other languages (``text``, ``csv``, none) are
  not examples and are not collected.

Every command must exit 0, and print no traceback on stderr whatever its status:
a script whose worker processes fail prints their tracebacks and may still exit
0 (a report without pictures).  The blocks of one page run in page order in one
working directory, so that a block can read what an earlier one wrote
(``results.csv``, then the report); running one block alone (``-k``) first runs the
blocks above it.  The directory holds the bundled sample meshes (``tooth.ply``,
``sphere.ply``, ``saddle.ply``) and copies of the shared meshes
(``../shared/data/meshes``) as ``crowns/`` and ``scans/``, and MorphoTester's sample
crowns (``../shared/data/morphotester``) as ``morphotester/``: copies, so that an
example writing beside them never touches the shared data.  A block that names
``crowns``, ``scans`` or ``morphotester/`` is skipped, saying so, where the shared
data is absent.

Markers, each on its own line directly before a block (several may be stacked):

- ``<!-- example: skip (REASON) -->``: not run; the test is skipped with REASON
  (``<!-- not run: REASON -->``, the signDNE migration page's form, is the same);
- ``<!-- example: exit N -->``: every command of the block (or the script) exits
  with status N, as the page says it does;
- ``<!-- example: file NAME -->``: the block is the content of the file NAME
  (a ``groups.csv`` a reader would type): it is written into the working
  directory when its turn comes, and is not a test of its own;
- ``<!-- example: slow -->``: the block takes more than 30 s (``-m "not slow"``).
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from conftest import MESHES, SHARED

MORPHOTESTER = SHARED / "data" / "morphotester"

ROOT = Path(__file__).resolve().parents[1]
PYTHON = sys.executable
TIMEOUT = 1800  # seconds per command: a hang fails the test instead of the run

SHELL_LANGUAGES = {"bash", "sh", "shell", "console"}
PYTHON_LANGUAGES = {"python", "py"}
BRIDGE_LANGUAGES = {"r", "matlab", "octave"}

_FENCE = re.compile(r"^(?P<indent>[ \t]*)(?P<fence>`{3,}|~{3,})\s*(?P<lang>[^\s`{]*)")
_MARKER = re.compile(
    r"^\s*<!--\s*(?:example:\s*(?P<example>.*?)|not run:\s*(?P<not_run>.*?))\s*-->\s*$"
)
_SKIP = re.compile(r"skip\s*\((?P<reason>.+)\)")
_EXIT = re.compile(r"exit\s+(?P<status>\d+)")
_FILE = re.compile(r"file\s+(?P<name>\S+)")
_SHARED_NAMES = re.compile(r"(?<![\w./-])(crowns|scans)(?![\w.-])")
#: MorphoTester's sample crowns (``../shared/data/morphotester``), copied as ``morphotester/``.
_MORPHOTESTER_FOLDER = re.compile(r"(?<![\w./-])morphotester/")
_INSTALLS = re.compile(
    r"^\s*(\S*/)?(pip3?|pipx|conda|mamba|apt|apt-get|brew)\s+install\b"
    r"|^\s*(\S*/)?python3?\s+-m\s+(venv|pip)\b"
    r"|^\s*git\s+clone\b"
    r"|^\s*R\s+CMD\s+INSTALL\b"
    r"|install\.packages\("
)
_TRACEBACK = "Traceback (most recent call last)"
_RUNS_THE_SUITE = re.compile(r"^\s*(\S*/)?python3?\s+-m\s+pytest\b|^\s*pytest\b")


@dataclass
class Block:
    page: str  # relative to the repository
    line: int  # of the opening fence, 1-based
    lang: str
    code: str
    skip: str | None = None
    exit_status: int = 0
    file: str | None = None
    slow: bool = False
    problems: list[str] = field(default_factory=list)  # markers not understood

    @property
    def id(self) -> str:
        return f"{self.page}:{self.line}"


def pages() -> list[Path]:
    return [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]


def _apply_marker(block: Block, text: str) -> None:
    for part in (p.strip() for p in text.split(",")):
        if m := _SKIP.fullmatch(part):
            block.skip = m["reason"].strip()
        elif m := _EXIT.fullmatch(part):
            block.exit_status = int(m["status"])
        elif m := _FILE.fullmatch(part):
            block.file = m["name"]
        elif part == "slow":
            block.slow = True
        else:
            block.problems.append(f"{block.id}: marker {part!r} not understood")


def page_blocks(path: Path, root: Path = ROOT) -> list[Block]:
    """Every fenced block of `path`, with the markers directly above it."""
    relative = path.relative_to(root).as_posix()
    lines = path.read_text(encoding="utf-8").splitlines()
    blocks = []
    markers: list[tuple[int, str | None, str | None]] = []
    i = 0
    while i < len(lines):
        m = _FENCE.match(lines[i])
        if m is None:
            marker = _MARKER.match(lines[i])
            if marker is not None:
                markers.append((i + 1, marker["example"], marker["not_run"]))
            elif lines[i].strip() and markers:
                markers.append((i + 1, None, None))  # text between a marker and a block
            i += 1
            continue
        indent, fence = len(m["indent"]), m["fence"]
        closing = re.compile(rf"^\s*{re.escape(fence[0])}{{{len(fence)},}}\s*$")
        end = i + 1
        while end < len(lines) and not closing.match(lines[end]):
            end += 1
        body = [
            line[indent:] if line[:indent].strip() == "" else line for line in lines[i + 1 : end]
        ]
        block = Block(relative, i + 1, m["lang"].lower(), "\n".join(body) + "\n")
        for line, example, not_run in markers:
            if example is None and not_run is None:
                block.problems.append(f"{relative}:{line}: text between a marker and its block")
            elif not_run is not None:
                block.skip = not_run
            else:
                _apply_marker(block, example)
        markers = []
        blocks.append(block)
        i = end + 1
    blocks += [
        Block(relative, line, "", "", problems=[f"{relative}:{line}: a marker before no block"])
        for line, example, not_run in markers
        if example or not_run
    ]
    return blocks


def is_example(block: Block) -> bool:
    return block.lang in SHELL_LANGUAGES | PYTHON_LANGUAGES | BRIDGE_LANGUAGES


def shell_commands(block: Block) -> list[str]:
    """The block's command lines: continuations joined, comments and console output left out."""
    commands, pending = [], ""
    for raw in block.code.splitlines():
        line = raw
        if block.lang == "console" and not pending:
            if not line.lstrip().startswith("$ "):
                continue  # the command's output
            line = line.lstrip()[2:]
        if line.rstrip().endswith("\\"):
            pending += line.rstrip()[:-1].strip() + " "
            continue
        line, pending = pending + line.strip(), ""
        if line.strip() and not line.lstrip().startswith("#"):
            commands.append(line.strip())
    return commands


def runnable(command: str) -> str | None:
    """`command` with ``dentopo``/``python`` made this interpreter, or None if not run here."""
    try:
        first = shlex.split(command, comments=True)[0]
    except (ValueError, IndexError):
        return None
    quoted = shlex.quote(PYTHON)
    rest = command.lstrip()[len(first) :]
    if first == "dentopo":
        return f"{quoted} -m dentopo{rest}"
    if first in ("python", "python3"):
        return f"{quoted}{rest}"
    return None


def why_not_run(block: Block) -> str | None:
    """The skip reason of `block`, or None if it runs."""
    if block.skip is not None:
        return block.skip
    if block.lang in BRIDGE_LANGUAGES:
        return f"{block.lang} block: the R and MATLAB bridges are tested by tests/test_bridges.py"
    if block.lang in SHELL_LANGUAGES:
        commands = shell_commands(block)
        if any(_INSTALLS.search(c) for c in commands):
            return "installs"
        if any(_RUNS_THE_SUITE.search(c) for c in commands):
            return "runs the test suite"
        if not any(runnable(c) for c in commands):
            return "no dentopo or python command"
    if block.lang in PYTHON_LANGUAGES and _INSTALLS.search(block.code):
        return "installs"
    if _SHARED_NAMES.search(block.code) and not MESHES.is_dir():
        return f"uses crowns/ or scans/, the shared meshes, not found at {MESHES}"
    if _MORPHOTESTER_FOLDER.search(block.code) and not MORPHOTESTER.is_dir():
        return f"uses morphotester/, MorphoTester's sample crowns, not found at {MORPHOTESTER}"
    return None


ALL_BLOCKS = [block for page in pages() for block in page_blocks(page)]
EXAMPLES = [block for block in ALL_BLOCKS if is_example(block) and block.file is None]


def test_every_marker_is_understood_and_stands_before_a_block():
    problems = [problem for block in ALL_BLOCKS for problem in block.problems]
    assert problems == []
    assert EXAMPLES, "no examples found in README.md and docs/"


def test_the_parser_finds_blocks_markers_and_commands(tmp_path):
    page = tmp_path / "page.md"
    page.write_text(
        "# T\n\n<!-- example: exit 1, slow -->\n```bash\ndentopo a.ply \\\n  -o x.csv  # c\n"
        "ls\n```\n\n  ```python\n  print(1)\n  ```\n<!-- example: skip (needs X) -->\n\n"
        "```console\n$ dentopo --version\ndentopo 0.3\n```\n<!-- example: file g.csv -->\n"
        "```csv\nfile,group\n```\n```text\nout\n```\n",
        encoding="utf-8",
    )
    bash, python, console, csv, text = page_blocks(page, root=tmp_path)
    assert (bash.line, bash.exit_status, bash.slow, bash.lang) == (4, 1, True, "bash")
    assert shell_commands(bash) == ["dentopo a.ply -o x.csv  # c", "ls"]
    assert runnable("ls") is None and runnable("dentopo a.ply").endswith(" -m dentopo a.ply")
    assert (python.line, python.code, python.skip) == (10, "print(1)\n", None)
    assert console.skip == "needs X" and shell_commands(console) == ["dentopo --version"]
    assert csv.file == "g.csv" and not is_example(text)
    assert [b.problems for b in (bash, python, console, csv, text)] == [[]] * 5


# ---------------------------------------------------------------------------
# running the blocks of a page in order, in one working directory per page


def _run_as_a_reader(argv: list[str], cwd) -> subprocess.CompletedProcess:
    """`argv` run in `cwd` as a reader would (no input, this checkout's ``dentopo``), captured."""
    return subprocess.run(
        argv,
        cwd=cwd,
        env=_environment(),
        stdin=subprocess.DEVNULL,
        capture_output=True,
        text=True,
        errors="replace",
        timeout=TIMEOUT,
    )


def _environment() -> dict[str, str]:
    env = dict(os.environ)
    env["PATH"] = os.path.dirname(PYTHON) + os.pathsep + env.get("PATH", "")
    source = str(ROOT / "src")
    env["PYTHONPATH"] = os.pathsep.join(p for p in (source, env.get("PYTHONPATH")) if p)
    env["MPLBACKEND"] = "Agg"
    for name in ("DISPLAY", "WAYLAND_DISPLAY", "DENTOPO_SCHEDULER"):  # no windows, no cluster
        env.pop(name, None)
    return env


def _prepare(directory: Path) -> None:
    from importlib.resources import files

    samples = files("dentopo.samples")
    for name in ("tooth.ply", "sphere.ply", "saddle.ply"):
        (directory / name).write_bytes(samples.joinpath(name).read_bytes())
    if MESHES.is_dir():
        for name in ("crowns", "scans"):
            shutil.copytree(MESHES, directory / name)
    if MORPHOTESTER.is_dir():
        folder = directory / "morphotester"
        folder.mkdir()
        for path in MORPHOTESTER.glob("*.ply"):
            shutil.copy(path, folder)


class Page:
    """One page's working directory and how far down the page its blocks have run."""

    def __init__(self, directory: Path, scripts: Path):
        self.directory, self.scripts, self.done = directory, scripts, -1
        _prepare(directory)

    def run(self, block: Block) -> list[str]:
        """Run `block`; the problems found (commands that exited otherwise than stated)."""
        if block.file is not None:
            (self.directory / block.file).write_text(block.code, encoding="utf-8")
            return []
        if block.lang in PYTHON_LANGUAGES:
            script = self.scripts / f"{Path(block.page).stem}_{block.line}.py"
            script.write_text(block.code, encoding="utf-8")
            return self._check(block, [PYTHON, str(script)], f"the script at {block.id}")
        problems = []
        for command in shell_commands(block):
            if (line := runnable(command)) is not None:
                problems += self._check(block, ["bash", "-o", "pipefail", "-c", line], command)
        return problems

    def _check(self, block: Block, argv: list[str], what: str) -> list[str]:
        try:
            done = _run_as_a_reader(argv, self.directory)
        except subprocess.TimeoutExpired:
            return [f"{block.id}: {what}: still running after {TIMEOUT} s"]
        if done.returncode != block.exit_status:
            return [
                f"{block.id}: {what}\n  exited {done.returncode}, the page says "
                f"{block.exit_status}; the end of its stderr:\n{_tail(done.stderr)}"
            ]
        if _TRACEBACK in _without_dask_shutdown_noise(done.stderr):
            return [
                f"{block.id}: {what}\n  exited {done.returncode} as the page says, but printed "
                f"a traceback; its stderr from there:\n"
                f"{_tail(done.stderr[done.stderr.index(_TRACEBACK) :])}"
            ]
        return []


#: The last exception of a traceback dask's worker logs when its heartbeat finds the scheduler
#: already closed as a ``LocalCluster`` shuts down: a race inside dask, not the example's.
_DASK_SHUTDOWN = re.compile(r"^distributed\.comm\.core\.CommClosedError: .*heartbeat")
_CHAINED = ("The above exception", "During handling of the above exception")


def _without_dask_shutdown_noise(stderr: str) -> str:
    """`stderr` without the tracebacks (chains included) that end in dask's shutdown race."""
    kept: list[str] = []
    chain: list[str] = []
    last_exception = None
    for line in [*stderr.splitlines(), ""]:
        if line.startswith((_TRACEBACK, *_CHAINED)):
            chain.append(line)
            last_exception = None  # a traceback (again): its exception is still to come
            continue
        if chain and (last_exception is None or not line.strip()):
            chain.append(line)  # a frame, a blank line, or the exception that ends the chain
            if last_exception is None and line.strip() and not line[0].isspace():
                last_exception = line
            continue
        if chain:  # the chain has ended
            if not (last_exception and _DASK_SHUTDOWN.match(last_exception)):
                kept.extend(chain)
            chain, last_exception = [], None
        kept.append(line)
    if not (last_exception and _DASK_SHUTDOWN.match(last_exception)):
        kept.extend(chain)  # a chain still open at the end
    return "\n".join(kept)


def _tail(text: str, limit: int = 3000) -> str:
    """The last whole lines of `text` within `limit` characters (a traceback's end)."""
    lines, size = [], 0
    for line in reversed(text.rstrip().splitlines()):
        size += len(line) + 1
        if size > limit and lines:
            break
        lines.append(line[-limit:])
    return "\n".join(reversed(lines))


@pytest.fixture(scope="session")
def page_dirs(tmp_path_factory):
    made: dict[str, Page] = {}

    def get(page: str) -> Page:
        if page not in made:
            root = tmp_path_factory.mktemp(re.sub(r"\W", "_", page))
            (root / "work").mkdir()
            (root / "scripts").mkdir()
            made[page] = Page(root / "work", root / "scripts")
        return made[page]

    return get


def _param(block: Block):
    return pytest.param(block, id=block.id, marks=[pytest.mark.slow] if block.slow else [])


@pytest.mark.parametrize("block", [_param(b) for b in EXAMPLES])
def test_example_runs(block, page_dirs):
    reason = why_not_run(block)
    if reason is not None:
        pytest.skip(f"{block.id}: {reason}")
    page = page_dirs(block.page)
    same_page = [b for b in ALL_BLOCKS if b.page == block.page]
    index = same_page.index(block)
    for earlier in same_page[page.done + 1 : index]:  # what this block may read
        if earlier.file is not None or (is_example(earlier) and why_not_run(earlier) is None):
            page.run(earlier)  # its own test reports its problems
    page.done = max(page.done, index)
    problems = page.run(block)
    assert problems == [], "\n".join(problems)


_DASK_RACE = """\
2026-12-04 21:30:00,000 - distributed.worker - ERROR - Failed to communicate with scheduler
Traceback (most recent call last):
  File ".../distributed/comm/tcp.py", line 226, in read
    frames_nosplit_nbytes_bin = await stream.read_bytes(fmt_size)
tornado.iostream.StreamClosedError: Stream is closed

The above exception was the direct cause of the following exception:

Traceback (most recent call last):
  File ".../distributed/worker.py", line 1165, in heartbeat
    response = await retry_operation(
distributed.comm.core.CommClosedError: in <TCP (closed) ConnectionPool.heartbeat_worker \
local=tcp://127.0.0.1:40504 remote=tcp://127.0.0.1:44729>: Stream is closed
"""

_OURS = """\
Traceback (most recent call last):
  File "script.py", line 3, in <module>
    write_report("results.csv")
ValueError: no row
"""


def test_only_dasks_shutdown_race_is_not_taken_for_an_examples_traceback():
    assert _TRACEBACK not in _without_dask_shutdown_noise(_DASK_RACE)
    assert "Failed to communicate" in _without_dask_shutdown_noise(_DASK_RACE)
    for text in (_OURS, _DASK_RACE + _OURS, _OURS + _DASK_RACE, _DASK_RACE.replace("heart", "")):
        assert _TRACEBACK in _without_dask_shutdown_noise(text)
    assert "ValueError: no row" in _without_dask_shutdown_noise(_DASK_RACE + _OURS)


GALLERY = sorted((ROOT / "examples" / "gallery").glob("plot_*.py"))


@pytest.mark.parametrize("script", GALLERY, ids=lambda path: path.name)
def test_a_gallery_example_runs_as_a_script(script, tmp_path):
    # the docs build runs them in its own process; a reader runs them with `python FILE`
    copy = tmp_path / script.name
    copy.write_text(script.read_text(encoding="utf-8"), encoding="utf-8")
    done = _run_as_a_reader([PYTHON, str(copy)], tmp_path)
    assert done.returncode == 0, f"{script.name} exited {done.returncode}:\n{_tail(done.stderr)}"
    assert _TRACEBACK not in done.stderr, _tail(done.stderr)


def test_the_gallery_has_examples():
    assert len(GALLERY) >= 5, GALLERY
