"""
Read a reference dataset: the Chapter 3 voltage-stretch curves
==============================================================

The curated datasets are netCDF files read with xarray;
:func:`debench.reference.datasets.read_dataset` verifies the file's sha256 and its
attributes on every read. Each variable says what it is (``long_name``) and its units,
which label the plot. Here: the normalised voltage that holds circle A of the
pre-stretched actuator at a stretch, for two pre-stretches and two values of the
electrostrictive factor c, and the voltage at which the film breaks down.
"""

import matplotlib.pyplot as plt
from debench.reference.datasets import read_dataset

ds = read_dataset("ch3_voltage_stretch_membrane")
print(ds.attrs["title"])
for name in ("lambda_a", "phibar", "phibar_breakdown"):
    print(f"{name}: {ds[name].attrs['long_name']} [{ds[name].attrs['units']}]")

# %%
# The curves are stored on a common point index per pre-stretch ``lamP``; the
# abscissa is ``lambda_a`` (the stretch of circle A).
fig, ax = plt.subplots(figsize=(6, 4), layout="constrained")
for lamP, color in ((1.25, "tab:blue"), (3.0, "tab:orange")):
    cur = ds.sel(lamP=lamP)
    for c, ls in ((0.0, "-"), (-0.053, "--")):
        ax.plot(cur["lambda_a"], cur["phibar"].sel(c=c), ls, color=color,
                label=f"lamP = {lamP}, c = {c}")
    ax.plot(cur["lambda_a"], cur["phibar_breakdown"], ":", color=color,
            label=f"lamP = {lamP}, breakdown")
ax.set_xlabel(f"{ds['lambda_a'].attrs['long_name']} [{ds['lambda_a'].attrs['units']}]")
ax.set_ylabel("normalised voltage phibar [1]")
ax.set_ylim(0, 1.0)
ax.legend(fontsize=8)
plt.show()
