"""Studies beyond memory and beyond one machine: :func:`planar.sweep_designs` in batches of
designs on a dask cluster, each batch written to a Zarr store as it finishes.

Needs the ``dask`` extra (dask.distributed and zarr), imported only here. The cluster is a
LocalCluster on this machine (127.0.0.1, worker processes) made for the call, or any running
dask cluster given by its scheduler's address (or a ``distributed.Client``). Each batch is one
task: its designs are built, compiled and swept on a worker exactly as the in-memory call
sweeps that batch (so the store is bit-identical to ``sweep_designs(..., batch=batch)``), and
the client writes it to the store when it arrives. The store records the batches written; a
call on a store that holds some batches of the same study computes only the missing ones, so
an interrupted run resumes where it stopped. Memory: two batches are in flight per worker
thread (submitted as others finish), and the client holds one batch's results at a time.

Store layout (a Zarr group): the :class:`planar.DesignSweep` arrays ``inputs`` (D, N, f),
``q``, ``qd``, ``qdd`` (D, N, n), ``status``, ``residual``, ``iterations``, ``singularity``,
``branch``, ``gap`` (D, N); ``batched`` and ``events`` (the number of events met) per design;
``position/NAME`` (D, N, 2) for each of ``points``; and in its attributes the study (D, batch,
points, and a digest of the builder, designs, values, rates, fixed parameters and options: the
same study is the same digest), the batches written, the designs that could not be built, with why,
and the bodies whose coordinates ``q`` holds (three each after the ground).
"""

import hashlib
import itertools
import os
import warnings

import numpy as np
import zarr
from dask.distributed import Client, LocalCluster, as_completed
from distributed.deploy import Cluster

from planar.designs import BATCH, check_fixed, design_table, join, study_options, sweep_part, values_of
from planar.errors import InputError
from planar.progress import Progress
from planar.results import Status

ARRAYS = ("inputs", "q", "qd", "qdd", "status", "residual", "iterations", "singularity", "branch", "gap")
# what a design that could not be built holds: NaN, status NOT_ASSEMBLABLE, no iterations or events
FILL = {"status": int(Status.NOT_ASSEMBLABLE)}


def _digest(build, table, values, *rest):
    """A fingerprint of what the study computes (the builder's name, the designs, their values
    (for a function, those of the first and last design), rates, fixed parameters and options):
    a store of another study with the same sizes is refused, not taken as done."""
    # (a Vary by its class and numbers: its repr holds an address, another in each process)
    name = getattr(build, "__qualname__", None) or (type(build).__qualname__, getattr(build, "numbers", None))
    given = [values_of(values, table[d], d, 1) for d in (0, len(table) - 1)] if callable(values) else [values]
    h = hashlib.sha256()
    _feed(h, (name, table, rest, given))
    return h.hexdigest()


def _feed(h, x):
    """Feed ``x`` to the hash ``h``: an array by its bytes (its repr elides), a container item
    by item, anything else by its repr."""
    if isinstance(x, (np.ndarray, np.generic)) and np.asarray(x).dtype != object:
        a = np.ascontiguousarray(x)
        h.update(f"{a.dtype.str}{a.shape}".encode() + a.tobytes())
    elif isinstance(x, (dict, list, tuple, np.ndarray)):
        h.update(type(x).__name__.encode())
        for item in (x.items() if isinstance(x, dict) else x):
            _feed(h, item)
        h.update(b")")
    else:
        h.update(repr(x).encode() + b",")


