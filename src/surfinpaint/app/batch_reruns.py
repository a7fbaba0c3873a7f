"""A batch rerun's rows for the files it does not fill again: their outputs are up to date
(:func:`~surfinpaint.app.batch_inputs.up_to_date`), and only an OBJ's material library or
texture may have changed since, which is copied again beside the output without refilling
the mesh (the fill does not read them)."""

from __future__ import annotations

import dataclasses
import os
import warnings
from pathlib import Path

from surfinpaint.app.batch_inputs import FileJob, picture_path
from surfinpaint.app.batch_summary import MESSAGE_SEPARATOR, FileRow, named_in_summary
from surfinpaint.app.progress import named
from surfinpaint.errors import MeshError
from surfinpaint.io.materials import (
    changed_materials,
    copy_materials,
    libraries_of,
    rewrite_recorded_copies,
)

__all__ = ["rerun_row", "skipped_row"]

# How a rerun's note on materials copied again starts: the last part of the row's message,
# followed only by the copies' warnings; a later rerun's row drops them (what it did is new)
_RECOPIED = f"{MESSAGE_SEPARATOR}its materials "


def skipped_row(job: FileJob, earlier: FileRow | None) -> FileRow:
    """The row of a file whose output is up to date, with the counts of the run that wrote
    it when its summary (``earlier``: its row there) has them."""
    note = f"{job.output} is newer than the input: kept (overwrite refills it)"
    if earlier is None or earlier.output != job.output or \
            earlier.status == "failed":
        return FileRow(job.name, job.output, "skipped", message=note,
                       picture=job.picture_output)
    # the picture up to date (with png), else the one an earlier run wrote, if still there
    picture = job.picture_output or (
        earlier.picture if picture_path(job.target).is_file() else None)
    if earlier.status == "skipped":
        return dataclasses.replace(earlier, picture=picture,
                                   message=earlier.message.split(_RECOPIED)[0])
    before = f"; written by an earlier run ({earlier.status}" + \
        (f": {earlier.message})" if earlier.message else ")")
    return dataclasses.replace(earlier, status="skipped", seconds=0.0, message=note + before,
                               picture=picture)


def rerun_row(job: FileJob, earlier: FileRow | None) -> FileRow | None:
    """The row of ``job``, whose output is up to date, in a rerun: skipped
    (:func:`skipped_row`); where a material file an earlier run copied beside the OBJ
    output (:attr:`FileJob.copied`) changed beside the input since, or is gone from beside
    the output, with the materials copied again first
    (:func:`~surfinpaint.io.materials.copy_materials`: a copy the user changed is kept,
    with a warning, which is also raised here) and the new record, in the row and in the
    OBJ output's header (:func:`~surfinpaint.io.materials.rewrite_recorded_copies`, which
    a later ``fill`` into it reads); None when they cannot be (the OBJ unreadable now):
    the file is filled again, which says why."""
    row = skipped_row(job, earlier)
    if not job.copied:
        return row
    try:
        changed = changed_materials(job.source, dict(job.copied),
                                    job.target.stat().st_mtime_ns)
        missing = [relative for relative, _ in job.copied
                   if not (job.target.parent / relative).is_file()]
        if not changed and not missing:
            return row
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            materials = copy_materials(job.source, job.target, libraries_of(job.source),
                                       reserved=(job.picture,) if job.picture else (),
                                       ours=dict(job.copied))
        # the OBJ's own record of its copies, as fill would have written it (session 38:
        # it kept the first run's, so a later fill into it kept the new copies, warned)
        rewrite_recorded_copies(job.target, materials.record)
    except (OSError, MeshError):
        return None
    copied = [(Path(job.output).parent / path.relative_to(job.target.parent)).as_posix()
              for path in materials]
    why = [f"{what} ({', '.join(files)})" for what, files in (
        ("changed beside the input", changed), ("missing beside the output", missing))
        if files]
    message = f"{row.message}{_RECOPIED}{' and '.join(why)}: " + (
        f"copied again ({', '.join(copied)}), the mesh not refilled" if copied
        else "none copied again")
    # said as batch says a filled file's: the input, and the output where it is written
    written = {named_in_summary(job, os.fspath(job.target)): "writing"}
    for caught_warning in caught:
        text = named_in_summary(job, str(caught_warning.message))
        warnings.warn(named(text, job.name, written), caught_warning.category, stacklevel=2)
        message += f"{MESSAGE_SEPARATOR}{text}"
    return dataclasses.replace(row, message=message, materials=materials.record)
