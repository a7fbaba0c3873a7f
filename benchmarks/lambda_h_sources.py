"""Where the λ-H fill's error comes from with the mesh discretization (the default), on the
tuning-side holes where it loses to the trilaplacian fill and on comparable ones where it wins
(session 39; docs/error_sources.md "Session 39 (helper)").

``error_sources.py`` did this for the old grid pipeline. Here each hole (cut as
``smooth_selfcheck_study.py`` cuts it) is filled with parts of the mesh pipeline replaced by
the truth. Errors are two-sided mean distances to the removed surface in % of the hole's
diameter (``accuracy.py``'s measure, 4000 samples). Columns:

- ``fair2``, ``fair3``: the faired fills (one triangulation and refinement).
- ``λ-H``: the library's λ-H fill (S0 = fair3, the coupled solve on the patch, its checks:
  ``Candidates.lambda_h``, as ``conformal_raw`` makes it).
- ``λ-H direct``: the coupled solve alone from S0 = fair3 (``inpaint_patch_on_mesh``, no
  checks, no crease split): the stage the columns below replace.
- ``on truth``: the fair3 fill's vertices moved to their closest points on the removed surface:
  the error of the fill's own triangles interpolating the truth at their vertices (not a
  lower bound: a fill may do better between its vertices).
- ``λ-H proj``: the coupled solve from that projected fill (S0 of the truth's shape, with the
  fill's triangles and so a map of the truth's shape).

On the truth's own triangulation (the removed vertices as the fill; no column here pays the
piecewise-linear floor, so compare them with each other and with ``fair3 T``):

- ``fair3 T``: trilaplacian fairing of the truth's interior vertices (the like-for-like
  baseline).
- ``λ-H T``: the coupled solve from S0 = the truth (its map, its triangles).
- ``clean``: λ and H measured on the true patch (``vertex_lambda_h`` on its LSCM map), then
  both inpainted biharmonically over the hole (``L M⁻¹ L``, the coupled solve's operator) from
  the true values around it, then the rebuild ``L φ = M 2λ²H n`` (normals lagged).
- ``true λ``: as ``clean`` with λ true in the hole (H inpainted).
- ``true H``: as ``clean`` with H true in the hole (λ inpainted).
- ``true λ,H``: the rebuild alone from the true λ and H.

And the relative RMS error, over the hole's vertices, of the H that each predicts (H of its
own surface on its own LSCM map, against the true H): ``H err clean`` (the biharmonic
prediction), ``H err fair3 T`` and ``H err λ-H T``; and ``λ err clean``.

    python benchmarks/lambda_h_sources.py --out /tmp/lhs.jsonl            # the 30 holes
    python benchmarks/lambda_h_sources.py --table /tmp/lhs.jsonl

A candidate, given as one ``ConformalOptions`` keyword and its values: the λ-H fill of the
30 holes at each value, or the written fill (self-check on, ``conformal``) on every hole of
a tuning-side set, and issue 14's measures against main's rows of
``smooth_selfcheck_study.py`` (its fair2, fair3 and CGAL fills; the written fill replaced by
the candidate's). Session 39's candidate, ``curvature_pull`` (λ and H pulled towards S0's),
is an option on branch ``s39-lhstudy`` (``2b4c433``) only: it failed the bar.

    python benchmarks/lambda_h_sources.py --option curvature_pull --values 0,0.03,0.1 \
        --out /tmp/w.jsonl                                                     # 30 holes
    python benchmarks/lambda_h_sources.py --set smooth_tuning --option curvature_pull \
        --values 0.1 --out /tmp/p.jsonl
    python benchmarks/lambda_h_sources.py --compare main_rows.jsonl ... --with /tmp/p.jsonl

Session 40: truth-free disagreements between predictions of H per hole (``h_signals``:
the λ-H fill's own H, the trilaplacian fill's, the biharmonic and harmonic continuations
of the rim's), on the 30 holes or on every hole of a set, how they separate the holes
above 1.5× the better faired fill among main's written λ-H fills (main's rows of
``smooth_selfcheck_study.py``), and a veto (the λ-H fill not kept where a signal is above
τ) replayed from those rows:

    python benchmarks/lambda_h_sources.py --signals --out /tmp/s.jsonl              # 30 holes
    python benchmarks/lambda_h_sources.py --table /tmp/s.jsonl
    python benchmarks/lambda_h_sources.py --signals --set animals --out /tmp/a.jsonl
    python benchmarks/lambda_h_sources.py --compare main_rows.jsonl ... --with /tmp/a.jsonl \
        --signal-table          # or: --sweep --values 0.5,1 [--instead faired]
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import scipy.sparse as sp

sys.path.insert(0, str(Path(__file__).parent))
import accuracy  # noqa: E402
import smooth_selfcheck_study as study  # noqa: E402
from error_sources import truth_as_fill  # noqa: E402

from surfinpaint.errors import FillError  # noqa: E402
from surfinpaint.fill.conformal.candidates import Candidates  # noqa: E402
from surfinpaint.fill.conformal.mesh_pass import inpaint_patch_on_mesh  # noqa: E402
from surfinpaint.fill.conformal.options import SOLVER_TOL, ConformalOptions  # noqa: E402
from surfinpaint.fill.conformal.patch import hole_patch_and_boundary  # noqa: E402
from surfinpaint.fill.liepa.baseline import faired_fills  # noqa: E402
from surfinpaint.fill.liepa.fairing import fair  # noqa: E402
from surfinpaint.geometry import mean_value, parameterization  # noqa: E402
from surfinpaint.geometry.linalg import definite_lu  # noqa: E402
from surfinpaint.geometry.mesh import (  # noqa: E402
    laplacian_and_areas,
    mean_edge_length,
    vertex_normals,
)
from surfinpaint.geometry.metrics import (  # noqa: E402
    closest_point_on_triangles,
    surface_distance,
)
from surfinpaint.representation.vertex_lambda_h import vertex_lambda_h  # noqa: E402

# session 38's 15 tuning-side holes where a kept λ-H fill is > 1.5x the better faired fill
# (docs/selfcheck.md "Session 38 (helper)"), and 15 holes of the same sets where the λ-H fill
# was written and is < 0.8x the better faired fill, chosen on smooth tubes and organic shapes
# (the CAD holes the λ-H fill makes exact are left out: nothing to learn there)
MISSES = (("smooth_tuning", "octopus", 2), ("tuning", "airplane", 1), ("cad_tuning", "shaft", 3),
          ("smooth_tuning", "cowrie", 3), ("tuning", "bunny", 1), ("animals", "animal9", 5),
          ("animals", "animal10", 6), ("animals", "animal1", 1), ("smooth_tuning", "piglet", 0),
          ("smooth_tuning", "piglet", 5), ("smooth_tuning", "octopus", 5),
          ("animals", "animal11", 2), ("cad_tuning", "channel", 5),
          ("smooth_tuning", "octopus", 1), ("tuning", "torus", 4))
WINS = (("smooth_tuning", "knot8", 3), ("smooth_tuning", "knot8", 6),
        ("smooth_tuning", "theta_tube", 5), ("smooth_tuning", "wavy_torus", 5),
        ("smooth_tuning", "piglet", 3), ("smooth_tuning", "cowrie", 1),
        ("smooth_tuning", "horn", 3), ("smooth_tuning", "handle_ball", 2),
        ("tuning", "airplane", 2), ("tuning", "torus", 6), ("tuning", "tooth", 4),
        ("animals", "animal9", 3), ("animals", "animal10", 1), ("animals", "animal11", 4),
        ("cad_tuning", "shaft", 2))
COLUMNS = ("fair2", "fair3", "λ-H", "λ-H direct", "on truth", "λ-H proj", "fair3 T", "λ-H T",
           "clean", "true λ", "true H", "true λ,H")
FIDELITY = (0.01, 0.1, 1.0)
RATIOS = ("H err clean", "H err fair3 T", "H err λ-H T", "λ err clean", "H err surface",
          "H err tri", "H err harmonic", "H err λ²H",
          *(f"H err S0 {w:g}" for w in FIDELITY))
SAMPLES = 4000
# the rebuild's lagged normals: at most this many solves, stopping below this step (in mean
# edge lengths); where a full step diverges, half steps
REBUILD_STEPS = 60
REBUILD_TOL = 1e-4


def error_pct(points: np.ndarray, fill_faces: np.ndarray, cut) -> float:
    """Two-sided mean distance of the fill (``fill_faces`` over ``points``) to the removed
    surface, in % of the hole's diameter."""
    ids, local = np.unique(fill_faces, return_inverse=True)
    d = surface_distance(points[ids], local.reshape(-1, 3), cut.truth_vertices,
                         cut.truth_faces, n_samples=SAMPLES)
    return 100.0 * d.mean / cut.diameter


