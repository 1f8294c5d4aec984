"""Hostile preparation protocols (issue 29, items 1, 2 and 7): refused in one line, or finite.

Every protocol value either passes the protocol check and gives a finite mesh,
or is refused naming the value: :class:`ProtocolError` from the library, exit 2
with one line from ``dentopo prepare`` and ``dentopo FILES --prepare P`` before
any file is read; a value the check cannot judge (a filter that diverges on
this mesh) fails the file with its parameters named, exit 1.  No written mesh
ever holds a non-finite coordinate.  Every protocol file is read or refused in
one line (nested too deeply, a control character in its name, a byte-order
mark), and whatever a protocol writes reads back the same.

The command runs go through ``main(argv)`` in one subprocess per group
(``faults.harness``): a traceback or a crash fails the case.
"""

from __future__ import annotations

import json
import os

import numpy as np
import pytest

from dentopo import prepare
from dentopo.batch import OUTPUT_FOLDER_MARK, find_mesh_files
from dentopo.mesh import read_ply
from dentopo.prepare import Protocol, ProtocolError, _pipeline, read_protocol
from dentopo.prepare._protocol import MAX_SMOOTH_ITERATIONS, parse_protocol
from dentopo.samples import tooth
from faults.harness import python


@pytest.fixture(scope="module")
def crown():
    mesh = tooth(rings=10)  # 331 vertices, 600 faces
    return np.array(mesh.vertices), np.array(mesh.faces)


@pytest.fixture
def raw(tmp_path):
    folder = tmp_path / "raw"
    folder.mkdir()
    tooth(rings=10).export(folder / "tooth.ply")
    return folder


#: Values the check refuses: (protocol changes, the name the message must hold).
REFUSED = [
    ({"smooth": "laplacian", "smooth_step": 5.0, "smooth_iterations": 200}, "smooth_step"),
    ({"smooth": "laplacian", "smooth_step": 1.5}, "smooth_step"),
    ({"smooth": "hc", "smooth_step": 1e300}, "smooth_step"),
    ({"smooth": "hc", "smooth_mu": 1e300}, "smooth_mu"),
    ({"smooth": "taubin", "smooth_step": 1e200}, "smooth_step"),
    ({"smooth": "taubin", "smooth_mu": 2.0}, "smooth_mu"),
    ({"smooth": "implicit", "smooth_step": 1e300}, "smooth_step"),
    ({"smooth": "laplacian", "smooth_iterations": 10**9}, "smooth_iterations"),
    ({"crop_plane": (1.7e308, 1.7e308, 0.0, 1.0, 1.0, 0.0)}, "crop_plane"),
    ({"smooth": "laplacian", "smooth_step": 1.0 + 2**-40}, "smooth_step"),
]

#: Directions whose components overflow or underflow when squared, and the plain direction
#: each names: the same prepared mesh, finite.
SAME_DIRECTION = [
    ({"up": (1e308, 1e308, 1e308)}, {"up": (1.0, 1.0, 1.0)}),
    ({"up": (5e-324, 0.0, 0.0)}, {"up": (1.0, 0.0, 0.0)}),
    ({"up": tuple(x * 5e-324 for x in (-10.0, 3.0, 20.0))}, {"up": (-10.0, 3.0, 20.0)}),
    (
        {"crop_plane": (0.0, 0.0, 0.0, 5e-324, 0.0, 0.0)},
        {"crop_plane": (0.0, 0.0, 0.0, 1.0, 0.0, 0.0)},
    ),
    (
        {"crop_plane": (0.0, 0.0, 0.0, 1e308, 1e308, 0.0)},
        {"crop_plane": (0.0, 0.0, 0.0, 1.0, 1.0, 0.0)},
    ),
]

#: Values the check passes but on which the filter diverges on this crown (checked after).
DIVERGING = [
    ({"smooth": "taubin", "smooth_step": 0.1, "smooth_mu": 1.0, "smooth_iterations": 1000}, "mu 1"),
    ({"smooth": "hc", "smooth_step": 0.1, "smooth_mu": 0.01, "smooth_iterations": 1000}, "mu 0.01"),
]


# --- the library -----------------------------------------------------------------------------


@pytest.mark.parametrize(("changes", "named"), REFUSED)
def test_a_value_that_would_break_a_step_is_refused_by_the_check_naming_it(changes, named):
    with pytest.raises(ProtocolError, match=named) as caught:
        Protocol(**changes)
    assert "\n" not in str(caught.value)


@pytest.mark.parametrize(("hostile", "plain"), SAME_DIRECTION)
def test_a_direction_that_overflows_when_squared_is_the_direction_it_names(crown, hostile, plain):
    got = prepare(crown, **hostile)
    want = prepare(crown, **plain)
    assert np.isfinite(got.vertices).all() and np.isfinite(got.transform).all()
    np.testing.assert_allclose(got.vertices, want.vertices, rtol=0, atol=1e-12)


