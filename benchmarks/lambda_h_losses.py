"""Where the λ-H fill's error comes from on the holes where it is written and loses to the
faired fills (session 51 helper; docs/candidates.md "Session 51 (helper): where the λ-H fill's
error comes from on smooth closed shapes").

Step 1, ``--collect``: the cases. From ``validation.py`` rows (holdouts; ``conformal`` status
``ok`` is a written λ-H fill) and ``selfcheck_table.py`` caches (``library.method ==
"conformal"``), every hole where the written λ-H fill is > 1.5× the better faired fill
(``loss``) or more than 1.5× closer than it (``control``).

Step 2, ``--run``: per case, on the truth's own triangulation (the removed vertices as the
fill, ``error_sources.truth_as_fill``), on the patch and map the library's coupled solve
would use there (``mesh_pass._mapped_patch``, ``rings_in_patch`` rings), the coupled λ-H
solve of :mod:`surfinpaint.representation.on_mesh` with parts of it replaced by the truth
(λ and H measured on the truth at the same vertices and map, as the solve measures them):

- ``λ-H T``: the coupled solve as the library makes it (λ and H inpainted);
- ``true λ``: λ at the free vertices pinned to the truth's, H inpainted (coupled);
- ``true H``: H at the free vertices pinned to the truth's, λ inpainted;
- ``true λ,H``: both pinned: the rebuild's own floor (the discrete Laplacian's tangential
  part is not in ``L φ = M 2λ²H n``);
- ``fair3 T``: trilaplacian fairing of the truth's interior vertices (the like-for-like
  baseline); ``fair2``, ``fair3``, ``λ-H``: the faired fills and the library's λ-H fill
  (S0 = fair3, ``Candidates.lambda_h``) on the fill's own triangles.

Screens of the H model, on the same patch (each a coupled solve; ``lagged_solve``, no Newton
stage, so a variant that needs one is missing):

- ``H biharmonic``, ``H triharmonic``, ``H surface bih``, ``H harmonic``: H over the free
  vertices pinned to the continuation of the truth's H on every other vertex (``L M⁻¹ L``,
  ``L M⁻¹ L M⁻¹ L``, ``L (λ²M)⁻¹ L``, ``L``), λ inpainted: uncoupled H models, compared with
  each other (all far worse than the coupled ``λ-H T``: the rim's discrete H is noisy and
  the coupled solve does not take the ring next to the hole as data);
  ``H of fair3 T``: H pinned to the trilaplacian fill's own;
- ``κ=…``: the library's coupled solve with ``κ/ē² L`` added to H's ``L M⁻¹ L`` (ē the map's
  mean edge): towards a harmonic continuation;
- ``rim avg k``: the library's coupled solve with the H data (the stencil's, from the known
  surface) averaged k times with their known neighbours first.

Errors: two-sided mean distance to the removed surface in % of the hole's diameter (4000
samples, ``lambda_h_sources.error_pct``). And the inpainted λ and H at the ``λ-H T`` fixed
point against the truth's (relative RMS over the free vertices; ``H err d1`` over the free
vertices next to a fixed one, ``H err deep`` over the rest), and fair3 T's own H on the same
map (``H err fair3 T``).

    python benchmarks/lambda_h_losses.py --collect /tmp/cases.json \\
        --rows /work/s43/holdout19.json ... --caches /work/s49/chooser/tuning.jsonl ...
    python benchmarks/lambda_h_losses.py --run /tmp/cases.json --out /tmp/rows.jsonl \\
        [--kinds organic,smooth,teeth,brain] [--same-meshes]
    python benchmarks/lambda_h_losses.py --table /tmp/rows.jsonl [--run /tmp/cases.json ...]

Only tuning-side sets and the spent holdouts 9–26 are read (``--run`` refuses others).
"""

from __future__ import annotations

import argparse
import json
import re
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import dijkstra

sys.path.insert(0, str(Path(__file__).parent))
import cgal_s0  # noqa: E402 - its guard: the newest spent holdout
import smooth_selfcheck_study as study  # noqa: E402
from error_sources import truth_as_fill  # noqa: E402
from lambda_h_sources import (  # noqa: E402
    biharmonic,
    error_pct,
    faired_and_lambda_h,
    patch_error,
    relative_rms,
)

