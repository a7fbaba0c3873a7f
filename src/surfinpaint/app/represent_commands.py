"""``surfinpaint represent`` and ``rebuild``: a disk's λ-H representation (on its own
triangles, a grid or quadtrees) written with its round trip, and the surface rebuilt from
a representation file."""

from __future__ import annotations

import argparse

from surfinpaint.app.fill_options import UsageError as _UsageError
from surfinpaint.app.fill_options import positive_int, whole_number
from surfinpaint.app.progress import QuietConsole, add_quiet, warning_line
from surfinpaint.errors import MeshError, MissingFileError
from surfinpaint.io.formats import read_mesh, write_mesh
from surfinpaint.lazy import lazy_module

# imported at their first use (surfinpaint.lazy), as the command line's other heavy parts
lambda_h_figures = lazy_module("surfinpaint.app.lambda_h_figures")
representation = lazy_module("surfinpaint.representation.represent")
exports = lazy_module("surfinpaint.representation.exports")

__all__ = ["add_representation_parsers", "run_rebuild", "run_represent", "target_list"]


def _grid_options(args: argparse.Namespace) -> dict:
    options = {"sampling": args.sampling, "subdivide": args.subdivide,
               "spacing": args.spacing, "grading": args.grading}
    return {k: v for k, v in options.items() if v is not None}


def _quadtree_options(args: argparse.Namespace) -> dict:
    options = {"sampling": args.sampling, "targets": args.targets}
    return {k: v for k, v in options.items() if v is not None}


def target_list(text: str) -> tuple[float, ...]:
    """``--targets 0.1,0.05,0.02``: the quadtrees' cell sides, × the diagonal, coarse to
    fine (an argparse ``type``)."""
    try:
        targets = tuple(float(t) for t in text.split(",") if t.strip())
    except ValueError:
        targets = ()
    if not targets or any(not 0 < t < 1 for t in targets) or \
            any(b >= a for a, b in zip(targets, targets[1:], strict=False)):
        raise argparse.ArgumentTypeError(
            f"--targets takes decreasing numbers in (0, 1), comma-separated, got {text!r}")
    return targets


def _print_round_trip(says: QuietConsole, check, what: str, source: str) -> None:
    """A round trip's line: a line of the report where it converged, else a warning (kept
    by ``-q``) named for the input ``source``, as every command's warnings are."""
    from rich.markup import escape

    if check.converged:
        says.say(f"{what} [green]{escape(check.summary())}[/green]")
    else:
        says.warn(warning_line(f"{what} {check.summary()}", source))


def _print_export(says: QuietConsole, form, source: str) -> None:
    """A resampled form's own round trip, named by its kind and size."""
    if form.check is None:
        return
    size = exports.form_size(form)
    _print_round_trip(says, form.check, f"quadtree export ({size}):"
                      if form.discretization == "quadtree" else f"grid export {size}:", source)


def _check_represent_options(args: argparse.Namespace) -> None:
    """Refuse an option that nothing asked for would read, and an output not named .npz
    (NumPy archives in a file named otherwise would be taken for something else)."""
    for option, path in (("-o", args.output), ("--export-grid", args.export_grid),
                         ("--export-quadtree", args.export_quadtree)):
        if path is not None and not str(path).lower().endswith(".npz"):
            raise _UsageError(f"{option} {str(path)!r}: a representation is a NumPy .npz "
                              "archive; name it .npz")
    grids = args.discretization == "grid" or args.export_grid
    trees = args.discretization == "quadtree" or args.export_quadtree
    if args.grading is not None and args.spacing != "graded":
        raise _UsageError("--grading is for --spacing graded")
    grid_only = [name for name, value in (("--resolution", args.resolution),
                                          ("--spacing", args.spacing),
                                          ("--grading", args.grading),
                                          ("--subdivide", args.subdivide)) if value is not None]
    if grid_only and not grids:
        raise _UsageError(f"{', '.join(grid_only)}: for --discretization grid or --export-grid")
    if args.targets is not None and not trees:
        raise _UsageError("--targets is for --discretization quadtree or --export-quadtree")
    if args.sampling is not None and not (grids or trees):
        raise _UsageError("--sampling is for a grid or quadtree (--discretization grid or "
                          "quadtree, --export-grid, --export-quadtree)")