@pytest.mark.parametrize(("changes", "named"), DIVERGING)
def test_a_filter_that_diverges_fails_naming_its_parameters(crown, changes, named):
    with pytest.raises(ValueError, match="diverged") as caught:
        prepare(crown, **changes)
    assert f"step 0.1, {named}" in str(caught.value) and "1000 iterations" in str(caught.value)


def test_the_laplacian_step_is_bounded_where_it_cannot_diverge(crown):
    with pytest.raises(ProtocolError, match="smooth_step must be at most 1 for laplacian"):
        Protocol(smooth="laplacian", smooth_step=1.0 + 2**-40)
    done = prepare(
        crown, smooth="laplacian", smooth_step=1.0, smooth_iterations=MAX_SMOOTH_ITERATIONS
    )
    assert np.isfinite(done.vertices).all()
    assert np.ptp(done.vertices, axis=0).max() <= np.ptp(crown[0], axis=0).max() * (1 + 1e-12)


@pytest.mark.parametrize("step", ["clean", "orient", "crop", "decimate", "smooth"])
def test_no_step_can_hand_on_a_non_finite_mesh(crown, monkeypatch, step):
    module = getattr(_pipeline, f"_{step}")
    real = module.run

    def broken(vertices, faces, **options):
        outcome = real(vertices, faces, **options)
        bad = np.array(outcome.vertices, dtype=np.float64)
        bad[len(bad) // 2, 1] = np.nan
        return type(outcome)(bad, outcome.faces, outcome.transform, outcome.plane)

    monkeypatch.setattr(module, "run", broken)
    options = {"crop_fraction": 0.9, "faces": 400, "smooth": "taubin"}
    with pytest.raises(ValueError, match=f"the {step} step .*non-finite") as caught:
        prepare(crown, **options)
    assert "\n" not in str(caught.value)


def test_a_crop_above_everything_says_where_the_mesh_and_the_plane_lie(crown):
    with pytest.raises(ValueError, match="removes the whole mesh") as caught:
        prepare(crown, crop_below=1e308)
    text = str(caught.value)
    assert "-1e+308 to -1e+308" not in text
    assert "the plane lies at 1e+308" in text


# --- protocol files --------------------------------------------------------------------------


def _nested(depth: int, kind: str) -> str:
    if kind == "arrays":
        return "name = " + "[" * depth + "]" * depth + "\n"
    return "name = " + "{a = " * depth + "1" + "}" * depth + "\n"


@pytest.mark.parametrize("kind", ["arrays", "tables"])
def test_a_protocol_nested_too_deeply_is_refused_in_one_line(tmp_path, kind):
    path = tmp_path / "deep.toml"
    path.write_text(_nested(50_000, kind), encoding="utf-8")
    with pytest.raises(ProtocolError, match="nest too deeply") as caught:
        read_protocol(path)
    assert "deep.toml" in str(caught.value) and "\n" not in str(caught.value)


def test_a_nested_value_is_named_in_a_short_message():
    with pytest.raises(ProtocolError, match="name must be a text") as caught:
        parse_protocol(_nested(300, "arrays"))
    assert len(str(caught.value)) < 200


def test_a_byte_order_mark_is_read_past(tmp_path):
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + b'name = "bom"\n[decimate]\nfaces = 1000\n')
    protocol = read_protocol(path)
    assert protocol.name == "bom" and protocol.faces == 1000


@pytest.mark.parametrize("escape", ["\\u007F", "\\u0000", "\\u001B", "\\n", "\\u0085", "\\u2028"])
def test_a_name_with_a_control_character_is_refused_naming_it(tmp_path, escape):
    path = tmp_path / "p.toml"
    path.write_text(f'name = "a{escape}b"\n', encoding="utf-8")
    with pytest.raises(ProtocolError, match=r"name must not hold .* U\+") as caught:
        read_protocol(path)
    assert "\n" not in str(caught.value)


#: Hostile texts: every ASCII control character, quotes, backslashes, TOML's own syntax,
#: lone surrogates, non-characters, a very long text.
HOSTILE = [
    *(f"a{chr(code)}b" for code in [*range(0x20), 0x7F, 0x80, 0x85, 0x9F]),
    'say "hi"',
    "back\\slash\\",
    "\\u0041 is not A",
    "'''",
    '"""',
    "x = 1\n[clean]",
    "a\ud800b",
    "\udfff",
    "a\u2028b",
    "\ufeffbom",
    "\ufffe\uffff",
    "\U0010ffff",
    "é 中 🦷",
    "",
    " " * 3,
    "n" * 100_000,
]


