import pandas as pd, numpy as np
df = pd.read_parquet("data/explore_highway_fleet_seed2014")          # every chunk file at once
df = df[df["class"].isin(["stable", "limit_cycle", "bistable"])]    # classified rows only
df["vibrates"] = df["class"].isin(["limit_cycle", "bistable"])
g = df.groupby(["variant", "wheel"])["vibrates"].agg(["sum", "count"])
z, p, n = 1.959963984540054, g["sum"] / g["count"], g["count"]
centre = (p + z**2 / (2 * n)) / (1 + z**2 / n)                      # Wilson 95% interval
half = z / (1 + z**2 / n) * np.sqrt(p * (1 - p) / n + z**2 / (4 * n**2))
print(pd.DataFrame({"p": p, "lo": centre - half, "hi": centre + half}))
pair = df.pivot(index=["variant", "sample_id"], columns="wheel", values="vibrates")
print(pd.crosstab(pair["follower"], pair["driving"]))                # McNemar's 2x2 table
