"""Modules that import an optional extra at the top are left out of the doctest collection over
planar/ where that extra cannot be imported (their tests skip themselves)."""

import importlib.util

OPTIONAL = {"planar/cluster.py": ("dask.distributed", "zarr"), "planar/compiled/engine.py": ("numba",),
            "planar/compiled/assembly.py": ("numba",)}


def _importable(name):
    try:
        return importlib.util.find_spec(name) is not None
    except ImportError:
        return False


collect_ignore = [path for path, needs in OPTIONAL.items() if not all(_importable(n) for n in needs)]
