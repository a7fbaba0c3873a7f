"""The λ-H fills that fall back because they fold over or cut through the surface (issue 20,
docs/convergence.md session 13): what a fold-free fill near them would be worth.

Per hole of one of ``lambda_h_fallbacks.py``'s families it fills the hole by the λ-H fill
(``select=False``), keeps the inputs of the damped check that rejected it
(``checks.damped_fill``: the λ-H fill, its start S0 = the trilaplacian fill, the patch), and
writes one JSON row with the error against the removed truth (two-sided mean distance, % of
the hole's diameter, as ``eggcrate.error``) of

- ``fair2`` (the bilaplacian fill, what ``select=False`` writes on a fallback), ``fair3``
  (S0) and ``lambda_h`` (the undamped λ-H fill that failed); the faired fills and the λ-H
  fill share their triangles (``same_triangles``: checked);
- ``blend_s0``: the largest fold-free blend ``S0 + t (λH − S0)``, ``t`` found by 8 halvings
  of ``(0, min(DAMPING_STEPS))`` with the damped check's own rule (the start's folds and
  crossings allowed), and its ``t``;
- ``blend_fair2``: the largest fold-free blend toward the bilaplacian fill instead (its
  own folds and crossings allowed), ``t`` on a grid;
- ``nearest_lambda_h``: the fill nearest the λ-H fill (least squares in edge lengths) under
  the fold condition itself — every checked edge the start does not fold keeps its normals
  within ``FOLD_ANGLE`` less 0.02 in cosine — by SLSQP from S0 (``_check``: the damped
  check's verdict on it, crossings included), and ``nearest_damped``: the same toward the
  last damping step ``S0 + 0.15 (λH − S0)`` (untangling the damped fill);
- ``oracle_blend``: the lowest error of any blend of the λ-H fill with either faired fill
  (t = 0, 0.05, ..., 1; folds not checked, the truth used: a bound on what blending can
  reach), with its faired end and ``t``;
- with ``--default``, the error of what the default (``select=True``) writes.

    PYTHONPATH=src .venv/bin/python benchmarks/fold_overs.py quad|brain|egg OUT.jsonl
        (--keys "quad v8 r2.0,..." | --only ROWS.jsonl | --all) [--default] [--seed S]
    --only: the holes whose row in a lambda_h_fallbacks.py run fell back folding over or
    cutting through the surface; --all: every hole (a row with only its outcome where no
    fill was rejected); --seed: the brain probes or quadruped holes of another seed.
"""

import argparse
import json
import sys
import warnings
from pathlib import Path

import numpy as np
from scipy.optimize import minimize

sys.path.insert(0, str(Path(__file__).resolve().parent))
import eggcrate  # noqa: E402
import lambda_h_fallbacks  # noqa: E402

from surfinpaint import ConformalOptions  # noqa: E402
from surfinpaint.errors import FillError  # noqa: E402
from surfinpaint.fill.conformal import candidates, checks, conformal_fill  # noqa: E402
from surfinpaint.fill.liepa.baseline import faired_fills  # noqa: E402
from surfinpaint.geometry.mesh import edge_faces, face_normals, mean_edge_length  # noqa: E402

REASONS = ("folds over", "cuts through", "intersects itself")


def quad_holes(seed):
    """The quadruped's holes (``built_meshes.holes``) around the centres of another seed."""
    import built_meshes

    from surfinpaint.geometry.cutting import cut_geodesic_disk
    if seed == 1:  # the family's own (built_meshes.holes: seed 0)
        yield from lambda_h_fallbacks.quad_holes()
        return
    v, f = built_meshes.quadruped()
    h = mean_edge_length(v, f)
    for centre in np.random.default_rng(seed).choice(len(v), 40, replace=False):
        for radius in (2.0, 3.5):
            try:
                cut = cut_geodesic_disk(v, f, int(centre), radius * h)
            except ValueError:
                continue
            yield f"quad s{seed} v{centre} r{radius}", lambda cut=cut: cut


def capture_rejections():
    """Wrap the damped check the candidates call; return the list it appends the inputs of
    every rejected fill to."""
    rejected, damped = [], candidates.damped_fill

    def wrapper(vertices, start, moving, patch, n_fill, **kw):
        try:
            return damped(vertices, start, moving, patch, n_fill, **kw)
        except FillError:
            rejected.append((vertices.copy(), start.copy(), moving.copy(), patch.copy(),
                             n_fill, kw))
            raise

    candidates.damped_fill = wrapper
    return rejected


def verdict(trial, reference, patch, n_fill, kw):
    """'' when ``trial`` passes the damped check with ``reference``'s folds and crossings
    allowed, else the reason."""
    allowed = checks.fold_count(reference, patch, n_fill, crease=kw.get("crease"))
    crossed = checks.crossings(reference, patch, n_fill,
                               self_crossing=kw.get("self_crossing", True))
    try:
        checks.check_patch(trial, patch, n_fill, self_crossing=kw.get("self_crossing", True),
                           crease=kw.get("crease"), allowed_folds=allowed,
                           allowed_crossings=crossed)
    except FillError as exc:
        return str(exc)
    return ""


