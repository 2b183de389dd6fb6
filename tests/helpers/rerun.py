"""Reading a rerun recording back with the SDK (``pip install 'vslsp[rerun]'``)."""

from __future__ import annotations

import pyarrow as pa
from rerun.chunk import RrdReader


def rows(path) -> dict[str, list[dict]]:
    """Entity path -> its rows (each a column name -> value; ``sim_time`` in nanoseconds), static
    rows left out."""
    found: dict[str, list[dict]] = {}
    for chunk in RrdReader(path).stream().to_chunks():
        if chunk.is_static:
            continue
        batch = chunk.to_record_batch()
        columns = {
            name: (column.cast(pa.int64()) if pa.types.is_duration(column.type) else column).to_pylist()
            for name, column in zip(batch.schema.names, batch.columns)
        }
        found.setdefault(chunk.entity_path, []).extend(dict(zip(columns, values)) for values in zip(*columns.values()))
    return found