def patch_error(truth: np.ndarray, ids: np.ndarray, positions: np.ndarray,
                truth_faces: np.ndarray, cut) -> float:
    """:func:`error_pct` of the truth's triangles with the patch's vertices ``ids`` moved to
    ``positions`` (a rebuild on the truth's own patch)."""
    moved = truth.copy()
    moved[ids] = positions
    return error_pct(moved, truth_faces, cut)


def projected(points: np.ndarray, cut) -> np.ndarray:
    """``points`` moved to their closest points on the removed surface (brute force: the
    holes are small)."""
    tri = cut.truth_vertices[cut.truth_faces]
    out = np.empty_like(points)
    for i, p in enumerate(points):
        q = closest_point_on_triangles(np.broadcast_to(p, (len(tri), 3)), tri[:, 0],
                                       tri[:, 1], tri[:, 2])
        out[i] = q[np.argmin(((q - p) ** 2).sum(axis=1))]
    return out


def mapped_truth_patch(points, faces, loop, fill_faces, rings):
    """The patch (fill plus ``rings`` rings, fewer while LSCM flips or squashes a triangle)
    and its LSCM map: ids, local faces, uv; None where no ring count down to 2 maps."""
    for k in range(rings, 1, -1):
        patch, _, boundary = hole_patch_and_boundary(faces, loop, fill_faces, k)
        ids, local = np.unique(patch, return_inverse=True)
        local = local.reshape(-1, 3)
        uv = parameterization.lscm(points[ids], local, boundary=None if boundary is None
                                   else np.searchsorted(ids, boundary))
        if len(mean_value.bad_faces(points[ids], local, uv)) == 0:
            return ids, local, uv
    return None


def biharmonic(values: np.ndarray, Q: sp.csr_matrix, free: np.ndarray) -> np.ndarray:
    """``values`` with the free entries replaced by the solution of ``(Q x)_free = 0``."""
    f, k = np.flatnonzero(free), np.flatnonzero(~free)
    Q_fk = Q[f][:, k]
    data = values[k]
    used = np.flatnonzero(np.abs(Q_fk).sum(axis=0).A1 > 0)
    if not np.isfinite(data[used]).all():
        raise FillError("the biharmonic stencil reaches the patch's border")
    out = values.copy()
    out[f] = definite_lu(Q[f][:, f].tocsc()).solve(-(Q_fk[:, used] @ data[used]))
    return out