def nearest_fold_free(vertices, moving, start, target, patch, n_fill, h):
    """The positions of ``moving`` nearest ``target`` (in edge lengths) whose checked edges
    the start does not fold keep cos(normals) >= cos(FOLD_ANGLE) + 0.02: SLSQP from S0."""
    _, owner, count = edge_faces(patch)
    pairs = owner[(count == 2) & ((owner[:, 0] < n_fill) | (owner[:, 1] < n_fill))]

    def cosines(x):
        trial = vertices.copy()
        trial[moving] = x.reshape(-1, 3)
        normals = face_normals(trial, patch)
        return np.einsum("ij,ij->i", normals[pairs[:, 0]], normals[pairs[:, 1]])

    bound = np.cos(np.radians(checks.FOLD_ANGLE))
    kept = cosines(start.ravel()) >= bound
    goal = target.ravel()
    found = minimize(lambda x: np.sum((x - goal) ** 2) / h ** 2, start.ravel(),
                     jac=lambda x: 2 * (x - goal) / h ** 2, method="SLSQP",
                     constraints=[dict(type="ineq",
                                       fun=lambda x: cosines(x)[kept] - bound - 0.02)],
                     options=dict(maxiter=200))
    out = vertices.copy()
    out[moving] = found.x.reshape(-1, 3)
    return out, found.message


def blend_of(fill):
    """Whether the fill written is a blend of a rejected λ-H fill with a faired one
    (``method._blended``): with which, and the λ-H fill's share."""
    d = fill.diagnostics
    blended = d is not None and d.blended_with is not None
    return dict(blended_with=d.blended_with if blended else None,
                blend_t=d.damping if blended else None)


def study(key, cut, rejected, default):
    rejected.clear()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = conformal_fill(cut.vertices, cut.faces, cut.loop,
                                ConformalOptions(select=False))
    row = dict(key=key, kind=result.kind, failure=result.failure, selection=result.selection,
               **blend_of(result))
    if not rejected or row["blended_with"] is None and result.kind == "conformal":
        return row | dict(damping=getattr(result.diagnostics, "damping", None))
    row["written"] = round(eggcrate.error(cut, result.vertices, result.faces), 3)
    lam, s0, moving, patch, n_fill, kw = rejected[-1]
    n = len(cut.vertices)
    fill_faces = patch[:n_fill]
    fair = faired_fills(cut.vertices, cut.faces, cut.loop, (2, 3))

    def at(x):
        out = lam.copy()
        out[moving] = x
        return out

    def error(positions):
        return round(eggcrate.error(cut, positions[n:], fill_faces), 3)

    start, bilaplacian = at(s0), at(fair[2][0][moving - n])
    row |= dict(moving=len(moving), same_triangles=bool(
        np.array_equal(fill_faces, fair[2][1]) and np.allclose(s0, fair[3][0][moving - n])),
        fair2=error(bilaplacian), fair3=error(start), lambda_h=error(lam))
    low, high = 0.0, min(checks.DAMPING_STEPS)
    for _ in range(8):
        mid = 0.5 * (low + high)
        if verdict(at(s0 + mid * (lam[moving] - s0)), start, patch, n_fill, kw):
            high = mid
        else:
            low = mid
    row |= dict(t_s0=round(low, 4), blend_s0=error(at(s0 + low * (lam[moving] - s0))))
    ok = [t for t in (0.02, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 1.0)
          if not verdict(at(bilaplacian[moving] + t * (lam[moving] - bilaplacian[moving])),
                         bilaplacian, patch, n_fill, kw)]
    t2 = max(ok, default=0.0)
    row |= dict(t_fair2=t2, blend_fair2=error(
        at(bilaplacian[moving] + t2 * (lam[moving] - bilaplacian[moving]))))
    best = min((error(at(end[moving] + t * (lam[moving] - end[moving]))), name, t)
               for name, end in (("fair2", bilaplacian), ("fair3", start))
               for t in np.round(np.linspace(0.0, 1.0, 21), 2))
    row |= dict(oracle_blend=best[0], oracle_end=best[1], oracle_t=float(best[2]))
    h = mean_edge_length(cut.vertices, cut.faces)
    for name, target in (("nearest_lambda_h", lam[moving]),
                         ("nearest_damped", s0 + min(checks.DAMPING_STEPS) * (lam[moving] - s0))):
        positions, message = nearest_fold_free(start, moving, s0, target, patch, n_fill, h)
        row |= {name: error(positions) if np.isfinite(positions).all() else None,
                f"{name}_check": verdict(positions, start, patch, n_fill, kw)[:60],
                f"{name}_solver": str(message)[:40]}
    if default:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            chosen = conformal_fill(cut.vertices, cut.faces, cut.loop)
        row |= dict(default_kind=chosen.kind, default_order=chosen.fair_order,
                    default_failed=chosen.failure is not None or
                    blend_of(chosen)["blended_with"] is not None,
                    default_blend=blend_of(chosen),
                    default=round(eggcrate.error(cut, chosen.vertices, chosen.faces), 3))
    return row


def main():
    p = argparse.ArgumentParser()
    p.add_argument("family", choices=("egg", "quad", "brain"))
    p.add_argument("out")
    p.add_argument("--keys", default="")
    p.add_argument("--only")
    p.add_argument("--default", action="store_true")
    p.add_argument("--all", action="store_true")
    p.add_argument("--seed", type=int, default=1)
    a = p.parse_args()
    keys = set(filter(None, a.keys.split(",")))
    if a.only:
        keys |= {r["key"] for r in map(json.loads, open(a.only))
                 if r["kind"] != "conformal" and any(s in r["failure"][-90:] for s in REASONS)}
    gen = {"egg": lambda_h_fallbacks.egg_holes, "quad": lambda x=None: quad_holes(a.seed),
           "brain": lambda x=None: lambda_h_fallbacks.brain_holes(a.seed)}[a.family]
    rejected = capture_rejections()
    with open(a.out, "w") as out:
        for key, make in gen():
            if a.all or key in keys:
                row = study(key, make(), rejected, a.default)
                out.write(json.dumps(row) + "\n")
                out.flush()
                print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main()