def run_represent(args: argparse.Namespace) -> int:
    """``surfinpaint represent``: returns the exit code (0 on success)."""
    says = QuietConsole(args.quiet)
    _check_represent_options(args)
    vertices, faces = read_mesh(args.mesh)
    grid = _grid_options(args)
    if args.discretization == "grid":
        grid["resolution"] = args.resolution or 256
    options = {"auto": {}, "mesh": {}, "grid": grid,
               "quadtree": _quadtree_options(args)}[args.discretization]
    with says.stages() as stage:
        rep = representation.represent(
            vertices, faces, discretization=args.discretization, map=args.map,
            check=not args.no_check, progress=stage, **options)
    rep.save(args.output)
    written = [str(args.output)]
    if rep.check is not None:
        _print_round_trip(says, rep.check, f"{rep.discretization} representation:",
                          str(args.mesh))
    if args.export_grid:
        with says.stages() as stage:
            exported = exports.grid_export(rep, args.resolution,
                                                  check=not args.no_check, progress=stage,
                                                  **grid)
        exported.save(args.export_grid)
        written.append(str(args.export_grid))
        _print_export(says, exported, str(args.mesh))
    if args.export_quadtree:
        with says.stages() as stage:
            trees = exports.quadtree_export(rep, check=not args.no_check,
                                                   progress=stage, **_quadtree_options(args))
        trees.save(args.export_quadtree)
        written.append(str(args.export_quadtree))
        _print_export(says, trees, str(args.mesh))
    if args.export:
        with says.stages() as stage:
            form = exports.resampled_export(rep, check=not args.no_check, progress=stage)
        form.save(args.export)
        written.append(str(args.export))
        _print_export(says, form, str(args.mesh))
    if args.png:
        lambda_h_figures.plot_representation(rep, args.png)
        written.append(str(args.png))
    says.say("wrote " + ", ".join(written))
    return 0


def run_rebuild(args: argparse.Namespace) -> int:
    """``surfinpaint rebuild``: returns the exit code (0 on success)."""
    says = QuietConsole(args.quiet)
    try:
        rep = representation.load_representation(args.representation)
    except FileNotFoundError:
        raise MissingFileError(str(args.representation)) from None
    except (IsADirectoryError, PermissionError) as exc:  # said as a mesh file's read says it
        why = "is a directory, not a representation file" if isinstance(
            exc, IsADirectoryError) else "permission denied: the file cannot be read"
        raise MeshError(why, path=str(args.representation)) from None
    except (OSError, KeyError, ValueError) as exc:
        raise MeshError(f"not a λ-H representation file ({exc})",
                        path=str(args.representation)) from exc
    # the methods a file of each kind takes (a mesh file has taken --method laplacian, once
    # the default, as a no-op)
    methods = {"grid": None, "mesh": (None, "laplacian"), "quadtree": (None,)}
    if methods[rep.discretization] is not None and args.method not in methods[
            rep.discretization]:
        raise _UsageError(f"--method is for grid representations; a {rep.discretization} "
                          "representation is rebuilt on its own triangles")
    with says.stages() as stage:
        stage(f"rebuilding from λ and H ({args.representation})")
        if rep.discretization == "grid":
            out = representation.rebuild(rep, method=args.method)
        else:
            out = representation.rebuild(rep, progress=stage)
    write_mesh(args.output, out.vertices, out.faces)
    _print_round_trip(says, representation.round_trip(rep, out),
                      "against the stored original:", str(args.representation))
    says.say(f"wrote {args.output}")
    return 0


def add_representation_parsers(sub) -> None:
    """``surfinpaint represent`` and ``rebuild``."""
    _add_represent_parser(sub)
    _add_rebuild_parser(sub)


