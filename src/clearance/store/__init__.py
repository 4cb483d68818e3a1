"""Store: `Result`, everything a simulation produced, with names for every column, and the
declaration of its output channels. File formats (NetCDF, CSV, MAT) are in `clearance.io`."""
