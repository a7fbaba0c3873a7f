"""Test and benchmark meshes: synthetic surfaces generated here, and loaders for real meshes
that ship inside other installed packages (PyMeshLab, nilearn, pymeshfix).

Every function returns ``(vertices, faces)``: an ``(n, 3)`` float array and an ``(f, 3)``
int array. Synthetic meshes are deterministic, have fairly regular triangles and are closed,
edge-manifold and consistently oriented with outward normals (``bumpy_disk`` is the open
exception: one boundary loop, normals pointing up).

The real meshes are never copied into this repository; they are read from the installed
package that ships them, and a missing package raises :class:`ModuleNotFoundError` naming
what to install.
"""

from __future__ import annotations

import importlib
import importlib.resources
import tempfile
import warnings
from pathlib import Path

import numpy as np

from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.geometry.mesh import unique_edges, vertex_normals
from surfinpaint.io.atomic import atomic_open
from surfinpaint.io.formats import MeshWarning, read_mesh
from surfinpaint.lazy import lazy_module

optimize = lazy_module("scipy.optimize")  # generating the bundled meshes only

__all__ = [
    "bumpy_disk",
    "cube",
    "default_demo_mesh",
    "default_demo_path",
    "fsaverage5",
    "lens",
    "pymeshfix_bunny",
    "pymeshlab_sample",
    "regenerate_default_data",
    "snowman",
    "sphere",
    "tooth",
    "torus",
]

DATA_DIR = Path(__file__).parent / "meshes"
DEMO_FILE = "snowman_holes.ply"


# --------------------------------------------------------------------------- helpers


def _signed_volume(vertices: np.ndarray, faces: np.ndarray) -> float:
    v = vertices[faces]
    return float(np.einsum("ij,ij->i", v[:, 0], np.cross(v[:, 1], v[:, 2])).sum() / 6.0)


def _outward(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Flip all faces of a consistently oriented closed mesh if its volume is negative."""
    return faces[:, ::-1].copy() if _signed_volume(vertices, faces) < 0 else faces


def _orient_convex(vertices: np.ndarray, faces: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """Orient every face of a convex (star-shaped about ``centre``) mesh away from ``centre``."""
    v = vertices[faces]
    n = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])
    flip = np.einsum("ij,ij->i", n, v.mean(axis=1) - centre) < 0
    out = faces.copy()
    out[flip] = out[flip][:, ::-1]
    return out


def _zip_rings(a: np.ndarray, b: np.ndarray, ta: np.ndarray, tb: np.ndarray) -> np.ndarray:
    """Triangulate the band between two closed rings of vertex ids ``a`` and ``b``.

    ``ta`` and ``tb`` are the rings' angular positions in [0, 1). The triangles follow the
    merged angular order, so they are as close to equilateral as the two spacings allow.
    A ring of a single vertex (a pole) gives a fan.
    """
    na, nb = len(a), len(b)
    # an event "advance ring a from i to i+1" happens at the midpoint between a[i] and a[i+1]
    ea = ta + 0.5 / na
    eb = tb + 0.5 / nb
    # start both rings at the vertex with smallest angle
    ia0, ib0 = int(np.argmin(ta)), int(np.argmin(tb))
    ea = np.roll(ea, -ia0)
    eb = np.roll(eb, -ib0)
    a = np.roll(a, -ia0)
    b = np.roll(b, -ib0)
    key = np.concatenate([ea, eb])
    is_a = np.concatenate([np.ones(na, bool), np.zeros(nb, bool)])
    order = np.argsort(key, kind="stable")
    is_a = is_a[order]
    # position on each ring before each event
    pa = np.concatenate([[0], np.cumsum(is_a)[:-1]])
    pb = np.concatenate([[0], np.cumsum(~is_a)[:-1]])
    ca, cb = a[pa % na], b[pb % nb]
    na_, nb_ = a[(pa + 1) % na], b[(pb + 1) % nb]
    tri = np.where(is_a[:, None], np.stack([ca, na_, cb], 1), np.stack([ca, nb_, cb], 1))
    keep = (tri[:, 0] != tri[:, 1]) & (tri[:, 1] != tri[:, 2]) & (tri[:, 0] != tri[:, 2])
    return tri[keep]


def _revolution(rho: np.ndarray, z: np.ndarray, edge_length: float,
                closed: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Surface of revolution about the z axis of a profile sampled densely as ``(rho, z)``.

    The profile is resampled uniformly in arc length with spacing ``edge_length``; ring ``k``
    gets about ``2π ρ_k / edge_length`` vertices, staggered by half a step between rings, so the
    triangles are nearly equilateral. ``rho`` must vanish at both ends when ``closed`` (the two
    poles become single vertices), and at the first sample only when not closed (a disk).
    """
    s = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(rho), np.diff(z)))])
    m = max(2, int(round(s[-1] / edge_length)))
    st = np.linspace(0.0, s[-1], m + 1)
    r_k = np.interp(st, s, rho)
    z_k = np.interp(st, s, z)
    r_k[0] = 0.0
    if closed:
        r_k[-1] = 0.0
    counts = np.where(r_k > 1e-12, np.maximum(6, np.round(2 * np.pi * r_k / edge_length)), 1)
    counts = counts.astype(np.int64)
    starts = np.concatenate([[0], np.cumsum(counts)])
    rings, angles, pts = [], [], []
    for k, c in enumerate(counts):
        t = (np.arange(c) + 0.5 * (k % 2)) / c
        rings.append(np.arange(starts[k], starts[k + 1]))
        angles.append(t % 1.0)
        th = 2 * np.pi * t
        pts.append(np.column_stack([r_k[k] * np.cos(th), r_k[k] * np.sin(th),
                                    np.full(c, z_k[k])]))
    faces = np.concatenate([_zip_rings(rings[k], rings[k + 1], angles[k], angles[k + 1])
                            for k in range(len(counts) - 1)])
    return np.concatenate(pts), faces


