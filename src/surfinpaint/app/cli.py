"""Command-line interface:
``surfinpaint holes|fill|batch|represent|rebuild|demo|report|experiments``.

Exit codes: 0 success (including "nothing to fill"), 1 bad input or failure (for ``batch``:
any file failed), 2 usage error, 130 after Ctrl-C and 143 after SIGTERM (one line printed,
temporary files removed; ``batch``: the same command again picks up the rest).
"""

from __future__ import annotations

import argparse
import contextlib
import importlib.util
import logging
import signal
import sys
import time
import warnings
from collections.abc import Iterator, Sequence
from pathlib import Path

import numpy as np

from surfinpaint import __version__, compiled
from surfinpaint.app.batch_command import add_batch_parser
from surfinpaint.app.fill_options import UsageError as _UsageError
from surfinpaint.app.fill_options import (
    add_all_loops,
    add_fill_options,
    add_hole_numbers,
    add_islands,
    add_keep_margins,
    add_max_hole_edges,
    add_zip_seams,
    fill_options,
)
from surfinpaint.app.fill_report import (
    Summary,
    count_warnings,
    hole_lines,
    nothing_to_fill,
    print_warnings,
    tell,
)
from surfinpaint.app.holes_table import holes_table
from surfinpaint.app.interrupts import (
    Interrupted,
    interruptions_raised,
    raise_interruption,
    raise_noted,
    raise_pending,
    signals_raise,
)
from surfinpaint.app.outputs import (
    OutputError,
    OutputOverwritesInput,
    check_output_directory,
    check_output_file,
    check_outputs_distinct,
    write_with_materials,
)
from surfinpaint.app.progress import (
    LazyConsole,
    QuietConsole,
    add_quiet,
    progress_bar,
)
from surfinpaint.app.represent_commands import add_representation_parsers
from surfinpaint.errors import InputError, MeshError, agreeing, how_many, mesh_size, preview
from surfinpaint.fill import warmup
from surfinpaint.fill.holes import (
    warn_degenerate,
)
from surfinpaint.fill.objects import fill_mesh_data
from surfinpaint.fill.pipeline import METHODS, fill_holes
from surfinpaint.fill.unjoined import unjoined_borders_note
from surfinpaint.geometry.repair import repair_faces
from surfinpaint.io.atomic import remove_unfinished
from surfinpaint.io.base import MeshWarning
from surfinpaint.io.formats import (
    files_written,
    output_format,
    overlays_with,
    read_mesh,
    read_mesh_data,
    write_mesh,
)
from surfinpaint.lazy import lazy_module

# imported at their first use (surfinpaint.lazy): a fill never needs them (docs/scale.md,
# session 14: a faired fill's start 0.65 -> 0.56 s CPU)
batch = lazy_module("surfinpaint.app.batch")
data = lazy_module("surfinpaint.data")
experiments = lazy_module("surfinpaint.app.experiments")
figures = lazy_module("surfinpaint.app.figures")
report = lazy_module("surfinpaint.app.report")

EXIT_OK, EXIT_FAILURE, EXIT_USAGE = 0, 1, 2

# a file this large holds a mesh whose kernels fill_holes would load beside its passes
# (about warmup.BESIDE_MIN_FACES faces in a binary PLY): they start loading before the read
LOAD_AHEAD_MIN_BYTES = 2_000_000


def _file_size(path) -> int:
    """The size of ``path`` in bytes; 0 when it cannot be read (the reader says why)."""
    try:
        return Path(path).stat().st_size
    except OSError:
        return 0


@contextlib.contextmanager
def _progress(enabled: bool, what: str = "filling") -> Iterator:
    """The ``progress`` callback of :func:`surfinpaint.fill_holes` moving a progress bar on
    stderr (:func:`~surfinpaint.app.progress.progress_bar`: its clock's thread runs only
    while the holes are filled in this process, so the holes' workers are forked), or None;
    ``what`` is its first label."""
    with progress_bar(enabled, None, what, ticking=True) as bar:
        yield bar.update if enabled else None


