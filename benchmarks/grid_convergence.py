"""Grid-level convergence of the λ-H representation and of the rebuild of a removed disk.

For Enneper's surface, the stereographic unit sphere and an isothermal torus (method.md §7),
on n × n grids (n = 17 … 129) over a parameter square of side 2:

* λ, H: max error of lambda_h against the exact values (λ relative to max λ, H absolute);
* rebuild: a disk of radius 0.3 is removed and rebuilt by each method from the exact (λ, H)
  and from the discrete (λ, H) of the grid surface itself (lambda_h); max position error
  relative to the 3D diameter of the removed patch;
* inpaint+rebuild: (λ, H) are removed on the disk dilated by 2 nodes, biharmonically
  inpainted, then the disk is rebuilt (the grid-level pipeline);
* order: log2 of the error ratio to the previous resolution; time: the rebuild only.

A second table adds noise to the discrete (λ, H) (Gaussian, relative to their spread) and
compares hard two-ring inpainting with the soft data-fidelity version (method.md §8).

Run: ``python benchmarks/grid_convergence.py [--sizes 17 33 65 129]``; prints markdown.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from scipy import ndimage

from surfinpaint.representation.analytic import SURFACES, grid, removed_disk
from surfinpaint.representation.fields import lambda_h
from surfinpaint.representation.inpainting import inpaint
from surfinpaint.representation.reconstruction import METHODS, reconstruct

VARIANTS = {  # label -> reconstruct arguments
    "gauss-codazzi": {"method": "gauss-codazzi"},
    "gauss-codazzi (integrate=normal)": {"method": "gauss-codazzi", "integrate": "normal"},
    "laplacian": {"method": "laplacian"},
}


def rebuild_error(lam, H, phi, known, h, method):
    given = np.where(known[..., None], phi, np.nan)
    t = time.perf_counter()
    out = reconstruct(lam, H, given, known, h, **VARIANTS[method])
    t = time.perf_counter() - t
    diameter = np.linalg.norm(np.ptp(phi[~known], axis=0))
    return np.abs(out - phi)[~known].max() / diameter, t


def order(errs: list[float]) -> list[str]:
    out = ["–"]
    for a, b in zip(errs[:-1], errs[1:], strict=True):
        out.append(f"{np.log2(a / b):.2f}" if a > 1e-11 and b > 1e-11 else "(exact)")
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[17, 33, 65, 129])
    args = parser.parse_args()

    print("### λ and H from lambda_h\n")
    print("| surface | n | λ rel. err | order | H abs. err | order |")
    print("|---|---|---|---|---|---|")
    for name, (f, ext) in SURFACES.items():
        el, eh = [], []
        for n in args.sizes:
            u, v, h = grid(n, ext)
            phi, lam, H = f(u, v)
            lh, Hh = lambda_h(phi, h)
            el.append(np.nanmax(abs(lh - lam)) / lam.max())
            eh.append(np.nanmax(abs(Hh - H)))
        for n, a, oa, b, ob in zip(args.sizes, el, order(el), eh, order(eh), strict=True):
            print(f"| {name} | {n} | {a:.2e} | {oa} | {b:.2e} | {ob} |")

    print("\n### Rebuild of a removed disk (radius 0.3), max error / patch diameter\n")
    print(
        "| surface | method | n | exact λ,H | order | discrete λ,H | order "
        "| inpainted λ,H | order | time (s) |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    for name in SURFACES:
        for method in VARIANTS:
            rows = []
            for n in args.sizes:
                phi, lam, H, known, h = removed_disk(name, n)
                e_exact, t = rebuild_error(lam, H, phi, known, h, method)
                ld, Hd = lambda_h(phi, h)
                e_disc, _ = rebuild_error(ld, Hd, phi, known, h, method)
                omega = ndimage.binary_dilation(~known, np.ones((3, 3), bool), iterations=2)
                li = inpaint(np.where(omega, np.nan, ld), omega)
                Hi = inpaint(np.where(omega, np.nan, Hd), omega)
                e_inp, _ = rebuild_error(li, Hi, phi, known, h, method)
                rows.append((n, e_exact, e_disc, e_inp, t))
            cols = list(zip(*rows, strict=True))
            o1, o2, o3 = order(list(cols[1])), order(list(cols[2])), order(list(cols[3]))
            for k, (n, a, b, c, t) in enumerate(rows):
                print(
                    f"| {name} | {method} | {n} | {a:.2e} | {o1[k]} | {b:.2e} | {o2[k]} "
                    f"| {c:.2e} | {o3[k]} | {t:.3f} |"
                )

    noise_table(65)


def noise_table(n: int, seeds: int = 5) -> None:
    print(f"\n### Noisy λ, H (n = {n}): rebuild error / patch diameter, mean of {seeds} seeds\n")
    fits = [("hard", {}), ("w=1, 4 rings", {"fidelity": 1.0}),
            ("w=0.1, 4 rings", {"fidelity": 0.1}), ("w=0.1, 8 rings", {"fidelity": 0.1,
                                                                     "rings": 8})]
    print("| surface | method | noise | " + " | ".join(f for f, _ in fits) + " |")
    print("|---|---|---|" + "---|" * len(fits))
    for name in SURFACES:
        phi, _, _, known, h = removed_disk(name, n)
        ld, Hd = lambda_h(phi, h)
        omega = ndimage.binary_dilation(~known, np.ones((3, 3), bool), iterations=2)
        for method in METHODS:
            for sigma in (0.01, 0.05):
                errs = np.zeros(len(fits))
                for seed in range(seeds):
                    rng = np.random.default_rng(seed)
                    ln = ld + sigma * np.nanstd(ld) * rng.standard_normal(ld.shape)
                    Hn = Hd + sigma * max(np.nanstd(Hd), 1.0) * rng.standard_normal(Hd.shape)
                    valid = np.isfinite(ld)
                    for k, (_, opts) in enumerate(fits):
                        li = inpaint(np.where(omega, np.nan, ln), omega, domain=valid, **opts)
                        Hi = inpaint(np.where(omega, np.nan, Hn), omega, domain=valid, **opts)
                        # the rebuild reads λ, H only on and near the unknown disk
                        errs[k] += rebuild_error(li, Hi, phi, known, h, method)[0] / seeds
                cells = " | ".join(f"{e:.2e}" for e in errs)
                print(f"| {name} | {method} | {sigma:g} | {cells} |")


if __name__ == "__main__":
    main()
