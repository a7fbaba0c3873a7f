"""Brain surfaces: GIFTI (``.gii``, ``.gii.gz``) and FreeSurfer geometry files, via nibabel,
with their per-vertex overlays (GIFTI ``.shape.gii`` / ``.func.gii`` / ``.label.gii``,
FreeSurfer ``curv``, ``thickness``, ``sulc``, ... and, when given, ``.annot`` and ``.label``)
read beside the surface and written beside the output; a segmentation's label table and a
GIFTI pointset's coordinate system are kept in the metadata and written back.

nibabel is imported inside the functions: it is needed only when such files are used. The
header checks each reader makes first are :mod:`surfinpaint.io.brain_checks`'s (those public
before, ``FREESURFER_MAGIC``, ``gifti_header``, ``morph_header``, ``check_overlay``,
``freesurfer_header``, are still importable from here).
"""

from __future__ import annotations

import gzip
import json
import re
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from surfinpaint.errors import MeshError, how_many, preview
from surfinpaint.io.base import Parsed
from surfinpaint.io.brain_checks import FREESURFER_MAGIC as FREESURFER_MAGIC
from surfinpaint.io.brain_checks import (
    MORPH_MAGIC,
    annot_header,
    annot_table,
    check_overlay,
    freesurfer_header,
    gifti_arrays,
    gifti_inflate,
    gifti_xml,
    label_file,
    overlay_errors,
    overlay_header,
)
from surfinpaint.io.brain_checks import gifti_header as gifti_header
from surfinpaint.io.brain_checks import morph_header as morph_header
from surfinpaint.io.meshdata import MeshData

#: FreeSurfer's per-vertex files beside ``lh.*`` / ``rh.*`` surfaces in a subject's ``surf/``.
FREESURFER_OVERLAYS = ("curv", "sulc", "thickness", "area", "volume", "jacobian_white",
                       "avg_curv", "curv.pial", "area.pial")
#: The endings of GIFTI data files (per-vertex overlays, not surfaces).
OVERLAY_SUFFIXES = (".shape.gii", ".func.gii", ".label.gii")
_GIFTI_DATA = (*OVERLAY_SUFFIXES, ".gii.gz", ".gii")
#: Metadata key prefix of an overlay's label table (``labels.NAME``: JSON rows ``[key, name,
#: red, green, blue, alpha]``, colours 0..1): the overlay is a segmentation, filled as labels
#: and written as ``.label.gii`` with its table.
LABEL_TABLE = "labels."
#: Metadata key prefix of what a GIFTI data overlay holds besides its numbers (``gifti.NAME``:
#: JSON ``{"kind": "func" or "shape", "meta": {...}, "arrays": [{"intent": code, "meta":
#: {...}}, ...]}``: its file's and arrays' metadata, a ``.func.gii``'s intents), written back.
GIFTI_OVERLAY = "gifti."
#: Metadata key of a GIFTI pointset's coordinate system (JSON: dataspace, xformspace, xform).
COORDINATE_SYSTEM = "coordsys"