def rebuild(points, faces, uv, free, lam, H) -> np.ndarray:
    """Positions of the free vertices solving ``L φ = M 2λ²H n`` (the coupled solve's rebuild)
    with ``lam`` and ``H`` given there, the normals lagged from ``points`` on."""
    L, area = laplacian_and_areas(uv, faces)
    f, k = np.flatnonzero(free), np.flatnonzero(~free)
    lu = definite_lu(L[f][:, f].tocsc())
    g = lu.solve(-(L[f][:, k] @ points[k]))
    weight = (area * 2.0 * lam**2 * H)[f]
    scale = mean_edge_length(points, faces)
    for relax in (1.0, 0.5):
        phi = points.copy()
        for _ in range(REBUILD_STEPS * (1 if relax == 1.0 else 2)):
            new = g + lu.solve(vertex_normals(phi, faces)[f] * weight[:, None])
            step = float(np.abs(new - phi[f]).max()) / scale
            if not np.isfinite(step) or step > 10.0:
                break
            phi[f] += relax * (new - phi[f])
            if step < REBUILD_TOL:
                return phi
        else:
            return phi  # not settled: the last iterate
    raise FillError("the rebuild diverges")


def relative_rms(x: np.ndarray, truth: np.ndarray) -> float:
    return float(np.sqrt(np.mean((x - truth) ** 2) / np.mean(truth**2)))


def h_of(points, local, free) -> np.ndarray:
    """H at the free vertices of a patch, on its own LSCM map."""
    uv = parameterization.lscm(points, local)
    return vertex_lambda_h(points, local, uv)[1][free]


def faired_and_lambda_h(cut, options: ConformalOptions, row: dict, notes: list) -> tuple:
    """The errors of the faired fills (``row["fair2"]``, ``row["fair3"]``) and of the library's
    λ-H fill from S0 = fair3 (``row["λ-H"]``; a crease or a failure in ``notes``); returns S0
    (the trilaplacian fill's new vertices and faces)."""
    vertices, faces, loop = cut.vertices, cut.faces, cut.loop
    made = faired_fills(vertices, faces, loop, [2, 3])
    for order in (2, 3):
        new_v, new_f, _ = made[order]
        row[f"fair{order}"] = error_pct(np.vstack([vertices, new_v]), new_f, cut)
    s0 = made[3][:2]
    try:
        lh = Candidates.for_hole(vertices, faces, loop, options).lambda_h(vertices, faces,
                                                                          loop, s0)
        row["λ-H"] = error_pct(np.vstack([vertices, lh.vertices]), lh.faces, cut)
        if lh.crease:
            notes.append("crease")
    except FillError as exc:
        notes.append(f"λ-H: {str(exc)[:80]}")
    return s0


def hole_row(cut) -> dict:
    """Every column of one hole (NaN where a variant fails)."""
    vertices, faces, loop = cut.vertices, cut.faces, cut.loop
    n = len(vertices)
    options = ConformalOptions()
    rings = options.rings_in_patch
    row: dict = {c: float("nan") for c in (*COLUMNS, *RATIOS)}
    notes: list[str] = []
    s0 = faired_and_lambda_h(cut, options, row, notes)
    all_v = np.vstack([vertices, s0[0]])
    moving = n + np.arange(len(s0[0]))

    def coupled_solve_from(start: np.ndarray, column: str, label: str) -> None:
        """The coupled solve alone from the fill vertices of ``start``: its error in
        ``row[column]``, or its failure in the notes."""
        try:
            new, *_ = inpaint_patch_on_mesh(start, faces, loop, s0[1], moving, rings=rings,
                                            iterations=options.solver_iterations,
                                            tol=SOLVER_TOL)
        except FillError as exc:
            notes.append(f"{label}: {str(exc)[:80]}")
            return
        solved = start.copy()
        solved[moving] = new
        row[column] = error_pct(solved, s0[1], cut)

    coupled_solve_from(all_v, "λ-H direct", "direct")
    on_truth = all_v.copy()
    on_truth[moving] = projected(all_v[moving], cut)
    row["on truth"] = error_pct(on_truth, s0[1], cut)
    coupled_solve_from(on_truth, "λ-H proj", "λ-H proj")
    truth, truth_faces, inner = truth_as_fill(cut)
    whole = np.vstack([faces, truth_faces])
    fair3 = fair(truth, whole, inner, 3)
    row["fair3 T"] = error_pct(fair3, truth_faces, cut)
    try:
        new, *_ = inpaint_patch_on_mesh(truth, faces, loop, truth_faces, inner, rings=rings,
                                        iterations=options.solver_iterations, tol=SOLVER_TOL)
        lh_t = truth.copy()
        lh_t[inner] = new
        row["λ-H T"] = error_pct(lh_t, truth_faces, cut)
    except FillError as exc:
        lh_t = None
        notes.append(f"λ-H T: {str(exc)[:80]}")
    mapped = mapped_truth_patch(truth, faces, loop, truth_faces, rings)
    if mapped is None:
        notes.append("no map of the truth's patch")
        row["notes"] = "; ".join(notes)
        return row
    ids, local, uv = mapped
    points = truth[ids]
    free = np.isin(ids, inner)
    lam, H = vertex_lambda_h(points, local, uv)
    L, area = laplacian_and_areas(uv, local)
    Q = (L @ sp.diags(1.0 / area) @ L).tocsr()
    try:
        lam_inp, H_inp = biharmonic(lam, Q, free), biharmonic(H, Q, free)
    except FillError as exc:
        notes.append(str(exc))
        row["notes"] = "; ".join(notes)
        return row
    row["H err clean"] = relative_rms(H_inp[free], H[free])
    # other predictions of H from the same true data (the screen of step 2): the biharmonic
    # energy in the surface's metric (areas λ²M), triharmonic and harmonic in the plane's,
    # and λ²H (n · Δ_uv φ / 2) biharmonic, divided by the inpainted λ²
    Q_surface = (L @ sp.diags(1.0 / (area * lam**2)) @ L).tocsr()
    screens = {"H err surface": lambda: biharmonic(H, Q_surface, free),
               "H err tri": lambda: biharmonic(H, (Q @ sp.diags(1.0 / area) @ L).tocsr(),
                                               free),
               "H err harmonic": lambda: biharmonic(H, L.tocsr(), free),
               "H err λ²H": lambda: biharmonic(lam**2 * H, Q, free) / lam_inp**2}
    for name, predict in screens.items():
        try:
            row[name] = relative_rms(predict()[free], H[free])
        except FillError:
            pass
    row["λ err clean"] = relative_rms(lam_inp[free], lam[free])
    for name, lam_x, H_x in (("clean", lam_inp, H_inp), ("true λ", lam, H_inp),
                             ("true H", lam_inp, H), ("true λ,H", lam, H)):
        try:
            phi = rebuild(points, local, uv, free, lam_x, H_x)
        except FillError as exc:
            notes.append(f"{name}: {exc}")
            continue
        row[name] = patch_error(truth, ids, phi, truth_faces, cut)
    H_fair3 = h_of(fair3[ids], local, free)
    row["H err fair3 T"] = relative_rms(H_fair3, H[free])
    # the biharmonic energy plus w·|H − H_S0|² (areas M, per mean map edge⁴): the prediction
    # pulled towards the H of the trilaplacian fill (here on the truth's triangles)
    edge_uv = mean_edge_length(np.column_stack([uv, np.zeros(len(uv))]), local)
    for w in FIDELITY:
        pull = sp.diags(np.where(free, w * area / edge_uv**4, 0.0))
        target = np.zeros(len(H))
        target[free] = H_fair3
        mixed = H.copy()
        mixed[free] = np.nan_to_num(H[free])  # (free entries are unknowns)
        f, k = np.flatnonzero(free), np.flatnonzero(~free)
        A = (Q + pull).tocsr()
        rhs = (pull @ target)[f] - Q[f][:, k] @ np.nan_to_num(H[k])
        row[f"H err S0 {w:g}"] = relative_rms(definite_lu(A[f][:, f].tocsc()).solve(rhs),
                                             H[free])
    if lh_t is not None:
        row["H err λ-H T"] = relative_rms(h_of(lh_t[ids], local, free), H[free])
    row["notes"] = "; ".join(notes)
    return row


