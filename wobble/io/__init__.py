"""Files: the TOML body catalogue, CF netCDF output, Earth-orientation readers."""