from surfinpaint.errors import FillError  # noqa: E402
from surfinpaint.fill.conformal.mesh_pass import _mapped_patch  # noqa: E402
from surfinpaint.fill.conformal.options import SOLVER_TOL, ConformalOptions  # noqa: E402
from surfinpaint.fill.liepa.fairing import fair  # noqa: E402
from surfinpaint.geometry.linalg import definite_lu  # noqa: E402
from surfinpaint.geometry.mesh import boundary_halfedges, vertex_adjacency  # noqa: E402
from surfinpaint.geometry.vertex_measures import vertex_normals_and_areas  # noqa: E402
from surfinpaint.representation import on_mesh  # noqa: E402
from surfinpaint.representation.vertex_lambda_h import border_vertices  # noqa: E402

BENCH = Path(__file__).parent
# the spent holdouts (tuning-side study data); later ones are never read here
SPENT = range(9, cgal_s0.NEWEST_SPENT_HOLDOUT + 1)
LOSS, CONTROL = 1.5, 1.5
SMOOTHING = 3
RIM = 3
# the coupled solve with a harmonic term in H's inpainting, κ/ē² L added to L M⁻¹ L
KAPPAS = (0.03, 0.1, 0.3, 1.0)
# the coupled solve with the H data (the stencil's, from the known surface) averaged with the
# known neighbours this many times first: is the rim's noise what the inpainting carries in?
RIM_AVERAGES = (1, 3)
COLUMNS = ("fair2", "fair3", "λ-H", "fair3 T", "λ-H T", "true λ", "true H", "true λ,H",
           "H biharmonic", "H triharmonic", "H surface bih", "H harmonic", "H of fair3 T",
           *(f"κ={k:g}" for k in KAPPAS), *(f"rim avg {k}" for k in RIM_AVERAGES))
MEASURES = ("H err λ-H T", "H err d1", "H err deep", "H err fair3 T", "H low λ-H T",
            "H low fair3 T", "H bias λ-H T", "H bias fair3 T", "λ err λ-H T", "λ err deep",
            "H rim/in", "H rim noise")
VARIANTS = {"λ-H T": (False, False), "true λ": (True, False), "true H": (False, True),
            "true λ,H": (True, True)}
# H over the free vertices pinned to a prediction from the truth's H on the fixed vertices
# (λ inpainted, coupled): the continuation models of H, judged by the surface they give
PREDICTIONS = ("H biharmonic", "H triharmonic", "H surface bih", "H harmonic", "H of fair3 T")


# --------------------------------------------------------------------------- step 1: cases


def _case(which, mesh, hole, kind, edges, fair2, fair3, written, lambda_h_written):
    better = min(fair2, fair3)
    ratio = written / better
    group = ("loss" if lambda_h_written and ratio > LOSS else
             "control" if lambda_h_written and ratio * CONTROL < 1.0 else "")
    return {"set": which, "mesh": mesh, "hole": hole, "kind": kind, "edges": edges,
            "fair2": fair2, "fair3": fair3, "written": written, "ratio": ratio,
            "closer": "fair3" if fair3 < fair2 else "fair2", "group": group}


def cases_of_rows(path: Path) -> list[dict]:
    """Cases of a ``validation.py`` rows file (the set named by its rows' split)."""
    rows = json.loads(path.read_text())["rows"]
    by = {}
    for r in rows:
        by.setdefault((r["case"], r["hole"]), {})[r["method"]] = r
    out = []
    for (mesh, k), m in by.items():
        if not {"fair", "fair3", "conformal"} <= set(m):
            continue
        if not all(np.isfinite(m[x]["mean_pct"]) for x in ("fair", "fair3", "conformal")):
            continue
        c = m["conformal"]
        out.append(_case(c["extra"]["split"], mesh, k, c["extra"]["kind"], c["boundary_edges"],
                         m["fair"]["mean_pct"], m["fair3"]["mean_pct"], c["mean_pct"],
                         c["status"] == "ok"))
    return out


