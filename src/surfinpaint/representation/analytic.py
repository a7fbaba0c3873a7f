"""Analytic conformal surfaces with exact conformal factor λ and mean curvature H.

Ground truth for the grid level (method.md §7): every function takes parameter arrays of
the same shape (usually from :func:`grid`) and returns ``(phi, lam, H)`` with ``phi`` of shape
``u.shape + (3,)``. Conventions follow method.md §1: ``|φu| = |φv| = λ``, ``n = φu × φv`` and
``Δφ = 2 λ² H n``.
"""

from __future__ import annotations

import numpy as np

__all__ = ["SURFACES", "enneper", "grid", "isothermal_torus", "removed_disk",
           "stereographic_sphere"]


def grid(
    n: int, extent: tuple[float, float, float, float] = (-1.0, 1.0, -1.0, 1.0)
) -> tuple[np.ndarray, np.ndarray, float]:
    """A uniform ``n × n`` grid over ``[u0, u1] × [v0, v1]``.

    Parameters
    ----------
    n : int
        Nodes per side (``n >= 2``).
    extent : (u0, u1, v0, v1)
        The parameter rectangle. The spacing is taken from the u side; the v side should be
        as long so that the grid is square (a ValueError is raised otherwise).

    Returns
    -------
    u, v : (n, n) arrays
        ``u[i, j] = u0 + i h``, ``v[i, j] = v0 + j h`` (``indexing="ij"``).
    h : float
        The spacing.

    Examples
    --------
    >>> u, v, h = grid(3)
    >>> h, u[:, 0].tolist()
    (1.0, [-1.0, 0.0, 1.0])
    """
    if n < 2:
        raise ValueError(f"grid needs at least 2 nodes per side, got {n}")
    u0, u1, v0, v1 = (float(x) for x in extent)
    if not np.isclose(u1 - u0, v1 - v0):
        raise ValueError(f"grid extent must be square, got {u1 - u0} by {v1 - v0}")
    h = (u1 - u0) / (n - 1)
    t = np.arange(n) * h
    u, v = np.meshgrid(u0 + t, v0 + t, indexing="ij")
    return u, v, h


def enneper(u: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Enneper's minimal surface.

    φ = (u − u³/3 + uv², −v + v³/3 − vu², u² − v²), λ = 1 + u² + v², H = 0.
    """
    u = np.asarray(u, dtype=float)
    v = np.asarray(v, dtype=float)
    phi = np.stack([u - u**3 / 3 + u * v**2, -v + v**3 / 3 - v * u**2, u**2 - v**2], axis=-1)
    return phi, 1.0 + u**2 + v**2, np.zeros_like(u)


def stereographic_sphere(
    u: np.ndarray, v: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The unit sphere by inverse stereographic projection from the north pole.

    φ = (2u, 2v, u² + v² − 1)/(1 + u² + v²), λ = 2/(1 + u² + v²), H = +1
    (``n = φu × φv`` points inward).
    """
    u = np.asarray(u, dtype=float)
    v = np.asarray(v, dtype=float)
    s = 1.0 + u**2 + v**2
    phi = np.stack([2 * u / s, 2 * v / s, (u**2 + v**2 - 1) / s], axis=-1)
    return phi, 2.0 / s, np.ones_like(u)


def isothermal_torus(
    theta: np.ndarray, sigma: np.ndarray, R: float = 2.0, r: float = 1.0
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A torus of revolution in isothermal coordinates (θ, σ).

    With c = √(R² − r²), σ(ψ) = (2r/c)·arctan(√((R−r)/(R+r))·tan(ψ/2)) (continued
    monotonically past ψ = ±π), φ = ((R + r cos ψ) cos θ, (R + r cos ψ) sin θ, r sin ψ),
    λ = R + r cos ψ and H = −(R + 2r cos ψ)/(2r(R + r cos ψ)); ``n = φθ × φσ`` is outward.

    Raises
    ------
    ValueError
        If not ``R > r > 0``.
    """
    if not (R > r > 0):
        raise ValueError(f"isothermal_torus needs R > r > 0, got R={R}, r={r}")
    theta = np.asarray(theta, dtype=float)
    sigma = np.asarray(sigma, dtype=float)
    c = np.sqrt(R * R - r * r)
    s = sigma * c / (2 * r)
    k = np.sqrt((R + r) / (R - r))
    # Invert σ(ψ) on the branch that is continuous in σ: ψ/2 = atan(k tan s) + π·round(s/π).
    half = np.arctan(k * np.tan(s)) + np.pi * np.round(s / np.pi)
    psi = 2 * half
    rho = R + r * np.cos(psi)
    phi = np.stack([rho * np.cos(theta), rho * np.sin(theta), r * np.sin(psi)], axis=-1)
    H = -(R + 2 * r * np.cos(psi)) / (2 * r * rho)
    return phi, rho, H


#: The surfaces the grid level is checked and measured on (method.md §7): name -> (the
#: surface, as the functions above, and its parameter rectangle ``(u0, u1, v0, v1)``); the
#: torus with its default radii R = 2, r = 1.
SURFACES = {
    "enneper": (enneper, (-1.0, 1.0, -1.0, 1.0)),
    "sphere": (stereographic_sphere, (-1.0, 1.0, -1.0, 1.0)),
    "torus": (isothermal_torus, (-1.0, 1.0, 0.0, 2.0)),
}


def removed_disk(name: str, n: int, radius: float = 0.3
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, float]:
    """The rebuild case of :data:`SURFACES`' ``name`` on an ``n × n`` :func:`grid`: the
    nodes within ``radius`` of a point beside the rectangle's centre (+0.1 in u, −0.05 in
    v) are the removed disk.

    Returns
    -------
    phi, lam, H : arrays
        The surface and its exact λ and H on the grid.
    known : (n, n) bool array
        False on the removed disk.
    h : float
        The grid spacing.
    """
    surface, extent = SURFACES[name]
    u, v, h = grid(n, extent)
    phi, lam, H = surface(u, v)
    cu, cv = 0.5 * (extent[0] + extent[1]) + 0.1, 0.5 * (extent[2] + extent[3]) - 0.05
    known = (u - cu) ** 2 + (v - cv) ** 2 > radius**2
    return phi, lam, H, known, h
