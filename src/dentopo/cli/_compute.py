"""The main command, ``dentopo PATH...``: compute a table with one row per mesh.

Finds the mesh files, computes them as a batch (:mod:`dentopo.batch`), writes
the table (:mod:`dentopo.formats`) and, if asked, draws the curvature
(:mod:`dentopo.figures`, whose pyvista is imported only then).  Only the CLI
prints: results to stdout or files, messages and progress to stderr.  Its
parser and option values are in :mod:`._arguments`, the checks made before any
file is read in :mod:`._checks`, the picture step in :mod:`._pictures`.

Exit codes: 0 all files ok; 1 some file failed (or the display is unavailable,
or the table could not be written); 2 usage error (including "no mesh files
found", an output that cannot be written and a missing extra, checked before
any file is computed); 130 interrupted by Ctrl-C or SIGTERM (the rows done are
written).  With ``-o FILE`` each finished row is also kept in a journal beside
FILE as it finishes, so that a run killed outright loses only the meshes in
flight (see :mod:`._output`).
"""

from __future__ import annotations

import os
import signal
import sys
import warnings
from dataclasses import replace

from .._jit import lean_numba_typing
from .._optional import MissingExtraError
from ..batch import (
    Interrupted,
    Outcome,
    Settings,
    available_cores,
    find_mesh_files,
    guard_interrupts,
    make_settings,
    merge_records,
    metric_groups,
    missing_metrics,
    plan_batch,
    relabel_resumed,
    replaced_message,
    replaced_per_vertex_files,
    resumable_files,
    run_tasks,
    warm_up,
    warm_up_wanted,
)
from ..formats import (
    DEFAULT_PER_VERTEX_FORMATS,
    NotAJournalError,
    PerVertexOptions,
    layout,
    read_table,
    write_table,
)
from ..samples import sample_paths
from ._arguments import (
    CURVATURE_FIELDS,
    METRIC_PICTURES,
    SCHEDULER_ENV,
    STDOUT,
    build_parser,
    metrics_asked,
    rendering_requested,
    split_pairs,
)
from ._checks import missing_extra, outputs_problem, picture_problem, usage_problem
from ._compiling import MENTION_SECONDS, MORE, CompileNotice, done_text, more_text, notice_text
from ._hints import CommandLineHints
from ._output import TableOutput
from ._pictures import NO_DISPLAY, draw_pictures, load_renderer
from ._progress import Progress, counted
from ._progress import say as _say
from ._table import print_layout, print_table, table_columns


def settings_from_args(args) -> Settings:
    """The batch's settings from the main command's options (raises ValueError or TypeError)."""
    return make_settings(
        bandwidth=args.bandwidth,
        cutoff=args.cutoff,
        distance_type=args.distance_type,
        sign_method=args.sign_method,
        method=args.method,
        geometry=args.geometry,
        metrics=metrics_asked(args),
        alpha=args.alpha,
        find_alpha=args.find_alpha,
        opcr_steps=args.opcr_steps,
        opcr_step=args.opcr_step,
        min_faces=args.min_faces,
        min_area=args.min_area,
        dne_outliers=args.dne_outliers,
        dne_boundary=args.dne_boundary,
        dne_kappa=args.dne_kappa,
        arc_boundary=args.arc_boundary,
        arc_range=tuple(args.arc_range),
        orient=args.orient,
        duplicates=args.duplicates,
        prepare=args.prepare,
        unit=args.unit,
        mt_condition_check=args.mt_condition == "on",
        mt_outliers=args.mt_outliers,
        mt_percentile=args.mt_percentile,
        mt_smooth=args.mt_smooth,
        mt_min_patch=args.mt_min_patch,
        pcv_rays=args.pcv_rays,
        pcv_hemisphere=not args.pcv_sphere,
        pcv_method=args.pcv_method,
    )