def cases_of_cache(path: Path) -> list[dict]:
    """Cases of a ``selfcheck_table.py --library`` cache (the set named by the file)."""
    out, seen = [], set()
    for line in path.read_text().splitlines():
        r = json.loads(line)
        lib = r.get("library") or {}
        key = (r["mesh"], r["hole"])
        if key in seen or "true" not in lib or not {"fair2", "fair3"} <= set(r["true"]):
            continue
        seen.add(key)
        out.append(_case(path.stem, r["mesh"], r["hole"], r["kind"], r["n_edges"],
                         r["true"]["fair2"], r["true"]["fair3"], lib["true"],
                         lib.get("method") == "conformal" and not lib.get("crease")))
    return out


def selected(cases: list[dict], groups, kinds=None, same_meshes: bool = False) -> list[dict]:
    """The cases of ``groups`` and ``kinds`` (all kinds when None); with ``same_meshes``, the
    controls only on meshes (of a set) that have a loss among them."""
    out = [c for c in cases if c["group"] in groups and (kinds is None or c["kind"] in kinds)]
    if same_meshes:
        lost = {(c["set"], c["mesh"]) for c in out if c["group"] == "loss"}
        out = [c for c in out if c["group"] == "loss" or (c["set"], c["mesh"]) in lost]
    return out


# --------------------------------------------------------------------------- step 2: oracles


class PinnedSystem(on_mesh._CoupledSystem):
    """The library's coupled λ-H system with λ and/or H at the free vertices pinned to given
    values instead of inpainted, or H inpainted with ``L M⁻¹ L + κ/ē² L`` (``harmonic`` = κ,
    ē the map's mean edge length: between the library's biharmonic model, κ = 0, and a
    harmonic one); λ stays biharmonic. :meth:`_lagged_solve` is the library's otherwise
    (checked: no pin and κ = 0 give its fill to round-off)."""

    lam_pin: np.ndarray | None = None
    H_pin: np.ndarray | None = None

    def __init__(self, points, faces, uv, free, natural=None, harmonic=0.0, averages=0):
        super().__init__(points, faces, uv, free, natural)
        if averages:
            self.H_stencil = self.averaged_stencil_H(points, averages)
        # λ's operators as the library's; H's own, from Q + κ L where κ > 0
        self.lam_Q_fk = self.Q_fk
        if harmonic <= 0.0:
            return
        if self.n_crease:
            raise FillError("the harmonic term is screened on patches without a natural border")
        f, L, area = self.f, self.L, self.area
        uv3 = np.column_stack([uv, np.zeros(len(uv))])
        edge = on_mesh.mean_edge_length(uv3, faces)
        Q = (L @ sp.diags(1.0 / area) @ L + (harmonic / edge**2) * L).tocsr()[f]
        self.Q_lu = definite_lu(Q[:, f].tocsc())
        self.Q_ft, self.Q_fs = Q[:, self.tied], Q[:, self.stencil]
        self.Y = self.Q_lu.solve(self.Q_ft.toarray())

    def averaged_stencil_H(self, points, times):
        """H at the stencil, each pass the mean over the vertex and its neighbours among the
        known vertices (not free, not tied to them, not on the patch's border)."""
        if len(self.natural_data):
            raise FillError("the rim average is screened on patches without a natural border")
        n = len(points)
        H = lambda_h_at(points, self.faces, None, L=self.L, area=self.area)[1]
        known = np.ones(n, dtype=bool)
        known[self.f] = known[self.tied] = False
        known[border_vertices(self.faces)] = False
        A = (vertex_adjacency(self.faces, n).astype(float) + sp.identity(n)).tocsr()
        A = A @ sp.diags(known.astype(float))
        weight = np.maximum(np.asarray(A.sum(axis=1)).ravel(), 1.0)
        H = np.where(known, H, 0.0)
        for _ in range(times):
            H = np.where(known, (A @ H) / weight, 0.0)
        return H[self.stencil]

    def _lagged_solve(self, phi):
        f, tied, area, lam = self.f, self.tied, self.area, self.lam
        H_stencil = self.stencil_H(phi) if len(self.natural_data) else self.H_stencil
        normals, areas = vertex_normals_and_areas(phi, self.near)
        m = self.moving
        lam[m] = np.sqrt(areas[m] / area[m])
        lam[f] = (self.lam_pin[f] if self.lam_pin is not None
                  else self.lam_lu.solve(-(self.lam_Q_fk @ lam[self.fixed])))
        s = 2.0 * lam**2
        d_n = normals[f] * (area[f] * s[f])[:, None]
        if self.H_pin is not None:
            H_f = self.H_pin[f]
        else:  # the library's H solve (H at the tied ring tied to φ)
            w_n = normals[tied] / (area[tied] * s[tied])[:, None]
            K = self.Z_t * (w_n @ d_n.T)
            if self.n_crease:
                K = np.hstack([K, np.zeros((len(tied), self.n_crease))])
            b = (-(self.Q_ft @ np.einsum("ij,ij->i", w_n, self.L_t_phi))
                 - self.Q_fs @ H_stencil)
            y = self.Q_lu.solve(b)
            C = np.eye(len(tied)) + K @ self.Y
            H_f = (y - self.Y @ np.linalg.solve(C, K @ y))[:len(f)]
        new = self.g + self.L_lu.solve(d_n * H_f[:, None])
        if not np.isfinite(new).all():
            raise FillError("the pinned λ-H solve is not finite")
        return new, None


