lon,lat,pressure
