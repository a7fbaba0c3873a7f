"""The header checks of brain surfaces and their overlays (GIFTI, FreeSurfer surfaces,
morphometry, ``.annot`` and ``.label`` files): the first step of each reader of
:mod:`surfinpaint.io.brain`, which calls them before nibabel, and the whole of ``batch``'s
pre-flight of such a file (:func:`surfinpaint.io.formats.check_file`, :func:`check_overlay`),
which gives them the file's first bytes (a GIFTI file: all of it, for its end and its data;
an ``.annot``: its colour table too; a ``.label``: all of it): the check and the reader say
the same words.
"""

from __future__ import annotations

import binascii
import contextlib
import gzip
import math
import os
import re
import struct
import zlib
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from surfinpaint.errors import MeshError, MissingFileError
from surfinpaint.io.base import describe

__all__ = ["ANNOT_TABLE_MAX", "FREESURFER_MAGIC", "MORPH_MAGIC", "annot_header",
           "annot_table", "check_overlay", "freesurfer_header", "gifti_arrays", "gifti_header",
           "gifti_inflate", "gifti_xml", "label_file", "morph_header", "overlay_errors",
           "overlay_header"]

FREESURFER_MAGIC = b"\xff\xff\xfe"
MORPH_MAGIC = b"\xff\xff\xff"

#: What may come before an XML file's root element: blanks, ``<?xml ...?>``, comments and
#: ``<!DOCTYPE ...>`` (GIFTI's has no internal subset)
_XML_PROLOGUE = re.compile(rb"(?:\s+|<\?.*?\?>|<!--.*?-->|<!DOCTYPE[^>]*>)*", re.S)
#: How an XML file whose root is ``<GIFTI>`` ends: its closing tag, then blanks, comments
#: and processing instructions (one blank at a time: ``\s+`` under ``*`` would backtrack
#: exponentially on a long run of blanks followed by anything else)
_GIFTI_END = re.compile(rb"</GIFTI\s*>(?:\s|<\?.*?\?>|<!--.*?-->)*", re.S)


def gifti_xml(xml: bytes, arrays: bool = True) -> None:
    """Raise for a GIFTI file's XML (all of it) whose root element is not ``<GIFTI>``, that
    is no XML at all, that does not end with the root's closing tag (a file cut short), that
    has no ``<DataArray>``, or (``arrays``) one of whose DataArrays' data are corrupt
    (:func:`gifti_arrays`: as costly as inflating them, which a reader does anyway; the
    readers check them only when nibabel fails, for its words)."""
    xml = xml.removeprefix(b"\xef\xbb\xbf")
    end = _XML_PROLOGUE.match(xml).end()
    start = xml[end:end + 64]  # not xml[end:] (a copy of all of it)
    root = re.match(rb"<([A-Za-z_][\w:.-]*)", start)
    if root and root[1] != b"GIFTI":
        raise MeshError(f"not a GIFTI file (its XML root element is <{root[1].decode()}>, "
                        "not <GIFTI>)")
    if start and not start.startswith(b"<"):
        raise MeshError(f"not a GIFTI file (not XML: it starts {start[:24]!r})")
    # before the DataArray: a file cut short is that, wherever the cut fell
    if start and not _gifti_ends(xml):
        raise MeshError("GIFTI file is truncated (it does not end with its closing tag "
                        "</GIFTI>)")
    if not start or b"<DataArray" not in xml:
        raise MeshError("GIFTI file has no DataArray (no surface and no data)")
    if arrays:
        gifti_arrays(xml)


def _gifti_ends(xml: bytes) -> bool:
    """Whether GIFTI XML ends with its root's closing tag and then only blanks, comments
    and processing instructions (what XML allows after the root element)."""
    at = xml.rfind(b"</GIFTI")
    return at >= 0 and _GIFTI_END.fullmatch(xml, at) is not None


def gifti_inflate(data: bytes) -> bytes:
    """A GIFTI file's XML: ``data`` inflated when it is gzip-compressed (``.gii.gz``), else
    as it is; raises for a gzip stream that is corrupt or cut short."""
    if data[:2] != b"\x1f\x8b":
        return data
    try:
        return gzip.decompress(data)
    except (OSError, EOFError, zlib.error) as exc:
        raise MeshError(f"corrupt gzip data ({describe(exc)})") from None


