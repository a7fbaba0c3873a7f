"""Consistent face orientation: flip the winding of the faces that disagree with their
neighbours, as few as possible, the way ``trimesh.repair.fix_winding`` does.

Two faces sharing an edge are consistently oriented when they traverse it in opposite
directions. Each face gets a flip parity; an interior edge traversed in opposite directions
asks its two faces for the same parity, one traversed in the same direction for different
ones. The constraints are solved per piece (faces joined through edges of exactly two
faces) as the connected components of a doubled graph, node ``(face, parity)``: a piece can
be oriented exactly when no face's two nodes meet (else, like a Möbius strip, it is
non-orientable, and it is left as it is). Within an orientable piece the smaller of the two
parity classes is flipped (on a tie, the class without the piece's lowest face id).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from surfinpaint.errors import how_many
from surfinpaint.geometry.degenerate import triangle_rows
from surfinpaint.geometry.edges import EdgeTable

__all__ = ["orient_faces", "orientation_note", "turn_outward"]


def orient_faces(faces: np.ndarray) -> tuple[np.ndarray, np.ndarray, list[np.ndarray]]:
    """Flip faces so that each orientable piece is consistently oriented.

    A face is flipped by swapping its last two vertex ids; faces stay in their order and
    nothing else changes. Edges with more than two faces join no faces (remove them first:
    :func:`surfinpaint.geometry.repair.remove_nonmanifold_faces`); faces that repeat a vertex
    join none either and are never flipped.

    Parameters
    ----------
    faces : (f, 3) int array

    Returns
    -------
    oriented : (f, 3) int64 array
        The faces, the flipped ones with their winding reversed (a new array).
    flipped : (k,) int64 array
        Ids of the flipped faces, sorted.
    non_orientable : list of int64 arrays
        The face ids of each piece that cannot be oriented consistently (left as it was),
        each sorted, the pieces in the order of their lowest face id.

    Examples
    --------
    Two triangles of a square, the second one wound against the first:

    >>> oriented, flipped, bad = orient_faces(np.array([[0, 1, 2], [0, 2, 3], [0, 3, 4],
    ...                                                 [0, 1, 4]]))
    >>> flipped.tolist(), oriented[3].tolist(), bad
    ([3], [0, 4, 1], [])
    """
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    oriented = f.copy()
    m = len(f)
    if m == 0:
        return oriented, np.zeros(0, np.int64), []
    triangles, _, rows = triangle_rows(f)
    proper = np.arange(m) if rows is None else rows
    table = EdgeTable.build(triangles, int(f.max()) + 1)
    h1, h2 = table.interior_pairs()
    p, q = proper[h1 // 3], proper[h2 // 3]
    # the same direction on both faces (forward alike): one of the two must be flipped
    differ = (table.forward[h1] == table.forward[h2]).astype(np.int64)
    # node 2 t + s: face t with parity s; constraint x_p ^ x_q = d joins (p, s)-(q, s ^ d)
    rows = np.concatenate([2 * p, 2 * p + 1])
    cols = np.concatenate([2 * q + differ, 2 * q + (1 - differ)])
    graph = sp.csr_matrix((np.ones(len(rows), np.int8), (rows, cols)), shape=(2 * m, 2 * m))
    _, label = connected_components(graph, directed=False)
    even, odd = label[0::2], label[1::2]
    pieces = sp.csr_matrix((np.ones(len(p), np.int8), (p, q)), shape=(m, m))
    _, piece = connected_components(pieces, directed=False)
    lowest = np.full(piece.max() + 1, m, dtype=np.int64)
    np.minimum.at(lowest, piece, np.arange(m))
    orientable = np.ones(len(lowest), dtype=bool)
    orientable[piece[even == odd]] = False
    # parity relative to the piece's lowest face: 1 where it must turn the other way
    parity = (even != even[lowest[piece]]).astype(np.int64)
    ones = np.bincount(piece, weights=parity, minlength=len(lowest))
    size = np.bincount(piece, minlength=len(lowest))
    flip_ones = ones <= size - ones  # the smaller class; a tie keeps the lowest face's
    flip = orientable[piece] & ((parity == 1) == flip_ones[piece])
    flipped = np.flatnonzero(flip)
    oriented[flipped] = oriented[flipped][:, [0, 2, 1]]
    bad = [np.flatnonzero(piece == k) for k in np.flatnonzero(~orientable)]
    return oriented, flipped, bad


def turn_outward(vertices: np.ndarray, faces: np.ndarray,
                 skip: list[np.ndarray] | tuple = ()) -> tuple[np.ndarray, list[np.ndarray]]:
    """Turn each closed piece of consistently oriented faces outward.

    A piece (faces joined through edges of exactly two faces) is closed when none of its
    edges is a boundary edge: it encloses a volume, and its faces wind outward when the
    signed volume they enclose (the sum of ``v0 · (v1 × v2) / 6`` over them) is positive.
    The faces of a closed piece with a negative signed volume are all flipped (last two
    ids swapped); open pieces, the pieces of ``skip`` (face ids, e.g. those
    :func:`orient_faces` could not orient) and faces that repeat a vertex are left alone.

    Returns
    -------
    faces : (f, 3) int64 array
        A new array.
    turned : list of int64 arrays
        The face ids of each piece turned, sorted, the pieces in the order of their lowest
        face id.

    Examples
    --------
    A tetrahedron wound inward:

    >>> v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.]])
    >>> f = np.array([[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]])
    >>> out, turned = turn_outward(v, f)
    >>> [t.tolist() for t in turned], out[0].tolist()
    ([[0, 1, 2, 3]], [0, 2, 1])
    """
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    out, m = f.copy(), len(f)
    if m == 0:
        return out, []
    triangles, _, rows = triangle_rows(f)
    proper = np.arange(m) if rows is None else rows
    table = EdgeTable.build(triangles, int(f.max()) + 1)
    h1, h2 = table.interior_pairs()
    joined = sp.csr_matrix((np.ones(len(h1), np.int8), (proper[h1 // 3], proper[h2 // 3])),
                           shape=(m, m))
    n_pieces, piece = connected_components(joined, directed=False)
    closed = np.ones(n_pieces, dtype=bool)
    closed[piece[proper[(table.count[table.face_edge] != 2).any(axis=1)]]] = False
    repeats = np.ones(m, dtype=bool)
    repeats[proper] = False
    closed[piece[repeats]] = False
    for left in skip:
        closed[piece[np.asarray(left, dtype=np.int64)]] = False
    # about the vertices' mean: the volume of a closed piece does not depend on the origin,
    # its rounding does
    v = np.asarray(vertices, dtype=np.float64)
    v = v - v[np.unique(f)].mean(axis=0)
    volume = np.einsum("ij,ij->i", v[f[:, 0]], np.cross(v[f[:, 1]], v[f[:, 2]])) / 6
    inward = closed & (np.bincount(piece, weights=volume, minlength=n_pieces) < 0)
    turn = np.flatnonzero(inward[piece])
    out[turn] = out[turn][:, [0, 2, 1]]
    return out, [np.flatnonzero(piece == k) for k in np.flatnonzero(inward)]


def outward_note(turned: list[np.ndarray], shown: int = 10) -> str:
    """The words reporting the closed pieces :func:`turn_outward` turned (their face ids as
    the caller numbers them), naming the first ``shown`` faces of each.

    >>> outward_note([np.arange(12)], shown=2)
    'turned 1 closed piece outward (negative volume): its 12 faces (0, 1, ...) flipped'
    """
    many = len(turned) != 1
    faces = "; ".join(
        f"{how_many(len(t), 'face', 'faces')} ({', '.join(str(int(i)) for i in t[:shown])}"
        f"{', ...' if len(t) > shown else ''})" for t in turned)
    return (f"turned {how_many(len(turned), 'closed piece', 'closed pieces')} outward "
            f"(negative volume): {'their' if many else 'its'} {faces} flipped")


def orientation_note(flipped: np.ndarray, shown: int = 10) -> str:
    """The words reporting the faces :func:`orient_faces` flipped (ids as the caller numbers
    them), naming the first ``shown``.

    >>> orientation_note(np.array([4, 9]))
    'flipped 2 faces (4, 9) to orient each piece of the surface consistently'
    """
    ids = ", ".join(str(int(t)) for t in flipped[:shown])
    more = ", ..." if len(flipped) > shown else ""
    return (f"flipped {how_many(len(flipped), 'face', 'faces')} ({ids}{more}) "
            "to orient each piece of the surface consistently")