def read_gifti(data: bytes, path: Path) -> Parsed:

    xml = gifti_inflate(data)
    gifti_xml(xml, arrays=False)
    image = _gifti_image(xml)
    points = image.get_arrays_from_intent("NIFTI_INTENT_POINTSET")
    triangles = image.get_arrays_from_intent("NIFTI_INTENT_TRIANGLE")
    if not points:
        raise MeshError("GIFTI file has no NIFTI_INTENT_POINTSET array (not a surface)")
    if not triangles:
        raise MeshError("GIFTI file has no NIFTI_INTENT_TRIANGLE array (not a surface)")
    vertices = np.asarray(points[0].data, dtype=np.float64)
    faces = np.asarray(triangles[0].data)
    if vertices.ndim != 2 or vertices.shape[1] != 3:
        raise MeshError(f"GIFTI pointset has shape {vertices.shape}, expected (n, 3)")
    if faces.ndim != 2 or faces.shape[1] != 3:
        raise MeshError(f"GIFTI triangle array has shape {faces.shape}, expected (f, 3)")
    out = Parsed(vertices, np.full(len(faces), 3, np.int64), faces.astype(np.int64).ravel())
    out.metadata.update({str(k): str(v) for k, v in image.meta.items()})
    out.metadata.update({f"pointset.{k}": str(v) for k, v in points[0].meta.items()})
    coordsys = points[0].coordsys
    # written back as read (a lab's tools place the surface by it); nibabel's default
    # (unknown spaces, the identity), which any pointset written without one gets, says nothing
    if coordsys is not None and (coordsys.dataspace or coordsys.xformspace or not np.array_equal(
            np.asarray(coordsys.xform, dtype=np.float64), np.eye(4))):
        out.metadata[COORDINATE_SYSTEM] = json.dumps(
            {"dataspace": int(coordsys.dataspace), "xformspace": int(coordsys.xformspace),
             "xform": np.asarray(coordsys.xform, dtype=np.float64).tolist()})
    for k, array in enumerate(image.darrays):
        if array is points[0] or array is triangles[0]:
            continue
        values = np.asarray(array.data)
        name = array.meta.get("Name") or f"array_{k}"
        if values.ndim and len(values) == len(vertices):
            out.attributes[_safe(name)] = values
        else:
            out.dropped.append(f"GIFTI data array {name!r} (shape {values.shape}, not one row "
                               "per vertex) is not kept")
    return out


def _gifti_image(xml: bytes):
    """nibabel's image of GIFTI XML; where nibabel fails, a DataArray whose data are corrupt
    is said as ``batch``'s pre-flight says it (:func:`~surfinpaint.io.brain_checks.
    gifti_arrays`, not run first: it costs about as much as nibabel's own decoding)."""
    import nibabel as nib

    try:
        return nib.gifti.GiftiImage.from_bytes(xml)
    except Exception:
        gifti_arrays(xml)
        raise


def read_freesurfer(data: bytes, path: Path) -> Parsed:
    from nibabel.freesurfer import read_geometry

    freesurfer_header(data, len(data))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # nibabel warns about missing volume info footers
        vertices, faces, info, stamp = read_geometry(str(path), read_metadata=True,
                                                     read_stamp=True)
    out = Parsed(np.asarray(vertices, dtype=np.float64), np.full(len(faces), 3, np.int64),
                 np.asarray(faces, dtype=np.int64).ravel())
    if stamp:
        out.metadata["create_stamp"] = str(stamp)
    if info:
        out.metadata["volume_info"] = json.dumps(
            {k: np.asarray(v).tolist() if not isinstance(v, str) else v
             for k, v in info.items()})
    return out


# ------------------------------------------------------------------------------ overlays


def surface_base(path: Path) -> str:
    """The surface's name without its format suffix: overlays are named ``BASE.NAME...``
    (``lh.pial.gii`` -> ``lh.pial``; a FreeSurfer surface's name is its base: ``lh.white``)."""
    name = path.name
    for suffix in (".surf.gii.gz", ".surf.gii", ".gii.gz", ".gii"):
        if name.lower().endswith(suffix):
            return name[:-len(suffix)]
    return name


def _safe(name: str) -> str:
    return re.sub(r"[^\w.-]", "_", str(name)) or "overlay"