def lagged_solve(system, points, iterations):
    """The library's lagged iteration on ``system`` (in full steps mixed by Anderson, then in
    half steps with three times the iterations), without its Newton stage, whose Jacobian is
    the unpinned system's: a variant that needs it fails (FillError)."""
    try:
        return on_mesh._coupled_solve(system, points, iterations, SOLVER_TOL, 1.0)
    except FillError:
        return on_mesh._coupled_solve(system, points, 3 * iterations, SOLVER_TOL, 0.5)


def lambda_h_at(points, faces, uv, L=None, area=None):
    """λ and H at every vertex as the coupled system measures them (λ² = 3D / map area,
    ``H = n · (L φ) / (2λ² M)``), with the system's own operators (the map's ``L`` and
    ``area``, made from ``uv`` when not given)."""
    if L is None:
        L, area = on_mesh.laplacian_and_areas(uv, faces)
    normals, areas = vertex_normals_and_areas(points, faces)
    lam2 = areas / area
    H = np.einsum("ij,ij->i", L @ points, normals) / (2.0 * lam2 * area)
    return np.sqrt(lam2), H


def depth_from_fixed(faces, free):
    """Hops from each vertex to the nearest vertex not ``free``."""
    A = vertex_adjacency(faces, len(free)).astype(float)
    fixed = np.flatnonzero(~free)
    d = dijkstra(sp.csr_matrix(A), unweighted=True, indices=fixed, min_only=True)
    return d


def oracle_row(cut) -> dict:
    """Every column and measure of one hole (NaN where a variant fails)."""
    faces, loop = cut.faces, cut.loop
    options = ConformalOptions()
    row: dict = {c: float("nan") for c in (*COLUMNS, *MEASURES)}
    notes: list[str] = []
    faired_and_lambda_h(cut, options, row, notes)
    truth, truth_faces, inner = truth_as_fill(cut)
    fair3_t = fair(truth, np.vstack([faces, truth_faces]), inner, 3)
    row["fair3 T"] = error_pct(fair3_t, truth_faces, cut)
    try:
        _, ids, local, uv, used, map_name = _mapped_patch(truth, faces, loop, truth_faces,
                                                          options.rings_in_patch)
    except FillError as exc:
        row["notes"] = f"no map: {exc}"
        return row
    row["rings"], row["map"] = int(used), map_name
    on_border = np.zeros(len(truth), dtype=bool)
    on_border[boundary_halfedges(faces).ravel()] = True
    on_border[loop] = False
    points, free, natural = truth[ids], np.isin(ids, inner), on_border[ids]
    lam_true, H_true = lambda_h_at(points, local, uv)
    pins = {name: (lam_true if pin_lam else None, H_true if pin_H else None, 0.0)
            for name, (pin_lam, pin_H) in VARIANTS.items()}
    pins.update({name: (None, H, 0.0) for name, H in predictions(points, local, uv, free, lam_true,
                                                            H_true, fair3_t[ids]).items()})
    pins.update({f"κ={k:g}": (None, None, k) for k in KAPPAS})
    pins.update({f"rim avg {k}": (None, None, 0.0, k) for k in RIM_AVERAGES})
    for name, (lam_pin, H_pin, *kappa) in pins.items():
        try:
            if name == "λ-H T":  # the library's solve, with its Newton stage
                solved = on_mesh.inpaint_on_mesh(points, local, uv, free, natural=natural,
                                                 iterations=options.solver_iterations,
                                                 tol=SOLVER_TOL)
            else:
                system = PinnedSystem(points, local, uv, free, natural, *kappa)
                system.lam_pin, system.H_pin = lam_pin, H_pin
                solved = lagged_solve(system, points, options.solver_iterations)
        except FillError as exc:
            notes.append(f"{name}: {str(exc)[:60]}")
            continue
        row[name] = patch_error(truth, ids, solved, truth_faces, cut)
        if name == "λ-H T":
            measured(row, local, uv, free, solved, lam_true, H_true, fair3_t[ids])
    row["notes"] = "; ".join(notes)
    return row