def gifti_header(data: bytes, arrays: bool = True) -> None:
    """Raise the :class:`MeshError` :func:`~surfinpaint.io.brain.read_gifti` (or
    :func:`~surfinpaint.io.brain.read_overlays`) raises first for a GIFTI file (plain or
    gzip-compressed) whose bytes are ``data`` (all of them): a gzip stream corrupt or cut
    short, not XML, an XML root that is not ``<GIFTI>``, no closing tag (a truncated file),
    no ``DataArray``, or (``arrays``) a DataArray whose data are corrupt
    (:func:`gifti_arrays`): the check of :func:`surfinpaint.io.formats.check_file` and
    :func:`check_overlay`."""
    gifti_xml(gifti_inflate(data), arrays)


#: A DataArray's start tag, its attributes (a quoted value may hold a ``>``), and the
#: attributes' names and values
_DATA_ARRAY = re.compile(rb"""<DataArray\b((?:[^>"']|"[^"]*"|'[^']*')*)>""")
_ATTRIBUTE = re.compile(rb"""([\w:.-]+)\s*=\s*(?:"([^"]*)"|'([^']*)')""")
#: GIFTI's encodings (as nibabel names them: each by its code, label or name) of data held
#: in the file; ``ExternalFileBinary`` data, in another file, are left to the reader
_ENCODINGS = {**dict.fromkeys(("ASCII", "GIFTI_ENCODING_ASCII"), "ASCII"),
              **dict.fromkeys(("Base64Binary", "B64BIN", "GIFTI_ENCODING_B64BIN"), "base64"),
              **dict.fromkeys(("GZipBase64Binary", "B64GZ", "GIFTI_ENCODING_B64GZ"), "gzip")}
#: Bytes per value of GIFTI's (NIfTI's) data types; an array of another type is left to
#: the reader
_VALUE_BYTES = {f"NIFTI_TYPE_{name}": size for name, size in (
    ("UINT8", 1), ("INT8", 1), ("INT16", 2), ("UINT16", 2), ("INT32", 4), ("UINT32", 4),
    ("INT64", 8), ("UINT64", 8), ("FLOAT32", 4), ("FLOAT64", 8))}


def gifti_arrays(xml: bytes) -> None:
    """Raise for the first ``<DataArray>`` of GIFTI XML whose data held in the file do not
    decode (base64, gzip) or do not hold its ``Dim0`` × ``Dim1`` × ... values of its
    ``DataType``: a payload cut or corrupted, or dimensions that are wrong. The message
    names the DataArray by its position (from 0, as nibabel's ``darrays``) and intent.
    What this cannot tell (no ``<Data>`` element, external data, another data type) is
    left to the reader, so that no file nibabel reads fails here."""
    for k, tag in enumerate(_DATA_ARRAY.finditer(xml)):
        attrs = {m[1].decode(): (m[2] if m[3] is None else m[3]).decode("utf-8", "replace")
                 for m in _ATTRIBUTE.finditer(tag[1])}
        end = xml.find(b"</DataArray", tag.end())
        after = xml.find(b"<DataArray", tag.end())
        if tag[1].endswith(b"/") or 0 <= after < end:  # no data of its own: the reader's
            continue
        begin = xml.find(b"<Data>", tag.end(), end)
        stop = xml.find(b"</Data>", begin, end)
        if begin < 0 or stop < 0:
            continue
        problem = _array_problem(attrs, xml[begin + len(b"<Data>"):stop])
        if problem is not None:
            raise MeshError(f"GIFTI DataArray {k} ({attrs.get('Intent', 'no Intent')}) is "
                            f"corrupt: {problem}")