def cmd_holes(args: argparse.Namespace) -> int:
    vertices, faces = read_mesh(args.mesh, data_warning=False)  # it only lists the holes
    title = f"{args.mesh}: {mesh_size(len(vertices), len(faces))}"
    if len(unused := _on_no_face(len(vertices), faces)):  # the vertices' count, then this
        title = title.replace(", ", f" ({len(unused)} on no face), ", 1)
    if args.repair:
        repair = repair_faces(vertices, faces)
        faces = repair.faces
        title += f" ({len(repair.removed)} removed by --repair: the numbering `fill --repair` " \
            "uses)" + "".join(f"; --repair {note}" for note in repair.notes())
    warn_degenerate(vertices, faces, str(args.mesh))
    unjoined = unjoined_borders_note(vertices, holes_table(
        vertices, faces, str(args.mesh), title, holes=args.holes, include_border=args.all,
        keep_margins=args.keep_margins, max_hole_edges=args.max_hole_edges,
        zip_seams=args.zip_seams, islands=args.islands), zip_seams=args.zip_seams)
    if unjoined is not None:
        warnings.warn(f"{args.mesh}: {unjoined}", MeshWarning, stacklevel=1)
    return EXIT_OK


def cmd_fill(args: argparse.Namespace) -> int:
    out = QuietConsole(args.quiet)  # -q: warnings and errors only; -qq: errors only
    console, say = out.warnings_console, out.say
    holes = args.holes
    output_format(args.output)  # an unusable output name fails now, not after the fill
    options = fill_options(args)
    if args.jobs is not None and args.jobs < 1:
        raise _UsageError(f"--jobs must be at least 1, got {args.jobs}")
    started = time.perf_counter()
    if _file_size(args.mesh) >= LOAD_AHEAD_MIN_BYTES:  # the kernels load while it is read
        warmup.load_ahead(options["method"])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        mesh = read_mesh_data(args.mesh, overlays=_overlays(args))
        vertices, faces = mesh.vertices, mesh.faces
        with _progress(out.progress) as progress:
            result, filled = fill_mesh_data(mesh, holes=holes, progress=progress,
                                            jobs=args.jobs, **options)
        # the OBJ's .mtl and the textures it names, beside the output: its texture shows
        materials = write_with_materials(args.mesh, args.output, filled, len(vertices),
                                         reserved=[p for p in (args.png, args.json) if p])
    summary = Summary.of(result, time.perf_counter() - started)
    if len(result.removed_faces):
        removed = how_many(len(result.removed_faces), "face", "faces")
        say(f"--repair removed {removed} around non-manifold "
            "edges and bow-tie vertices; the holes they left were filled too")
    if len(unused := _on_no_face(len(vertices), result.faces)):
        k = len(unused)
        say(f"{how_many(k, 'vertex', 'vertices')} of the input {agreeing(k, 'lies', 'lie')} "
            f"on no face ({preview(unused.tolist(), 5)}): kept at "
            f"{agreeing(k, 'its id', 'their ids')}, with {agreeing(k, 'its', 'their')} "
            "values, on no face of the output either (a fill adds vertices of its own)")
    if not result.reports:
        # a closed surface has no outer border to speak of (fsaverage's pial surface)
        why = nothing_to_fill(result.faces, keep_margins=args.keep_margins)
        say(f"{args.mesh}: nothing to fill ({why}); wrote the mesh unchanged to {args.output}")
    files = {"input": str(args.mesh), "output": str(args.output), "png": args.png}
    tell(result, summary, caught, console=console, report=out.progress,
         verbose=args.verbose, json_path=args.json, files=files,
         options={**options, "holes": holes, "jobs": args.jobs}, source=args.mesh,
         other_files=_other_files(args))
    carried = [*filled.attributes, *(f"{k} (per face)" for k in filled.face_attributes),
               *(f"{k} (per corner)" for k in filled.corner_attributes)]
    if carried and len(result.vertices) > len(vertices):
        say(f"attributes filled in at the new vertices and faces: {', '.join(carried)}")
    if args.png:
        try:
            figures.before_after(vertices, faces, result, args.png)
            say(f"wrote {args.png}")
        except Exception as exc:  # as in a batch: a warning, the mesh is written
            raise_interruption(exc)
            warnings.warn(f"{args.png}: picture not drawn: {type(exc).__name__}: {exc}",
                          MeshWarning, stacklevel=1)
    # the overlays beside a brain surface are files of their own: each is named
    written = [str(args.output), *(str(p) for p in files_written(args.output, filled)[1:]),
               *map(str, materials)]
    say(f"wrote {', '.join(written)}" + (f" and {args.json}" if args.json else ""))
    return EXIT_OK


def _on_no_face(n: int, faces: np.ndarray) -> np.ndarray:
    """The ids below ``n`` that no face uses: a brain lab that cut a region's faces keeps
    its vertices (and their overlay values) at their ids, in the hole, on no face."""
    used = np.zeros(max(n, int(faces.max(initial=-1)) + 1), bool)
    used[faces.ravel()] = True
    return np.flatnonzero(~used[:n])


