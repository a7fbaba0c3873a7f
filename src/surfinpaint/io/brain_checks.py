"""The header checks of brain surfaces and their overlays (GIFTI, FreeSurfer surfaces,
morphometry and ``.annot`` files): the first step of each reader of
:mod:`surfinpaint.io.brain`, which calls them before nibabel, and the whole of ``batch``'s
pre-flight of such a file (:func:`surfinpaint.io.formats.check_file`, :func:`check_overlay`),
which gives them the file's first (and, for a GIFTI file, last) bytes: the check and the
reader say the same words.
"""

from __future__ import annotations

import contextlib
import os
import re
import struct
import zlib
from collections.abc import Iterator
from pathlib import Path

from surfinpaint.errors import MeshError, MissingFileError
from surfinpaint.io.base import describe

__all__ = ["FREESURFER_MAGIC", "GIFTI_TAIL_BYTES", "MORPH_MAGIC", "annot_header",
           "check_overlay", "freesurfer_header", "gifti_header", "gifti_xml", "morph_header",
           "overlay_errors", "overlay_header"]

FREESURFER_MAGIC = b"\xff\xff\xfe"
MORPH_MAGIC = b"\xff\xff\xff"
#: How many of a GIFTI file's last bytes the pre-flight looks for its end in: its closing
#: root tag, and whatever blanks, comments and processing instructions may follow it
GIFTI_TAIL_BYTES = 1 << 12

#: What may come before an XML file's root element: blanks, ``<?xml ...?>``, comments and
#: ``<!DOCTYPE ...>`` (GIFTI's has no internal subset)
_XML_PROLOGUE = re.compile(rb"(?:\s+|<\?.*?\?>|<!--.*?-->|<!DOCTYPE[^>]*>)*", re.S)
#: How an XML file whose root is ``<GIFTI>`` ends: its closing tag, then blanks, comments
#: and processing instructions (one blank at a time: ``\s+`` under ``*`` would backtrack
#: exponentially on a long run of blanks followed by anything else)
_GIFTI_END = re.compile(rb"</GIFTI\s*>(?:\s|<\?.*?\?>|<!--.*?-->)*", re.S)


def gifti_xml(xml: bytes, whole: bool, tail: bytes | None = None) -> None:
    """Raise for GIFTI XML (its start, or ``whole``) whose root element is not ``<GIFTI>``,
    that is no XML at all, that does not end with the root's closing tag (``tail``: its
    last bytes; ``whole``: those of ``xml``), or (``whole``) that has no ``<DataArray>``."""
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
    if start and (whole or tail is not None) and not _gifti_ends(xml if whole else tail,
                                                                 whole):
        raise MeshError("GIFTI file is truncated (it does not end with its closing tag "
                        "</GIFTI>)")
    if whole and (not start or b"<DataArray" not in xml):
        raise MeshError("GIFTI file has no DataArray (no surface and no data)")


def _gifti_ends(tail: bytes, whole: bool) -> bool:
    """Whether GIFTI XML whose last bytes are ``tail`` (``whole``: all of it) ends with its
    root's closing tag and then only blanks, comments and processing instructions; True
    too where a part cannot tell (no closing tag in it, and it is blank or ends with a
    ``>``: a long comment may follow the root), so that no file the reader takes fails."""
    at = tail.rfind(b"</GIFTI")
    if at >= 0:
        return _GIFTI_END.fullmatch(tail, at) is not None
    return not whole and tail.rstrip()[-1:] in (b"", b">")


def gifti_header(head: bytes, size: int, tail: bytes = b"") -> None:
    """Raise the :class:`MeshError` :func:`~surfinpaint.io.brain.read_gifti` (or
    :func:`~surfinpaint.io.brain.read_overlays`) raises first for a GIFTI file (plain or
    gzip-compressed) of ``size`` bytes starting with ``head``: not XML, an XML root that is
    not ``<GIFTI>``, a plain file whose last bytes ``tail`` (when given, at least
    :data:`GIFTI_TAIL_BYTES` of them or all) do not end it (a truncated file), or (``head``
    the whole file) no ``DataArray``: the check of
    :func:`surfinpaint.io.formats.check_file`. A gzip stream is inflated as far as ``head``
    goes, its end not looked for (that needs all of it inflated); its errors are left to
    the reader."""
    whole = len(head) >= size
    if head[:2] == b"\x1f\x8b":
        stream = zlib.decompressobj(zlib.MAX_WBITS | 16)
        try:
            head = stream.decompress(head, 1 << 16)
        except zlib.error:
            return
        whole, tail = stream.eof and not stream.unused_data, b""  # one member, inflated whole
    gifti_xml(head, whole, tail or None)


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


def annot_header(head: bytes, size: int) -> None:
    """Raise for a FreeSurfer ``.annot`` file of ``size`` bytes starting with ``head`` (its
    first 4 bytes or more) too short for what its header announces: its vertex count
    (big-endian int32, as nibabel's ``read_annot`` reads it), a (vertex, label) pair of
    int32 for each, then its colour table's flag and entry count, int32 each (a text file's
    first bytes read as the count announce gigabytes). The colour table is left to the
    reader: it follows the labels, at the end of the file."""
    count = struct.unpack_from(">i", head)[0] if len(head) >= 4 else -1
    need = 4 + 8 * count + 8
    if count < 0 or size < need:
        raise MeshError("FreeSurfer annotation is truncated, or no annotation (its header "
                        f"announces {max(count, 0)} vertices = {max(need, 12)} bytes before "
                        f"its colour table, the file has {size})")


def overlay_header(p: Path, head: bytes, size: int, tail: bytes = b"") -> None:
    """Raise for an overlay ``p`` of ``size`` bytes starting with ``head`` (and, for a
    GIFTI file, ending with ``tail``: :func:`gifti_header`) whose header its reader cannot
    read."""
    if size == 0:
        raise MeshError("overlay file is empty")
    name = p.name.lower()
    if name.endswith((".gii", ".gii.gz")):
        gifti_header(head, size, tail)
    elif name.endswith(".annot"):
        annot_header(head, size)
    else:
        morph_header(head, size)


def check_overlay(path: str | Path) -> None:
    """Raise the :class:`MeshError` :func:`~surfinpaint.io.brain.read_overlays` raises
    first for the overlay file ``path``, word for word, when it is missing, unreadable,
    empty or its header is bad, from its first 8 KiB (and a GIFTI file's last 4 KiB:
    ``batch``'s pre-flight); not whether it has one value per vertex."""
    p = Path(path)
    with overlay_errors(p), open(p, "rb") as fh:
        head, size = fh.read(1 << 13), os.fstat(fh.fileno()).st_size
        tail = b""
        if len(head) < size and p.name.lower().endswith(".gii"):
            fh.seek(size - GIFTI_TAIL_BYTES)
            tail = fh.read()
        overlay_header(p, head, size, tail)
