"""same_vdb.py A.vdb B.vdb: whether two .vdb files hold the same probes, grid by grid
(irradiance, validity, stderr), bit for bit, read by pyopenvdb (Debian's python3)."""
import sys

import pyopenvdb as vdb


def values(path, name):
    return sorted((tuple(v.min), v.value) for v in vdb.read(path, name).citerOnValues())


for name in ("irradiance", "validity", "stderr"):
    a, b = values(sys.argv[1], name), values(sys.argv[2], name)
    print(name, len(a), "probes,", "the same bits" if a == b else "DIFFERENT")
