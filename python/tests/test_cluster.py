"""tswm.run over the partitions of a lane table on a real Dask cluster
(a LocalCluster of two worker processes), as docs/python.md shows it:
the rows collected equal one run of the whole table, value for value, in
lane order.

`lane` is a row's index within the table tswm.run was given, so each
partition numbers its rows from 0: that column is checked as it comes
from each partition (0 .. rows - 1), then set from the whole table's
index and compared with the rest."""

import os
import sys

import numpy as np
import pyarrow as pa
import pytest

import tswm


def dask_or_skip():
    try:
        import dask.dataframe  # noqa: F401
        import distributed  # noqa: F401
    except ImportError:
        if os.environ.get("CI"):
            pytest.fail('CI: dask is required (.ci/run installs "dask[distributed,dataframe]")')
        pytest.skip('no dask in this Python (pip install "dask[distributed,dataframe]")')


#: The lanes' base: Coulomb friction and a load; the table varies the rest.
BASE = {"base": {"friction": "coulomb", "f2": -4774.0, "t_end": 1.5}}


def drives():
    """2,000 drives: numbers of two types, words (laws), missing cells."""
    import pandas as pd

    rng = np.random.default_rng(36)
    n = 2000
    friction = rng.choice(["coulomb", "paper"], n)
    mu = np.where(friction == "coulomb", rng.uniform(0.02, 0.12, n), np.nan)
    return pd.DataFrame(
        {
            "gamma_deg": rng.uniform(2.0, 30.0, n),
            "f2": rng.integers(-6000, 6000, n),
            "friction": pd.Categorical(friction),
            "mu": mu,
            "motor_off": np.where(rng.random(n) < 0.3, 0.5, np.nan),
        }
    )


def run_part(part):
    """One partition's lanes as tswm.run gives them, `lane` as it comes,
    and the rows' index in the whole table beside it (to compare)."""
    lanes = tswm.run(BASE, lanes=part, backend="cpu", threads=1, progress=False).to_pandas()
    lanes["row"] = part.index
    lanes["worker"] = os.getpid()
    return lanes.set_axis(part.index)


def test_partitions_on_a_dask_cluster_equal_one_run(tmp_path):
    dask_or_skip()
    import cloudpickle
    import dask.dataframe as dd
    from dask.distributed import Client, LocalCluster

    # The workers cannot import this test module: send its functions whole.
    cloudpickle.register_pickle_by_value(sys.modules[__name__])
    table = drives()
    whole = tswm.run(BASE, lanes=table, backend="cpu", progress=False)
    with LocalCluster(
        n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None,
        local_directory=str(tmp_path),
    ) as cluster, Client(cluster) as client:
        workers = client.run(os.getpid)
        assert len(workers) == 2 and os.getpid() not in workers.values()
        parts = dd.from_pandas(table, npartitions=7)
        sizes = parts.map_partitions(len).compute().tolist()
        got = parts.map_partitions(run_part, meta=run_part(table.head(1)).iloc[:0]).compute()
    # Every row ran on a worker process, and the rows come back in order.
    assert set(got["worker"]) <= set(workers.values())
    assert got["row"].tolist() == list(range(len(table)))
    # `lane` as each partition numbers it: its rows from 0.
    assert sum(sizes) == len(table) and len(sizes) == 7
    assert got["lane"].tolist() == [k for n in sizes for k in range(n)]
    # Numbered by the whole table's index, the rows are one run's.
    got["lane"] = got.pop("row")
    got = got.drop(columns="worker")
    assert list(got.columns) == whole.column_names
    assert pa.Table.from_pandas(got, schema=whole.schema, preserve_index=False).equals(whole)