# --------------------------------------------------------------------------- session 40
# truth-free disagreements between predictions of H over the hole (session 40's screen:
# docs/error_sources.md "Session 40 (helper)"): does the λ-H fill's prediction of H disagree
# with other predictions where it is unreliable?
SIGNALS = ("d lh-f3", "d bih-f3", "d harm-bih", "d lh-bih", "d harm-f3", "d lh-f3 rim",
           "d bih-f3 rim", "d lh-f3 3d", "d pos")


def h_signals(vertices, faces, loop, lh_vertices, f3_vertices, fill_faces, rings) -> dict:
    """Truth-free disagreements between predictions of H over the hole's new vertices, for a
    λ-H fill and the trilaplacian fill on the same triangles ``fill_faces``.

    Each surface's H is measured on its own LSCM map of the patch (the fill and ``rings``
    rings, fewer while the map flips a triangle; ``vertex_lambda_h``). ``bih`` and ``harm``
    are the biharmonic (``L M⁻¹ L``) and harmonic continuations of the λ-H patch's H from
    the known vertices, on its map. ``d a-b``: RMS of (a − b) over the new vertices divided
    by the RMS of b there; ``… rim``: divided by the RMS of H on the known vertices of the
    patch instead (the rim's own scale); ``d lh-f3 3d``: H from the 3D cotangent Laplacian
    (no map); ``d pos``: RMS distance of the two fills' new vertices in mean edge lengths
    of the loop. Missing keys: that prediction could not be made.
    """
    n = len(vertices)
    lh_all = np.vstack([vertices, lh_vertices])
    f3_all = np.vstack([vertices, f3_vertices])
    edge = float(np.mean(np.linalg.norm(vertices[loop] - vertices[np.roll(loop, 1)], axis=1)))
    out = {"d pos": float(np.sqrt(np.mean(((lh_vertices - f3_vertices) ** 2).sum(axis=1))))
           / edge}
    mapped = mapped_truth_patch(lh_all, faces, loop, fill_faces, rings)
    if mapped is None:
        return out
    ids, local, uv = mapped
    free = ids >= n
    H_lh = vertex_lambda_h(lh_all[ids], local, uv)[1]
    H_f3 = vertex_lambda_h(f3_all[ids], local, parameterization.lscm(f3_all[ids], local))[1]
    H3_lh = vertex_lambda_h(lh_all[ids], local, lh_all[ids])[1]
    H3_f3 = vertex_lambda_h(f3_all[ids], local, f3_all[ids])[1]
    rim = np.sqrt(np.nanmean(H_lh[~free] ** 2))
    predictions = {"lh": H_lh[free], "f3": H_f3[free]}
    L, area = laplacian_and_areas(uv, local)
    for name, Q in (("bih", (L @ sp.diags(1.0 / area) @ L).tocsr()), ("harm", L.tocsr())):
        try:
            predictions[name] = biharmonic(H_lh, Q, free)[free]
        except FillError:
            pass

    def rms(x):  # a numpy float: a flat fill's zero H gives inf or NaN, not an error
        return np.sqrt(np.mean(x**2))

    for a, b in (("lh", "f3"), ("bih", "f3"), ("harm", "bih"), ("lh", "bih"), ("harm", "f3")):
        if a in predictions and b in predictions:
            out[f"d {a}-{b}"] = float(rms(predictions[a] - predictions[b])
                                      / rms(predictions[b]))
            if f"d {a}-{b} rim" in SIGNALS:
                out[f"d {a}-{b} rim"] = float(rms(predictions[a] - predictions[b]) / rim)
    out["d lh-f3 3d"] = float(rms(H3_lh[free] - H3_f3[free]) / rms(H3_f3[free]))
    return out


