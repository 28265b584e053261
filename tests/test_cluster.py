"""Design studies on dask: batches on a LocalCluster of two worker processes written to a Zarr
store, bit-identical to the in-memory call, and an interrupted run resumed."""

import numpy as np
import pytest

pytest.importorskip("dask.distributed")
pytest.importorskip("zarr")

from dask.distributed import LocalCluster  # noqa: E402

import planar  # noqa: E402
from planar import cluster  # noqa: E402
from planar.mechanisms import four_bar  # noqa: E402

TH = np.radians(np.arange(0.0, 360.0, 15.0))
FIXED = dict(ground=4.0, rocker=3.0, coupler_point=(1.0, 0.5))
# regular crank-rockers, a triple rocker (limits: swept alone) and one that does not assemble
DESIGNS = {"crank": [1.0, 1.1, 3.0, 1.2, 2.0, 0.9, 1.3], "coupler": [3.5, 3.4, 3.0, 3.6, 0.5, 3.5, 3.3]}


class Stop(Exception):
    pass


def _compare(stored, study):
    for k in cluster.ARRAYS:
        np.testing.assert_array_equal(stored[k], getattr(study, k), err_msg=k)
    np.testing.assert_array_equal(stored["position/C"], study.position("C"))
    np.testing.assert_array_equal(stored["batched"], study.batched)
    assert stored["events"].tolist() == [len(e) for e in study.events]
    assert stored["failed"] == {d: e for d, e in enumerate(study.errors) if e is not None}


def test_a_study_on_two_workers_is_the_in_memory_study_and_resumes_after_an_interruption(tmp_path):
    study = planar.sweep_designs(four_bar, DESIGNS, TH, 1.5, fixed=FIXED, batch=2)
    assert study.batched.tolist() == [True, True, False, True, False, True, True]
    store = tmp_path / "study.zarr"
    seen = []

    def interrupt(done, total):
        seen.append((done, total))
        if done == 2:
            raise Stop  # as a run killed after two batches were written

    with pytest.raises(Stop):
        cluster.sweep_designs_to_store(four_bar, DESIGNS, TH, 1.5, store=store, points=("C",), fixed=FIXED, batch=2,
                                       progress=interrupt)
    with pytest.raises(planar.InputError, match="misses 2 of its 4 batches"):
        cluster.load(store)
    written = cluster.zarr.open_group(str(store)).attrs["done"]
    assert len(written) == 2 and seen == [(1, 4), (2, 4)]
    # resumed on a running cluster given by its scheduler's address
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None) as running:
        computed = cluster.sweep_designs_to_store(four_bar, DESIGNS, TH, 1.5, store=store, points=("C",),
                                                  fixed=FIXED, batch=2, cluster=running.scheduler_address,
                                                  progress=lambda done, total: seen.append((done, total)))
    assert sorted(computed) == sorted(set([0, 2, 4, 6]) - set(written))
    assert seen[-1] == (4, 4)
    _compare(cluster.load(store), study)
    # all written: nothing left to compute
    assert cluster.sweep_designs_to_store(four_bar, DESIGNS, TH, 1.5, store=store, points=("C",), fixed=FIXED,
                                          batch=2) == []
    # the same sizes, other values: another study (it was taken as done, the first study's numbers given back)
    with pytest.raises(planar.InputError, match="holds another study"):
        cluster.sweep_designs_to_store(four_bar, DESIGNS, TH + 1.0, 1.5, store=store, points=("C",), fixed=FIXED,
                                       batch=2)


def test_a_store_of_another_study_is_refused(tmp_path):
    store = tmp_path / "study.zarr"
    cluster.zarr.open_group(str(store), mode="a").attrs["study"] = dict(D=3, batch=2, points=[])
    with pytest.raises(planar.InputError, match="holds another study"):
        cluster.sweep_designs_to_store(four_bar, DESIGNS, TH, store=store, fixed=FIXED, batch=2)
    cluster.zarr.open_group(str(tmp_path / "empty.zarr"), mode="a")
    with pytest.raises(planar.InputError, match="no store of a design study"):
        cluster.load(tmp_path / "empty.zarr")
    with pytest.raises(planar.InputError, match="no store at"):
        cluster.load(tmp_path / "none.zarr")


def test_batches_agree_with_one_batch_to_rounding():
    one = planar.sweep_designs(four_bar, DESIGNS, TH, fixed=FIXED)
    two = planar.sweep_designs(four_bar, DESIGNS, TH, fixed=FIXED, batch=2)
    np.testing.assert_array_equal(one.status, two.status)
    np.testing.assert_allclose(one.q, two.q, rtol=0, atol=1e-12)
    with pytest.raises(planar.InputError, match="batch must be"):
        planar.sweep_designs(four_bar, DESIGNS, TH, fixed=FIXED, batch=0)


