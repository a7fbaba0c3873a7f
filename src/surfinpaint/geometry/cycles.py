"""Boundary loops as the cycles of a permutation of boundary edges, found in vectorized
numpy (no Python step per edge or per loop)."""

from __future__ import annotations

import numpy as np

__all__ = ["simple_cycles"]


def simple_cycles(half: np.ndarray) -> list[np.ndarray] | None:
    """:func:`~surfinpaint.geometry.mesh.boundary_loops`' loops in its order, without a
    Python step per edge or per loop, when every boundary vertex starts and ends exactly
    one boundary edge (no pinched loop, no open chain: the successor of each edge is a
    permutation of the edges); None otherwise (the walk then splits the pinches and names
    what does not close).

    ``half``: the boundary half-edges sorted by tail. Each cycle of the successor map is a
    loop; the walk finds them in the order of their first edge in ``half`` and follows
    each from that edge, then sorts them longest first (stably): the same here, with the
    position of each edge along its cycle found by pointer doubling (O(b log L) for b
    boundary edges and a longest loop of L; a triangle soup's 10^5 loops of 3 edges took
    seconds as a walk).
    """
    tails, heads = half[:, 0], half[:, 1]
    m = len(tails)
    if (np.any(tails[1:] == tails[:-1])
            or not np.array_equal(np.sort(heads), tails)):  # a pinch or an open chain
        return None
    successor = np.searchsorted(tails, heads)  # the edge leaving each edge's head
    # each cycle's first edge (its smallest index): the smallest index reached when
    # jumping 1, 2, 4, ... edges ahead, until the jumps have gone round every cycle
    first = np.minimum(np.arange(m), successor)
    jump = successor.copy()
    span = 1
    while span < m:
        first = np.minimum(first, first[jump])
        jump = jump[jump]
        span *= 2
        if np.array_equal(first[successor], first):  # constant on every cycle
            break
    # steps from the cycle's first edge: the edge before the first ends each chain
    ahead = np.where(successor == first, -1, successor)
    steps_to_end = (ahead >= 0).astype(np.int64)
    link = np.where(ahead >= 0, ahead, np.arange(m))
    while True:
        moved = steps_to_end[link]
        if not moved.any():
            break
        steps_to_end += moved
        link = link[link]
    length = np.bincount(first, minlength=m)
    position = length[first] - 1 - steps_to_end
    walk = np.lexsort((position, first))  # by cycle (first edge), then along it
    starts = np.flatnonzero(length)  # the first edges, increasing: the walk's order
    sizes = length[starts]
    ends = np.cumsum(sizes)
    vertices = tails[walk]
    # longest first, stable among equal lengths (list.sort's order)
    by_length = np.argsort(-sizes, kind="stable")
    return [vertices[ends[k] - sizes[k]:ends[k]].copy() for k in by_length.tolist()]