def compute_main(argv: list[str], subcommands: tuple[str, ...] = ()) -> int:
    """Run the main command with `argv`; the exit code."""
    lean_numba_typing()  # no cffi function nor np.convolve in a kernel: 0.14 s of a warm start
    parser = build_parser(subcommands)
    try:
        args = parser.parse_args(split_pairs(argv))
    except SystemExit as stop:  # --help, --version, or a usage error (2)
        return stop.code if isinstance(stop.code, int) else 0

    problem = usage_problem(args)
    if problem:
        _say(problem)
        return 2
    try:
        settings = settings_from_args(args)
    except (TypeError, ValueError) as exc:
        _say(str(exc))
        return 2
    problem = picture_problem(args, settings.metrics)
    if problem:
        _say(problem)
        return 2
    if (
        args.color_by in CURVATURE_FIELDS
        and "ariadne" not in settings.metrics
        and (rendering_requested(args))
    ):
        _say(
            f"--color-by {args.color_by} (the default) draws ariaDNE, which is not among "
            f"--metrics: add ariadne, or choose --color-by {', '.join(METRIC_PICTURES)}"
        )
        return 2
    try:  # also checks --limits and --percentile before any work
        per_vertex = PerVertexOptions(
            formats=args.per_vertex_format or DEFAULT_PER_VERTEX_FORMATS,
            limits=tuple(args.limits) if args.limits else None,
            percentile=args.percentile,
        )
    except (TypeError, ValueError) as exc:
        _say(str(exc))
        return 2
    scheduler = args.scheduler or os.environ.get(SCHEDULER_ENV) or None
    problem = missing_extra(args, settings, scheduler)
    if problem:  # now, not after a batch has been computed
        _say(problem)
        return 2

    paths = list(args.paths)
    if args.samples:
        paths += [str(path) for path in sample_paths().values()]
    if not paths:
        _say("no mesh files given (try --help, or --samples)")
        return 2
    with warnings.catch_warnings(record=True) as caught:  # e.g. .dae files without pycollada
        warnings.simplefilter("always")
        found = find_mesh_files(paths)
    for warning in caught:
        _say(f"warning: {warning.message}")
    for pattern in found.unmatched:
        _say(f"no mesh files in {pattern!r}")
    if not found.files:
        _say("no mesh files found")
        return 2
    files = found.files

    rendering = rendering_requested(args)
    single = args.show or args.screenshot or args.html
    if single and len(files) != 1:
        _say(
            f"--show, --screenshot and --html draw one mesh; {len(files)} were given (see --panel)"
        )
        return 2
    problem = outputs_problem(args, files, settings, per_vertex)  # before anything is written
    if problem:
        _say(problem)
        return 2
    render = load_renderer() if rendering else None
    if rendering and render is None:
        return 2
    if args.show and not render.has_display():  # now, not after the meshes are computed
        _say(NO_DISPLAY)
        return 2

    output = None
    if args.output not in (None, STDOUT):
        columns = layout(args.columns, settings.metrics, settings.rotations())
        output = TableOutput(args.output, columns, quiet=args.quiet)
    # Ctrl-C and SIGTERM (a scheduler's time limit) stop the run, never while a row or the
    # table is being written; the rows done are written, and the exit code is 130.
    with guard_interrupts(signal.SIGINT, signal.SIGTERM) as guard:
        try:
            code = _run(args, files, settings, per_vertex, scheduler, render, output, guard)
        except KeyboardInterrupt as exc:  # before the first mesh: waiting for the lock, ...
            _say(f"{_interruption(exc)} before any file was computed")
            code = INTERRUPTED
        finally:
            if output is not None:
                output.close()
        guard.pending = None  # everything is done and said
    return code


#: The exit code of a run stopped by Ctrl-C or SIGTERM (the rows done are written).
INTERRUPTED = 130


def _interruption(exc: BaseException) -> str:
    """``interrupted`` (Ctrl-C) or ``interrupted (SIGTERM)``."""
    name = getattr(exc, "name", "SIGINT")
    return "interrupted" if name == "SIGINT" else f"interrupted ({name})"


def _compile_first(settings: Settings, jobs: int, progress: Progress, *, quiet: bool) -> None:
    """Compile the kernels of `settings` before the first mesh (on `jobs` cores), saying so."""
    missing = missing_metrics(settings)
    if not missing:
        return
    processes = len(metric_groups(missing, jobs))
    # in this process, the line comes with the first kernel compiled (none: no line); in
    # several, before they start (a missing stamp: a new install, or new sources)
    notice = CompileNotice(notice_text(missing, processes), progress.message)
    if not quiet and processes > 1:
        notice.say(notice.text)
    elif not quiet:
        notice.start()
    try:
        warm = warm_up(settings, jobs=jobs)
    except KeyboardInterrupt:
        raise
    except Exception as exc:  # the meshes compile what they need, as they would have
        progress.message(f"warning: compiling before the first mesh failed ({exc})")
        return
    finally:
        notice.stop()
    if not quiet and (warm.compiled or processes > 1):
        progress.message(done_text(warm))