def predictions(points, faces, uv, free, lam_true, H_true, fair3_points) -> dict:
    """Predictions of H over the free vertices from the truth's H on the others
    (``lambda_h_sources.biharmonic``: the free entries of ``Q x = 0``), each model that could
    be made: ``L M⁻¹ L`` (the library's), ``L M⁻¹ L M⁻¹ L``, ``L (λ²M)⁻¹ L`` (the surface's
    metric), ``L``; and the trilaplacian fill's own H."""
    L, area = on_mesh.laplacian_and_areas(uv, faces)
    Mi = sp.diags(1.0 / area)
    Q = (L @ Mi @ L).tocsr()
    models = {"H biharmonic": Q, "H triharmonic": (Q @ Mi @ L).tocsr(),
              "H surface bih": (L @ sp.diags(1.0 / (area * lam_true**2)) @ L).tocsr(),
              "H harmonic": L.tocsr()}
    out = {}
    for name, op in models.items():
        try:
            out[name] = biharmonic(H_true, op, free)
        except (FillError, RuntimeError):
            pass
    out["H of fair3 T"] = lambda_h_at(fair3_points, faces, uv)[1]
    return out


def measured(row, faces, uv, free, solved, lam_true, H_true, fair3_points) -> None:
    """The λ-H T fill's λ and H (its own, measured on the map) against the truth's, by depth,
    and fair3 T's H."""
    lam, H = lambda_h_at(solved, faces, uv)
    depth = depth_from_fixed(faces, free)
    f = np.flatnonzero(free)
    rim = depth[f] <= 1
    scale = np.sqrt(np.mean(H_true[f] ** 2))

    def rel(x, where):
        return float(np.sqrt(np.mean((x[f][where] - H_true[f][where]) ** 2)) / scale) \
            if where.any() else float("nan")

    row["H err λ-H T"] = relative_rms(H[f], H_true[f])
    row["H err d1"], row["H err deep"] = rel(H, rim), rel(H, ~rim)
    row["λ err λ-H T"] = relative_rms(lam[f], lam_true[f])
    deep = f[~rim]
    row["λ err deep"] = relative_rms(lam[deep], lam_true[deep]) if len(deep) else float("nan")
    H_fair3 = lambda_h_at(fair3_points, faces, uv)[1]
    row["H err fair3 T"] = relative_rms(H_fair3[f], H_true[f])
    # the error's smooth part: vertex noise in the discrete H hardly moves the rebuilt
    # surface, a smooth error does (the error over the patch, zero on the fixed vertices, averaged
    # with the mesh's neighbours SMOOTHING times)
    A = vertex_adjacency(faces, len(free)).astype(float) + sp.identity(len(free))
    average = sp.diags(1.0 / np.asarray(A.sum(axis=1)).ravel()) @ A
    for name, x in (("H low λ-H T", H), ("H low fair3 T", H_fair3)):
        e = np.where(free, x - H_true, 0.0)
        for _ in range(SMOOTHING):
            e = average @ e
        row[name] = float(np.sqrt(np.mean(e[f] ** 2)) / scale)
    # the signed mean error of H over the hole (3D areas), in units of the truth's mean |H|
    # there, positive where the fill is more curved (in the truth's mean sense) than the truth:
    # a bias moves the rebuilt surface as a whole, noise at the vertices hardly
    w = on_mesh.laplacian_and_areas(uv, faces)[1][f] * lam_true[f] ** 2
    sign = np.sign(np.sum(w * H_true[f])) or 1.0
    for name, x in (("H bias λ-H T", H), ("H bias fair3 T", H_fair3)):
        row[name] = float(sign * np.sum(w * (x[f] - H_true[f])) / np.sum(w * np.abs(H_true[f])))
    # how much H changes across the hole compared with around it: the truth's spread of H over
    # the free vertices over its spread over the fixed ones of the patch
    known = np.flatnonzero(~free & np.isfinite(H_true))
    row["H rim/in"] = float(np.std(H_true[f]) / max(np.std(H_true[known]), 1e-300))
    # the noise of the data the inpainting starts from: the truth's H on the fixed vertices
    # within RIM rings of the free ones, less its neighbour average, over its RMS there
    near = np.flatnonzero(~free & (depth_from_fixed(faces, ~free) <= RIM))
    smooth = average @ np.nan_to_num(H_true)
    row["H rim noise"] = float(np.sqrt(np.mean((H_true[near] - smooth[near]) ** 2))
                               / np.sqrt(np.mean(H_true[near] ** 2)))