def _smooth_union_profile(centres, radii, blend: float, n: int = 20000, exp=np.exp,
                          log=np.log):
    """Dense profile (ρ, z) of the smooth union of balls on the z axis.

    ρ(z)² = smax_i(r_i² − (z − c_i)²) with the log-sum-exp smooth maximum of width ``blend``,
    so the surface is smooth everywhere, including the necks and the two poles. ``exp`` and
    ``log`` compute that maximum (numpy's by default; see :func:`snowman`).
    """
    centres = np.asarray(centres, float)
    radii = np.asarray(radii, float)

    def g(zz):
        zz = np.atleast_1d(zz)
        q = (radii[None, :] ** 2 - (zz[:, None] - centres[None, :]) ** 2) / blend
        qm = q.max(axis=1, keepdims=True)
        return blend * (qm[:, 0] + log(exp(q - qm).sum(axis=1)))

    lo = (centres - radii).min()
    hi = (centres + radii).max()
    z0 = optimize.brentq(lambda t: g(t)[0], lo - 2 * blend - 1.0, lo + 1e-9) if g(lo)[0] > 0 else lo
    z1 = optimize.brentq(lambda t: g(t)[0], hi - 1e-9, hi + 2 * blend + 1.0) if g(hi)[0] > 0 else hi
    # cosine spacing resolves the square-root behaviour at the poles
    z = z0 + (z1 - z0) * 0.5 * (1 - np.cos(np.pi * np.linspace(0, 1, n)))
    rho = np.sqrt(np.maximum(g(z), 0.0))
    rho[0] = rho[-1] = 0.0
    return rho, z


# --------------------------------------------------------------------------- synthetic meshes


