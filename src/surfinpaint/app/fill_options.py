"""The command line's fill options, shared by ``fill`` and ``batch``: the flags
(:func:`add_fill_options`) and the :func:`surfinpaint.fill_holes` arguments they give
(:func:`fill_options`, which builds the :class:`~surfinpaint.ConformalOptions`)."""

from __future__ import annotations

import argparse

from surfinpaint.fill.conformal import ConformalOptions, GridOptions
from surfinpaint.fill.islands import ISLAND_MODES
from surfinpaint.fill.pipeline import METHODS

__all__ = ["UsageError", "add_all_loops", "add_fair_smoothing", "add_fill_options",
           "add_hole_numbers",
           "add_islands", "add_keep_margins", "add_max_hole_edges", "add_zip_seams",
           "fill_options",
           "hole_list", "positive_int", "smoothing_length", "whole_number"]


class UsageError(Exception):
    """A usage error of the command line (exit code 2)."""


def hole_list(text: str) -> list[int]:
    """``--holes 0,2,5`` or ``--holes 0-3,7``: hole numbers as ``surfinpaint holes`` lists
    them, a range ``a-b`` taking both ends (an argparse ``type``).

    Examples
    --------
    >>> hole_list("0-3,7")
    [0, 1, 2, 3, 7]
    """
    numbers: list[int] = []
    for item in (t.strip() for t in text.split(",")):
        first, dash, last = item.partition("-")
        try:
            low, high = int(first), int(last if dash else first)
        except ValueError:
            if not item:
                continue
            raise argparse.ArgumentTypeError(
                f"--holes takes comma-separated hole numbers and ranges (0,2,5 or 0-3,7), "
                f"got {text!r}") from None
        if high < low:
            raise argparse.ArgumentTypeError(f"--holes: the range {item!r} runs backwards")
        numbers.extend(range(low, high + 1))
    if not numbers:  # an empty shell variable: not "fill nothing" (nor "fill them all")
        raise argparse.ArgumentTypeError(f"--holes names no hole, got {text!r}")
    return numbers


def whole_number(minimum: int):
    """An argparse ``type``: a whole number of at least ``minimum`` (else a usage error,
    exit 2)."""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"must be at least {minimum}, got {value}")
        return value

    return parse


positive_int = whole_number(1)


def smoothing_length(text: str) -> float | str | None:
    """``--fair-smoothing``: "auto", "off" (None) or a positive length in mean edges (an
    argparse ``type``).

    Examples
    --------
    >>> smoothing_length("auto"), smoothing_length("off"), smoothing_length("0.4")
    ('auto', None, 0.4)
    """
    if text in ("auto", "off"):
        return None if text == "off" else text
    try:
        value = float(text)
    except ValueError:
        value = -1.0
    if not value > 0.0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"expected auto, off or a positive length in mean "
                                         f"edges, got {text!r}")
    return value


def _conformal_options(args: argparse.Namespace):
    """The conformal method's options from the flags of ``fill`` (None with ``--method
    fair``; conformal flags with it are a usage error)."""
    grid_flags = {"inpaint": args.inpaint, "reconstruct": args.reconstruct}
    if args.discretization != "grid" and (args.reconstruct or args.inpaint == "harmonic"):
        raise UsageError("--reconstruct and --inpaint harmonic need --discretization grid "
                          "(the mesh discretization inpaints biharmonically and rebuilds "
                          "in the Laplacian form, solved together)")
    if args.crease_angle is not None and not 0.0 < args.crease_angle < 180.0:
        raise UsageError(f"--crease-angle must be between 0 and 180 degrees, got "
                          f"{args.crease_angle:g}")
    if args.method != "conformal":
        given = [flag for flag, value in (
            ("--discretization grid", args.discretization == "grid"),
            ("--no-creases", args.no_creases), ("--crease-angle", args.crease_angle),
            ("--no-plane-test", args.no_plane_test), ("--no-ear-cut", args.no_ear_cut),
            ("--fair-smoothing", args.fair_smoothing != "auto"),
            ("--inpaint", args.inpaint), ("--reconstruct", args.reconstruct)) if value]
        if given:
            raise UsageError(f"{', '.join(given)}: options of --method conformal")
        return None
    kw = {"discretization": args.discretization, "creases": not args.no_creases,
          "plane_test": not args.no_plane_test, "fair_smoothing": args.fair_smoothing}
    if args.no_ear_cut:
        kw["ear_cut_flat"] = None
    if args.crease_angle is not None:
        kw["crease_angle"] = args.crease_angle
    if args.discretization == "grid":
        kw["grid"] = GridOptions(**{k: v for k, v in grid_flags.items() if v})
    return ConformalOptions(**kw)


def fill_options(args: argparse.Namespace) -> dict:
    """The keyword arguments of :func:`surfinpaint.fill_holes` given by the fill options
    (:func:`add_fill_options`) of ``fill`` and ``batch``; usage errors raised."""
    return {"method": args.method, "include_border": args.all,
            "keep_margins": args.keep_margins,
            "max_hole_edges": args.max_hole_edges, "repair": args.repair,
            "zip_seams": args.zip_seams, "islands": args.islands,
            "fair_order": args.fair_order, "options": _conformal_options(args)}


# The options that choose which loops are filled: one definition each, for `fill` and
# `batch` (add_fill_options; --holes: fill only) and for `holes` and `report`, which say what
# such a fill does