def signal_row(cut) -> dict:
    """The faired and λ-H fills' errors (as ``hole_row``'s) and :func:`h_signals` of one
    hole; the signals are left out for a crease fill (its two sides are filled on their own,
    on other triangles than the trilaplacian fill's) or a failed λ-H fill."""
    vertices, faces, loop = cut.vertices, cut.faces, cut.loop
    options = ConformalOptions()
    row: dict = {"notes": ""}
    made = faired_fills(vertices, faces, loop, [2, 3])
    for order in (2, 3):
        new_v, new_f, _ = made[order]
        row[f"fair{order}"] = error_pct(np.vstack([vertices, new_v]), new_f, cut)
    s0 = made[3][:2]
    try:
        lh = Candidates.for_hole(vertices, faces, loop, options).lambda_h(vertices, faces,
                                                                          loop, s0)
    except FillError as exc:
        row["λ-H"], row["notes"] = float("nan"), f"λ-H: {str(exc)[:80]}"
        return row
    row["λ-H"] = error_pct(np.vstack([vertices, lh.vertices]), lh.faces, cut)
    row["crease"] = bool(lh.crease)
    if not lh.crease and np.array_equal(lh.faces, s0[1]):
        row.update(h_signals(vertices, faces, loop, lh.vertices, s0[0], s0[1],
                             options.rings_in_patch))
    return row


def run_signals(out: Path, which: str | None) -> None:
    """:func:`signal_row` of the 30 holes (``which`` None) or of every hole of a set."""
    done = {(r["set"], r["mesh"], r["hole"]) for r in study.read(out)} if out.exists() else set()
    if which is None:
        holes = ((s, m, k, c) for s, m, k, c in cuts([w for w in MISSES + WINS
                                                        if w not in done]))
    else:
        holes = ((which, m, k, c) for m, _, k, _, c in study.holes_of(which)
                 if (which, m, k) not in done)
    for which_set, mesh_id, k, cut in holes:
        t0 = time.perf_counter()
        with warnings.catch_warnings(), np.errstate(divide="ignore", invalid="ignore"):
            warnings.simplefilter("ignore")
            row = signal_row(cut)
        key = (which_set, mesh_id, k)
        row.update({"set": which_set, "mesh": mesh_id, "hole": k, "edges": len(cut.loop),
                    "group": "miss" if key in MISSES else "win" if key in WINS else "",
                    "seconds": time.perf_counter() - t0})
        with out.open("a") as fh:
            fh.write(json.dumps(row, default=float) + "\n")
        print(f"{which_set} {mesh_id} #{k}: λ-H {row['λ-H']:.3f} fair3 {row['fair3']:.3f} "
              + " ".join(f"{c} {row[c]:.3f}" for c in SIGNALS if c in row)
              + f" ({row['seconds']:.0f} s) {row['notes']}", file=sys.stderr, flush=True)


def separation(miss: np.ndarray, win: np.ndarray) -> tuple[float, int, float]:
    """How well a signal, larger on misses, separates ``miss`` from ``win`` values: the
    probability that a miss's value is above a win's (ties half), and the fewest holes on
    the wrong side of one threshold (misses at or below it plus wins above it) with the
    smallest such threshold."""
    auc = float(np.mean((miss[:, None] > win[None, :]) + 0.5 * (miss[:, None] == win[None, :])))
    cuts_at = np.concatenate([[-np.inf], np.sort(np.concatenate([miss, win]))])
    wrong = [(int(np.sum(miss <= t) + np.sum(win > t)), t) for t in cuts_at]
    fewest, tau = min(wrong, key=lambda x: (x[0], x[1]))
    return auc, fewest, float(tau)


def screen_table(rows: list[dict]) -> str:
    """Per signal: medians over misses and wins, the separation (:func:`separation`) on the
    holes where the signal was made; then every hole's signals."""
    out = ["| signal | misses: median (n) | wins: median (n) | P(miss > win) | fewest wrong "
           "at one threshold (τ) |", "|---|---|---|---|---|"]
    for c in SIGNALS:
        x = {g: np.array([r[c] for r in rows if r["group"] == g and np.isfinite(r.get(c,
                                                                                       np.nan))])
             for g in ("miss", "win")}
        if not len(x["miss"]) or not len(x["win"]):
            continue
        auc, fewest, tau = separation(x["miss"], x["win"])
        out.append(f"| {c} | {np.median(x['miss']):.3f} ({len(x['miss'])}) | "
                   f"{np.median(x['win']):.3f} ({len(x['win'])}) | {auc:.2f} | "
                   f"{fewest} / {len(x['miss']) + len(x['win'])} ({tau:.3f}) |")
    out += ["", "| group | hole | λ-H / better faired | " + " | ".join(SIGNALS) + " |",
            "|---|---|---|" + "---|" * len(SIGNALS)]
    for r in sorted(rows, key=lambda r: (r["group"] != "miss", r["set"], r["mesh"], r["hole"])):
        ratio = r["λ-H"] / min(r["fair2"], r["fair3"])
        out.append(f"| {r['group']} | {r['mesh']} #{r['hole']} | {ratio:.2f} | " + " | ".join(
            f"{r[c]:.3f}" if np.isfinite(r.get(c, np.nan)) else "—" for c in SIGNALS) + " |")
    return "\n".join(out)