@pytest.mark.parametrize("kwargs, message", [
    # (each raised by zarr, dask or Python, most after the cluster had started)
    (dict(store="{file}"), "cannot be opened as a study's Zarr folder"),  # (FileExistsError)
    (dict(store="{file}/sub"), "cannot be opened as a study's Zarr folder"),  # (NotADirectoryError)
    (dict(store="a\x00b"), "store must be the path of a folder"),  # (ValueError)
    (dict(store=""), "store must be the path of a folder"),  # (it wrote into the working folder)
    (dict(store=3), "store must be the path of a folder"),  # (a folder named 3)
    (dict(workers=0), "workers must be a whole number from 1 to 256"),  # (returned as if computed)
    (dict(workers=10**9), "workers must be a whole number from 1 to 256"),  # (a MemoryError)
    (dict(progress=5), "progress must be a function"),  # (a TypeError after the first batch)
    (dict(points=5), "points must be a list"),
    (dict(points=[b"C"]), "points must be a list of point names"),  # (the store's attributes: not JSON)
])
def test_bad_store_arguments_are_refused_before_the_cluster_starts(tmp_path, kwargs, message):
    (tmp_path / "file").write_text("x")
    store = kwargs.pop("store", str(tmp_path / "study.zarr"))
    store = store.format(file=tmp_path / "file") if isinstance(store, str) else store
    with pytest.raises(planar.InputError, match=message):
        cluster.sweep_designs_to_store(four_bar, {"crank": [1.0, 1.1]}, TH, store=store, **dict(dict(batch=1, workers=1),
                                                                                                **kwargs))


def test_a_store_that_is_no_study_is_refused_by_load(tmp_path):
    (tmp_path / "file").write_text("x")
    with pytest.raises(planar.InputError, match="no store at"):
        cluster.load(tmp_path / "file")
    group = __import__("zarr").open_group(str(tmp_path / "odd.zarr"), mode="w")
    group.attrs.update(study=5)  # (a TypeError, then KeyErrors for other records)
    with pytest.raises(planar.InputError, match="is no store of a design study"):
        cluster.load(tmp_path / "odd.zarr")


@pytest.mark.parametrize("cluster_arg, message", [
    (3, "cluster must be None .* or a dask Cluster, got 3"),  # (a TypeError)
    ("tcp://127.0.0.1:1", "no dask scheduler answers there"),  # (an OSError)
])
def test_a_cluster_that_is_none_is_refused(tmp_path, cluster_arg, message):
    with pytest.raises(planar.InputError, match=message):
        cluster.sweep_designs_to_store(four_bar, {"crank": [1.0, 1.1]}, TH, store=tmp_path / "s.zarr",
                                       cluster=cluster_arg)


def test_batches_of_other_sizes_or_bodies_are_refused_before_they_are_written(tmp_path):
    from dask.distributed import Client

    def values(design):  # (a later batch of another number of values)
        return TH if design["crank"] < 1.05 else TH[:5]

    def build(crank):  # (a later batch of other bodies)
        return four_bar(crank=crank) if crank < 1.05 else planar.mechanisms.slider_crank(crank=crank)

    with LocalCluster(n_workers=1, processes=False, dashboard_address=None) as local, \
            Client(local) as client:
        for store, (b, v, message) in enumerate([(four_bar, values, r"the designs from [01] give inputs of shape"),
                                                 (build, TH, r"the designs from [01] have bodies .*'(slider|rocker)'\]")]):
            with pytest.raises(planar.InputError, match=message):
                cluster.sweep_designs_to_store(b, {"crank": [1.0, 1.1]}, v, store=tmp_path / f"{store}.zarr",
                                               batch=1, cluster=client, progress=lambda done, total: None)
            with pytest.raises(planar.InputError, match="misses 1 of its 2 batches"):
                cluster.load(tmp_path / f"{store}.zarr")


def test_damaged_records_of_a_store_are_refused(tmp_path):
    store = tmp_path / "s.zarr"
    with LocalCluster(n_workers=1, processes=False, dashboard_address=None) as local:
        cluster.sweep_designs_to_store(four_bar, {"crank": [1.0, 1.1]}, TH, store=store, points=("C",),
                                       fixed=dict(coupler_point=(1.0, 0.5)), cluster=local.scheduler_address,
                                       progress=lambda done, total: None)
    group = cluster.zarr.open_group(str(store), mode="a")
    good = dict(group.attrs)
    assert cluster.load(store)["bodies"] == ["ground", "crank", "coupler", "rocker"]
    # (each was an AttributeError, ValueError, TypeError or KeyError; a study of 1e12 designs hung)
    for key, value, message in [("failed", [1], "records .* are missing or damaged"),
                                ("failed", {"x": "why"}, "records .* are missing or damaged"),
                                ("done", ["a"], "records .* are missing or damaged"),
                                ("study", dict(good["study"], points=3), "records .* are missing or damaged"),
                                ("study", dict(good["study"], batch=True), "records .* are missing or damaged"),
                                ("study", dict(good["study"], D=-5), "records .* are missing or damaged"),
                                ("study", dict(good["study"], points=["Q"]), r"misses the arrays \['position/Q'\]"),
                                ("study", dict(good["study"], D=10**12),
                                 r"misses 499999999999 of its 500000000000 batches \(of designs 2, 4, 6, 8, 10, ...\)")]:
        group.attrs.update(good)
        group.attrs[key] = value
        with pytest.raises(planar.InputError, match=message):
            cluster.load(store)
        if key != "study":
            with pytest.raises(planar.InputError, match=message):
                cluster.sweep_designs_to_store(four_bar, {"crank": [1.0, 1.1]}, TH, store=store, points=("C",),
                                               fixed=dict(coupler_point=(1.0, 0.5)))
