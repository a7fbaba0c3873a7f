"""A truth-free test on the hole itself: how much each candidate's fill of the hole moves
when one or two more rings around it are hidden and the larger hole is filled again (its
"stability"), for replaying rules (``benchmarks/selfcheck_replay.py``). The hidden-ring and
sibling tests score the candidates on other holes; this one asks whether a candidate's
prediction of this hole's own surface depends on where its rim is.

Per hole and candidate (the self-check's test fills, ``Candidates.for_tests``): samples of
the candidate's fill of the hole, their mean distance to the same candidate's fill of the
hole with ``k`` rings hidden (k = 1, 2), in % of the hole diameter.

    python benchmarks/selfcheck_stability.py --split tuning --cache /tmp/stability.jsonl
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import selfcheck_table  # noqa: E402

from surfinpaint.errors import NUMERICAL_ERRORS, MeshError  # noqa: E402
from surfinpaint.fill.conformal import ConformalOptions  # noqa: E402
from surfinpaint.fill.conformal.candidates import Candidates  # noqa: E402
from surfinpaint.fill.holes import loop_diameter  # noqa: E402
from surfinpaint.geometry.cutting import ring_distances  # noqa: E402
from surfinpaint.geometry.mesh import boundary_loops  # noqa: E402
from surfinpaint.geometry.metrics import point_mesh_distance, sample_surface  # noqa: E402

HIDE = (1, 2)


def enlarged_hole(vertices, faces, loop, k):
    """The faces kept and the loop of the hole with ``k`` more rings hidden (as
    ``hidden_ring_scores`` hides them), or None."""
    ring = ring_distances(faces, len(vertices), loop, k + 0.5)
    near = ring <= k - 1
    kept = faces[~near[faces].any(axis=1)]
    border = (ring <= k) & ~near
    try:
        loops = boundary_loops(kept)
    except MeshError:
        return None
    enlarged = [lp for lp in loops if border[lp].mean() > 0.5]
    return (kept, enlarged[0]) if len(enlarged) == 1 else None


def stability(vertices, faces, loop, options: ConformalOptions, n_samples=2000) -> dict:
    """{k: {candidate: mean distance (% of diameter) from its fill of the hole to its fill
    of the hole with k more rings hidden}} (inf where a fill failed)."""
    tests = Candidates.for_hole(vertices, faces, loop, options).for_tests()
    diameter = loop_diameter(vertices[loop])
    own = tests(vertices, faces, loop)
    out = {}
    for k in HIDE:
        hole = enlarged_hole(vertices, faces, loop, k)
        if hole is None:
            continue
        try:
            again = tests(vertices, hole[0], hole[1])
        except NUMERICAL_ERRORS:
            continue
        scores = {}
        for name, fill in own.items():
            other = again.get(name)
            if isinstance(fill, Exception) or other is None or isinstance(other, Exception):
                scores[name] = float("inf")
                continue
            v = np.concatenate([vertices, fill.vertices])
            samples = sample_surface(v, fill.faces, n_samples, seed=0)
            d = point_mesh_distance(samples, np.concatenate([vertices, other.vertices]),
                                    other.faces)
            scores[name] = float(100.0 * d.mean() / diameter)
        out[str(k)] = scores
    return out


def build(cache: Path, split, meshes) -> list[dict]:
    def compute(entry, k, hole, cut, local):
        started = time.perf_counter()
        s = stability(local.vertices, local.faces, local.local_loop, options)
        row = {"mesh": entry["mesh"], "hole": k, "split": entry["split"],
               "stability": s, "seconds": time.perf_counter() - started}
        print(f"{entry['mesh']} #{k}: {s} ({row['seconds']:.1f} s)", file=sys.stderr,
              flush=True)
        return row

    options = ConformalOptions()
    return selfcheck_table.cached_rows(cache, split, meshes, options, compute)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--split", choices=("tuning", "validation"), default=None)
    parser.add_argument("--meshes", default=None, help="comma-separated mesh ids")
    parser.add_argument("--cache", required=True, help="JSONL file of rows (appended)")
    args = parser.parse_args(argv)
    return build(Path(args.cache), args.split, args.meshes.split(",") if args.meshes else None)


if __name__ == "__main__":
    main()
