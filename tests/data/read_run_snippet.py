import pandas as pd, polars as pl, duckdb
run = "data/explore_highway_fleet_seed2014"
rows = pd.read_parquet(run)                                   # pandas skips the _-named files
rows_pl = pl.read_parquet(f"{run}/chunk-*.parquet")           # polars reads the chunks by name
rows_db = duckdb.sql(f"select * from '{run}/chunk-*.parquet'").df()   # duckdb: the same glob
