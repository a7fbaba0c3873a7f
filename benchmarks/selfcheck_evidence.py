"""More truth-free evidence per hole than the self-check gathers, for replaying rules that
need it (``benchmarks/selfcheck_replay.py --evidence``): each sibling hole's scores on
their own (``siblings`` of them, the library's first ones come first) and the hidden-ring
test with 1, 2 and 3 rings hidden. Holes are cut as ``benchmarks/selfcheck_table.py`` cuts
them (the same neighbourhood, the same candidates and test fills as ``conformal_fill``).

    python benchmarks/selfcheck_evidence.py --split tuning --cache /tmp/evidence.jsonl

The siblings are the library's own (``sibling_scores(..., each=True)``; their centres are
placed in farthest-point order, so the first two are the default test's two).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
import selfcheck_table  # noqa: E402

from surfinpaint.fill import selfcheck  # noqa: E402
from surfinpaint.fill.conformal import ConformalOptions  # noqa: E402
from surfinpaint.fill.conformal.candidates import Candidates  # noqa: E402

HIDE = (1, 2, 3)


def each_sibling(vertices, faces, loop, tests, options, count) -> list[dict]:
    """The scores of each of the first ``count`` sibling holes that could be cut."""
    return selfcheck.sibling_scores(vertices, faces, loop, tests, siblings=count,
                                    gap_rings=options.gap_rings,
                                    patch_rings=options.rings_in_patch, each=True)


def hole_evidence(vertices, faces, loop, options: ConformalOptions, siblings: int) -> dict:
    """Hidden-ring scores per number of hidden rings and per-sibling scores."""
    candidates = Candidates.for_hole(vertices, faces, loop, options)
    tests = candidates.for_tests()
    started = time.perf_counter()
    hidden = {str(k): selfcheck.hidden_ring_scores(vertices, faces, loop, tests,
                                                   hide_rings=k,
                                                   patch_rings=options.rings_in_patch)
              for k in HIDE}
    sib = each_sibling(vertices, faces, loop, tests, options, siblings)
    return {"hidden_by_rings": hidden, "siblings_each": sib,
            "seconds": time.perf_counter() - started}


def build(cache: Path, split: str | None, meshes, siblings: int) -> list[dict]:
    def compute(entry, k, hole, cut, local):
        row = hole_evidence(local.vertices, local.faces, local.local_loop, options, siblings)
        print(f"{entry['mesh']} #{k}: {len(row['siblings_each'])} siblings "
              f"({row['seconds']:.1f} s)", file=sys.stderr, flush=True)
        return {"mesh": entry["mesh"], "hole": k, "split": entry["split"], **row}

    options = ConformalOptions()
    return selfcheck_table.cached_rows(cache, split, meshes, options, compute)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--split", choices=("tuning", "validation"), default=None)
    parser.add_argument("--meshes", default=None, help="comma-separated mesh ids")
    parser.add_argument("--cache", required=True, help="JSONL file of rows (appended)")
    parser.add_argument("--siblings", type=int, default=6)
    args = parser.parse_args(argv)
    meshes = args.meshes.split(",") if args.meshes else None
    return build(Path(args.cache), args.split, meshes, args.siblings)


if __name__ == "__main__":
    main()