# --------------------------------------------------------------------------- running


def set_manifest(which: str) -> None:
    """Make ``study.holes_of`` read a spent holdout's manifest; refuse any other holdout."""
    if which in study.SETS:
        return
    m = re.fullmatch(r"holdout(\d+)", which)
    if m is None or int(m.group(1)) not in SPENT:
        raise SystemExit(f"{which}: not a tuning-side set or a spent holdout (9–{SPENT[-1]})")
    study.SETS[which] = BENCH / f"{which}_manifest.json"


def run(cases: list[dict], out: Path) -> None:
    done = {(r["set"], r["mesh"], r["hole"]) for r in study.read(out)} if out.exists() else set()
    todo = [c for c in cases if (c["set"], c["mesh"], c["hole"]) not in done]
    for which in dict.fromkeys(c["set"] for c in todo):
        set_manifest(which)
        mine = {(c["mesh"], c["hole"]): c for c in todo if c["set"] == which}
        for mesh_id, _, k, _, cut in study.holes_of(which, {m for m, _ in mine}):
            case = mine.get((mesh_id, k))
            if case is None:
                continue
            t0 = time.perf_counter()
            with warnings.catch_warnings(), np.errstate(all="ignore"):
                warnings.simplefilter("ignore")
                row = oracle_row(cut)
            row.update({key: case[key] for key in ("set", "mesh", "hole", "kind", "edges",
                                                   "group", "ratio", "closer")})
            row["seconds"] = time.perf_counter() - t0
            with out.open("a") as fh:
                fh.write(json.dumps(row, default=float) + "\n")
            print(f"{which} {mesh_id} #{k} ({case['group']}): "
                  + " ".join(f"{c} {row[c]:.3f}" for c in COLUMNS)
                  + f" ({row['seconds']:.0f} s) {row['notes']}", file=sys.stderr, flush=True)


# --------------------------------------------------------------------------- tables

RATIOS = (("λ-H", "fair3"), ("λ-H T", "fair3 T"), ("λ-H T", "λ-H"), ("true λ", "λ-H T"),
          ("true H", "λ-H T"), ("true λ,H", "λ-H T"), ("true λ", "fair3 T"),
          ("true H", "fair3 T"), ("true λ,H", "fair3 T"), ("H err λ-H T", "H err fair3 T"),
          ("H low λ-H T", "H low fair3 T"),
          ("H err deep", "H err d1"))


SCREENS = (*((p, "H biharmonic") for p in PREDICTIONS[1:]), ("H of fair3 T", "fair3 T"),
           *((f"κ={k:g}", "λ-H T") for k in KAPPAS),
           *((f"rim avg {k}", "λ-H T") for k in RIM_AVERAGES))
KIND_RATIOS = (("λ-H", "fair3"), ("λ-H T", "fair3 T"), ("true λ", "λ-H T"), ("true H", "λ-H T"),
               ("true λ,H", "λ-H T"))


def _median(x) -> str:
    x = np.asarray([v for v in x if np.isfinite(v)])
    return f"{np.median(x):.2f} ({len(x)})" if len(x) else "—"