def vetoed(main_rows: list[dict], signal_rows: list[dict], signal: str, tau: float,
           instead: str = "fair3") -> list[dict]:
    """Candidate rows (for :func:`compare`) of a veto replayed on main's rows of
    ``smooth_selfcheck_study.py``: where main wrote the λ-H fill (status ``ok``) and
    ``signal`` of that hole is above ``tau``, the written error is ``instead``'s
    (``"fair3"``, or ``"faired"``: the faired fill the self-check would write next,
    its ``lib_faired``); elsewhere main's. A hole without the signal is not vetoed."""
    said = {(r["set"], r["mesh"], r["hole"]): r.get(signal, float("nan")) for r in signal_rows}
    out = []
    for r in main_rows:
        key = (r["set"], r["mesh"], r["hole"])
        error = r["errors"]["conformal"]
        if r["status"]["conformal"] == "ok" and said.get(key, float("nan")) > tau:
            name = "fair3" if instead == "fair3" else r["evidence"]["lib_faired"]
            error = r["errors"]["fair" if name == "fair2" else name]
        out.append({"set": r["set"], "mesh": r["mesh"], "hole": r["hole"], "error": error})
    return out


def written_signal_table(main_rows: list[dict], signal_rows: list[dict]) -> str:
    """On every hole where main wrote the λ-H fill (status ``ok``) and the signals were
    made: per signal, how it separates the holes above 1.5× the better faired fill from the
    others (:func:`separation`), per set and on the union; then the holes above 1.5× with
    the rank of their signal among the set's written λ-H fills (1: the largest)."""
    said = {(r["set"], r["mesh"], r["hole"]): r for r in signal_rows}
    holes = []
    for r in main_rows:
        key = (r["set"], r["mesh"], r["hole"])
        if r["status"]["conformal"] == "ok" and key in said:
            e = r["errors"]
            holes.append((r["set"], key, e["conformal"] / min(e["fair"], e["fair3"]), said[key]))
    out = ["| signal | set | written λ-H fills with it | above 1.5×: median | others: median "
           "| P(above > other) | fewest wrong at one threshold (τ) |",
           "|---|---|---|---|---|---|---|"]
    for c in SIGNALS:
        for which in [*dict.fromkeys(h[0] for h in holes), "union"]:
            hs = [h for h in holes if which in ("union", h[0])
                  and np.isfinite(h[3].get(c, np.nan))]
            above = np.array([h[3][c] for h in hs if h[2] > 1.5])
            other = np.array([h[3][c] for h in hs if h[2] <= 1.5])
            if not len(above) or not len(other):
                out.append(f"| {c} | {which} | {len(hs)} | — | {np.median(other):.3f} | — | — |")
                continue
            auc, fewest, tau = separation(above, other)
            out.append(f"| {c} | {which} | {len(hs)} | {np.median(above):.3f} "
                       f"({len(above)}) | {np.median(other):.3f} | {auc:.2f} | {fewest} "
                       f"({tau:.3f}) |")
    out += ["", "| set | hole | written / better faired | " + " | ".join(
        f"{c} (rank)" for c in SIGNALS) + " |", "|---|---|---|" + "---|" * len(SIGNALS)]
    for which, key, ratio, sig in holes:
        if ratio <= 1.5:
            continue
        cells = []
        for c in SIGNALS:
            if not np.isfinite(sig.get(c, np.nan)):
                cells.append("—")
                continue
            same = [h[3].get(c, np.nan) for h in holes if h[0] == which]
            rank = 1 + int(np.sum(np.array(same) > sig[c]))
            cells.append(f"{sig[c]:.3f} ({rank} / {int(np.isfinite(same).sum())})")
        out.append(f"| {which} | {key[1]} #{key[2]} | {ratio:.2f} | " + " | ".join(cells) + " |")
    return "\n".join(out)


def veto_sweep(main_rows: list[dict], signal_rows: list[dict], taus: list[float],
               instead: str = "fair3") -> str:
    """Issue 14's measures per set for the veto of every signal at every τ (:func:`vetoed`),
    one line each, and whether it passes the bar: fewer holes above 1.5× on the union and
    no set's per-hole median / CGAL or worst mesh / fair2 worse than main's."""
    sets = list(dict.fromkeys(r["set"] for r in main_rows))

    def measures(written_rows):
        new = {(r["set"], r["mesh"], r["hole"]): r["error"] for r in written_rows}
        out = {}
        for which in sets:
            rs = [r for r in main_rows if r["set"] == which]
            out[which] = written_measures(rs, np.array([new[(r["set"], r["mesh"], r["hole"])]
                                                        for r in rs]))
        return out

    base = measures([{"set": r["set"], "mesh": r["mesh"], "hole": r["hole"],
                      "error": r["errors"]["conformal"]} for r in main_rows])
    lines = ["| signal | τ | vetoed | " + " | ".join(f"{w}: median / CGAL, worst / fair2, "
                                                      "> 1.5×" for w in sets)
             + " | > 1.5× (union) | passes |", "|---|---|---|" + "---|" * len(sets) + "---|---|",
             "| main | | 0 | " + " | ".join(f"{base[w][0]:.3f}, {base[w][1][0]:.3f}, "
                                            f"{base[w][2]}" for w in sets)
             + f" | {sum(base[w][2] for w in sets)} | |"]
    for c in SIGNALS:
        for tau in taus:
            rows = vetoed(main_rows, signal_rows, c, tau, instead)
            changed = sum(a["error"] != r["errors"]["conformal"]
                          for a, r in zip(rows, main_rows, strict=True))
            m = measures(rows)
            worse = [w for w in sets if m[w][0] > base[w][0] + 1e-12
                     or m[w][1][0] > base[w][1][0] + 1e-12]
            above = sum(m[w][2] for w in sets)
            ok = above < sum(base[w][2] for w in sets) and not worse
            lines.append(f"| {c} | {tau:g} | {changed} | " + " | ".join(
                f"{m[w][0]:.3f}, {m[w][1][0]:.3f}, {m[w][2]}" for w in sets)
                + f" | {above} | {'yes' if ok else 'no'} |")
    return "\n".join(lines)


