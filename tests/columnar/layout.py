"""The layout of a lanes.parquet as pyarrow sees it, one fact a line:
row group sizes, each column chunk's codec, the text columns' encodings
and which column chunks carry a minimum and maximum.
Usage: layout.py PARQUET."""
import sys

import pyarrow.parquet as pq

meta = pq.ParquetFile(sys.argv[1]).metadata
print("row_groups", " ".join(str(meta.row_group(g).num_rows) for g in range(meta.num_row_groups)))
codecs = set()
for g in range(meta.num_row_groups):
    rg = meta.row_group(g)
    for c in range(rg.num_columns):
        col = rg.column(c)
        codecs.add(col.compression)
        if g == 0:
            print(
                "column",
                col.path_in_schema,
                col.physical_type,
                ",".join(sorted(col.encodings)),
                "minmax" if col.statistics is not None and col.statistics.has_min_max else "-",
            )
print("codecs", " ".join(sorted(codecs)))