def overlays_beside(path: Path, fmt: str) -> list[Path]:
    """The overlay files of a surface of format ``fmt`` ("gii", "gii.gz" or "freesurfer"):
    ``BASE.NAME.shape.gii`` / ``.func.gii`` / ``.label.gii`` and FreeSurfer morphometry files
    ``BASE.NAME`` (what :func:`overlay_outputs` writes), and, for a FreeSurfer surface named
    ``lh.*`` or ``rh.*`` (not a GIFTI one: :func:`subject_overlays`), ``lh.curv``,
    ``lh.thickness``, ... beside it (:data:`FREESURFER_OVERLAYS`)."""
    base = surface_base(path)
    folder = path.parent
    found = sorted(folder.glob(f"{_glob_escape(base)}.*.shape.gii"))
    found += sorted(folder.glob(f"{_glob_escape(base)}.*.func.gii"))
    found += sorted(folder.glob(f"{_glob_escape(base)}.*.label.gii"))
    found = [p for p in found if not _of_another_surface(p, base, path)]
    found += [p for p in sorted(folder.glob(f"{_glob_escape(path.name)}.*"))
              if p not in found and is_morphometry(p)
              and not _of_another_surface(p, path.name, path)]
    return found + subject_overlays(path, fmt)


#: How a surface file beside may be named after its base (``lh.pial.filled`` + one of these).
_SURFACE_ENDINGS = ("", ".gii", ".gii.gz", ".surf.gii", ".surf.gii.gz")


def _of_another_surface(overlay: Path, base: str, path: Path) -> bool:
    """Whether an overlay found as ``BASE.REST`` is that of another surface beside, named
    ``BASE.R`` for leading dotted parts R of REST: ``lh.pial.filled.sulc.shape.gii`` is
    ``lh.pial.filled.gii``'s, written beside ``lh.pial.gii``, not ``lh.pial.gii``'s."""
    name = overlay.name
    for suffix in OVERLAY_SUFFIXES:
        if name.lower().endswith(suffix):
            name = name[:-len(suffix)]
            break
    parts = name[len(base) + 1:].split(".")
    for k in range(1, len(parts)):
        stem = f"{base}.{'.'.join(parts[:k])}"
        for ending in _SURFACE_ENDINGS:
            other = path.parent / (stem + ending)
            if other != path and other.is_file() and not is_morphometry(other):
                return True
    return False


def subject_overlays(path: Path, fmt: str) -> list[Path]:
    """FreeSurfer's ``lh.curv``, ``lh.thickness``, ... beside a FreeSurfer surface (``fmt``
    "freesurfer") named ``lh.*`` or ``rh.*`` (:data:`FREESURFER_OVERLAYS`): the subject's,
    found by name only, so they may belong to another surface of the subject (the original
    one, beside a filled one). None for a surface of another format: a GIFTI surface named
    ``lh.*`` (``lh.pial.gii``, converted or resampled) need not have the subject's vertices;
    its overlays beside are named after it, or given (``overlays=[...]``, ``--overlay``)."""
    hemi = re.match(r"^(lh|rh)\.", path.name)
    if not hemi or fmt != "freesurfer":
        return []
    return [p for name in FREESURFER_OVERLAYS
            if (p := path.parent / f"{hemi.group(1)}.{name}") != path and is_morphometry(p)]


def _glob_escape(text: str) -> str:
    return re.sub(r"([*?\[])", r"[\1]", text)


def is_morphometry(p: Path) -> bool:
    """Whether ``p`` is a FreeSurfer morphometry (curv) file: a per-vertex overlay such as
    ``lh.sulc``, by its magic bytes ``FF FF FF``."""
    try:
        with open(p, "rb") as fh:
            return p.is_file() and fh.read(3) == MORPH_MAGIC
    except OSError:
        return False