def cuts(wanted):
    """(set, mesh, hole, cut) of the holes ``wanted``, in their sets' order."""
    for which in dict.fromkeys(s for s, _, _ in wanted):
        keys = {(m, k) for s, m, k in wanted if s == which}
        meshes = {m for m, _ in keys}
        for mesh_id, _, k, _, cut in study.holes_of(which, meshes):
            if (mesh_id, k) in keys:
                yield which, mesh_id, k, cut


def run(out: Path, wanted) -> None:
    done = {(r["set"], r["mesh"], r["hole"]) for r in study.read(out)} if out.exists() else set()
    todo = [w for w in wanted if w not in done]
    for which, mesh_id, k, cut in cuts(todo):
        t0 = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            row = hole_row(cut)
        row.update({"set": which, "mesh": mesh_id, "hole": k, "edges": len(cut.loop),
                    "group": "miss" if (which, mesh_id, k) in MISSES else "win",
                    "seconds": time.perf_counter() - t0})
        with out.open("a") as fh:
            fh.write(json.dumps(row, default=float) + "\n")
        print(f"{which} {mesh_id} #{k}: " + " ".join(f"{c} {row[c]:.3f}" for c in COLUMNS)
              + f" ({row['seconds']:.0f} s) {row['notes']}", file=sys.stderr, flush=True)


def run_values(option: str, values: list[float], out: Path) -> None:
    """The library's λ-H fill (S0 = fair3, ``Candidates.lambda_h``) with the
    ``ConformalOptions`` keyword ``option`` at each of ``values`` on the 30 holes: errors
    ``<option>=<value>``."""
    for which, mesh_id, k, cut in cuts(MISSES + WINS):
        vertices, faces, loop = cut.vertices, cut.faces, cut.loop
        s0 = faired_fills(vertices, faces, loop, [2, 3])[3][:2]  # as Candidates makes S0
        row = {"set": which, "mesh": mesh_id, "hole": k,
               "group": "miss" if (which, mesh_id, k) in MISSES else "win"}
        for w in values:
            options = ConformalOptions(**{option: w})
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                try:
                    lh = Candidates.for_hole(vertices, faces, loop, options).lambda_h(
                        vertices, faces, loop, s0)
                    row[f"{option}={w:g}"] = error_pct(np.vstack([vertices, lh.vertices]), lh.faces,
                                               cut)
                except FillError:
                    row[f"{option}={w:g}"] = float("nan")
        with out.open("a") as fh:
            fh.write(json.dumps(row) + "\n")
        print(f"{mesh_id} #{k}: " + " ".join(f"{w:g} {row[f'{option}={w:g}']:.3f}"
                                             for w in values),
              file=sys.stderr, flush=True)


def run_set(which: str, option: str, value: float, out: Path, samples: int = 10000) -> None:
    """The written fill (self-check on) with the ``ConformalOptions`` keyword ``option`` at
    ``value`` on every hole of the set ``which``, scored as ``smooth_selfcheck_study.py``
    scores ``conformal``."""
    method = f"conformal_{option}{value:g}"
    accuracy.CONFORMAL_VARIANTS[method] = {option: value}
    done = {(r["mesh"], r["hole"]) for r in study.read(out)} if out.exists() else set()
    for mesh_id, _, k, hole, cut in study.holes_of(which):
        if (mesh_id, k) in done:
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = accuracy.score(cut, method, mesh_id, k, hole["radius_h"], samples)
        row = {"set": which, "mesh": mesh_id, "hole": k, option: value, "status": r.status,
               "error": r.mean_pct if r.status in study.validation.FILLED else float("nan"),
               "note": r.note, "seconds": r.seconds}
        with out.open("a") as fh:
            fh.write(json.dumps(row, default=float) + "\n")
        print(f"{which} {mesh_id} #{k}: {row['error']:.3f} ({r.seconds:.1f} s)",
              file=sys.stderr, flush=True)


def compare(main_rows: list[dict], candidate_rows: list[dict]) -> str:
    """Issue 14's measures per set of main's written fill and of the candidate's (on the
    holes both have), and the holes whose written fill changed by more than 1 %."""
    new = {(r["set"], r["mesh"], r["hole"]): r["error"] for r in candidate_rows}
    rows = [r for r in main_rows if (r["set"], r["mesh"], r["hole"]) in new]
    lines = ["| set | holes | main: median / CGAL, worst mesh / fair2, > 1.5× | candidate: "
             "median / CGAL, worst mesh / fair2, > 1.5× |", "|---|---|---|---|"]
    for which in [*dict.fromkeys(r["set"] for r in rows), "union"]:
        rs = [r for r in rows if which in ("union", r["set"])]
        cells = []
        for written in ([r["errors"]["conformal"] for r in rs],
                        [new[(r["set"], r["mesh"], r["hole"])] for r in rs]):
            m = written_measures(rs, np.array(written))
            cells.append(f"{m[0]:.3f}, {m[1][0]:.3f} ({m[1][1]}), {m[2]}")
        lines.append(f"| {which} | {len(rs)} | " + " | ".join(cells) + " |")
    lines += ["", "Holes whose written fill changed by more than 1 % (main → candidate; "
              "fair2, fair3):", ""]
    for r in rows:
        a, b = r["errors"]["conformal"], new[(r["set"], r["mesh"], r["hole"])]
        if not np.isclose(a, b, rtol=0.01):
            lines.append(f"- {r['set']} {r['mesh']} #{r['hole']}: {a:.3f} → {b:.3f} "
                         f"({b / a:.2f}×; fair2 {r['errors']['fair']:.3f}, fair3 "
                         f"{r['errors']['fair3']:.3f})")
    return "\n".join(lines)


