"""lanes.parquet read by pyarrow equals lanes.csv read by pyarrow's CSV
reader: the same columns and types, floats bit for bit, nulls where the
CSV cell is empty (text columns too, which Parquet's Arrow schema gives
as dictionary columns of strings with int16 keys). Usage: same_values.py
PARQUET CSV."""
import sys

import pyarrow as pa
import pyarrow.csv as pcsv
import pyarrow.parquet as pq

parquet, csv = sys.argv[1], sys.argv[2]
p = pq.read_table(parquet)
WORDS = pa.dictionary(pa.int16(), pa.string())
# The CSV reader takes the words as strings: the dictionary's values.
types = {f.name: pa.string() if f.type == WORDS else f.type for f in p.schema}
c = pcsv.read_csv(
    csv,
    convert_options=pcsv.ConvertOptions(
        column_types=types, strings_can_be_null=True, quoted_strings_can_be_null=True
    ),
)
assert p.column_names == c.column_names, (p.column_names, c.column_names)
for f in p.schema:
    assert f.type in (pa.float64(), pa.int64(), WORDS), (f.name, f.type)
    assert c.schema.field(f.name).type == types[f.name], f.name
    a, b = p.column(f.name).combine_chunks(), c.column(f.name).combine_chunks()
    if f.type == WORDS:
        a = a.cast(pa.string())
    assert a.null_count == b.null_count, (f.name, a.null_count, b.null_count)
    assert a.is_null().equals(b.is_null()), f.name
    if f.type == pa.float64():
        # Bit for bit: compare the values' bits where present.
        ab = a.fill_null(0.0).to_numpy().view("u8")
        bb = b.fill_null(0.0).to_numpy().view("u8")
        assert (ab == bb).all(), f.name
    else:
        assert a.equals(b), f.name
print(f"{p.num_rows} rows, {p.num_columns} columns equal")