def is_gifti_data(p: Path) -> bool:
    """Whether ``p``, a ``.gii`` or ``.gii.gz`` file by its name, holds data arrays and no
    surface (no ``NIFTI_INTENT_POINTSET`` array): an overlay named as nilearn names
    fsaverage's, ``sulc_left.gii.gz``, beside ``pial_left.gii.gz``, which no name rule tells
    from a surface. Read until the pointset's intent is seen (a surface's first array, at
    its start) or to the end (an overlay: small); an unreadable file is not called data (its
    reader's error names it)."""
    lower = p.name.lower()
    if not lower.endswith((".gii", ".gii.gz")):
        return False
    opener = gzip.open if lower.endswith(".gz") else open
    seen, arrays = b"", False
    try:
        with opener(p, "rb") as fh:
            while chunk := fh.read(1 << 16):
                text = seen[-64:] + chunk  # a tag cut between two chunks
                if b"NIFTI_INTENT_POINTSET" in text:
                    return False
                arrays = arrays or b"<DataArray" in text
                seen = chunk
    except (OSError, EOFError, gzip.BadGzipFile, ValueError):
        return False
    return arrays


def overlay_name(overlay: Path, surface: Path | None = None) -> str:
    """The attribute name of an overlay file: ``lh.pial.thickness.shape.gii`` beside
    ``lh.pial.gii`` -> ``thickness``; ``lh.curv`` -> ``curv``."""
    name = overlay.name
    for suffix in (*_GIFTI_DATA, ".annot", ".label"):
        if name.lower().endswith(suffix):
            name = name[:-len(suffix)]
            break
    if surface is not None:
        for base in (surface.name, surface_base(surface)):
            if name.startswith(base + "."):
                name = name[len(base) + 1:]
                break
    return _safe(re.sub(r"^(lh|rh)\.", "", name))


def label_overlays(metadata: dict[str, str]) -> list[str]:
    """The names of the attributes that are segmentations: those with a label table
    (:data:`LABEL_TABLE`), read from a ``.label.gii`` or FreeSurfer ``.annot`` overlay."""
    return [k[len(LABEL_TABLE):] for k in metadata if k.startswith(LABEL_TABLE)]


def _gifti_label_table(image) -> str | None:
    """A GIFTI data file's label table as :data:`LABEL_TABLE` JSON, or None (no labels)."""
    labels = image.labeltable.labels
    if not labels and not any(a.intent == 1002 for a in image.darrays):  # NIFTI_INTENT_LABEL
        return None
    return json.dumps([[int(lab.key), str(getattr(lab, "label", None) or ""),
                        *(float(c) for c in lab.rgba)]
                       for lab in labels])


