"""CGAL's variant of Liepa's refinement: the ordered flip pass and the refinement rounds."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
import trimesh
from scipy.spatial import Delaunay

from surfinpaint.fill.conformal.candidates import Candidates
from surfinpaint.fill.conformal.options import ConformalOptions
from surfinpaint.fill.liepa.baseline import conventional_fill, faired_fills
from surfinpaint.fill.liepa.flip_passes import CGAL_ROUNDS, flip_pass
from surfinpaint.fill.liepa.refinement import refine_patch
from surfinpaint.fill.liepa.triangulation import minimum_weight_triangulation
from surfinpaint.geometry.mesh import boundary_loops, face_areas, unique_edges


def _inside(a, b, c, s):
    """1 - |s - centre| / radius for the smallest ball through a, b, c (scalar reference)."""
    u, w = b - a, c - a
    n = np.cross(u, w)
    centre = a + (np.dot(w, w) * np.cross(n, u) + np.dot(u, u) * np.cross(w, n)) / (
        2 * np.dot(n, n))
    return 1.0 - np.linalg.norm(s - centre) / np.linalg.norm(centre - a)


def _sequential_pass(p, faces, edges, fixed):
    """The pass as a plain loop: each listed edge, at its turn, flips when it fails."""
    f = [list(t) for t in faces]
    fixed = {frozenset(e) for e in fixed.tolist()}
    seen = set()
    flips = 0
    for u, v in edges.tolist():
        key = frozenset((u, v))
        if key in seen or key in fixed:
            continue
        seen.add(key)
        # the face with u -> v and the one with v -> u
        sides = {}
        for t, tri in enumerate(f):
            for k in range(3):
                x, y = tri[k], tri[(k + 1) % 3]
                if {x, y} == {u, v}:
                    sides[(x, y)] = (t, tri[(k + 2) % 3])
        if len(sides) != 2:
            continue
        (a, b), (t1, c) = next(iter(sides.items()))
        t2, d = sides[(b, a)]
        existing = {frozenset((tri[k], tri[(k + 1) % 3])) for tri in f for k in range(3)}
        score = max(_inside(p[a], p[b], p[c], p[d]), _inside(p[b], p[a], p[d], p[c]))
        old_n = np.cross(p[b] - p[a], p[c] - p[a]) + np.cross(p[a] - p[b], p[d] - p[b])
        n1 = np.cross(p[d] - p[a], p[c] - p[a])
        n2 = np.cross(p[b] - p[d], p[c] - p[d])
        if score > -1e-9 and frozenset((c, d)) not in existing and n1 @ old_n > 0 \
                and n2 @ old_n > 0:
            f[t1], f[t2] = [a, d, c], [d, b, c]
            flips += 1
    return np.array(f), flips


def _canonical(faces):
    """Each triangle rotated to start at its smallest id (orientation kept), rows sorted."""
    f = np.asarray(faces)
    r = np.argmin(f, axis=1)
    rolled = np.stack([f[np.arange(len(f)), (r + k) % 3] for k in range(3)], axis=1)
    return sorted(map(tuple, rolled.tolist()))


def _jittered_patch(seed):
    """A non-Delaunay, slightly non-planar triangulation of a square (hull edges fixed)."""
    rng = np.random.default_rng(seed)
    g = np.stack(np.meshgrid(np.linspace(0, 1, 12), np.linspace(0, 1, 12)), -1).reshape(-1, 2)
    inner = (g > 0).all(1) & (g < 1).all(1)
    g[inner] += rng.uniform(-0.02, 0.02, (inner.sum(), 2))
    moved = g + rng.uniform(-0.015, 0.015, g.shape) * inner[:, None]
    tri = Delaunay(moved).simplices
    q = np.column_stack([moved, np.zeros(len(g))])
    up = np.cross(q[tri[:, 1]] - q[tri[:, 0]], q[tri[:, 2]] - q[tri[:, 0]])[:, 2] > 0
    tri = np.where(up[:, None], tri, tri[:, ::-1])  # oriented in the plane it was made in
    p = np.column_stack([g, 0.03 * rng.standard_normal(len(g))])
    normal = np.cross(p[tri[:, 1]] - p[tri[:, 0]], p[tri[:, 2]] - p[tri[:, 0]])
    assert (normal[:, 2] > 0).all()  # and not folded where it is
    e, _, count = unique_edges(tri)
    return p, tri, e, e[count == 1]


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_flip_pass_is_the_sequential_loop(seed):
    p, tri, edges, hull = _jittered_patch(seed)
    order = edges[np.random.default_rng(seed).permutation(len(edges))]
    got, flips = flip_pass(p, tri, order, fixed_edges=hull)
    want, want_flips = _sequential_pass(p, tri, order, hull)
    assert want_flips > 3  # the case has work to do
    assert flips == want_flips
    assert _canonical(got) == _canonical(want)
    # the order matters, and the pass follows it: reversed, it is the reversed loop
    got_r, _ = flip_pass(p, tri, order[::-1], fixed_edges=hull)
    want_r, _ = _sequential_pass(p, tri, order[::-1], hull)
    assert _canonical(got_r) == _canonical(want_r)
    # a flip keeps the surface: same area, hull untouched, still edge-manifold
    assert face_areas(p, got).sum() == pytest.approx(face_areas(p, tri).sum(), rel=0.05)
    e, _, count = unique_edges(got)
    assert {tuple(x) for x in e[count == 1].tolist()} == {tuple(x) for x in hull.tolist()}
    assert (count <= 2).all()


def test_flip_pass_skips_fixed_and_forbidden_edges():
    # a square split by the long diagonal of a thin rhombus: the diagonal fails the test
    p = np.array([[0, 0, 0], [2, 0, 0], [2.2, 1, 0], [0.2, 1, 0]], float)
    quad = np.array([[0, 1, 2], [0, 2, 3]])
    diagonal = np.array([[0, 2]])
    flipped, flips = flip_pass(p, quad, diagonal)
    assert flips == 1 and _canonical(flipped) == _canonical([[0, 1, 3], [1, 2, 3]])
    assert flip_pass(p, quad, diagonal, fixed_edges=diagonal)[1] == 0
    assert flip_pass(p, quad, diagonal, forbidden_edges=np.array([[1, 3]]))[1] == 0


def _disk(k=60):
    t = np.linspace(0, 2 * np.pi, k, endpoint=False)
    p = np.column_stack([np.cos(t), np.sin(t), np.zeros(k)])
    loop = np.arange(k)
    return p, loop, minimum_weight_triangulation(p, loop)


def test_cgal_style_disk_has_the_analytic_vertex_count_and_edge_lengths():
    p, loop, tri = _disk()
    h = np.linalg.norm(p[1] - p[0])
    p_in = p.copy()
    new_v, patch = refine_patch(p, tri, loop, style="cgal")
    assert np.array_equal(p, p_in)  # the input is not modified
    allv = np.vstack([p, new_v])
    # planar, inside the disk, covering it exactly, no fold (all normals as the bare
    # triangulation's)
    assert np.abs(new_v[:, 2]).max() == 0
    assert np.linalg.norm(new_v[:, :2], axis=1).max() < 1
    area = face_areas(allv, patch)
    assert area.sum() == pytest.approx(face_areas(p, tri).sum(), rel=1e-12)
    side = np.sign(np.cross(p[tri[0, 1]] - p[tri[0, 0]], p[tri[0, 2]] - p[tri[0, 0]])[2])
    normal = np.cross(allv[patch[:, 1]] - allv[patch[:, 0]], allv[patch[:, 2]] - allv[patch[:, 0]])
    assert (side * normal[:, 2] > 0).all()
    # equilateral triangles of side h over the polygon's area A: T = A / (√3 h² / 4), and a
    # triangulated disk with k boundary vertices has (T - k + 2) / 2 interior vertices
    expected = (area.sum() / (np.sqrt(3) / 4 * h**2) - len(loop) + 2) / 2
    assert 0.75 * expected < len(new_v) < 1.25 * expected
    e, _, count = unique_edges(patch)
    length = np.linalg.norm(allv[e[count == 2, 0]] - allv[e[count == 2, 1]], axis=1)
    assert 0.8 * h < length.mean() < 1.25 * h
    # the loop's vertices and edges are kept, and only they are original
    assert set(np.unique(patch[patch < len(p)]).tolist()) == set(loop.tolist())
    loop_edges = np.sort(np.column_stack([loop, np.roll(loop, -1)]), axis=1)
    assert {tuple(x) for x in e[count == 1].tolist()} == {tuple(x) for x in loop_edges.tolist()}


def test_cgal_style_density_follows_the_boundary_scales():
    k, radius = 80, 3.0
    t = np.linspace(0, 2 * np.pi, k, endpoint=False)
    p = np.column_stack([radius * np.cos(t), radius * np.sin(t), np.zeros(k)])
    loop = np.arange(k)
    tri = minimum_weight_triangulation(p, loop)
    coarse, cp = refine_patch(p, tri, loop, scales=np.full(k, 0.3), style="cgal")
    fine, fp = refine_patch(p, tri, loop, scales=np.full(k, 0.15), style="cgal")

    def mean_inner_edge(new_v, patch):
        allv = np.vstack([p, new_v])
        e, _, count = unique_edges(patch)
        e = e[(count == 2) & (e >= len(p)).all(axis=1)]  # between new vertices
        return np.linalg.norm(allv[e[:, 0]] - allv[e[:, 1]], axis=1).mean()

    # half the scale: about half the edge length and four times the vertices
    assert mean_inner_edge(fine, fp) / mean_inner_edge(coarse, cp) == pytest.approx(0.5, rel=0.1)
    assert len(fine) / len(coarse) == pytest.approx(4, rel=0.2)
    # with σ below the loop's edge length, the count is the analytic one of side-σ
    # equilateral triangles (as in the disk test above)
    area = face_areas(p, tri).sum()
    assert len(fine) == pytest.approx((area / (np.sqrt(3) / 4 * 0.15**2) - k + 2) / 2, rel=0.15)
    assert mean_inner_edge(fine, fp) == pytest.approx(0.15, rel=0.15)


def test_cgal_style_stops_when_a_pass_flips_nothing():
    # one triangle, tiny scales: the first split's pass has nothing to flip (the flips would
    # recreate loop edges), and CGAL stops there; Liepa's rounds go on splitting
    p = np.array([[0, 0, 0], [1, 0, 0], [0.5, np.sqrt(3) / 2, 0]])
    loop = np.arange(3)
    tri = np.array([[0, 1, 2]])
    cgal_v, cgal_f = refine_patch(p, tri, loop, scales=np.full(3, 1e-3), style="cgal")
    assert len(cgal_v) == 1 and len(cgal_f) == 3
    np.testing.assert_allclose(cgal_v[0], p.mean(axis=0))
    liepa_v, _ = refine_patch(p, tri, loop, scales=np.full(3, 1e-3), max_iterations=3)
    assert len(liepa_v) > 10
    assert CGAL_ROUNDS == 10


def test_cgal_style_on_a_sphere_hole_closes_it_without_folds():
    m = trimesh.creation.icosphere(4)
    v, f = np.asarray(m.vertices), np.asarray(m.faces)
    faces = f[~(np.linalg.norm(v - v[0], axis=1)[f] < 0.7).all(axis=1)]
    loop = boundary_loops(faces)[0]
    tri = minimum_weight_triangulation(v, loop, faces)
    new_v, patch = refine_patch(v, tri, loop, faces=faces, style="cgal")
    liepa_v, _ = refine_patch(v, tri, loop, faces=faces)
    assert len(new_v) == pytest.approx(len(liepa_v), rel=0.2)
    _, _, count = unique_edges(np.vstack([faces, patch]))
    assert (count == 2).all()  # closes the hole, edge-manifold
    allv = np.vstack([v, new_v])
    normal = np.cross(allv[patch[:, 1]] - allv[patch[:, 0]], allv[patch[:, 2]] - allv[patch[:, 0]])
    assert (np.einsum("ij,j->i", normal, v[0]) > 0).all()  # all face out of the sphere
    assert (patch[patch < len(v)] >= 0).all() and set(
        np.unique(patch[patch < len(v)]).tolist()) == set(loop.tolist())


def test_unknown_style():
    p, loop, tri = _disk(8)
    with pytest.raises(ValueError, match="style must be one of"):
        refine_patch(p, tri, loop, style="isotropic")


def test_the_refinement_option_reaches_the_fills():
    m = trimesh.creation.icosphere(4)
    v, f = np.asarray(m.vertices), np.asarray(m.faces)
    faces = f[~(np.linalg.norm(v - v[0], axis=1)[f] < 0.7).all(axis=1)]
    loop = boundary_loops(faces)[0]
    tri = minimum_weight_triangulation(v, loop, faces)
    want = refine_patch(v, tri, loop, faces=faces, style="cgal")
    liepa = refine_patch(v, tri, loop, faces=faces)
    assert len(want[0]) != len(liepa[0]) or not np.array_equal(want[1], liepa[1])
    s0 = conventional_fill(v, faces, loop, fair=False, refinement="cgal")
    assert np.array_equal(s0[0], want[0]) and np.array_equal(s0[1], want[1])
    faired = faired_fills(v, faces, loop, (2, 3), refinement="cgal")
    assert np.array_equal(faired[3][1], want[1])
    options = ConformalOptions(s0_refinement="cgal")
    cands = Candidates.for_hole(v, faces, loop, options).faired(v, faces, loop)
    assert np.array_equal(cands["fair3"].faces, want[1])
    np.testing.assert_array_equal(cands["fair3"].vertices, faired[3][0])
    initial = Candidates.for_hole(v, faces, loop, replace(options, start="initial"))
    assert np.array_equal(initial.initial(v, faces, loop)[1], want[1])