@pytest.mark.parametrize("field", ["name", "description", "source"])
def test_every_text_is_refused_or_read_back_the_same(tmp_path, field):
    path = tmp_path / "p.toml"
    for text in HOSTILE:
        try:
            protocol = Protocol(**{field: text}, faces=500)
        except ProtocolError as exc:
            assert "\n" not in str(exc) and len(str(exc)) < 300
            continue
        path.write_text(protocol.to_toml(), encoding="utf-8")
        back = read_protocol(path)
        assert getattr(back, field) == text, repr(text[:20])
        assert back == protocol and back.to_toml() == protocol.to_toml()


def test_texts_that_toml_can_hold_are_not_refused():
    for text in ['say "hi"', "back\\slash\\", "'''", "x = 1\n[clean]"[:5], "n" * 100_000]:
        assert Protocol(name=text).name == text
    for text in ["line one\nline two", "tab\there", "\ufffe"]:
        assert Protocol(description=text).description == text
    for text in ["a\ud800b", "a\u0000b", "a\u007fb", "a\nb", "a\u2028b"]:
        with pytest.raises(ProtocolError, match="name must not hold"):
            Protocol(name=text)
    with pytest.raises(ProtocolError, match="lone surrogate"):
        Protocol(description="a\udc80b")
    with pytest.raises(ProtocolError, match="control character other than tab"):
        Protocol(source="a\u007fb")


# --- the commands ----------------------------------------------------------------------------

#: Runs ``main(argv)`` for each argv in one process; prints the exit codes and stderr.
MANY = """
import contextlib, io, json
from dentopo.cli import main
out = []
for argv in {argvs!r}:
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = main(argv)
    out.append([code, err.getvalue()])
print(json.dumps(out))
"""


def _run_many(argvs, cwd):
    ran = python(MANY.format(argvs=argvs), cwd=cwd)
    assert ran.returncode == 0, ran.describe()
    return json.loads(ran.stdout.strip().splitlines()[-1])


def _toml_value(value) -> str:
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, (tuple, list)):
        return "[" + ", ".join(repr(float(x)) for x in value) + "]"
    return repr(value)


def _protocol_file(path, changes: dict) -> None:
    """A hand-written protocol file of `changes` (not through Protocol: it may be refused)."""
    tables = {
        "smooth": ("smooth", "method"),
        "smooth_step": ("smooth", "step"),
        "smooth_mu": ("smooth", "mu"),
        "smooth_iterations": ("smooth", "iterations"),
        "crop_plane": ("crop", "plane"),
        "crop_below": ("crop", "below"),
        "up": ("orient", "up"),
    }
    by_table: dict[str, list[str]] = {}
    for key, value in changes.items():
        table, name = tables[key]
        by_table.setdefault(table, []).append(f"{name} = {_toml_value(value)}")
    text = 'name = "hostile"\n' + "".join(
        f"[{table}]\n" + "\n".join(lines) + "\n" for table, lines in by_table.items()
    )
    path.write_text(text, encoding="utf-8")


def _written_meshes(folder) -> list[str]:
    found = []
    for root, _, names in os.walk(folder):
        found += [os.path.join(root, n) for n in names if n.endswith(".ply")]
    return found


def _lines(stderr: str) -> list[str]:
    return [line for line in stderr.splitlines() if line.strip()]


def _both_commands(raw, tmp_path, cases, *, prepare=(), measure=()) -> list[list[str]]:
    """For each case's protocol changes, a file ``pN.toml`` and two argvs: ``prepare`` into
    ``outN`` and ``dentopo --prepare`` into ``outN.csv`` (with the extra options given)."""
    argvs = []
    for number, (changes, _) in enumerate(cases):
        protocol = tmp_path / f"p{number}.toml"
        _protocol_file(protocol, changes)
        out = tmp_path / f"out{number}"
        argvs.append(["prepare", str(raw), "-o", str(out), "--protocol", str(protocol), *prepare])
        argvs.append([str(raw), "--prepare", str(protocol), "-o", str(out) + ".csv", *measure])
    return argvs


def test_both_commands_refuse_every_refused_value_before_reading_a_file(raw, tmp_path):
    argvs = _both_commands(raw, tmp_path, REFUSED)
    names = [named for _, named in REFUSED for _ in range(2)]
    for (code, err), named, argv in zip(_run_many(argvs, tmp_path), names, argvs, strict=True):
        assert code == 2, (argv, err)
        assert len(_lines(err)) == 1 and named in err, (argv, err)
    assert not any(p.name.startswith("out") for p in tmp_path.iterdir())


def test_both_commands_prepare_a_hostile_direction_into_a_finite_mesh(raw, tmp_path):
    argvs = _both_commands(raw, tmp_path, SAME_DIRECTION, prepare=["-q"], measure=["-q"])
    for code, err in _run_many(argvs, tmp_path):
        assert code == 0, err
    for number in range(len(SAME_DIRECTION)):
        [mesh] = _written_meshes(tmp_path / f"out{number}")
        assert np.isfinite(read_ply(mesh)[0]).all()
        with open(tmp_path / f"out{number}.csv", encoding="utf-8") as table:
            assert ",ok," in table.read()