def _overlays(args: argparse.Namespace) -> bool | list:
    """``read_mesh_data``'s ``overlays`` for ``fill``: those found beside the surface, and
    the ``--overlay`` files (a usage error with a surface that has none)."""
    if not args.overlay:
        return True
    try:
        return overlays_with(args.mesh, args.overlay)
    except MeshError as exc:
        raise _UsageError(f"--overlay: {exc}") from None


def cmd_demo(args: argparse.Namespace) -> int:
    from rich.markup import escape


    says = QuietConsole(args.quiet)
    out = Path(args.output)
    out.mkdir(parents=True, exist_ok=True)
    source = data.default_demo_path()
    vertices, faces = read_mesh(source)
    says.say(f"demo mesh: {source} ({mesh_size(len(vertices), len(faces))})")
    holes_table(vertices, faces, "the demo mesh", "holes of the demo mesh")
    with _progress(says.progress) as progress:
        result = fill_holes(vertices, faces, method=args.method, progress=progress)
    filled = out / "filled.ply"
    write_mesh(filled, result.vertices, result.faces)

    picture = out / "before_after.png"
    figures.before_after(vertices, faces, result, picture)

    for r in result.reports:
        for line in hole_lines(r):
            says.say(escape(line))
    says.say(f"wrote {filled} and {picture}")
    return EXIT_OK


def cmd_compile(args: argparse.Namespace) -> int:
    """Compile every numba kernel into numba's disk cache now, in this process (or find
    them there), as a first run after an install otherwise does in the background."""
    says = QuietConsole(args.quiet)
    if importlib.util.find_spec("numba") is None:
        says.say("numba is not installed: nothing to compile (the kernels' numpy versions "
                 "are used, the same results)")
        return EXIT_OK
    start = time.perf_counter()
    with compiled.in_foreground():
        warmup.compile_kernels()
    says.say(f"surfinpaint's numba kernels are in numba's cache "
             f"({time.perf_counter() - start:.1f} s): later runs load them")
    return EXIT_OK


# the commands whose parsers need nothing beyond this module: with one of them named first,
# the report's and the experiments' parsers (whose modules import the λ-H representation,
# the figures and the page, ~0.1 s CPU) are not built (docs/scale.md, session 14)
_LIGHT_COMMANDS = frozenset({"holes", "fill", "batch", "represent", "rebuild", "demo",
                             "compile"})


