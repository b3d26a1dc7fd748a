#!/usr/bin/env python3
"""Writes the NetCDF trajectory cases of tests/data/loaders/nc (run from that
folder with Debian's python3-scipy; NetCDF-3 classic files). The files are
committed; this script documents how they were made."""
import numpy as np
from scipy.io import netcdf_file

FILL = -999.0


def write(path, dims, shape, variables, dtype="f4"):
    with netcdf_file(path, "w") as f:
        for name, n in zip(dims, shape):
            f.createDimension(name, n)
        for name, (data, attrs) in variables.items():
            v = f.createVariable(name, dtype, dims if np.ndim(data) == len(dims) else dims[-1:])
            v[:] = data
            for k, val in attrs.items():
                setattr(v, k, val)


# Three trajectories of four steps: the second ends at a missing pressure after
# two steps, the third after one (dropped).
lon = np.array([[0, 1, 2, 3], [10, 11, 12, 13], [20, 21, 22, 23]], "f4")
lat = np.array([[50, 50, 51, 51], [40, 41, 42, 43], [30, 30, 30, 30]], "f4")
p = np.array([[1000, 900, 800, 700], [500, 400, FILL, 300], [850, FILL, 850, 850]], "f4")
temp = np.array([[280, 275, 270, 265], [250, 245, 240, 235], [1, 2, 3, 4]], "f4")
write("valid/trajectories.nc", ("trajectory", "time"), (3, 4),
      {"lon": (lon, {}), "lat": (lat, {}), "pressure": (p, {"_FillValue": FILL, "units": "hPa"}),
       "temperature": (temp, {}), "time": (np.arange(4, dtype="f4"), {})})
# Met.3D: (ensemble, trajectory, time), pressure in Pa.
write("valid/met3d.nc", ("ensemble", "trajectory", "time"), (2, 2, 3),
      {"lon": (np.arange(12, dtype="f4").reshape(2, 2, 3), {}),
       "lat": (np.full((2, 2, 3), 45, "f4"), {}),
       "pressure": (np.full((2, 2, 3), 101325, "f4"), {"units": "Pa"}),
       "PV": (np.ones((2, 2, 3), "f4"), {})})
with open("invalid/not_netcdf.nc", "w") as f:
    f.write("CDF but not really\n")
with open("invalid/text.nc", "w") as f:
    f.write("lon,lat,pressure\n")
write("invalid/no_pressure.nc", ("trajectory", "time"), (3, 4), {"lon": (lon, {}), "lat": (lat, {})})
write("invalid/wrong_dims.nc", ("particle", "time"), (3, 4),
      {"lon": (lon, {}), "lat": (lat, {}), "pressure": (p, {})})
write("invalid/all_missing.nc", ("trajectory", "time"), (3, 4),
      {"lon": (lon, {}), "lat": (lat, {}), "pressure": (np.full((3, 4), FILL, "f4"), {"_FillValue": FILL})})
with open("invalid/truncated.nc", "wb") as f:
    f.write(open("valid/trajectories.nc", "rb").read()[:300])
