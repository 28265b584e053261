"""The benchmark's ``--quick`` path runs end to end and its numbers are sane; peers that are not
installed are skipped by the benchmark itself (the ``bench`` extra is optional)."""

import importlib.util
import json
import re
import sys
from pathlib import Path

import numpy as np

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"


def _load(name):
    spec = importlib.util.spec_from_file_location(name, BENCH / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


def test_quick_run_prints_every_section_with_small_errors(capsys):
    sweep_speed = _load("sweep_speed")
    sweep_speed.main(["--quick"])
    out = capsys.readouterr().out
    for name in sweep_speed.CASES:
        for engine in sweep_speed.ENGINES:
            assert re.search(rf"^{re.escape(name)}\s+{engine}\s+1000\s", out, re.M), (name, engine)
    assert re.search(r"k =  10: .* all solved: True", out)
    rows = re.findall(r"^planar Model\.sweep (engine=\w+(?: \(1 thread\))?)\s+full\s+(\d+)\s+([\d.]+)\s+[\d.]+\s+(.*)$",
                      out, re.M)
    want = {f"engine={e}" for e in sweep_speed.ENGINES} | ({"engine=numba (1 thread)"} if sweep_speed.numba else set())
    assert {r[0] for r in rows} == want
    rows = [r[1:] for r in rows]
    for _, us, errs in rows:
        assert float(us) > 0
        assert max(float(e) for e in errs.split("|")) < 1e-12
    for peer in sweep_speed.peers.PEERS:
        # a timed row of the side-by-side table starts with the peer's label (its "not
        # comparable" notes are printed whether it is installed or not)
        timed = re.search(rf"^{re.escape(peer.label)}\s+(positions|full)\s+\d+\s", out, re.M)
        assert bool(timed) == sweep_speed.peers.installed(peer), peer.label


def test_peer_errors_show_failed_points():
    peers = _load("peers")
    ref = {"C": np.zeros((3, 2)), "C_vel": np.ones((3, 2))}
    got = {"C": np.array([[0.0, 0.0], [np.nan, 0.0], [0.0, 0.0]]), "C_vel": np.full((3, 2), 1.5)}
    errs = peers.error(ref, got)
    assert np.isnan(errs["C"])
    assert errs["C_vel"] == 0.5 / 2


def test_rounds_alternate_the_runs_and_keep_the_best_of_each():
    sweep_speed = _load("sweep_speed")
    calls = []
    best = sweep_speed.rounds({"a": lambda: calls.append("a"), "b": lambda: calls.append("b")}, 3)
    assert calls == ["a", "b"] * 3
    assert set(best) == {"a", "b"} and all(0 < t < 1 for t in best.values())


def test_targets_print_every_engine_against_the_closed_form_and_the_installed_peers(capsys):
    sweep_speed = _load("sweep_speed")
    sweep_speed.targets([1000, 100_000], 1)
    out = capsys.readouterr().out
    assert "N = 1e+03" not in out  # the targets are at N >= 1e5
    configs = [f"engine={e}" for e in sweep_speed.ENGINES] + (["engine=numba (1 thread)"] if sweep_speed.numba else [])
    for label in configs:
        line = re.search(rf"^  N = 1e\+05, {re.escape(label)}: ([\d.]+) us full, ([\d.]+) us positions; "
                         rf"planar / closed form = ([\d.]+) \(target <= 2\)(.*)$", out, re.M)
        assert line, label
        assert min(float(line[1]), float(line[2]), float(line[3])) > 0
        for peer in sweep_speed.TARGET_PEERS.values():
            installed = sweep_speed.peers.installed(next(p for p in sweep_speed.peers.PEERS if p.label == peer))
            assert (f"/ {peer} = " in line[4]) == installed, (label, peer)


def test_the_fuzz_campaign_writes_a_line_a_sweep_and_sums_them_up(capsys, tmp_path):
    campaign = _load("fuzz_campaign")
    campaign.main(["4", "5", "--kinds", "slider_crank"])  # (its crank rocks: a start next to a limit too)
    lines = capsys.readouterr().out.splitlines()
    recs = [json.loads(line) for line in lines]
    assert [r["scenario"] for r in recs] == list("abcdefg")
    for r in recs:
        assert r["seed"] == 4 and r["kind"] == "slider_crank" and r["error"] is None and r["cpu"] > 0
        assert sum(r["status"].values()) in (30, 40, 180, 181, 210) and "NOT_CONVERGED" not in r["status"]
        assert (r.get("lost"), r.get("extra"), r.get("apart"), r.get("off")) == \
            ((None,) * 3 + (0,) if r["scenario"] == "g" else (0, 0, 0, None))
    # each mechanism's sweeps on one model (it remembers poses): the same statuses
    campaign.main(["4", "5", "--kinds", "slider_crank", "--warm"])
    warm = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert [r["status"] for r in warm] == [r["status"] for r in recs]
    path = tmp_path / "camp.jsonl"
    path.write_text("\n".join(lines) + "\n")
    campaign.main(["--summary", str(path)])
    out = capsys.readouterr().out
    assert out.startswith("7 sweeps, 1 mechanisms") and "lost: 0 sweeps" in out and "off: 0 sweeps" in out


def test_the_fuzz_campaign_counts_a_geared_five_bars_values_past_a_limit_apart_from_its_errors():
    from types import SimpleNamespace as NS
    from planar import Status

    campaign = _load("fuzz_campaign")
    values = np.array([0.0, 1.0, 2.0, 3.0])
    limit = [NS(kind="limit", input=1.5)]
    S, N = Status.SOLVED, Status.NOT_ASSEMBLABLE

    def sweep(status, events):
        return NS(status=np.array(status), inputs=values[:, None], q=np.zeros((4, 3)), events=events)

    # posed here, not in the dense sweep: before the limit an error, past it (both met it) a stretch
    r, ref = sweep([S, S, S, S], limit), sweep([S, N, N, S], limit)
    assert campaign.compare(r, ref, values, 1.0, 0.0, "geared_five_bar") == (0, 1, 1, 0)
    assert campaign.compare(r, ref, values, 1.0, 0.0, "four_bar") == (0, 0, 2, 0)
    # the other way round: lost
    assert campaign.compare(ref, r, values, 1.0, 0.0, "geared_five_bar") == (1, 1, 0, 0)