def _run(args, files, settings, per_vertex, scheduler, render, output, guard) -> int:
    """Compute the batch and write its table; the exit code."""
    rendering = render is not None
    previous: list[dict] = []
    if output is not None:
        try:
            output.lock()
        except OSError as exc:
            _say(f"cannot lock {args.output!r} for this run: {exc}")
            return 2
        try:
            output.recover()
        except NotAJournalError as exc:  # not a killed run's rows: say what it is
            _say(str(exc))
            return 2
        except (OSError, ValueError) as exc:
            _say(f"cannot add the rows of an earlier run kept in {output.journal_path!r}: {exc}")
            return 2
    if args.resume:
        if os.path.exists(args.output):
            try:
                previous = read_table(args.output)
            except (OSError, ValueError) as exc:
                _say(f"cannot resume from {args.output!r}: {exc}")
                return 2
        elif not args.quiet:
            _say(f"{args.output!r} does not exist yet: computing every file")
    done = set() if rendering else resumable_files(previous, settings)  # drawing needs results
    todo = [f for f in files if os.path.abspath(f) not in done]
    if args.resume and not args.quiet:
        if args.geometry is not None:  # the table does not record it: nothing can be reused
            _say("--geometry: the table does not record which mesh was read; computing every file")
        _say(f"resuming: {len(files) - len(todo)} of {len(files)} files already done")

    if args.per_vertex is not None:
        try:
            os.makedirs(args.per_vertex, exist_ok=True)
        except OSError as exc:
            _say(f"cannot create --per-vertex {args.per_vertex!r}: {exc}")
            return 2
    if output is not None and todo:
        try:
            output.start_journal()
        except NotAJournalError as exc:  # planted since it was checked
            _say(str(exc))
            return 2
        except OSError as exc:
            _say(f"cannot write {output.journal_path!r}: {exc}")
            return 2
    jobs = args.jobs or available_cores()
    tasks = plan_batch(
        todo,
        settings,
        per_vertex_dir=args.per_vertex,
        per_vertex=per_vertex,
        keep_results=rendering,
        absolute=scheduler is not None,
        batch=files,  # the names checked by outputs_problem, whichever files are left
    )
    replaced = replaced_per_vertex_files(tasks)
    if replaced:  # two runs into one folder: say so (one line), then replace
        more = f" (and the files of {len(replaced) - 1} more meshes)" if len(replaced) > 1 else ""
        _say(f"warning: {replaced_message(*replaced[0])}{more}")

    hints = CommandLineHints(build_parser())

    def in_command_words(outcome: Outcome) -> Outcome:
        return replace(
            outcome,
            record=hints.record(outcome.record),
            warnings=tuple(hints(message) for message in outcome.warnings),
        )

    progress = Progress(len(tasks), quiet=args.quiet)
    outcomes: dict[int, Outcome] = {}
    interrupted: BaseException | None = None
    unrecorded: OSError | None = None
    if scheduler is None and tasks and warm_up_wanted():  # a cluster's workers bring their own
        _compile_first(settings, jobs, progress, quiet=args.quiet)
    notice = CompileNotice(MORE, progress.message)
    if not args.quiet and jobs == 1 and scheduler is None:  # compiled here, not in workers
        notice.start()
    running = run_tasks(tasks, settings, jobs=jobs, scheduler=scheduler, on_phase=progress.phase)
    try:
        for outcome in running:
            outcome = in_command_words(outcome)  # hints name options, not keyword arguments
            outcomes[outcome.index] = outcome
            try:
                with guard.held():  # a row is appended whole
                    if output is not None:
                        output.record(outcome.record)
            except OSError as exc:  # a full disk: the rows could not be kept, so stop
                unrecorded = exc
                break
            if outcome.compiled >= MENTION_SECONDS and not args.quiet:
                progress.message(more_text(outcome.record["file"], outcome.compiled))
            for message in outcome.warnings:  # one short line each; the row keeps them whole
                progress.warning(outcome.record["file"], message)
            progress.update(outcome.record)
            guard.check()
    except KeyboardInterrupt as exc:
        interrupted = exc
    except MissingExtraError as exc:  # found only when running (installed but incomplete)
        progress.close()
        _say(str(exc))
        return 2
    except (ImportError, OSError) as exc:  # no dask, or the scheduler cannot be reached
        progress.close()
        _say(f"cannot run on scheduler {scheduler!r}: {exc}" if scheduler else str(exc))
        return 2
    finally:
        notice.stop()
        with guard.held():
            running.close()  # stops the workers, also on Ctrl-C
            progress.close()
    progress.explain()  # each long warning's explanation, once per run

    with guard.held():  # the table is written whole, even if Ctrl-C comes now
        code = _write(
            args, settings, output, files, tasks, previous, outcomes, interrupted, unrecorded
        )
    if interrupted is None and guard.pending is not None:  # came while writing: rows are safe
        interrupted = Interrupted(guard.pending)
        guard.pending = None
        _say(f"{_interruption(interrupted)} after the table was written")
    if interrupted is not None:
        return INTERRUPTED
    if args.report is not None and os.path.exists(args.output):
        from ._report import report_after_batch

        report = report_after_batch(
            args.output, args.report, quiet=args.quiet, prepare=settings.prepare
        )
        code = max(code, report)
    if code or not rendering:
        return code
    try:
        return max(code, draw_pictures(render, args, todo, outcomes))
    except KeyboardInterrupt as exc:  # e.g. in the window of --show
        _say(_interruption(exc))
        return INTERRUPTED


