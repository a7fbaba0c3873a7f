"""How well a λ-H representation gives its mesh back: the round-trip error, typed."""

from __future__ import annotations

import math
import os
from dataclasses import MISSING, asdict, dataclass, fields

import numpy as np

from surfinpaint.geometry.metrics import surface_distance
from surfinpaint.io.atomic import atomic_open

__all__ = ["RoundTrip", "measure_round_trip", "require_arrays", "save_npz"]

# surface samples for the two-sided distance of the self-check
SAMPLES = 20000


@dataclass(frozen=True)
class RoundTrip:
    """The distance between a mesh and the mesh rebuilt from its representation.

    Attributes
    ----------
    mean, hausdorff : float
        Two-sided surface distance (mean and maximum over samples of both surfaces,
        :func:`~surfinpaint.geometry.metrics.surface_distance`), in mesh units.
    diagonal : float
        The original's bounding-box diagonal, mesh units.
    vertex_max : float
        Largest distance between a rebuilt vertex and its original, mesh units.
    converged : bool
        Whether the rebuild converged (see ``message``).
    iterations : int
        Newton (or fixed-point) steps of the rebuild.
    message : str
        The rebuild's own account.
    seconds : float
        Time of the rebuild.
    floor_mean, floor_hausdorff : float
        A grid or quadtree representation's *sampling floor*, mesh units: the same
        distances for the mesh as an exact rebuild of its grid (or finest tree) gives it
        back (:func:`~surfinpaint.representation.grid_represent.sampled_vertices`,
        :func:`~surfinpaint.representation.quadtree_represent.sampled_tree_vertices`), the
        least error any rebuild of it can have. None for the mesh form (its floor is 0: it
        stores the mesh's own triangles) and in files written before it was measured.
    """

    mean: float
    hausdorff: float
    diagonal: float
    vertex_max: float
    converged: bool
    iterations: int
    message: str
    seconds: float
    floor_mean: float | None = None
    floor_hausdorff: float | None = None

    @property
    def mean_percent(self) -> float:
        """``mean`` in % of the bounding-box diagonal."""
        return 100.0 * self.mean / self.diagonal

    @property
    def hausdorff_percent(self) -> float:
        """``hausdorff`` in % of the bounding-box diagonal."""
        return 100.0 * self.hausdorff / self.diagonal

    def summary(self) -> str:
        """One line for people: both distances in mesh units and in % of the diagonal."""
        state = "converged" if self.converged else "DID NOT CONVERGE"
        line = (f"round trip: mean {self.mean:.3g} ({self.mean_percent:.3g} % of the "
                f"diagonal {self.diagonal:.3g}), Hausdorff {self.hausdorff:.3g} "
                f"({self.hausdorff_percent:.3g} %); rebuild {state}: {self.message}")
        if self.floor_mean is not None:
            line += (f"; its samples alone (no rebuild can be closer): mean "
                     f"{self.floor_mean:.3g} ({100 * self.floor_mean / self.diagonal:.3g} %), "
                     f"Hausdorff {self.floor_hausdorff:.3g} "
                     f"({100 * self.floor_hausdorff / self.diagonal:.3g} %)")
        return line

    def to_arrays(self, prefix: str = "check_") -> dict[str, np.ndarray]:
        """The fields as 0-d arrays for an ``.npz`` (a floor that is None left out)."""
        return {prefix + k: np.array(v) for k, v in asdict(self).items() if v is not None}

    @classmethod
    def from_arrays(cls, data, prefix: str = "check_") -> RoundTrip | None:
        """Read what :meth:`to_arrays` wrote; ``None`` when it is not there."""
        # the fields with defaults (the floor) are absent from older files
        required = [f.name for f in fields(cls) if f.default is MISSING]
        if not all(prefix + name in data for name in required):
            return None
        values = {f.name: data[prefix + f.name][()] for f in fields(cls)
                  if prefix + f.name in data}
        return cls(**{f.name: _typed(f.type, values[f.name]) for f in fields(cls)
                      if f.name in values})


def _typed(kind: str, value):
    return {"float": float, "float | None": float, "bool": bool, "int": int, "str": str}[kind](
        value)


def measure_round_trip(original: np.ndarray, rebuilt: np.ndarray, faces: np.ndarray, *,
                       converged: bool, iterations: int, message: str, seconds: float,
                       samples: int = SAMPLES, floor: np.ndarray | None = None) -> RoundTrip:
    """The :class:`RoundTrip` of a rebuilt mesh with the original's faces.

    ``samples`` surface points on each mesh (fixed seed) for the two-sided distance;
    ``floor``: the vertices as an exact rebuild gives them back (a grid representation's
    :func:`~surfinpaint.representation.grid_represent.sampled_vertices`), measured the same
    way into ``floor_mean`` and ``floor_hausdorff``.
    """
    v = np.asarray(original, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    diagonal = float(np.linalg.norm(np.ptp(v[np.unique(f)], axis=0)))
    mean, hausdorff, vertex_max = _distances(v, np.asarray(rebuilt, dtype=float), f, samples)
    floor_mean = floor_hausdorff = None
    if floor is not None:
        floor_mean, floor_hausdorff, _ = _distances(v, np.asarray(floor, dtype=float), f,
                                                    samples)
    return RoundTrip(mean=mean, hausdorff=hausdorff, diagonal=diagonal, vertex_max=vertex_max,
                     converged=converged, iterations=iterations, message=message,
                     seconds=seconds, floor_mean=floor_mean, floor_hausdorff=floor_hausdorff)


def _distances(v: np.ndarray, w: np.ndarray, f: np.ndarray, samples: int
               ) -> tuple[float, float, float]:
    """Two-sided mean and Hausdorff distance between ``w`` and ``v`` on the faces ``f``,
    and the largest vertex displacement (all infinite when ``w`` is not finite)."""
    if not np.isfinite(w).all():
        return math.inf, math.inf, math.inf
    d = surface_distance(w, f, v, f, n_samples=samples)
    return d.mean, d.hausdorff, float(np.linalg.norm(w - v, axis=1).max())


def save_npz(path: str | os.PathLike, arrays: dict[str, np.ndarray],
             check: RoundTrip | None = None) -> None:
    """Write ``arrays`` (and ``check``'s fields, :meth:`RoundTrip.to_arrays`, when given) to
    ``path`` as a compressed ``.npz`` through the one atomic writer
    (:func:`~surfinpaint.io.atomic.atomic_open`): a failed write leaves no partial file."""
    if check is not None:
        arrays = {**arrays, **check.to_arrays()}
    with atomic_open(path) as handle:
        np.savez_compressed(handle, **arrays)


def require_arrays(data, needed, path: str | os.PathLike, what: str) -> None:
    """Raise ``ValueError`` naming the arrays of ``needed`` that the loaded ``.npz``
    ``data`` lacks: the file at ``path`` is then not ``what`` (e.g. "a mesh λ-H
    representation")."""
    missing = sorted(set(needed) - set(data.files))
    if missing:
        raise ValueError(f"{path}: not {what} (missing {missing})")