def _command_word(argv: Sequence[str] | None) -> str | None:
    """The command the arguments name: their first word that is not an option."""
    words = sys.argv[1:] if argv is None else argv
    return next((w for w in words if not w.startswith("-")), None)


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The ``surfinpaint`` parser; with ``command`` one of the commands defined here, the
    ``report`` and ``experiments`` parsers are left out (their modules are not imported)."""
    parser = argparse.ArgumentParser(
        prog="surfinpaint",
        description="Fill holes in triangle meshes by conformal surface inpainting.",
    )
    parser.add_argument("--version", action="version", version=f"surfinpaint {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    _add_holes_parser(sub)
    _add_fill_parser(sub)
    add_batch_parser(sub)
    add_representation_parsers(sub)
    _add_demo_parser(sub)
    _add_compile_parser(sub)
    if command not in _LIGHT_COMMANDS:
        report.add_report_parser(sub)
        experiments.add_experiments_parser(sub)
    return parser


def _add_holes_parser(sub) -> None:
    """``holes``: the table of boundary loops."""
    p = sub.add_parser("holes", help="list the holes (boundary loops) of a mesh",
                       description="Print a table of the boundary loops of MESH: the holes "
                       "`fill` fills, the outer borders, and the loops `fill` leaves open, "
                       "each with why.")
    p.add_argument("mesh", help="input mesh (PLY, OBJ, STL, OFF, GIFTI, FreeSurfer)")
    p.add_argument("--repair", action="store_true",
                   help="first remove the faces around non-manifold edges and bow-tie vertices "
                   "and orient the faces consistently, as `fill --repair` does, and list the "
                   "holes of the result")
    choice = p.add_argument_group(
        "fill options", "say which loops `fill` with the same options leaves open")
    add_hole_numbers(choice)
    add_max_hole_edges(choice)
    add_zip_seams(choice)
    add_all_loops(choice)
    add_keep_margins(choice)
    add_islands(choice)
    add_quiet(p)
    p.set_defaults(func=cmd_holes)


def _add_fill_parser(sub) -> None:
    """``fill``: one mesh."""
    p = sub.add_parser("fill", help="fill holes and write the filled mesh",
                       description="Fill the holes of MESH and write OUT: the original "
                       "vertices unchanged and in order, then the new ones.")
    p.add_argument("mesh", help="input mesh")
    p.add_argument("-o", "--output", required=True, help="output mesh (format by extension)")
    add_hole_numbers(p)
    add_fill_options(p)
    p.add_argument("--jobs", type=int, metavar="N",
                   help="worker processes filling holes at once (default: all cores; 1: one "
                   "hole after another; the result is the same)")
    p.add_argument("--in-place", action="store_true",
                   help="allow -o to name the input file, replacing it (atomically: a "
                   "failed or interrupted fill leaves it as it was)")
    p.add_argument("--overlay", action="append", metavar="FILE",
                   help="a per-vertex overlay of a GIFTI or FreeSurfer surface, filled in at "
                   "the new vertices and written beside OUT (a GIFTI data file such as "
                   "nilearn's sulc_left.gii.gz, or a FreeSurfer morphometry file; a "
                   "segmentation, .label.gii, .annot or .label, is filled as labels and "
                   "written as .label.gii; repeat for more); the overlays named after the "
                   "surface (SURFACE.NAME.shape.gii, lh.sulc beside lh.pial, ...) are read "
                   "without it")
    p.add_argument("--png", help="also write a before/after picture (one that cannot be "
                   "drawn is a warning; the mesh is still written)")
    p.add_argument("--json", metavar="REPORT",
                   help="also write the report as JSON: per hole what was written and the "
                   "self-check's scores, the summary, the warnings, the options and the "
                   "version (fields: docs/report.md)")
    p.add_argument("-v", "--verbose", action="store_true",
                   help="per hole also the scores in mesh units, the time and the notes")
    add_quiet(p)
    p.set_defaults(func=cmd_fill)


def _add_demo_parser(sub) -> None:
    """``demo``: the bundled snowman."""
    p = sub.add_parser("demo", help="fill the bundled default mesh and draw before/after",
                       description="Fill the holes of the bundled snowman and write the "
                       "filled mesh and a before/after picture.")
    p.add_argument("-o", "--output", default="demo-out", help="output folder")
    p.add_argument("--method", choices=METHODS, default="conformal")
    add_quiet(p)
    p.set_defaults(func=cmd_demo)


def _add_compile_parser(sub) -> None:
    """``compile``: the numba kernels into numba's cache, ahead of the first fill."""
    p = sub.add_parser("compile", help="compile the numba kernels now (optional: after an "
                       "install, before timing or in an image)",
                       description="Compile surfinpaint's numba kernels into numba's disk "
                       "cache now (about 8 s of CPU), so that no later run waits for them or "
                       "uses their numpy versions meanwhile. Without it the first run after "
                       "an install starts their compilation in the background. Nothing to do "
                       "when they are cached already.")
    add_quiet(p)
    p.set_defaults(func=cmd_compile)


# What each command reads and writes, for the checks made before any work: the input
# attributes, and per command its outputs as (attribute, option named in messages, kind).
_INPUTS = ("mesh", "representation", "truth")
_OUTPUTS = {
    "fill": (("output", "-o", "file"), ("png", "--png", "file"), ("json", "--json", "file")),
    "represent": (("output", "-o", "file"), ("png", "--png", "file"),
                  ("export", "--export", "file"), ("export_grid", "--export-grid", "file"),
                  ("export_quadtree", "--export-quadtree", "file")),
    "rebuild": (("output", "-o", "file"),),
    "batch": (("output", "-o", "dir"),),
    "demo": (("output", "-o", "dir"),),
    "report": (("output", "-o", "dir"),),
    "experiments": (("output", "-o", "dir"),),
}


def _check_outputs(args: argparse.Namespace) -> None:
    """Refuse, before any work, an output that cannot be written or would replace an input."""
    files, folders = {}, {}
    for attribute, option, kind in _OUTPUTS.get(args.command, ()):
        path = getattr(args, attribute, None)
        if path is not None:
            (files if kind == "file" else folders)[option] = str(path)
    picture = files.get("--png")
    if picture is not None and not picture.lower().endswith(".png"):
        raise _UsageError(f"--png {picture!r}: the picture is a PNG file; name it .png")
    inputs = [str(getattr(args, a)) for a in _INPUTS if getattr(args, a, None) is not None]
    check_outputs_distinct(files, inputs,
                           in_place="-o" if getattr(args, "in_place", False) else None)
    for option, path in files.items():
        check_output_file(path, option)
    for option, path in folders.items():
        check_output_directory(path, option)