def table(rows: list[dict]) -> str:
    groups = ("loss", "control")
    out = ["| ratio or measure | " + " | ".join(f"{g}: median (n)" for g in groups) + " |",
           "|---|---|---|"]
    for a, b in RATIOS:
        out.append(f"| {a} / {b} | " + " | ".join(
            _median([r[a] / r[b] for r in rows if r["group"] == g]) for g in groups) + " |")
    for c in MEASURES:
        out.append(f"| {c} | " + " | ".join(
            _median([r[c] for r in rows if r["group"] == g]) for g in groups) + " |")
    out += ["", "Screens (each against its base, on the holes where both were made): median "
            "ratio, holes > 10 % better / > 10 % worse:", "",
            "| variant / base | loss | control |", "|---|---|---|"]
    for a, b in SCREENS:
        cells = []
        for g in groups:
            x = np.array([r.get(a, np.nan) / r[b] for r in rows if r["group"] == g])
            x = x[np.isfinite(x)]
            cells.append(f"{np.median(x):.2f} ({len(x)}), {np.sum(x < 0.9)} / {np.sum(x > 1.1)}"
                         if len(x) else "—")
        out.append(f"| {a} / {b} | " + " | ".join(cells) + " |")
    kinds = sorted({r["kind"] for r in rows})
    out += ["", "Per kind (median, holes):", "",
            "| ratio | " + " | ".join(f"{k} {g}" for k in kinds for g in groups) + " |",
            "|---|" + "---|" * (2 * len(kinds))]
    for a, b in KIND_RATIOS:
        out.append(f"| {a} / {b} | " + " | ".join(
            _median([r[a] / r[b] for r in rows if r["group"] == g and r["kind"] == k])
            for k in kinds for g in groups) + " |")
    out += ["", "| group | set | hole | kind | edges | written / better faired | "
            + " | ".join((*COLUMNS, *MEASURES)) + " |", "|---|---|---|---|---|---|"
            + "---|" * (len(COLUMNS) + len(MEASURES))]
    for r in sorted(rows, key=lambda r: (r["group"] != "loss", r["kind"], r["set"], r["mesh"],
                                         r["hole"])):
        out.append(f"| {r['group']} | {r['set']} | {r['mesh']} #{r['hole']} | {r['kind']} | "
                   f"{r['edges']} | {r['ratio']:.2f} | " + " | ".join(
                       f"{r[c]:.3f}" if np.isfinite(r.get(c, np.nan)) else "—"
                       for c in (*COLUMNS, *MEASURES)) + " |")
    return "\n".join(out)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--collect", type=Path, help="write the cases here")
    parser.add_argument("--rows", type=Path, nargs="*", default=[],
                        help="validation.py rows files (holdouts)")
    parser.add_argument("--caches", type=Path, nargs="*", default=[],
                        help="selfcheck_table.py --library caches (set = file stem)")
    parser.add_argument("--run", type=Path, help="the cases file")
    parser.add_argument("--kinds", help="only these kinds, comma-separated")
    parser.add_argument("--groups", default="loss,control")
    parser.add_argument("--same-meshes", action="store_true",
                        help="controls only on the meshes that have a loss")
    parser.add_argument("--out", type=Path)
    parser.add_argument("--table", type=Path, nargs="*")
    args = parser.parse_args()
    if args.collect:
        cases = [c for p in args.rows for c in cases_of_rows(p)]
        cases += [c for p in args.caches for c in cases_of_cache(p)]
        args.collect.write_text(json.dumps(cases, indent=0))
        above = sum(c["ratio"] > LOSS for c in cases)
        print(f"written fill > {LOSS}x the better faired fill: {above} of {len(cases)} holes")
        for g in ("loss", "control"):
            mine = [c for c in cases if c["group"] == g]
            kinds = {k: sum(c["kind"] == k for c in mine) for k in sorted({c["kind"]
                                                                          for c in mine})}
            print(f"{g}: {len(mine)} of {len(cases)} holes; by kind {kinds}")
        return
    cases = None if args.run is None else selected(
        json.loads(args.run.read_text()), args.groups.split(","),
        None if args.kinds is None else args.kinds.split(","), args.same_meshes)
    if cases is not None and not args.table:
        run(cases, args.out)
        return
    rows = study.read(*args.table)
    if cases is not None:  # only the rows of these cases (their group as the cases say)
        wanted = {(c["set"], c["mesh"], c["hole"]): c["group"] for c in cases}
        rows = [r for r in rows if wanted.get((r["set"], r["mesh"], r["hole"])) == r["group"]]
    print(table(rows))


if __name__ == "__main__":
    main()
