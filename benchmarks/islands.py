"""Holes with islands: the fill of the annulus against the disk fills, on tuning-side meshes.

For each case an annulus of faces (geodesic distance from a centre vertex, along the edges,
between two radii) is cut from a tuning-side mesh: the faces inside it stay as an island,
a piece of its own inside the hole. Each fill is compared with the removed surface by the
benchmarks' two-sided mean distance (:func:`surfinpaint.geometry.metrics.surface_distance`,
as ``benchmarks/accuracy.py`` scores), in % of the hole's diameter:

- ``bridge2``, ``bridge3``: ``fill_holes`` with ``islands="bridge"`` (the default), the
  annulus filled and faired with order 2 or 3 (``method="fair", fair_order=``; the annulus
  fill is the same under either method), against the removed annulus;
- ``ignore``: today's fill (``islands="ignore"``, the conformal method): a disk through or
  by the island, against the removed annulus and the island (the whole disk of surface);
- ``removed``, ``removed_fair``: the island deleted first and the disk hole filled by the
  conformal method and by the faired fill (order 2), against the same whole disk.

For the bridge fills the distance to the whole disk is given too, the island (exact) counted
as part of the patch: the figure to set beside ``ignore`` and ``removed``.

``--sweep``: on the same meshes, annuli at 6 seeded centres a mesh, inner radius 2 or 3
and outer 6 or 9 mean edge lengths: per cut, whether the island was found and joined, the
intersecting pairs of triangles in the result and the two distances of ``bridge3`` and
``removed``.

Run::

    .venv/bin/python benchmarks/islands.py
    .venv/bin/python benchmarks/islands.py --sweep
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import dijkstra

sys.path.insert(0, str(Path(__file__).parent))
import validation_meshes as vm  # noqa: E402

from surfinpaint import data  # noqa: E402
from surfinpaint.fill.holes import find_holes  # noqa: E402
from surfinpaint.fill.pipeline import fill_holes  # noqa: E402
from surfinpaint.geometry.intersection import self_intersections  # noqa: E402
from surfinpaint.geometry.metrics import hole_patch_of, surface_distance  # noqa: E402


def geodesic(vertices: np.ndarray, faces: np.ndarray, centre: int) -> np.ndarray:
    """Shortest path lengths along the edges from vertex ``centre``."""
    e = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    w = np.linalg.norm(vertices[e[:, 0]] - vertices[e[:, 1]], axis=1)
    n = len(vertices)
    g = sp.coo_matrix((w, (e[:, 0], e[:, 1])), shape=(n, n)).tocsr()
    return dijkstra(g, directed=False, indices=centre)


def annulus_cut(vertices, faces, centre: int, r_in: float, r_out: float):
    """The faces kept (an island inside a hole) and the masks of the removed annulus and of
    the island, by their corners' mean geodesic distance from ``centre``."""
    d = geodesic(vertices, faces, centre)[faces].mean(axis=1)
    ring = (d > r_in) & (d < r_out)
    island = d <= r_in
    return faces[~ring], ring, island


def _sphere():
    v, f = data.sphere(4)
    c = v[f].mean(1)
    ang = np.degrees(np.arccos(np.clip(c[:, 2] / np.linalg.norm(c, axis=1), -1, 1)))
    ring, island = (ang > 8) & (ang < 25), ang <= 8
    return v, f, ring, island


def _cut(make, centre_of, r_in, r_out):
    def case():
        v, f = make()
        centre = centre_of(v, f)
        _, ring, island = annulus_cut(v, f, centre, r_in(v, f), r_out(v, f))
        return v, f, ring, island
    return case


def _edge(v, f):
    return float(np.linalg.norm(v[f[:, 0]] - v[f[:, 1]], axis=1).mean())


def _nearest(point):
    return lambda v, f: int(np.argmin(np.linalg.norm(v - np.asarray(point), axis=1)))


def _bunny_scan():
    bunny = vm.SOURCES["bunny"].make()
    scan = vm.simulated_scan(bunny.vertices, bunny.faces, (0.3, 0.2, 1.0), seed=1,
                             portable=True)
    return scan.vertices, scan.faces


def _scan_centre(v, f):
    """The vertex farthest from the scan's border and its own holes (along the edges)."""
    from surfinpaint.geometry.mesh import boundary_loops

    e = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    w = np.linalg.norm(v[e[:, 0]] - v[e[:, 1]], axis=1)
    g = sp.coo_matrix((w, (e[:, 0], e[:, 1])), shape=(len(v), len(v))).tocsr()
    d = dijkstra(g, directed=False, indices=np.concatenate(boundary_loops(f)), min_only=True)
    return int(np.argmax(np.where(np.isfinite(d), d, -1)))


CASES = {
    "sphere": _sphere,
    "torus": _cut(lambda: data.torus(), _nearest([1.4, 0.0, 0.0]),
                  lambda v, f: 2.5 * _edge(v, f), lambda v, f: 7 * _edge(v, f)),
    "scan_bunny_portable": _cut(_bunny_scan, _scan_centre, lambda v, f: 3 * _edge(v, f),
                                lambda v, f: 9 * _edge(v, f)),
    "pial_left": _cut(lambda: data.fsaverage5("pial", "left"), _nearest([-60.0, -20.0, 20.0]),
                      lambda v, f: 2.5 * _edge(v, f), lambda v, f: 7 * _edge(v, f)),
}