def _add_represent_parser(sub) -> None:
    """``surfinpaint represent``: a mesh to its λ-H representation."""
    p = sub.add_parser("represent", help="λ-H representation of a disk-like mesh",
                       description="Conformally map a disk-topology MESH to the plane and "
                       "store its conformal factor λ and mean curvature H, on the mesh's own "
                       "parameter triangles (default) or on a grid; then rebuild the mesh "
                       "from them and print the round-trip error.")
    p.add_argument("mesh", help="input mesh (a topological disk)")
    p.add_argument("-o", "--output", required=True, help="output .npz")
    p.add_argument("--discretization", choices=("auto", "mesh", "grid", "quadtree"),
                   default="auto",
                   help="auto (default): λ, H at the mesh's vertices, rebuilt on its triangles "
                   "(exact when the rebuild converges), or the quadtrees where that rebuild "
                   "does not converge and theirs does; mesh: always the former; grid: the "
                   "paper's regular grid; quadtree: trees refined where the map squeezes the "
                   "surface")
    p.add_argument("--map", choices=("rectangular", "lscm"), default="lscm",
                   help="conformal map: free-boundary LSCM (default: 2-4x more accurate "
                   "round trips, measured) or the paper's rectangular map")
    p.add_argument("--resolution", type=positive_int,
                   help="grid nodes along the long side (grid: default 256; --export-grid: "
                   "default from λ's range, doubled up to 1024 while the grid's samples "
                   "alone miss the mesh by more than 1 %% of the diagonal)")
    p.add_argument("--export", metavar="NPZ",
                   help="also write the resampled (image) form that gives the mesh back "
                   "within 0.1 %% mean / 1 %% Hausdorff of the diagonal: quadtrees, or the "
                   "square grid where they miss (a warning when neither does), and print "
                   "its own round trip")
    p.add_argument("--export-grid", metavar="NPZ",
                   help="also write the grid (image) form of the representation and print "
                   "its own round trip")
    p.add_argument("--export-quadtree", metavar="NPZ",
                   help="also write the quadtree form (nodes crowded where the map squeezes "
                   "the surface, as on a tall finger or a limb's tip) and print its own "
                   "round trip")
    p.add_argument("--targets", type=target_list, metavar="T1,T2,...",
                   help="quadtree: its trees' cell sides on the surface, × the bounding-box "
                   "diagonal, coarse to fine (default 0.4,0.2,0.1,0.05,0.02); the rebuild goes "
                   "through them in order")
    p.add_argument("--spacing", choices=("uniform", "graded"),
                   help="grid: the paper's square grid (default) or a graded one, densest "
                   "where the map squeezes the surface (a tall finger or a limb's tip)")
    p.add_argument("--grading", type=float, metavar="G",
                   help="graded grid: the share of nodes crowded where the map squeezes, in "
                   "[0, 1) (default 0.8; lower gives squarer cells, which rebuild better)")
    p.add_argument("--sampling", choices=("smooth", "pl"),
                   help="grid, quadtree: sample the C1 (Clough-Tocher) surface through the "
                   "vertices (the grid's default) or the piecewise-linear mesh (the "
                   "quadtree's default)")
    p.add_argument("--subdivide", type=whole_number(0), metavar="LEVELS",
                   help="grid: subdivision levels onto the smooth surface before the map "
                   "(default: automatic, from the mesh's crease angles; 0: none)")
    p.add_argument("--no-check", action="store_true",
                   help="do not rebuild and measure the round trip")
    p.add_argument("--png", help="also write λ and H as images")
    add_quiet(p)
    p.set_defaults(func=run_represent)


def _add_rebuild_parser(sub) -> None:
    """``surfinpaint rebuild``: a λ-H representation back to a mesh."""
    p = sub.add_parser("rebuild", help="rebuild a mesh from a λ-H representation",
                       description="Rebuild the surface from the (λ, H) stored in a .npz "
                       "written by `surfinpaint represent`, and print its distance to the "
                       "original stored with it.")
    p.add_argument("representation", help="a .npz from `surfinpaint represent`")
    p.add_argument("-o", "--output", required=True, help="output mesh")
    p.add_argument("--method", choices=("newton", "laplacian", "gauss-codazzi"),
                   help="grid reconstruction (default newton: the mesh form on the grid's "
                   "own triangles, coarse to fine; laplacian for grid files of format 1); "
                   "mesh and quadtree files are rebuilt by Newton's method on their own "
                   "triangles")
    add_quiet(p)
    p.set_defaults(func=run_rebuild)