def sweep_designs_to_store(build, designs, values, velocity=1.0, acceleration=0.0, *, store, points=(),
                           fixed=None, batch=BATCH, cluster=None, workers=2, progress=None, **options):
    """Sweep the designs as :func:`planar.sweep_designs` does, ``batch`` designs per dask task,
    writing each batch to the Zarr ``store`` (a path) as it finishes; batches the store holds
    already are not computed again. ``points``: names of points whose positions are stored.
    ``cluster``: None (a LocalCluster of ``workers`` processes on 127.0.0.1 for this call), the
    address of a running scheduler, or a ``distributed.Client``. ``progress(done, total)`` is
    called after each batch written (default: a bar on a terminal). Returns the batches'
    first design indices computed by this call.
    """
    table = design_table(designs)
    options = study_options(batch, options)
    check_fixed(fixed, table)
    if isinstance(points, str) or not all(isinstance(p, str) for p in _listed(points, "points")):
        raise InputError(f"points must be a list of point names, got {points!r}")
    points = tuple(points)
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or not 1 <= workers <= MAX_WORKERS:
        raise InputError(f"workers must be a whole number from 1 to {MAX_WORKERS} (processes of the LocalCluster "
                         f"made for the call), got {workers!r}")
    if cluster is not None and not isinstance(cluster, (str, Client, Cluster)):
        raise InputError(f"cluster must be None (a LocalCluster for the call), a scheduler's address such as "
                         f"'tcp://10.0.0.5:8786', a distributed.Client or a dask Cluster, got {cluster!r}")
    if progress is not None and not callable(progress):
        raise InputError(f"progress must be a function progress(done, total) or None, got {progress!r}")
    D = len(table)
    batch = min(int(batch), D)  # (the store's chunks: a batch larger than the study is the study)
    study = dict(D=D, batch=batch, points=list(points),
                 digest=_digest(build, table, values, velocity, acceleration, fixed, options))
    group = _open(store, "a")
    if "study" in group.attrs and group.attrs["study"] != study:
        raise InputError(f"store {store} holds another study {group.attrs['study']}, not {study}: give a new "
                         "store, or delete this one")
    _, done, failed = _records(group, store) if "study" in group.attrs else (study, [], {})
    group.attrs.update(study=study, done=done, failed=failed)
    todo = [lo for lo in range(0, D, batch) if lo not in set(group.attrs["done"])]
    total = -(-D // batch)
    report = progress or Progress("design batches")
    if not todo:
        return []
    with _client(cluster, workers) as client:
        def submit(lo):
            return client.submit(_batch_record, build, {d: table[d] for d in range(lo, min(lo + batch, D))}, lo,
                                 values, velocity, acceleration, fixed, options, points, pure=False)

        # two batches in flight per worker thread: the cluster holds no more results than that
        waiting = iter(todo)
        running = as_completed([submit(lo) for lo in itertools.islice(waiting, 2 * sum(client.nthreads().values()))])
        for job in running:
            lo, record = job.result()
            job.release()
            _write(group, lo, record, D, batch)
            report(len(group.attrs["done"]), total)
            for lo in itertools.islice(waiting, 1):
                running.add(submit(lo))
    return todo


MAX_WORKERS = 256  # processes of a LocalCluster made for a call


def _listed(value, what):
    try:
        return list(value)
    except TypeError:
        raise InputError(f"{what} must be a list, got {value!r}") from None


def _open(store, mode):
    """The Zarr group at ``store`` (a path), or an InputError naming it: a file, a folder that
    cannot be made or read, a store of other contents."""
    if not isinstance(store, (str, os.PathLike)) or not str(store) or "\x00" in str(store):
        raise InputError(f"store must be the path of a folder for the study (no NUL byte), got {store!r}")
    try:
        with warnings.catch_warnings():  # (zarr's note on files of other kinds in the folder: not the study's)
            warnings.simplefilter("ignore", UserWarning)
            return zarr.open_group(str(store), mode=mode)
    except FileNotFoundError:
        raise InputError(f"no store at {store}: give the path a study was written to") from None
    except (OSError, ValueError, TypeError, ImportError) as e:  # (a file, an array, unreadable metadata, a URL)
        raise InputError(f"store {store} cannot be opened as a study's Zarr folder ({type(e).__name__}: {e}): "
                         f"give a new folder, or the one a study was written to") from None


class _client:
    """The dask client of a call: a LocalCluster made for it, or the cluster given."""

    def __init__(self, cluster, workers):
        self.cluster, self.workers, self.own = cluster, workers, []

    def __enter__(self):
        if isinstance(self.cluster, Client):
            return self.cluster
        if self.cluster is None:
            local = LocalCluster(n_workers=self.workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                                 dashboard_address=None)
            self.own.append(local)
            self.cluster = local
        try:
            client = Client(self.cluster)
        except OSError as e:  # (no scheduler there, or none that answers)
            raise InputError(f"cluster {self.cluster!r}: no dask scheduler answers there ({e}): start one, or give "
                             "cluster=None for a LocalCluster on this machine") from None
        self.own.insert(0, client)
        return client

    def __exit__(self, *exc):
        for thing in self.own:
            thing.close()


def _batch_record(build, designs, lo, values, velocity, acceleration, fixed, options, points):
    """(lo, arrays) of one batch, computed on a worker: the study's arrays, point positions,
    per design ``batched``, the number of ``events`` and the ``failed`` designs' reasons."""
    hi = lo + len(designs)
    part = sweep_part(build, designs, lo, hi, values, velocity, acceleration, fixed, options)
    record = {"failed": {str(lo + k): e for k, e in enumerate(part.errors) if e is not None}}
    if part.out is None:
        return lo, record
    study = join([designs[d] for d in range(lo, hi)], [part], lo)
    record.update({k: getattr(study, k) for k in ARRAYS}, bodies=list(study.template.body_names))
    record["batched"] = study.batched
    record["events"] = np.array([len(e) for e in study.events])
    for name in points:
        record[f"position/{name}"] = study.position(name)
    return lo, record


def _write(group, lo, record, D, batch):
    """Write one batch's arrays (creating the store's arrays at the first), then mark it done;
    a batch whose arrays are of other sizes than the store's is refused before any is written."""
    arrays = {k: a for k, a in record.items() if k not in ("failed", "bodies")}
    if "bodies" in record and group.attrs.get("bodies", record["bodies"]) != record["bodies"]:
        raise InputError(f"the designs from {lo} have bodies {record['bodies']}, the study's first "
                         f"{group.attrs['bodies']}: a study sweeps designs of one structure")
    for key, a in arrays.items():
        if key in group and group[key].shape[1:] != a.shape[1:]:
            raise InputError(f"the designs from {lo} give {key} of shape {a.shape[1:]} each, the study's first "
                             f"{group[key].shape[1:]}: a study sweeps designs of one structure over one number of "
                             "values (check what the values function returns)")
    for key, a in arrays.items():
        if key not in group:
            fill = FILL.get(key, np.nan if a.dtype.kind == "f" else a.dtype.type(0))
            group.create_array(key, shape=(D,) + a.shape[1:], chunks=(batch,) + a.shape[1:], dtype=a.dtype,
                               fill_value=fill)
        group[key][lo : lo + len(a)] = a
    group.attrs.update(failed=dict(group.attrs["failed"], **record["failed"]), done=sorted(group.attrs["done"] + [lo]),
                       **({"bodies": record["bodies"]} if "bodies" in record else {}))


def _records(group, store):
    """The store's records (study, done, failed), each checked: a damaged one is refused."""
    study, done, failed = (group.attrs.get(k) for k in ("study", "done", "failed"))
    whole = lambda v: type(v) is int  # noqa: E731 (JSON's whole numbers; a bool is none)
    ok = (isinstance(study, dict) and whole(study.get("D")) and whole(study.get("batch")) and study["D"] > 0
          and study["batch"] > 0 and isinstance(study.get("points"), list)
          and all(isinstance(p, str) for p in study["points"]) and isinstance(study.get("digest"), str)
          and isinstance(done, list) and all(whole(lo) and 0 <= lo < study["D"] and lo % study["batch"] == 0
                                             for lo in done)
          and isinstance(failed, dict) and all(k.isdigit() and isinstance(v, str) for k, v in failed.items()))
    if not ok:
        raise InputError(f"{store} is no store of a design study (its records 'study', 'done' or 'failed' are "
                         f"missing or damaged: {repr(study)[:200]}): give the path a study was written to, or "
                         "delete this one")
    return study, sorted(set(done)), failed


def load(store):
    """The study in ``store``: a dict of numpy arrays (the names of the layout above),
    ``failed`` {design index: why}, ``done`` (the first design of each batch written) and
    ``bodies`` (their names, None where no design could be built).
    Raises :class:`planar.InputError` while batches are missing."""
    group = _open(store, "r")
    study, done, failed = _records(group, store)
    total = -(-study["D"] // study["batch"])
    if len(done) < total:  # (the first missing are among the first len(done) + 5 batches)
        written = set(done)
        missing = [lo for lo in itertools.islice(range(0, study["D"], study["batch"]), len(done) + 5)
                   if lo not in written][:5]
        raise InputError(f"store {store} misses {total - len(done)} of its {total} batches (of designs "
                         f"{', '.join(map(str, missing))}{', ...' if total - len(done) > 5 else ''}): run the study "
                         "again on it to compute them")
    names = ["position/" + p for p in study["points"]]
    with warnings.catch_warnings():  # (as in _open)
        warnings.simplefilter("ignore", UserWarning)
        keys = set(group.array_keys())  # (none where no design could be built)
        lost = sorted((set(ARRAYS) | set(names)) - keys - {n for n in names if n in group}) if keys else []
        if lost:
            raise InputError(f"store {store} misses the arrays {lost} of its study: run the study again into a "
                             "new store")
        out = {k: group[k][:] for k in [*sorted(keys), *(names if keys else ())]}
    out.update(failed={int(k): v for k, v in failed.items()}, done=done, bodies=group.attrs.get("bodies"))
    return out