def _score(v, result, report, truth_faces, diameter, with_faces=None):
    """The mean distance of ``report``'s fill (the island's faces too: ``with_faces``) to
    the truth, in % of ``diameter``."""
    faces = result.hole_faces()[result.reports.index(report)]
    pv, pf = hole_patch_of(result.vertices, faces, len(v), np.empty((0, 3), dtype=np.int64))
    if with_faces is not None:  # the island counted as part of the patch
        offset = len(pv)
        pv = np.vstack([pv, v])
        pf = np.vstack([pf, with_faces + offset])
    d = surface_distance(pv, pf, v, truth_faces)
    return 100.0 * d.mean / diameter


def run_case(name: str) -> dict:
    v, f, ring, island = CASES[name]()
    kept = f[~ring]
    holes = find_holes(v, kept)
    out = {"case": name, "loops": [(h.n_edges, h.is_border, h.component) for h in holes]}
    # the hole cut: the loop of the piece around the island along the removed annulus
    on_ring = np.zeros(len(v), dtype=bool)
    on_ring[f[ring]] = True
    number = max((k for k, h in enumerate(holes) if not h.is_border),
                 key=lambda k: on_ring[holes[k].loop].mean())
    hole = holes[number]
    diameter = hole.diameter
    annulus, disk = f[ring], f[ring | island]
    rows = {}
    for label, kw in (("bridge2", {"method": "fair", "fair_order": 2}),
                      ("bridge3", {"method": "fair", "fair_order": 3}),
                      ("ignore", {"islands": "ignore"})):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            res = fill_holes(v, kept, jobs=1, **kw)
        report = next(r for r in res.reports if r.index == number)
        crossing = len(self_intersections(res.vertices, res.faces))
        if label.startswith("bridge"):
            rows[label] = (_score(v, res, report, annulus, diameter),
                           _score(v, res, report, disk, diameter, f[island]),
                           report.outcome, report.note, crossing)
        else:
            rows[label] = (_score(v, res, report, annulus, diameter),
                           _score(v, res, report, disk, diameter),
                           report.outcome, f"{len(caught)} warnings", crossing)
    without = f[~ring & ~island]
    for label, kw in (("removed", {}), ("removed_fair", {"method": "fair", "fair_order": 2})):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = fill_holes(v, without, jobs=1, **kw)
        # the disk hole: the loop on the annulus's outer side
        report = max(res.reports, key=lambda r: on_ring[r.loop].mean())
        crossing = len(self_intersections(res.vertices, res.faces))
        rows[label] = (float("nan"), _score(v, res, report, disk, diameter),
                       report.outcome, report.note, crossing)
    out["diameter"] = diameter
    out["rows"] = rows
    return out


MESHES = {
    "torus": lambda: data.torus(),
    "scan_bunny_portable": _bunny_scan,
    "pial_left": lambda: data.fsaverage5("pial", "left"),
    "sphere": lambda: data.sphere(4),
}


def sweep() -> None:
    """The cuts of ``--sweep`` (see the module's docstring), one line each."""
    for name, make in MESHES.items():
        v, f = make()
        h = _edge(v, f)
        rng = np.random.default_rng(37)
        border = np.zeros(len(v), dtype=bool)  # a scan's border and its own holes
        for loop in find_holes(v, f):
            border[loop.loop] = True
        centres = rng.choice(len(v), 6, replace=False)
        for centre in centres:
            for r_in, r_out in ((2, 6), (3, 9)):
                kept, ring, island = annulus_cut(v, f, int(centre), r_in * h, r_out * h)
                if not ring.any() or not island.any() or border[f[ring | island]].any():
                    print(f"{name} centre {centre} r {r_in}-{r_out}h: reaches the border")
                    continue
                holes = find_holes(v, kept)
                on_ring = np.zeros(len(v), dtype=bool)
                on_ring[f[ring]] = True
                with warnings.catch_warnings(record=True) as caught:
                    warnings.simplefilter("always")
                    res = fill_holes(v, kept, jobs=1)
                report = max(res.reports, key=lambda r: on_ring[r.loop].mean())
                pairs = len(self_intersections(res.vertices, res.faces))
                d_bridge = _score(v, res, report, f[ring | island], report.diameter,
                                  f[island]) if report.islands else float("nan")
                without = f[~ring & ~island]
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    alone = fill_holes(v, without, jobs=1)
                other = max(alone.reports, key=lambda r: on_ring[r.loop].mean())
                d_removed = _score(v, alone, other, f[ring | island], report.diameter)
                said = sorted({str(w.message)[:60] for w in caught if "island" in str(w.message)})
                print(f"{name} centre {centre} r {r_in}-{r_out}h: {len(holes)} loops, "
                      f"{report.outcome}, islands {report.islands}, pairs {pairs}, "
                      f"bridge {d_bridge:.3f} %, removed {d_removed:.3f} % {said}")


def main() -> None:
    if sys.argv[1:] == ["--sweep"]:
        sweep()
        return
    for name in (sys.argv[1:] or CASES):
        out = run_case(name)
        print(f"{name}: loops {out['loops']}, hole diameter {out['diameter']:.4g}")
        print(f"  {'fill':14s} {'annulus %':>10s} {'disk %':>8s}  outcome  intersecting pairs")
        for label, (a, d, outcome, note, crossing) in out["rows"].items():
            print(f"  {label:14s} {a:10.3f} {d:8.3f}  {outcome}  {crossing}  {note or ''}")


if __name__ == "__main__":
    main()