def test_a_diverging_filter_fails_its_file_and_writes_no_mesh(raw, tmp_path):
    argvs = _both_commands(raw, tmp_path, DIVERGING, measure=["-q"])
    results = _run_many(argvs, tmp_path)
    for number, (_, named) in enumerate(DIVERGING):
        (code, err), (main_code, _) = results[2 * number], results[2 * number + 1]
        assert code == 1 and "diverged" in err and named in err, err
        assert _written_meshes(tmp_path / f"out{number}") == []
        assert main_code == 1
        with open(tmp_path / f"out{number}.csv", encoding="utf-8") as table:
            text = table.read()
        assert "diverged" in text and ",ok," not in text


def test_a_protocol_file_that_broke_the_reader_exits_2_in_one_line(raw, tmp_path):
    files = {
        "arrays.toml": _nested(50_000, "arrays").encode(),
        "tables.toml": _nested(50_000, "tables").encode(),
        "del.toml": b'name = "a\\u007Fb"\n',
    }
    argvs = []
    for name, data in files.items():
        (tmp_path / name).write_bytes(data)
        path = str(tmp_path / name)
        saved = str(tmp_path / f"saved-{name}")
        argvs.append(["prepare", "--protocol", path, "--save-protocol", saved])
        argvs.append(["prepare", str(raw), "-o", str(tmp_path / "out"), "--protocol", path])
        argvs.append([str(raw), "--prepare", path, "-o", str(tmp_path / "t.csv")])
    for (code, err), argv in zip(_run_many(argvs, tmp_path), argvs, strict=True):
        assert code == 2 and len(_lines(err)) == 1 and "Traceback" not in err, (argv, err)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([*files, "raw"])


def test_a_protocol_file_with_a_byte_order_mark_runs_in_both_commands(raw, tmp_path):
    path = tmp_path / "bom.toml"
    path.write_bytes(b'\xef\xbb\xbfname = "bom"\n[orient]\nmode = "none"\n')
    saved = tmp_path / "saved.toml"
    argvs = [
        ["prepare", str(raw), "-o", str(tmp_path / "out"), "--protocol", str(path), "-q"],
        ["prepare", "--protocol", str(path), "--save-protocol", str(saved), "-q"],
        [str(raw), "--prepare", str(path), "-o", str(tmp_path / "t.csv"), "-q"],
    ]
    assert [code for code, _ in _run_many(argvs, tmp_path)] == [0, 0, 0]
    assert read_protocol(saved).digest == Protocol(name="bom", orient="none").digest


def test_too_many_smoothing_iterations_is_a_usage_error(raw, tmp_path):
    argv = ["prepare", str(raw), "-o", str(tmp_path / "out"), "--smooth", "laplacian:1000000000"]
    [(code, err)] = _run_many([argv], tmp_path)
    assert code == 2 and len(_lines(err)) == 1
    assert "--smooth METHOD:ITERATIONS must be at most 10,000" in err


# --- the smaller points ----------------------------------------------------------------------


def test_an_output_folder_that_is_the_input_folder_is_named_as_the_reason(raw, tmp_path):
    [(code, err)] = _run_many([["prepare", str(raw), "-o", str(raw)]], tmp_path)
    assert code == 2 and len(_lines(err)) == 1
    assert "output folder" in err and str(raw) in err


def test_an_output_folder_inside_the_input_folder_is_no_input_later(raw, tmp_path):
    inside, outside = raw / "prepared", tmp_path / "prepared"
    argvs = [
        ["prepare", str(raw), "-o", str(out), "--orient", "none", "-q"] for out in (inside, outside)
    ]
    assert [code for code, _ in _run_many(argvs, tmp_path)] == [0, 0]
    assert (inside / OUTPUT_FOLDER_MARK).is_file() and (inside / "tooth.ply").is_file()
    assert find_mesh_files([str(raw)]).files == [str(raw / "tooth.ply")]
    assert not (outside / OUTPUT_FOLDER_MARK).exists()  # only where it would be searched


def test_an_output_folder_beside_the_input_files_is_no_input_later(raw, tmp_path):
    # the inputs given as files (a shell's raw/*.ply): their folder is searched later all the same
    beside = raw / "prepared-files"
    argv = ["prepare", str(raw / "tooth.ply"), "-o", str(beside), "--orient", "none", "-q"]
    assert [code for code, _ in _run_many([argv], tmp_path)] == [0]
    assert (beside / OUTPUT_FOLDER_MARK).is_file() and (beside / "tooth.ply").is_file()
    assert find_mesh_files([str(raw)]).files == [str(raw / "tooth.ply")]