def _array_problem(attrs: dict[str, str], payload: bytes) -> str | None:
    """What is wrong with a DataArray of attributes ``attrs`` whose ``<Data>`` holds
    ``payload``, as nibabel's reader would find it (its dimensions, then its data decoded
    and their size); None when nothing is, or this cannot tell."""
    try:
        rank = int(attrs.get("Dimensionality", 0))
        dims = [int(attrs[f"Dim{i}"]) for i in range(rank) if f"Dim{i}" in attrs]
    except ValueError:
        return None
    if len(dims) != rank:
        missing = ", ".join(f"Dim{i}" for i in range(rank) if f"Dim{i}" not in attrs)
        return f"its Dimensionality is {rank}, but it has no {missing}"
    encoding = _ENCODINGS.get(attrs.get("Encoding", ""))
    if encoding is None or b"<" in payload:  # external data, or CDATA: the reader's
        return None
    want = math.prod(dims)
    shape = f"{' × '.join(f'Dim{i}' for i in range(rank))} = {' × '.join(map(str, dims))}"
    if encoding == "ASCII":
        if b"#" in payload:  # nibabel's loadtxt cuts comments: the reader's
            return None
        have = len(payload.split())
        return None if have == want else f"{shape} = {want} values, its data hold {have}"
    try:
        raw = binascii.a2b_base64(payload)
        raw = zlib.decompress(raw) if encoding == "gzip" else raw
    except (binascii.Error, zlib.error) as exc:
        return f"its {attrs['Encoding']} data do not decode ({exc})"
    size = _VALUE_BYTES.get(attrs.get("DataType", ""))
    if size is None or len(raw) == want * size:
        return None
    return (f"{shape} = {want} values of {attrs['DataType']} = {want * size} bytes, its data "
            f"hold {len(raw)} bytes")


def freesurfer_header(head: bytes, size: int) -> None:
    """Raise the :class:`MeshError` :func:`~surfinpaint.io.brain.read_freesurfer` raises
    for a FreeSurfer file of ``size`` bytes starting with ``head`` (its first 4096 + 13
    bytes, or all of it) whose magic bytes are wrong or that is shorter than its header
    announces."""
    if head[:3] not in (FREESURFER_MAGIC, MORPH_MAGIC):
        raise MeshError("not a FreeSurfer surface (magic bytes are not FF FF FE)")
    if head[:3] == FREESURFER_MAGIC:
        # the two creation lines end in "\n\n"; the counts follow as big-endian int32
        end = head.find(b"\n\n", 3, 3 + 4096)
        if end < 0 or end + 10 > min(size, len(head)):
            raise MeshError("FreeSurfer surface is truncated (no header)")
        nv, nf = struct.unpack_from(">ii", head, end + 2)
        need = end + 10 + 12 * nv + 12 * nf
        if nv < 0 or nf < 0 or size < need:
            raise MeshError(f"FreeSurfer surface is truncated (header announces {nv} vertices "
                            f"and {nf} faces = {need} bytes, the file has {size})")


# ------------------------------------------------------------------------------ overlays


@contextlib.contextmanager
def overlay_errors(p: Path) -> Iterator[None]:
    """An overlay's reader's error names the overlay; any other failure: it cannot be read."""
    try:
        yield
    except MeshError as err:
        raise err.with_path(str(p)) from None
    except FileNotFoundError:
        raise MissingFileError(str(p)) from None
    except Exception as exc:
        raise MeshError(f"cannot read the overlay: {describe(exc)}", path=str(p)) from None


def morph_header(head: bytes, size: int) -> None:
    """Raise for a FreeSurfer morphometry file of ``size`` bytes starting with ``head`` (its
    first 15 bytes or more) shorter than its header announces: nibabel's reader would give
    fewer values (or, for a file without the ``FF FF FF`` magic bytes, read as an old-format
    curv file, a text file's first bytes as the count)."""
    if head[:3] == MORPH_MAGIC:
        count = struct.unpack_from(">i", head, 3)[0] if len(head) >= 7 else -1
        need, kind = 15 + 4 * count, "FreeSurfer overlay is truncated"
    else:
        count = int.from_bytes(head[:3], "big")
        need, kind = 6 + 2 * count, ("not a FreeSurfer overlay (no FF FF FF magic bytes), or an "
                                     "old-format curv file that is truncated")
    if count < 0 or size < need:
        raise MeshError(f"{kind} (its header announces {max(count, 0)} values = {need} bytes, "
                        f"the file has {size})")


