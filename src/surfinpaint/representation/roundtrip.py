"""How well a λ-H representation gives its mesh back: the round-trip error, typed."""

from __future__ import annotations

import os
from dataclasses import asdict, dataclass

import numpy as np

from surfinpaint.geometry.metrics import surface_distance
from surfinpaint.io.atomic import atomic_open

__all__ = ["RoundTrip", "measure_round_trip", "save_npz"]

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
    """

    mean: float
    hausdorff: float
    diagonal: float
    vertex_max: float
    converged: bool
    iterations: int
    message: str
    seconds: float

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
        return (f"round trip: mean {self.mean:.3g} ({self.mean_percent:.3g} % of the "
                f"diagonal {self.diagonal:.3g}), Hausdorff {self.hausdorff:.3g} "
                f"({self.hausdorff_percent:.3g} %); rebuild {state}: {self.message}")

    def to_arrays(self, prefix: str = "check_") -> dict[str, np.ndarray]:
        """The fields as 0-d arrays for an ``.npz``."""
        return {prefix + k: np.array(v) for k, v in asdict(self).items()}

    @classmethod
    def from_arrays(cls, data, prefix: str = "check_") -> RoundTrip | None:
        """Read what :meth:`to_arrays` wrote; ``None`` when it is not there."""
        names = [prefix + k for k in cls.__dataclass_fields__]
        if not all(name in data for name in names):
            return None
        values = {k: data[prefix + k][()] for k in cls.__dataclass_fields__}
        return cls(mean=float(values["mean"]), hausdorff=float(values["hausdorff"]),
                   diagonal=float(values["diagonal"]), vertex_max=float(values["vertex_max"]),
                   converged=bool(values["converged"]), iterations=int(values["iterations"]),
                   message=str(values["message"]), seconds=float(values["seconds"]))


def measure_round_trip(original: np.ndarray, rebuilt: np.ndarray, faces: np.ndarray, *,
                       converged: bool, iterations: int, message: str, seconds: float,
                       samples: int = SAMPLES) -> RoundTrip:
    """The :class:`RoundTrip` of a rebuilt mesh with the original's faces.

    ``samples`` surface points on each mesh (fixed seed) for the two-sided distance.
    """
    v = np.asarray(original, dtype=float)
    w = np.asarray(rebuilt, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    diagonal = float(np.linalg.norm(np.ptp(v[np.unique(f)], axis=0)))
    if np.isfinite(w).all():
        d = surface_distance(w, f, v, f, n_samples=samples)
        mean, hausdorff = float(d["mean"]), float(d["hausdorff"])
        vertex_max = float(np.linalg.norm(w - v, axis=1).max())
    else:
        mean = hausdorff = vertex_max = float("inf")
    return RoundTrip(mean=mean, hausdorff=hausdorff, diagonal=diagonal, vertex_max=vertex_max,
                     converged=converged, iterations=iterations, message=message,
                     seconds=seconds)


def save_npz(path: str | os.PathLike, arrays: dict[str, np.ndarray]) -> None:
    """Write ``arrays`` to ``path`` as a compressed ``.npz`` through the one atomic writer
    (:func:`~surfinpaint.io.atomic.atomic_open`): a failed write leaves no partial file."""
    with atomic_open(path) as handle:
        np.savez_compressed(handle, **arrays)