def _read_annot(p: Path) -> tuple[np.ndarray, str, list[str]]:
    """A FreeSurfer ``.annot`` file's labels (per vertex, the index of the colour table
    entry of its colour; -1 for value 0, as nibabel's ``read_annot``), its table as
    :data:`LABEL_TABLE` JSON, and a note on values no entry holds: read as -1, no label
    (nibabel gives them a neighbouring entry's index, or fails past the largest). Read here,
    not by nibabel, which allocates the table's announced size (:func:`annot_table`)."""
    data = p.read_bytes()
    start = annot_header(data, len(data))
    values = np.frombuffer(data, ">i4", (start - 4) // 4, 4)[1::2].astype(np.int64)
    entries = {index: (name, rgbt) for index, name, rgbt in annot_table(data[start:])}
    index = np.array(sorted(entries), dtype=np.int64)
    rgbt = np.array([entries[k][1] for k in index.tolist()], dtype=np.int64).reshape(-1, 4)
    packed = rgbt[:, 0] + (rgbt[:, 1] << 8) + (rgbt[:, 2] << 16)
    order = np.argsort(packed, kind="stable")  # equal colours: the lowest index
    at = np.minimum(np.searchsorted(packed[order], values), max(len(order) - 1, 0))
    found = (packed[order][at] == values) if len(order) else np.zeros(len(values), bool)
    labels = np.where(found & (values != 0), index[order][at] if len(order) else -1, -1)
    table = [[k, entries[k][0].decode("utf-8", "replace"), r / 255, g / 255, b / 255,
              1 - t / 255] for k, (r, g, b, t) in zip(index.tolist(), rgbt.tolist(),
                                                       strict=True)]
    return labels.astype(np.int32), json.dumps(table), _unknown_labels(p, values[
        ~found & (values != 0)])


def _gifti_record(p: Path, image) -> str | None:
    """A GIFTI data overlay's :data:`GIFTI_OVERLAY` JSON, or None where it holds nothing but
    its numbers (no metadata, every array's intent the one it is written with)."""
    kind = "func" if p.name.lower().endswith(".func.gii") else "shape"
    arrays = [{"intent": int(a.intent), "meta": dict(a.meta)} for a in image.darrays]
    plain = (1002, 2005)  # NIFTI_INTENT_LABEL, NIFTI_INTENT_SHAPE: what the writers use
    if kind == "shape" and not image.meta and all(
            not a["meta"] and a["intent"] in plain for a in arrays):
        return None
    return json.dumps({"kind": kind, "meta": dict(image.meta), "arrays": arrays})


def _read_label(p: Path, n: int, name: str) -> tuple[np.ndarray, str, list[str]]:
    """A FreeSurfer ``.label`` file as a segmentation of a surface of ``n`` vertices: 1 at
    the vertices it lists, 0 elsewhere, its table (0, 1 ``name``) as
    :data:`LABEL_TABLE` JSON (0 named "unknown", as in FreeSurfer's tables: nibabel reads
    a GIFTI label without a name as one without a ``label``), and a note when its value
    column, not read, holds values."""
    data = p.read_bytes()
    if not data:
        overlay_header(p, data, 0)  # the words every reader says of an empty overlay
    ids, stats = label_file(data)
    if len(ids) and ids.max() >= n:
        out = np.unique(ids[ids >= n])
        raise MeshError(f"label lists {how_many(len(out), 'vertex', 'vertices')} the surface "
                        f"does not have ({preview(out.tolist(), 5)}; it has {n} vertices)")
    values = np.zeros(n, np.int32)
    values[ids] = 1
    notes = [f"overlay {p.name}: its value column (not all 0) is not read: the label is 1 at "
             "the vertices it lists, 0 elsewhere"] if stats.any() else []
    table = [[0, "unknown", 0.0, 0.0, 0.0, 0.0], [1, name, 1.0, 1.0, 1.0, 1.0]]
    return values, json.dumps(table), notes


def _unknown_labels(p: Path, values: np.ndarray) -> list[str]:
    """The note on an ``.annot``'s vertices whose label values (``values``) its colour
    table does not hold: each value (its red, green, blue) and on how many vertices."""
    if not len(values):
        return []
    kinds, counts = np.unique(values, return_counts=True)
    rgb = [f"{v} (RGB {v & 255} {v >> 8 & 255} {v >> 16 & 255}) on "
           f"{how_many(c, 'vertex', 'vertices')}"
           for v, c in zip(kinds.tolist(), counts.tolist(), strict=True)]
    said = how_many(len(values), "vertex has a label value", "vertices have label values")
    return [f"overlay {p.name}: {said} its colour table does not hold, read as no label "
            f"(-1): {preview(rgb, 5)}"]


def read_overlays(files: Sequence[Path], n: int, surface: Path | None = None, *,
                  guessed: Sequence[Path] = ()
                  ) -> tuple[dict[str, np.ndarray], dict[str, str], list[str]]:
    """Per-vertex arrays from overlay files (GIFTI data files, FreeSurfer morphometry,
    ``.annot`` and ``.label`` files), the label tables of the segmentations among them
    (metadata ``labels.NAME``, :data:`LABEL_TABLE`), and what they hold that is not kept as read (a
    second overlay of the same name, kept under its file name; an overlay of ``guessed``
    without ``n`` values, not read: :func:`subject_overlays` of the surface, which may
    belong to another surface).

    Raises
    ------
    MeshError
        Naming the overlay file, when it cannot be read or (not one of ``guessed``) has not
        ``n`` values.
    """
    from nibabel.freesurfer import read_morph_data

    out, tables, dropped = {}, {}, []
    for p in files:
        p = Path(p)
        table, notes, record = None, [], None
        with overlay_errors(p):
            if p.name.lower().endswith((".gii", ".gii.gz")):
                xml = gifti_inflate(p.read_bytes())
                overlay_header(p, xml, len(xml), arrays=False)
                image = _gifti_image(xml)
                arrays = [np.asarray(a.data) for a in image.darrays]
                values = arrays[0] if len(arrays) == 1 else np.column_stack(arrays)
                table = _gifti_label_table(image) if values.ndim == 1 else None
                record = _gifti_record(p, image)
            elif p.name.lower().endswith(".label"):
                values, table, notes = _read_label(p, n, overlay_name(p, surface))
            else:
                check_overlay(p)
                values, table, notes = (
                    _read_annot(p) if p.name.lower().endswith(".annot") else
                    (np.asarray(read_morph_data(str(p))), None, []))
        if (values.ndim == 0 or len(values) != n) and p in guessed:
            dropped.append(f"overlay {p.name} has {len(values) if values.ndim else 0} values, "
                           f"the surface {n} vertices: another surface's, not read")
            continue
        if values.ndim == 0 or len(values) != n:
            raise MeshError(f"overlay has {len(values) if values.ndim else 0} values, the "
                            f"surface {n} vertices", path=str(p))
        name = overlay_name(p, surface)
        if name in out:
            # two files map to one name (lh.thickness beside lh.pial.thickness.shape.gii):
            # keep both, the later under its whole file name, and say so
            taken, name, k = name, _safe(p.name), 1
            while name in out:
                k += 1
                name = f"{_safe(p.name)}_{k}"
            dropped.append(f"overlay {p.name} would be named {taken!r} like an earlier "
                           f"overlay; it is kept as {name!r}")
        out[name] = values
        dropped += notes
        if table is not None:
            tables[LABEL_TABLE + name] = table
        if record is not None:
            tables[GIFTI_OVERLAY + name] = record
    return out, tables, dropped


def _gifti_type(a: np.ndarray) -> tuple[np.ndarray, str] | None:
    """The array in a GIFTI data type (uint8, int32, float32) and its name, or None."""
    if a.dtype in (np.uint8, np.bool_):
        return a.astype(np.uint8), "NIFTI_TYPE_UINT8"
    if a.dtype.kind in "iu":
        if a.size and (a.min() < np.iinfo(np.int32).min or a.max() > np.iinfo(np.int32).max):
            return None
        return a.astype(np.int32), "NIFTI_TYPE_INT32"
    if a.dtype.kind == "f":
        return a.astype(np.float32), "NIFTI_TYPE_FLOAT32"
    return None


def _writable(mesh: MeshData) -> dict[str, np.ndarray]:
    return {k: a for k, a in mesh.attributes.items() if a.ndim <= 2 and _gifti_type(a)}


def unstored_brain(mesh: MeshData) -> list[str]:
    """What a GIFTI surface and its overlays cannot store."""
    kept = _writable(mesh)
    names = [f"per-vertex {k} ({a.dtype}, shape {a.shape})" for k, a in mesh.attributes.items()
             if k not in kept]
    names += [f"per-face {k}" for k in mesh.face_attributes]
    names += [f"per-corner {k}" for k in mesh.corner_attributes]
    return ([f"GIFTI and FreeSurfer store per-vertex numbers only: {', '.join(names)} not "
             "written"] if names else []) + [
        f"overlay {k!r}: label {key} has no name: written as {_label_name(key, '')!r} "
        "(nibabel cannot read a label table entry without one)"
        for k in kept if LABEL_TABLE + k in mesh.metadata
        for key, text, *_ in json.loads(mesh.metadata[LABEL_TABLE + k]) if not text]


def _label_name(key: int, text: str) -> str:
    """A label table entry's name as written: an empty one named by its key (nibabel reads
    a ``<Label>`` without text as having no ``label``, and its ``get_labels_as_dict``
    fails)."""
    return text or f"label {key}"


def unstored_freesurfer(mesh: MeshData) -> list[str]:
    """What a FreeSurfer surface and its overlays cannot store: a GIFTI overlay's metadata
    where it becomes a morphometry file."""
    morph = [k for k, a in _writable(mesh).items()
             if a.ndim == 1 and LABEL_TABLE + k not in mesh.metadata]
    return unstored_brain(mesh) + [f"metadata {k!r} is not stored in a FreeSurfer surface"
                                   for k in mesh.metadata
                                   if k not in ("create_stamp", "volume_info")
                                   and not k.startswith((LABEL_TABLE, GIFTI_OVERLAY))] + [
        f"overlay {k!r}: its GIFTI metadata is not stored in a FreeSurfer morphometry file"
        for k in morph if GIFTI_OVERLAY + k in mesh.metadata]


def overlay_outputs(path: Path, mesh: MeshData, fmt: str) -> list[tuple[Path, Callable]]:
    """The overlay files written beside a surface, each as (path, write(handle)).

    GIFTI: ``BASE.NAME.shape.gii`` (``BASE``: the output's name without ``.gii``/``.gii.gz``;
    an overlay read from a ``.func.gii``: ``BASE.NAME.func.gii``; each GIFTI file with the
    metadata and intents it was read with, :data:`GIFTI_OVERLAY`);
    FreeSurfer: ``OUT.NAME`` morphometry files (float32) for 1-D arrays, ``OUT.NAME.shape.gii``
    for arrays of several columns. Float arrays are stored as float32, integers as int32.
    A segmentation (an attribute with a label table in the metadata, :data:`LABEL_TABLE`)
    is written as ``BASE.NAME.label.gii`` (FreeSurfer: ``OUT.NAME.label.gii``) with its
    table, for either surface format.
    """
    out = []
    for name, a in _writable(mesh).items():
        table = mesh.metadata.get(LABEL_TABLE + name)
        record = json.loads(mesh.metadata.get(GIFTI_OVERLAY + name, "{}"))
        name = _safe(name)
        if table is not None and a.ndim == 1 and a.dtype.kind in "iub":
            base = path.name if fmt == "freesurfer" else surface_base(path)
            out.append((path.with_name(f"{base}.{name}.label.gii"),
                        _label_writer(a, table, record)))
        elif fmt == "freesurfer" and a.ndim == 1:
            out.append((path.with_name(f"{path.name}.{name}"), _morph_writer(a)))
        else:
            base = path.name if fmt == "freesurfer" else surface_base(path)
            kind = record.get("kind", "shape")
            out.append((path.with_name(f"{base}.{name}.{kind}.gii"), _shape_writer(a, record)))
    return out


def _as_read(record: dict, n_arrays: int, intent: str) -> tuple[dict, list[dict]]:
    """A :data:`GIFTI_OVERLAY` record's file metadata and, when it has ``n_arrays``, its
    arrays' intents and metadata (else ``intent`` and none)."""
    arrays = record.get("arrays", [])
    if len(arrays) != n_arrays:
        arrays = [{"intent": intent, "meta": {}}] * n_arrays
    return record.get("meta", {}), arrays


def _shape_writer(a: np.ndarray, record: dict) -> Callable:
    """Writes ``a`` as a GIFTI data file, an array a column, each with its intent and
    metadata as read (:data:`GIFTI_OVERLAY` ``record``), else ``NIFTI_INTENT_SHAPE``."""
    def write(fh) -> None:
        import nibabel as nib

        columns = [a] if a.ndim == 1 else [a[:, k] for k in range(a.shape[1])]
        meta, read = _as_read(record, len(columns), "NIFTI_INTENT_SHAPE")
        arrays = []
        for c, r in zip(columns, read, strict=True):
            values, dtype = _gifti_type(np.ascontiguousarray(c))
            arrays.append(nib.gifti.GiftiDataArray(values, intent=r["intent"], datatype=dtype,
                                                   meta=nib.gifti.GiftiMetaData(r["meta"])))
        fh.write(nib.gifti.GiftiImage(darrays=arrays,
                                      meta=nib.gifti.GiftiMetaData(meta)).to_bytes())
    return write


def _label_writer(a: np.ndarray, table: str, record: dict) -> Callable:
    def write(fh) -> None:
        import nibabel as nib

        labels = nib.gifti.GiftiLabelTable()
        for key, text, *rgba in json.loads(table):
            label = nib.gifti.GiftiLabel(key, *rgba)
            label.label = _label_name(key, text)
            labels.labels.append(label)
        meta, (read,) = _as_read(record, 1, "NIFTI_INTENT_LABEL")
        values = nib.gifti.GiftiDataArray(a.astype(np.int32), intent="NIFTI_INTENT_LABEL",
                                          datatype="NIFTI_TYPE_INT32",
                                          meta=nib.gifti.GiftiMetaData(read["meta"]))
        fh.write(nib.gifti.GiftiImage(darrays=[values], labeltable=labels,
                                      meta=nib.gifti.GiftiMetaData(meta)).to_bytes())
    return write


def _morph_writer(a: np.ndarray) -> Callable:
    def write(fh) -> None:
        from nibabel.freesurfer import write_morph_data

        write_morph_data(fh, np.asarray(a, dtype=np.float32))
    return write


def gifti_bytes(mesh: MeshData) -> bytes:
    import nibabel as nib

    meta = {k: v for k, v in mesh.metadata.items()
            if not k.startswith(("pointset.", LABEL_TABLE, GIFTI_OVERLAY))
            and k != COORDINATE_SYSTEM}
    point_meta = {k[len("pointset."):]: v for k, v in mesh.metadata.items()
                  if k.startswith("pointset.")}
    coordsys = None
    if COORDINATE_SYSTEM in mesh.metadata:
        kept = json.loads(mesh.metadata[COORDINATE_SYSTEM])
        coordsys = nib.gifti.GiftiCoordSystem(kept["dataspace"], kept["xformspace"],
                                              np.asarray(kept["xform"]))
    points = nib.gifti.GiftiDataArray(mesh.vertices.astype(np.float32),
                                      intent="NIFTI_INTENT_POINTSET",
                                      datatype="NIFTI_TYPE_FLOAT32", coordsys=coordsys,
                                      meta=nib.gifti.GiftiMetaData(point_meta))
    triangles = nib.gifti.GiftiDataArray(mesh.faces.astype(np.int32),
                                         intent="NIFTI_INTENT_TRIANGLE",
                                         datatype="NIFTI_TYPE_INT32")
    return nib.gifti.GiftiImage(darrays=[points, triangles],
                                meta=nib.gifti.GiftiMetaData(meta)).to_bytes()


def write_gifti(fh, tmp: str, mesh: MeshData, ascii: bool) -> None:
    fh.write(gifti_bytes(mesh))


def write_gifti_gz(fh, tmp: str, mesh: MeshData, ascii: bool) -> None:
    fh.write(gzip.compress(gifti_bytes(mesh)))


def write_freesurfer(fh, tmp: str, mesh: MeshData, ascii: bool) -> None:
    from nibabel.freesurfer import write_geometry

    info = mesh.metadata.get("volume_info")
    volume_info = None
    if info:
        volume_info = {k: v if isinstance(v, str) else np.asarray(v)
                       for k, v in json.loads(info).items()}
    stamp = mesh.metadata.get("create_stamp")
    # nibabel writes by file name; it goes to the same temporary file
    write_geometry(tmp, mesh.vertices.astype(np.float32), mesh.faces.astype(np.int32),
                   create_stamp=stamp, volume_info=volume_info)