def written_measures(rows: list[dict], written: np.ndarray) -> tuple:
    """(median of written / CGAL, (worst mesh median / fair2 median, mesh), holes above 1.5×
    the better faired fill) of ``written`` errors over ``rows``."""
    e = {m: np.array([r["errors"][m] for r in rows]) for m in ("fair", "fair3", "cgal")}
    per_mesh = []
    for key in dict.fromkeys((r["set"], r["mesh"]) for r in rows):
        idx = [i for i, r in enumerate(rows) if (r["set"], r["mesh"]) == key]
        per_mesh.append((float(np.median(written[idx]) / np.median(e["fair"][idx])), key[1]))
    above = int(np.sum(written / np.minimum(e["fair"], e["fair3"]) > 1.5))
    return float(np.nanmedian(written / e["cgal"])), max(per_mesh), above


def table(rows: list[dict]) -> str:
    """The rows as a markdown table, misses first, and the medians of ratios per group."""
    heads = (*COLUMNS, *RATIOS)
    out = ["| group | hole | edges | " + " | ".join(heads) + " |",
           "|---|---|---|" + "---|" * len(heads)]
    rows = sorted(rows, key=lambda r: (r["group"] != "miss", r["set"], r["mesh"], r["hole"]))
    for r in rows:
        out.append(f"| {r['group']} | {r['mesh']} #{r['hole']} | {r['edges']} | "
                   + " | ".join(f"{r[c]:.3f}" if np.isfinite(r[c]) else "—" for c in heads)
                   + " |")
    out += ["", "Median over the group's holes (holes where both are finite):", "",
            "| ratio | misses | wins |", "|---|---|---|"]
    pairs = (("λ-H", "fair3"), ("λ-H direct", "λ-H"), ("on truth", "fair3"),
             ("λ-H proj", "fair3"), ("λ-H proj", "λ-H direct"), ("λ-H T", "fair3 T"),
             ("λ-H T", "λ-H direct"), ("clean", "fair3 T"), ("clean", "λ-H T"),
             ("true λ", "fair3 T"), ("true H", "fair3 T"), ("true λ,H", "fair3 T"),
             ("H err clean", "H err fair3 T"), ("H err λ-H T", "H err fair3 T"),
             ("H err surface", "H err clean"), ("H err tri", "H err clean"),
             ("H err harmonic", "H err clean"), ("H err λ²H", "H err clean"),
             *((f"H err S0 {w:g}", "H err clean") for w in FIDELITY))
    for a, b in pairs:
        cells = []
        for group in ("miss", "win"):
            x = np.array([r[a] / r[b] for r in rows if r["group"] == group])
            x = x[np.isfinite(x)]
            cells.append(f"{np.median(x):.2f} ({len(x)})" if len(x) else "n/a")
        out.append(f"| {a} / {b} | " + " | ".join(cells) + " |")
    for c in RATIOS:
        cells = []
        for group in ("miss", "win"):
            x = np.array([r[c] for r in rows if r["group"] == group])
            x = x[np.isfinite(x)]
            cells.append(f"{np.median(x):.2f} ({len(x)})" if len(x) else "n/a")
        out.append(f"| {c} | " + " | ".join(cells) + " |")
    return "\n".join(out)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", type=Path)
    parser.add_argument("--table", type=Path, nargs="*")
    parser.add_argument("--only", choices=("miss", "win"))
    parser.add_argument("--set", choices=(*study.SETS, "animals"))
    parser.add_argument("--option", help="a ConformalOptions keyword: the candidate")
    parser.add_argument("--values", help="its values, comma-separated (--set: the first)")
    parser.add_argument("--compare", type=Path, nargs="*")
    parser.add_argument("--with", dest="candidate", type=Path, nargs="*")
    parser.add_argument("--signals", action="store_true",
                        help="the truth-free disagreements of H (the 30 holes, or --set's)")
    parser.add_argument("--veto", choices=SIGNALS,
                        help="with --compare main rows --with signal rows: the λ-H fill "
                             "not kept where this signal is above each of --values")
    parser.add_argument("--signal-table", action="store_true",
                        help="with --compare main rows --with signal rows: how each signal "
                             "separates main's written λ-H fills above 1.5×")
    parser.add_argument("--sweep", action="store_true",
                        help="with --compare main rows --with signal rows: every signal's "
                             "veto at each of --values, one line each")
    parser.add_argument("--instead", choices=("fair3", "faired"), default="fair3")
    args = parser.parse_args()
    if args.table:
        rows = study.read(*args.table)
        print(table(rows) if "λ-H proj" in rows[0] else screen_table(rows))
        return
    if args.compare and args.signal_table:
        print(written_signal_table(study.read(*args.compare), study.read(*args.candidate)))
        return
    if args.compare and args.sweep:
        print(veto_sweep(study.read(*args.compare), study.read(*args.candidate),
                         [float(t) for t in args.values.split(",")], args.instead))
        return
    if args.compare and args.veto:
        main_rows, signal_rows = study.read(*args.compare), study.read(*args.candidate)
        for tau in (float(t) for t in args.values.split(",")):
            print(f"\n### veto: {args.veto} > {tau:g}, {args.instead} written instead\n")
            print(compare(main_rows, vetoed(main_rows, signal_rows, args.veto, tau,
                                            args.instead)))
        return
    if args.compare:
        print(compare(study.read(*args.compare), study.read(*args.candidate)))
        return
    if args.signals:
        run_signals(args.out, args.set)
        return
    values = [float(w) for w in args.values.split(",")] if args.values else []
    if args.set:
        run_set(args.set, args.option, values[0], args.out)
        return
    if args.option:
        run_values(args.option, values, args.out)
        return
    wanted = {"miss": MISSES, "win": WINS}.get(args.only, MISSES + WINS)
    run(args.out, wanted)


if __name__ == "__main__":
    main()