def label_file(data: bytes) -> tuple[np.ndarray, np.ndarray]:
    """The vertex numbers and values of a FreeSurfer ``.label`` file (all of it: a comment
    line, the vertex count, then ``vertex x y z value`` per line, as ``mri_label2label`` and
    nibabel's ``read_label`` have them); raise where it is not one, or lists another number
    of vertices than its count announces (a file cut short)."""
    lines = data.decode("utf-8", "replace").splitlines()
    count = lines[1].strip() if len(lines) > 1 else ""
    if not count.isdigit():
        raise MeshError("not a FreeSurfer label (its second line should be its vertex count, "
                        f"it reads {count[:24]!r})")
    fields = " ".join(lines[2:]).split()
    if len(fields) != 5 * int(count):
        raise MeshError(f"FreeSurfer label is truncated, or not one: its header announces "
                        f"{count} vertices (5 numbers each), {len(fields)} numbers follow")
    try:
        rows = np.array(fields, dtype=float).reshape(-1, 5)
    except ValueError:
        raise MeshError("FreeSurfer label: not every entry is a number") from None
    ids = rows[:, 0]
    if len(ids) and ((ids < 0).any() or (ids != np.round(ids)).any()):
        raise MeshError("FreeSurfer label: a vertex number is not a whole number >= 0: "
                        f"{ids[(ids < 0) | (ids != np.round(ids))][0]:g}")
    return ids.astype(np.int64), rows[:, 4]


def annot_header(head: bytes, size: int) -> int:
    """Raise for a FreeSurfer ``.annot`` file of ``size`` bytes starting with ``head`` (its
    first 4 bytes or more) too short for what its header announces: its vertex count
    (big-endian int32, as nibabel's ``read_annot`` reads it), a (vertex, label) pair of
    int32 for each, then its colour table's flag and entry count, int32 each (a text file's
    first bytes read as the count announce gigabytes). Else return where its colour table
    starts (after the labels, at the end of the file: :func:`annot_table`)."""
    count = struct.unpack_from(">i", head)[0] if len(head) >= 4 else -1
    need = 4 + 8 * count + 8
    if count < 0 or size < need:
        raise MeshError("FreeSurfer annotation is truncated, or no annotation (its header "
                        f"announces {max(count, 0)} vertices = {max(need, 12)} bytes before "
                        f"its colour table, the file has {size})")
    return need - 8


class _TableFields:
    """The fields of an ``.annot``'s colour table ``table`` in order (big-endian int32 and
    strings after their length), for :func:`annot_table`; raising, naming the entry (from
    0, of ``entries``; None: the table's header), where one runs past the file's end."""

    def __init__(self, table: bytes) -> None:
        self.table, self.at, self.entries = table, 0, 0

    def _where(self, entry: int | None) -> str:
        return "its header" if entry is None else f"entry {entry} of {self.entries}"

    def _skip(self, count: int, entry: int | None) -> int:
        """Where the next ``count`` bytes start; raises when they run past the end."""
        if self.at + count > len(self.table):
            raise MeshError(f"FreeSurfer annotation's colour table is truncated "
                            f"({self._where(entry)} runs past the end of the file)")
        self.at += count
        return self.at - count

    def ints(self, n: int, entry: int | None = None) -> tuple[int, ...]:
        return struct.unpack_from(f">{n}i", self.table, self._skip(4 * n, entry))

    def text(self, entry: int | None = None) -> bytes:
        """A string after its length (trailing NUL bytes cut, as numpy's ``S`` type)."""
        (length,) = self.ints(1, entry)
        if length < 0:
            raise MeshError(f"FreeSurfer annotation's colour table is corrupt "
                            f"({self._where(entry)} has a name of {length} bytes)")
        at = self._skip(length, entry)
        return self.table[at:at + length].rstrip(b"\0")


#: The most entries a colour table may announce: the colours (24 bits, ``R + G·256 +
#: B·65536``) a vertex's label value can name; nibabel allocates what a table announces
ANNOT_TABLE_MAX = 1 << 24