def add_fair_smoothing(parser) -> None:
    """``--fair-smoothing`` (``ConformalOptions.fair_smoothing``): ``fill``, ``batch`` and
    ``report``, which draws the fill ``fill`` with it writes."""
    parser.add_argument("--fair-smoothing", type=smoothing_length, default="auto",
                        metavar="{auto,off,LENGTH}",
                        help="the bilaplacian candidate as a thin-plate smoothing fill that "
                        "follows the known surface around the hole within its noise: 'auto' "
                        "(default) where that surface reads as a range scan's noise, 'off' "
                        "never, or always with this smoothing length in mean edges (the "
                        "report says per hole which were smoothed, and -v why not)")


def add_max_hole_edges(parser) -> None:
    """``--max-hole-edges N`` (``max_hole_edges``: holes over N boundary edges skipped)."""
    parser.add_argument("--max-hole-edges", type=positive_int, metavar="N",
                        help="skip holes with more than N boundary edges")


def add_zip_seams(parser) -> None:
    """``--zip-seams`` (``zip_seams``: seams of duplicated vertices zipped)."""
    parser.add_argument("--zip-seams", action="store_true",
                        help="close a seam of duplicated coincident vertices (a loop that "
                        "spans no area, as exporters write along a UV seam) by having its "
                        "faces use one vertex of each pair; without it such loops are left "
                        "open with a warning (no loop that spans no area is ever filled)")


def add_hole_numbers(parser) -> None:
    """``--holes 0,2,5`` (``holes``: only these loops, by ``surfinpaint holes``' numbers)."""
    parser.add_argument("--holes", type=hole_list,
                        help="only these holes, by the numbers `surfinpaint holes` gives "
                        "them: comma-separated, ranges taken whole (0,2,5 or 0-3,7; "
                        "default: every hole but the outer border); the others are left "
                        "open")


def add_all_loops(parser) -> None:
    """``--all`` (``include_border``: the loops that look like an outer border filled too)."""
    parser.add_argument("--all", action="store_true",
                        help="also fill loops that look like the surface's outer border")


def add_keep_margins(parser) -> None:
    """``--keep-margins`` (``keep_margins``: the loops that may be a margin left open)."""
    parser.add_argument("--keep-margins", action="store_true",
                        help="also leave open the loops that may be a margin of the surface "
                        "('the margin?' in `holes`): a piece's largest loop spanning 10-40%% "
                        "of its area (a tooth crown scanned down to the gum), or a loop "
                        "inside its outer border spanning at least 20%% (the inner edge of a "
                        "scanned ring or bore); filled by default, with a warning")


def add_islands(parser) -> None:
    """``--islands {bridge,ignore}`` (``islands``: what a hole with a floating piece of
    surface inside it is filled with)."""
    parser.add_argument("--islands", choices=ISLAND_MODES, default="bridge",
                        help="a small piece of surface with one loop lying inside a hole "
                        "(a scan's floating fragment) is that hole's island: 'bridge' "
                        "(default) fills the region between the two loops (faired, noted "
                        "'with its island'), 'ignore' fills the hole as a disk through or "
                        "by it, with a warning; the island is never deleted")


def add_fill_options(parser: argparse.ArgumentParser) -> None:
    """The options that say how holes are filled, shared by ``fill`` and ``batch`` (read
    back by :func:`fill_options`)."""
    p = parser.add_argument_group("fill options")
    p.add_argument("--method", choices=METHODS, default="conformal",
                   help="conformal (default) or the conventional fill 'fair'")
    add_max_hole_edges(p)
    add_zip_seams(p)
    add_all_loops(p)
    add_keep_margins(p)
    add_islands(p)
    p.add_argument("--repair", action="store_true",
                   help="remove the faces around non-manifold edges and bow-tie vertices "
                   "(where separate fans of faces meet) first, flip the fewest faces that "
                   "orient each piece consistently, and turn a closed piece wound inward "
                   "outward; then fill the holes that leaves")
    p.add_argument("--discretization", choices=("mesh", "grid"), default="mesh",
                   help="where the conformal method's λ and H live: on the patch's "
                   "triangles (default, measured more accurate) or on the paper's regular "
                   "grid over the conformal domain")
    p.add_argument("--no-creases", action="store_true",
                   help="fill every hole as smooth (by default sharp creases that cross a "
                   "hole, or meet at a corner in it, are continued across it and each "
                   "side filled on its own)")
    p.add_argument("--no-plane-test", action="store_true",
                   help="never lay a hole's faired fill on the plane of the surface around "
                   "it (by default, where that surface is a plane within its noise, as on "
                   "a range scan's flat face, or two planes meeting at a scanned edge, it "
                   "is, and no self-check runs)")
    p.add_argument("--no-ear-cut", action="store_true",
                   help="never write the ear-cut fill (by default, where the loop's ear-cut "
                   "triangulation is nearly all pieces of the known faces' planes and two "
                   "of them meet inside the hole, as across a machined part's edge, that "
                   "triangulation refined within its planes is written, and no self-check "
                   "runs)")
    add_fair_smoothing(p)
    p.add_argument("--crease-angle", type=float, metavar="DEG",
                   help="turn between neighbouring faces (degrees) above which an edge is "
                   "part of a crease (default 60)")
    p.add_argument("--inpaint", choices=("biharmonic", "harmonic"),
                   help="inpainting model for λ and H (default biharmonic; harmonic needs "
                   "--discretization grid)")
    p.add_argument("--reconstruct", choices=("gauss-codazzi", "laplacian"),
                   help="reconstruction from (λ, H) with --discretization grid")
    p.add_argument("--fair-order", type=int, choices=(1, 2, 3),
                   help="fairing order: 1 harmonic, 2 biharmonic (default of 'fair', the "
                   "classic baseline), 3 triharmonic; the conformal method chooses its "
                   "fallback between 2 and 3 per hole by its self-check unless told")
