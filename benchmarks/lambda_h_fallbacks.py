"""Per-hole λ-H outcomes on issue 20's tuning-side families, one JSON row a hole: the
egg-crate family (``eggcrate.py``, 180 holes), the coarse quadruped (``built_meshes.py``,
80 holes) and the brain probes (``brain_probes.py``'s 25 holes of 8 edge lengths on each
of the left pial and white surfaces, seed 1). Each hole is filled by the λ-H fill
(``select=False``); a row has its outcome, failure reason, CPU seconds, a hash of the new
vertices (bit-identity between runs), the error against the removed truth and the
bilaplacian fill's (two-sided mean distance, % of the hole's diameter, as
``eggcrate.py``), and where the last stage was used its residual (docs/convergence.md).

    PYTHONPATH=src .venv/bin/python benchmarks/lambda_h_fallbacks.py egg|quad|brain OUT.jsonl
        [--only ROWS.jsonl]   # only the holes that fell back in an earlier run's rows
    Rows also carry the least-squares stage's CPU seconds and lagged updates, per part
    (cpu_cont, cpu_lm, updates_cont, updates_lm; zero where the stage did not run).
"""
import argparse
import hashlib
import json
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import eggcrate  # noqa: E402

from surfinpaint import ConformalOptions  # noqa: E402
from surfinpaint.fill.conformal import conformal_fill  # noqa: E402
from surfinpaint.fill.liepa.baseline import faired_fill  # noqa: E402
from surfinpaint.geometry.cutting import cut_geodesic_disk  # noqa: E402
from surfinpaint.geometry.mesh import mean_edge_length  # noqa: E402


def egg_holes():
    for n in eggcrate.SIZES:
        for seed in eggcrate.SEEDS:
            for period, amplitude, jitter in eggcrate.FAMILY:
                for radius in eggcrate.RADII:
                    key = f"egg n{n} s{seed} p{period} a{amplitude} j{jitter} r{radius}"
                    yield key, lambda n=n, seed=seed, period=period, amplitude=amplitude, \
                        jitter=jitter, radius=radius: eggcrate.egg_crate(
                            n, seed, period, amplitude, jitter, radius)


def quad_holes():
    import built_meshes
    v, f = built_meshes.quadruped()
    for centre, radius, cut in built_meshes.holes(v, f):
        yield f"quad v{centre} r{radius}", lambda cut=cut: cut


def brain_holes(seed=1):
    """The brain probes; ``seed`` 1 is the family's (other seeds: more holes of the same
    kind, ``fold_overs.py --seed``; keyed with the seed when it is not 1)."""
    from surfinpaint.data import fsaverage5
    for surface in ("pial", "white"):
        v, f = fsaverage5(surface, "left")
        h = mean_edge_length(v, f)
        rng = np.random.default_rng(seed)
        tag = "" if seed == 1 else f" s{seed}"
        for k, centre in enumerate(rng.integers(len(v), size=25)):
            try:
                cut = cut_geodesic_disk(v, f, int(centre), 8 * h)
            except Exception:  # noqa: BLE001
                continue
            yield f"brain{tag} {surface} #{k}", lambda cut=cut: cut


class StageClock:
    """CPU seconds and lagged updates of the least-squares stage's two parts (the
    continuation and Levenberg–Marquardt), per hole: ``least_squares_stage``'s functions
    wrapped."""

    def __init__(self):
        from surfinpaint.representation import least_squares_stage, on_mesh
        self.reset()
        self.part = None
        update = on_mesh._CoupledSystem.update

        def counted(system, phi):
            if self.part is not None:
                self.updates[self.part] += 1
            return update(system, phi)

        on_mesh._CoupledSystem.update = counted
        for name, part in (("_continuation", "cont"), ("levenberg_marquardt", "lm")):
            setattr(least_squares_stage, name,
                    self.timed(getattr(least_squares_stage, name), part))

    def reset(self):
        self.seconds = {"cont": 0.0, "lm": 0.0}
        self.updates = {"cont": 0, "lm": 0}

    def timed(self, function, part):
        def wrapper(*args, **kwargs):
            self.part, t0 = part, time.process_time()
            try:
                return function(*args, **kwargs)
            finally:
                self.seconds[part] += time.process_time() - t0
                self.part = None
        return wrapper

    def row(self):
        return {f"cpu_{k}": round(v, 3) for k, v in self.seconds.items()} | {
            f"updates_{k}": v for k, v in self.updates.items()}


def main():
    p = argparse.ArgumentParser()
    p.add_argument("family")
    p.add_argument("out")
    p.add_argument("--only")
    p.add_argument("--keys", help="comma-separated substrings of the hole keys to run")
    a = p.parse_args()
    only = None
    if a.only:
        only = {r["key"] for r in map(json.loads, open(a.only)) if r["kind"] != "conformal"}
    gen = {"egg": egg_holes, "quad": quad_holes, "brain": brain_holes}[a.family]
    raw = ConformalOptions(select=False)
    out = open(a.out, "w")
    clock = StageClock()
    for key, make in gen():
        if only is not None and key not in only:
            continue
        if a.keys and not any(s in key for s in a.keys.split(",")):
            continue
        cut = make()
        clock.reset()
        t0 = time.process_time()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = conformal_fill(cut.vertices, cut.faces, cut.loop, raw)
        cpu = time.process_time() - t0
        row = dict(key=key, kind=result.kind, failure=result.failure, cpu=round(cpu, 3),
                   edges=len(cut.loop),
                   hash=hashlib.sha1(np.ascontiguousarray(result.vertices).tobytes()).hexdigest()[:12])
        row |= clock.row()  # the least-squares stage's parts (zero where it did not run)
        row["error"] = eggcrate.error(cut, result.vertices, result.faces)
        fv, ff, _ = faired_fill(cut.vertices, cut.faces, cut.loop, 2)
        row["fair2"] = eggcrate.error(cut, fv, ff)
        if result.kind != "conformal" or a.only:
            fv, ff, _ = faired_fill(cut.vertices, cut.faces, cut.loop, 3)
            row["fair3"] = eggcrate.error(cut, fv, ff)
        d = getattr(result, "diagnostics", None)
        if d is not None and d.mesh is not None:
            stage = d.mesh.least_squares
            row["lsq"] = None if stage is None else stage.residual
            row["weight"] = None if stage is None else stage.weight
            row["damping"] = d.damping
        out.write(json.dumps(row) + "\n")
        out.flush()
        print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main()