def _write(
    args, settings, output, files, tasks, previous, outcomes, interrupted, unrecorded
) -> int:
    """Write the table (or print it); the exit code so far (0, or 1 if a file failed)."""
    new = [outcomes[i].record for i in sorted(outcomes)]
    if interrupted is not None:
        _say(
            f"{_interruption(interrupted)}: {len(new)} of {len(tasks)} files done; "
            "rerun with --resume to finish"
        )
    if unrecorded is not None:
        _say(
            f"cannot keep the finished rows in {output.journal_path!r}: {unrecorded}; "
            f"stopped after {len(new)} of {len(tasks)} files"
        )
    if (interrupted or unrecorded) and output is not None and not previous:
        if os.path.exists(args.output):
            try:  # keep the old rows of the files not reached, so that nothing is lost
                previous = read_table(args.output)
            except (OSError, ValueError):
                previous = []
    relabelled = relabel_resumed(previous, settings)  # a protocol renamed since
    renamed = any(row is not was for row, was in zip(relabelled, previous, strict=True))
    records = merge_records(relabelled, new)
    mine = {os.path.abspath(f) for f in files}
    statuses = [r["status"] for r in records if os.path.abspath(r["file"]) in mine]
    failed = sum(status != "ok" for status in statuses)  # partial rows too: a metric is missing
    partial = statuses.count("partial")
    code = 1 if failed or unrecorded else 0

    columns = layout(args.columns, settings.metrics, settings.rotations())
    if failed and not columns.failed_rows:
        _say(f"{counted(failed, 'failed file')} left out of the table (--columns {columns.name})")
    computed = any(r["status"] != "error" for r in new)  # a partial row is a computed row
    if args.output == STDOUT:
        write_table(sys.stdout, records, columns=columns)
        sys.stdout.flush()
    elif output is not None and not new and interrupted is not None:
        output.discard_journal()  # nothing done, nothing to write
    elif (
        output is not None
        and not computed
        and os.path.exists(args.output)
        and (tasks or not renamed)  # every file done, a protocol renamed: written anew
    ):
        if tasks:  # every file failed (or none was reached): keep the old table as it is
            _say(f"no mesh was computed (every file failed): {args.output} left as it was")
        elif not args.quiet:
            _say(f"every file was already done: {args.output} left as it was")
        output.discard_journal()
    elif output is not None:
        try:
            written = output.write(records)
        except OSError as exc:
            kept = f"; the rows computed are kept in {output.journal_path}"
            _say(
                f"cannot write {args.output!r}: {exc}; it was left as it was"
                + (f"{kept}: rerun with --resume to add them" if new else "")
            )
            return 1
        if not args.quiet:
            detail = f"{failed - partial} failed" + (f", {partial} partial" if partial else "")
            _say(f"wrote {counted(written, 'row')} to {args.output} ({detail})")
    elif columns.name != "dentopo":
        print_layout(records, columns)
    else:
        print_table(records, columns=table_columns(settings.metrics))
    return code