def sphere(subdivisions: int = 4, radius: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Icosphere: a subdivided icosahedron projected onto the sphere.

    Parameters
    ----------
    subdivisions : int
        Number of 1-to-4 midpoint subdivisions; ``10·4^s + 2`` vertices.
    radius : float

    Returns
    -------
    vertices : (n, 3) float array
    faces : (2n − 4, 3) int array, outward oriented

    Examples
    --------
    >>> v, f = sphere(2)
    >>> v.shape, f.shape
    ((162, 3), (320, 3))
    """
    if subdivisions < 0:
        raise ValueError(f"subdivisions must be >= 0, got {subdivisions}")
    p = (1 + 5**0.5) / 2
    v = np.array([[-1, p, 0], [1, p, 0], [-1, -p, 0], [1, -p, 0], [0, -1, p], [0, 1, p],
                  [0, -1, -p], [0, 1, -p], [p, 0, -1], [p, 0, 1], [-p, 0, -1], [-p, 0, 1]],
                 float)
    f = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9],
                  [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2],
                  [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10],
                  [8, 6, 7], [9, 8, 1]], np.int64)
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    for _ in range(subdivisions):
        edges, face_edge, _ = unique_edges(f)
        mid = v[edges].mean(axis=1)
        mid /= np.linalg.norm(mid, axis=1, keepdims=True)
        m = face_edge + len(v)  # midpoint of the edge opposite each corner
        v = np.concatenate([v, mid])
        f = np.concatenate([
            np.column_stack([f[:, 0], m[:, 2], m[:, 1]]),
            np.column_stack([f[:, 1], m[:, 0], m[:, 2]]),
            np.column_stack([f[:, 2], m[:, 1], m[:, 0]]),
            m,
        ])
    f = _orient_convex(v, f, np.zeros(3))
    return v * radius, f


def torus(R: float = 1.0, r: float = 0.4, n_major: int = 96,
          n_minor: int = 40) -> tuple[np.ndarray, np.ndarray]:
    """Ring torus about the z axis, a staggered (near-equilateral where possible) grid.

    Parameters
    ----------
    R, r : float
        Major and minor radius, ``R > r > 0``.
    n_major, n_minor : int
        Vertices around the z axis and around the tube (both >= 3).

    Returns
    -------
    vertices : (n_major·n_minor, 3) float array
    faces : (2·n_major·n_minor, 3) int array, outward oriented
    """
    if not R > r > 0:
        raise ValueError(f"need R > r > 0, got R={R}, r={r}")
    if n_major < 3 or n_minor < 3:
        raise ValueError(f"need n_major, n_minor >= 3, got {n_major}, {n_minor}")
    i, j = np.meshgrid(np.arange(n_major), np.arange(n_minor), indexing="ij")
    # stagger alternate tube rings by half a step: triangles closer to equilateral
    u = 2 * np.pi * (i + 0.5 * (j % 2)) / n_major
    w = 2 * np.pi * j / n_minor
    v = np.stack([(R + r * np.cos(w)) * np.cos(u), (R + r * np.cos(w)) * np.sin(u),
                  r * np.sin(w)], axis=-1).reshape(-1, 3)

    def vid(a, b):
        return (a % n_major) * n_minor + (b % n_minor)

    i, j = i.ravel(), j.ravel()
    odd = (j % 2).astype(bool)
    # row j even: vertex (i, j+1) sits at i+1/2; odd: vertex (i, j) sits at i+1/2
    a, b, c, d = vid(i, j), vid(i + 1, j), vid(i, j + 1), vid(i + 1, j + 1)
    f1 = np.where(odd[:, None], np.stack([a, b, d], 1), np.stack([a, b, c], 1))
    f2 = np.where(odd[:, None], np.stack([a, d, c], 1), np.stack([b, d, c], 1))
    f = np.concatenate([f1, f2])
    return v, _outward(v, f)


def cube(n: int = 16) -> tuple[np.ndarray, np.ndarray]:
    """Unit cube [0, 1]³ with sharp edges; each side an n×n grid of squares split in two.

    Vertices on the cube's edges and corners are shared between sides, so the mesh is closed.

    Parameters
    ----------
    n : int
        Squares per side of each face (>= 1).

    Returns
    -------
    vertices : (6n² + 2, 3) float array
    faces : (12n², 3) int array, outward oriented
    """
    if n < 1:
        raise ValueError(f"n must be >= 1, got {n}")
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    i, j = i.ravel(), j.ravel()
    quads = []
    for axis in range(3):
        for side in (0, n):
            corners = []
            for di, dj in ((0, 0), (1, 0), (1, 1), (0, 1)):
                p = np.empty((len(i), 3), np.int64)
                p[:, axis] = side
                p[:, (axis + 1) % 3] = i + di
                p[:, (axis + 2) % 3] = j + dj
                corners.append(p)
            quads.append(np.stack(corners, axis=1))
    quads = np.concatenate(quads)  # (6n², 4, 3) integer lattice points
    lattice, inverse = np.unique(quads.reshape(-1, 3), axis=0, return_inverse=True)
    q = inverse.reshape(-1, 4)
    f = np.concatenate([q[:, [0, 1, 2]], q[:, [0, 2, 3]]])
    v = lattice / n
    return v, _orient_convex(v, f, np.full(3, 0.5))


def lens(edge_length: float = 0.05, radius: float = 1.5) -> tuple[np.ndarray, np.ndarray]:
    """Lens: two equal spherical caps meeting at a sharp circular rim (a curved crease).

    Both caps are parts of spheres of ``radius`` (mean curvature ``1 / radius``) through the
    unit circle in the plane z = 0, which is the rim: a ring of vertices where the normals
    turn by ``180° - 2 arcsin(1 / radius)`` (96° at the default; flatter caps make a sharper
    rim).

    Parameters
    ----------
    edge_length : float
        Target edge length (adjusted so that the rim is a ring of the mesh).
    radius : float
        The caps' sphere radius, > 1.

    Returns
    -------
    vertices, faces
        A closed genus-0 surface, outward oriented.
    """
    if radius <= 1.0:
        raise ValueError(f"radius must be > 1, got {radius}")
    centre = np.sqrt(radius**2 - 1.0)
    half = np.arcsin(1.0 / radius)  # the cap's half angle
    t = np.linspace(0.0, half, 4000)
    rho, z = radius * np.sin(t), radius * np.cos(t) - centre
    steps = 2 * max(1, int(round(radius * half / edge_length)))  # even: the rim is a ring
    rho = np.concatenate([rho, rho[-2::-1]])
    z = np.concatenate([z, -z[-2::-1]])
    v, f = _revolution(rho, z, 2 * radius * half / steps)
    return v, _outward(v, f)


def snowman(edge_length: float = 0.06, *, exp=np.exp, log=np.log
            ) -> tuple[np.ndarray, np.ndarray]:
    """Snowman: three balls on the z axis blended into one smooth surface.

    Balls of radii 1, 0.7, 0.5 centred at z = 0, 1.45, 2.6; the surface of revolution of
    their smooth union (log-sum-exp blend of ρ², width 0.2), so it is smooth everywhere,
    with two concave necks (radii 0.565 at z ≈ 0.94 and 0.40 at z ≈ 2.18): a closed genus-0
    surface from z = −1 to z = 3.1.

    Parameters
    ----------
    edge_length : float
        Target edge length.
    exp, log : callable
        The blend's elementwise functions: numpy's AVX-512 loops give other last bits than
        its others (the C library's), so a caller that needs fixed bytes passes its own.

    Returns
    -------
    vertices, faces
        About ``19.6 / edge_length²`` vertices (5443 at the default), outward oriented.
    """
    rho, z = _smooth_union_profile([0.0, 1.45, 2.6], [1.0, 0.7, 0.5], blend=0.2, exp=exp,
                                   log=log)
    v, f = _revolution(rho, z, edge_length)
    return v, _outward(v, f)


def tooth(edge_length: float = 0.05) -> tuple[np.ndarray, np.ndarray]:
    """Synthetic tooth-like surface (not a scan): a crown with 4 cusps on a narrower root.

    The body is a surface of revolution of a smooth union of a squat crown ellipsoid and a
    long thin root ellipsoid; four Gaussian cusp bumps are pushed out along the normals on
    the occlusal (top) side, leaving a central fossa between them.

    Parameters
    ----------
    edge_length : float
        Target edge length (the tooth is about 2.6 tall, 1.6 wide).

    Returns
    -------
    vertices, faces
        A closed genus-0 mesh, outward oriented.
    """
    # profile: crown ellipsoid (semi-axes 0.8 x 0.55 at z = 0.5), root ellipsoid (0.33 x 1.2
    # at z = -0.6); written as balls in a z-scaled frame, blended, then unscaled.
    zc = np.linspace(-1.9, 1.2, 20001)
    crown = 0.8**2 * (1 - ((zc - 0.5) / 0.55) ** 2)
    root = 0.33**2 * (1 - ((zc + 0.6) / 1.2) ** 2)
    blend = 0.02
    q = np.stack([crown, root], 1) / blend
    qm = q.max(axis=1, keepdims=True)
    g = blend * (qm[:, 0] + np.log(np.exp(q - qm).sum(axis=1)))
    inside = np.flatnonzero(g > 0)
    lo, hi = inside[0], inside[-1]
    # refine the poles where g crosses zero (linear interpolation on the dense grid)
    z0 = zc[lo - 1] + (zc[lo] - zc[lo - 1]) * (-g[lo - 1]) / (g[lo] - g[lo - 1])
    z1 = zc[hi] + (zc[hi + 1] - zc[hi]) * g[hi] / (g[hi] - g[hi + 1])
    t = 0.5 * (1 - np.cos(np.pi * np.linspace(0, 1, 20000)))
    z = z0 + (z1 - z0) * t
    gz = np.interp(z, zc, g)
    rho = np.sqrt(np.maximum(gz, 0.0))
    rho[0] = rho[-1] = 0.0
    v, f = _revolution(rho, z, edge_length)
    f = _outward(v, f)
    n = vertex_normals(v, f)
    ang = np.pi / 4 + np.pi / 2 * np.arange(4)
    cusps = np.column_stack([0.42 * np.cos(ang), 0.42 * np.sin(ang)])
    d2 = ((v[:, None, :2] - cusps[None]) ** 2).sum(-1)
    top = np.clip((v[:, 2] - 0.5) / 0.3, 0.0, 1.0)
    top = top * top * (3 - 2 * top)  # smoothstep: no bumps below the crown's equator
    bump = 0.22 * np.exp(-d2 / (2 * 0.17**2)).sum(axis=1) * top
    return v + n * bump[:, None], f


def bumpy_disk(n: int = 24, radius: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Open disk height field ``z = Σ bumps(x, y)`` over a disk: one boundary loop.

    Rings of vertices around a centre vertex (ring ``k`` has ``6k`` vertices), so triangles
    are near equilateral. Faces are oriented with normals pointing up (+z).

    Parameters
    ----------
    n : int
        Number of rings (>= 1).
    radius : float

    Returns
    -------
    vertices : (about 3n(n+1) + 1, 3) float array
    faces : (about 6n², 3) int array
    """
    if n < 1:
        raise ValueError(f"n must be >= 1, got {n}")
    rho = np.linspace(0.0, radius, n + 1)
    v, f = _revolution(rho, np.zeros(n + 1), radius / n, closed=False)
    x, y = v[:, 0] / radius, v[:, 1] / radius
    z = (0.25 * np.exp(-((x - 0.3) ** 2 + (y - 0.2) ** 2) / 0.08)
         - 0.18 * np.exp(-((x + 0.35) ** 2 + (y + 0.25) ** 2) / 0.06)
         + 0.05 * np.cos(3 * x) * np.sin(2 * y))
    v[:, 2] = radius * z
    nrm = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    if nrm[:, 2].sum() < 0:
        f = f[:, ::-1].copy()
    return v, f


# --------------------------------------------------------------------------- real meshes


def _package_root(package: str, purpose: str):
    try:
        module = importlib.import_module(package)
    except ModuleNotFoundError as err:
        raise ModuleNotFoundError(
            f"{purpose} ships with the Python package {package!r}; install it with "
            f"`pip install {package}` (or `pip install surfinpaint[test]`)"
        ) from err
    return importlib.resources.files(module)


def _load_mesh_file(path: Path) -> tuple[np.ndarray, np.ndarray]:
    # the loaders return the geometry of files known to load: what else a sample file holds
    # (a scanner's camera record, colours) is nothing a caller can act on
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MeshWarning)
        out = read_mesh(path)
    v, f = (out[0], out[1]) if isinstance(out, tuple) else (out.vertices, out.faces)
    return np.asarray(v, dtype=float), np.asarray(f, dtype=np.int64)


def pymeshlab_sample(name: str = "bunny.obj") -> tuple[np.ndarray, np.ndarray]:
    """A sample mesh shipped with PyMeshLab (``pymeshlab/tests/sample_meshes``).

    Parameters
    ----------
    name : str
        File name relative to that folder, e.g. ``"bunny.obj"`` (closed, 28k vertices),
        ``"bone.ply"``, ``"cow.obj"`` or ``"rangemaps/face000.ply"`` (an open range scan).

    Raises
    ------
    ModuleNotFoundError
        When PyMeshLab is not installed.
    FileNotFoundError
        When there is no such sample (the message lists the available ones).
    """
    folder = _package_root("pymeshlab", "this sample mesh") / "tests" / "sample_meshes"
    path = Path(str(folder / name))
    if not path.is_file():
        found = sorted(str(p.relative_to(Path(str(folder))))
                       for p in Path(str(folder)).rglob("*") if p.suffix in (".obj", ".ply"))
        raise FileNotFoundError(f"no PyMeshLab sample {name!r}; available: {', '.join(found)}")
    return _load_mesh_file(path)


def fsaverage5(surface: str = "pial", hemi: str = "left") -> tuple[np.ndarray, np.ndarray]:
    """FreeSurfer fsaverage5 cortical surface (10242 vertices) as shipped with nilearn.

    Parameters
    ----------
    surface : {"pial", "white", "infl", "sphere", "flat", "pial_inflated"}
    hemi : {"left", "right"}

    Returns
    -------
    vertices (in mm), faces

    Raises
    ------
    ModuleNotFoundError
        When nilearn is not installed.
    """
    if hemi not in ("left", "right"):
        raise ValueError(f"hemi must be 'left' or 'right', got {hemi!r}")
    folder = _package_root("nilearn", "fsaverage5") / "datasets" / "data" / "fsaverage5"
    path = Path(str(folder / f"{surface}_{hemi}.gii.gz"))
    if not path.is_file():
        raise ValueError(f"no fsaverage5 surface {surface!r} in nilearn ({path} is missing)")
    import nibabel

    image = nibabel.load(str(path))
    v, f = image.agg_data(("pointset", "triangle"))
    return np.asarray(v, dtype=float), np.asarray(f, dtype=np.int64)


def pymeshfix_bunny() -> tuple[np.ndarray, np.ndarray]:
    """The Stanford bunny shipped with pymeshfix (50k vertices) with its real, unfilled holes.

    The raw scan is not clean: it has holes, a few non-manifold edges and small islands.

    Raises
    ------
    ModuleNotFoundError
        When pymeshfix is not installed.
    """
    folder = _package_root("pymeshfix", "the pymeshfix bunny") / "examples"
    return _load_mesh_file(Path(str(folder / "StanfordBunny.ply")))


# --------------------------------------------------------------------------- packaged demo


def _demo_holes(vertices: np.ndarray):
    # one hole on the lower ball's side, one across the lower neck: different curvatures
    targets = np.array([[1.0, 0.0, -0.1], [0.0, -0.565, 0.94]])
    centres = np.argmin(((vertices[:, None] - targets[None]) ** 2).sum(-1), axis=0)
    return centres, np.array([0.6, 0.4])


def default_demo_mesh() -> tuple[np.ndarray, np.ndarray]:
    """The demo mesh: a snowman (edge length 0.07) with two geodesic-disk holes cut out.

    Returns the packaged file ``surfinpaint/meshes/snowman_holes.ply`` when present, else
    generates the same mesh.
    """
    path = DATA_DIR / DEMO_FILE
    if path.is_file():
        return _load_mesh_file(path)
    return _make_demo()


def default_demo_path() -> Path:
    """Path of the demo mesh file (binary PLY): the packaged one, or, when the package was
    installed without its data, a copy generated once into a temporary folder."""
    path = DATA_DIR / DEMO_FILE
    if path.is_file():
        return path

    folder = Path(tempfile.gettempdir()) / "surfinpaint-data"
    cached = folder / DEMO_FILE
    if not cached.is_file():
        regenerate_default_data(folder)
    return cached


def _make_demo() -> tuple[np.ndarray, np.ndarray]:
    v, f = snowman(edge_length=0.07)
    centres, radii = _demo_holes(v)
    cut = cut_holes(v, f, centres, radii)
    return cut.vertices, cut.faces


def _write_binary_ply(path: Path, vertices: np.ndarray, faces: np.ndarray) -> None:
    vertices = np.asarray(vertices, dtype="<f4")
    face_rec = np.empty(len(faces), dtype=[("n", "u1"), ("idx", "<i4", (3,))])
    face_rec["n"] = 3
    face_rec["idx"] = faces
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        "comment surfinpaint demo: snowman with two holes (surfinpaint.data)\n"
        f"element vertex {len(vertices)}\nproperty float x\nproperty float y\n"
        f"property float z\nelement face {len(faces)}\n"
        "property list uchar int vertex_indices\nend_header\n"
    )
    with atomic_open(path) as fh:
        fh.write(header.encode("ascii"))
        fh.write(vertices.tobytes())
        fh.write(face_rec.tobytes())


def regenerate_default_data(folder: str | Path | None = None) -> list[Path]:
    """(Re)write the packaged default meshes; returns the written paths.

    Run ``python -c "import surfinpaint.data as d; d.regenerate_default_data()"``.
    """
    folder = Path(folder) if folder is not None else DATA_DIR
    folder.mkdir(parents=True, exist_ok=True)
    v, f = _make_demo()
    path = folder / DEMO_FILE
    _write_binary_ply(path, v, f)
    return [path]