def _input_name(args: argparse.Namespace) -> str | None:
    """The one input file the command reads, as the user named it (None: ``batch``'s
    many, ``demo``'s bundled mesh, ``experiments``): its errors and warnings start with
    it."""
    source = getattr(args, "mesh", None) or getattr(args, "representation", None)
    return None if source is None else str(source)


def _other_files(args: argparse.Namespace) -> dict[str, str]:
    """The files the command reads or writes besides its one input (:func:`_input_name`),
    each with what it does with it ("writing" an output, "reading" ``--truth`` or an
    ``--overlay``): a warning that starts with one is said as ``INPUT (writing OUT): ...``
    (:func:`~surfinpaint.app.progress.named`)."""
    source = _input_name(args)
    if source is None:  # batch, demo, experiments: nothing is named for an input
        return {}
    files = {str(path): "writing" for attribute, _, kind in _OUTPUTS.get(args.command, ())
             if kind == "file" and (path := getattr(args, attribute, None)) is not None}
    read = [getattr(args, a, None) for a in _INPUTS] + list(getattr(args, "overlay", None) or ())
    files.update({str(path): "reading" for path in read
                  if path is not None and str(path) != source and str(path) not in files})
    return files


def _run(parser: argparse.ArgumentParser, args: argparse.Namespace, console) -> int:
    """Run one command, mapping each kind of failure to its exit code and one message."""
    source = _input_name(args)
    try:
        _check_outputs(args)
        with interruptions_raised():
            return args.func(args)
    except (_UsageError, OutputOverwritesInput) as exc:
        parser.print_usage(sys.stderr)
        console.print(f"surfinpaint: error: {_escape(str(exc))}")
        return EXIT_USAGE
    except OutputError as exc:
        console.print(f"[red]error:[/red] {_escape(str(exc))}")
        return EXIT_FAILURE
    except MeshError as exc:
        if exc.path is None and source is not None:
            exc = exc.with_path(source)  # problems found after reading: name the file
        console.print(f"[red]error:[/red] {_escape(str(exc))}")
        return EXIT_FAILURE
    except (InputError, NotImplementedError) as exc:
        console.print(f"[red]error:[/red] {_escape(str(exc))}")
        return EXIT_FAILURE
    except (OSError, ValueError, RuntimeError) as exc:
        named = f"{source}: " if source is not None and str(source) not in str(exc) else ""
        console.print(f"[red]error:[/red] {_escape(named)}{type(exc).__name__}: "
                      f"{_escape(str(exc))}")
        return EXIT_FAILURE


def _escape(text: str) -> str:
    """rich's markup escape, imported when a message is printed (a quiet run that succeeds
    never imports rich)."""
    from rich.markup import escape

    return escape(text)


class _Notices(logging.Handler):
    """The library's INFO notices (the one-time compilation of the numba kernels) as
    ``surfinpaint: ...`` lines on the current stderr, when they happen."""

    def emit(self, record: logging.LogRecord) -> None:
        print(f"surfinpaint: {record.getMessage()}", file=sys.stderr, flush=True)


_NOTICES = _Notices(logging.INFO)


def _show_notices() -> None:
    log = logging.getLogger("surfinpaint")
    if _NOTICES not in log.handlers:
        log.addHandler(_NOTICES)
    log.setLevel(logging.INFO)


def main(argv: Sequence[str] | None = None) -> int:
    """The ``surfinpaint`` command. Returns the exit code: 0 success, 1 failure, 2 usage
    error, 130 after Ctrl-C, 143 after SIGTERM (temporary files removed, one line printed)."""
    with signals_raise():
        try:
            raise_noted()  # a signal that came while the command line was imported
            parser = build_parser(_command_word(argv))
            args = parser.parse_args(argv)
            console = LazyConsole()  # made at its first line: a quiet run may print none
            quiet = args.quiet  # every command's -q (progress.add_quiet)
            if not quiet:
                _show_notices()
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                code = _run(parser, args, console)
            if quiet < 2:  # those the command did not print itself, named as it does
                print_warnings(console, count_warnings(caught), source=_input_name(args),
                               other_files=_other_files(args))
            raise_pending()  # a signal lost in the last moments: raised here, not after
            return code
        except (Interrupted, KeyboardInterrupt) as exc:
            if not isinstance(exc, Interrupted):  # a Ctrl-C that came before our handler
                exc = Interrupted(signal.SIGINT)
            remove_unfinished()  # a write interrupted before it could clean up after itself
            print(f"surfinpaint: {exc}; stopped, no partial output left", file=sys.stderr)
            return exc.exit_code


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