def annot_table(table: bytes) -> list[tuple[int, bytes, tuple[int, ...]]]:
    """The entries of the colour table of a FreeSurfer ``.annot`` file, ``table`` (its bytes
    from :func:`annot_header`'s offset to the end): per entry its index, name and red,
    green, blue and transparency, in the file's order (the old format's index: its place).
    Raises where nibabel's ``read_annot`` cannot read the table: no table (its flag is 0),
    a format version other than 2 or the old one (a positive entry count), an entry cut
    short by the file's end or with a negative name length, or (version 2) an entry whose
    index is not below the table's announced size (nibabel: an ``IndexError``; a negative
    index, which nibabel counts from the end and so writes over another entry, too); and
    where nibabel would allocate a table larger than label values can name
    (:data:`ANNOT_TABLE_MAX` entries). Messages name the entry, from 0."""
    fields = _TableFields(table)
    flag, entries = fields.ints(2)
    if not flag:
        raise MeshError("FreeSurfer annotation has no colour table (its flag after the "
                        "labels is 0)")
    if entries > 0:  # the old format: the count, the table's file name, then the entries
        _no_more_than(entries, "entries")
        fields.entries = entries
        fields.text()
        return [(k, fields.text(k), fields.ints(4, k)) for k in range(entries)]
    if entries != -2:
        raise MeshError(f"FreeSurfer annotation's colour table is of version {-entries} "
                        "(versions 2 and the old format are read)")
    (size,) = fields.ints(1)
    _no_more_than(size, "entries")
    fields.text()
    (fields.entries,) = fields.ints(1)
    out = []
    for k in range(fields.entries):
        (index,) = fields.ints(1, k)
        out.append((index, fields.text(k), fields.ints(4, k)))
        if not 0 <= index < size:
            raise MeshError(f"FreeSurfer annotation's colour table entry {k} has index "
                            f"{index}, outside 0 to {size - 1} (the table announces {size} "
                            "entries)")
    return out


def _no_more_than(size: int, what: str) -> None:
    """Raise for a colour table that announces more than :data:`ANNOT_TABLE_MAX` entries."""
    if size > ANNOT_TABLE_MAX:
        raise MeshError(f"FreeSurfer annotation's colour table announces {size} {what}, more "
                        f"than the {ANNOT_TABLE_MAX} colours a label value can name (a "
                        "corrupt table; not read)")


def overlay_header(p: Path, head: bytes, size: int, arrays: bool = True) -> None:
    """Raise for an overlay ``p`` of ``size`` bytes starting with ``head`` (a GIFTI file:
    all of it, :func:`gifti_header`, its data checked if ``arrays``) whose header its
    reader cannot read."""
    if size == 0:
        raise MeshError("overlay file is empty")
    name = p.name.lower()
    if name.endswith((".gii", ".gii.gz")):
        gifti_header(head, arrays)
    elif name.endswith(".annot"):
        annot_header(head, size)
    elif name.endswith(".label"):
        label_file(head)
    else:
        morph_header(head, size)


def check_overlay(path: str | Path) -> None:
    """Raise the :class:`MeshError` :func:`~surfinpaint.io.brain.read_overlays` raises
    first for the overlay file ``path``, word for word, when it is missing, unreadable,
    empty, its header is bad (from its first 8 KiB), an ``.annot``'s colour table is
    (:func:`annot_table`, read from where it starts), a ``.label``, read whole, is no label
    (:func:`label_file`), or a GIFTI file, read whole, is
    truncated or its data corrupt (:func:`gifti_header`): ``batch``'s pre-flight; not
    whether it has one value per vertex."""
    p = Path(path)
    name = p.name.lower()
    with overlay_errors(p), open(p, "rb") as fh:
        head = fh.read(-1 if name.endswith((".gii", ".gii.gz", ".label")) else 1 << 13)
        size = os.fstat(fh.fileno()).st_size
        overlay_header(p, head, size)
        if name.endswith(".annot"):
            fh.seek(annot_header(head, size))
            annot_table(fh.read())
