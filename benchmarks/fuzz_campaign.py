"""A fuzz campaign of sweeps as users and scripts drive them (docs/hardening.md): each seed one
random catalogue mechanism (dimensions 0.3-3 times the builder's defaults, random flags and
start), swept in six scenarios

    a  181 values monotone over 3 rad up or down from the start
    b  181 values shuffled over +-4 rad
    c  20 near values, then 10 far ones at 1e2..1e6 rad
    d  60 values asked three times each, shuffled
    e  a turn in 0.035 rad steps, then 30 values jumping over +-20 rad
    f  from a start 1e-9..1e-2 inside an end of the motion range, 181 values across it
    g  40 tracker moves (drags of up to 0.06 rad, steps of up to 0.5, jumps within 7 rad of the
       start) on a model that knows no pose, has swept a turn, or 30 values within 4 rad

and each sweep's values within 25 rad of the start against a dense sweep of them (their sorted
union with a 0.02 rad grid, on a fresh model; with --warm, every sweep of a mechanism on one
model, which remembers the poses it solved). One JSON line a sweep: the seed, the mechanism,
the scenario, its CPU seconds and count of each status, and the values it disagrees with the
dense sweep on: ``lost`` (the dense sweep poses them, this one does not), ``extra`` (the
other way) and ``apart`` (both posed, neither ``JUMPED``, a coordinate more than 1e-8 L apart,
an angle times L, up to whole turns). On a geared five-bar, whose loop closes in the
branch's modes on many stretches (its crank has no period), a value that both sweeps reach
only past a limit they meet between the start and it is counted ``past`` where it would be
lost, extra or apart: which stretch a search past a gap enters depends on the values asked
(docs/sweeps.md, events). Each move of g is checked against the sweep of its value alone on a
fresh model, as a move promises (statuses, event kinds, poses to 1e-10 L): ``off`` counts the
moves that differ (``past``, on a geared five-bar, where both met a limit between the start
and the value).

    python3 benchmarks/fuzz_campaign.py 0 50 > camp.jsonl            # seeds 0-49, numpy
    python3 benchmarks/fuzz_campaign.py 0 50 --kinds watt_six_bar --engine numba
    python3 benchmarks/fuzz_campaign.py 0 50 --warm                  # as a script sweeping one model
    python3 benchmarks/fuzz_campaign.py --summary camp.jsonl          # counts, slowest sweeps
"""

import argparse
import inspect
import json
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import planar  # noqa: E402
from planar.analysis import motion_range  # noqa: E402
from planar import Status  # noqa: E402
from planar.mechanisms import CATALOGUE  # noqa: E402
from planar.results import POSED  # noqa: E402

KINDS = ("four_bar", "slider_crank", "watt_six_bar", "stephenson_six_bar", "geared_five_bar", "gear_train",
         "planetary_gear_train", "inverted_slider_crank", "two_loop_six_bar")
NEAR = 25.0  # values this close to the start are checked against the dense sweep
WARM = False


def mechanism(kind, rng):
    """(one random mechanism of ``kind``, its builder's arguments): the builder's numeric
    defaults each scaled by 0.3-3, booleans drawn, a random start; None where the builder
    refuses the draw."""
    build = CATALOGUE[kind]
    kw = {}
    for name, p in inspect.signature(build).parameters.items():
        d = p.default
        if name in ("name", "driver", "fixed", "planets") or d is inspect.Parameter.empty:
            continue
        if isinstance(d, bool):
            kw[name] = bool(rng.integers(2))
        elif name in ("start", "frame_angle", "frame_angle_2", "slide_angle", "rack_angle", "phase"):
            kw[name] = float(rng.uniform(-np.pi, np.pi))
        elif isinstance(d, (int, float)):
            kw[name] = float(d * rng.uniform(0.3, 3.0)) if d else float(rng.uniform(-1, 1))
        elif isinstance(d, tuple):
            kw[name] = tuple(float(v * rng.uniform(0.3, 3.0)) for v in d)
    try:
        return build(**kw), kw
    except planar.PlanarError:
        return None, kw


def scenarios(u0, rng):
    """The values of scenarios a-e around the start u0."""
    way = 1 if rng.integers(2) else -1
    near = u0 + rng.uniform(-1, 1, 20)
    far = rng.choice([-1, 1], 10) * 10 ** rng.uniform(2, 6, 10)
    d = np.repeat(u0 + rng.uniform(-3, 3, 60), 3)
    rng.shuffle(d)
    return {"a": u0 + way * np.linspace(0, 3, 181), "b": rng.permutation(u0 + rng.uniform(-4, 4, 181)),
            "c": np.concatenate([near, far]), "d": d,
            "e": np.concatenate([u0 + way * np.arange(0, 2 * np.pi, 0.035), u0 + rng.uniform(-20, 20, 30)])}


def near_end(kind, kw, rng):
    """Scenario f: the builder's arguments with the start 1e-9..1e-2 inside an end of the
    motion range, and 181 values from there across the range; None where it has no end."""
    build = CATALOGUE[kind]
    try:
        ranges = motion_range(build(**kw))
    except planar.PlanarError:
        return None
    ends = [(lo, hi) for lo, hi in ranges if hi - lo < 2 * np.pi - 1e-9]
    if not ends:
        return None
    lo, hi = ends[rng.integers(len(ends))]
    inside = 10 ** rng.uniform(-9, -2)
    up = bool(rng.integers(2))
    start = lo + inside if up else hi - inside
    try:
        build(**dict(kw, start=float(start)))
    except planar.PlanarError:
        return None
    return dict(kw, start=float(start)), start + (1 if up else -1) * np.linspace(0, (hi - lo) * 1.3, 181)


def compare(r, ref, values, L, u0, kind):
    """Lost, past, extra and apart values of sweep r from the start u0 against the dense sweep
    ref (values: ref's)."""
    posed = POSED[np.asarray(r.status)]
    u = np.asarray(r.inputs)[:, 0]
    k = np.searchsorted(values, u)
    ok = (k < values.size) & (np.abs(values[np.minimum(k, values.size - 1)] - u) == 0)
    k = np.minimum(k, values.size - 1)
    ref_posed = POSED[np.asarray(ref.status)][k] & ok
    lost = ok & ref_posed & ~posed
    extra = ok & ~ref_posed & posed
    # (a value JUMPED to is on the branch but not shown continuous with the one before: its
    # pose may be another circuit's, a geared linkage's arm some turns on)
    jumped = (np.asarray(r.status) == Status.JUMPED) | (np.asarray(ref.status)[k] == Status.JUMPED)
    apart = ok & ref_posed & posed & ~jumped
    if apart.any():
        d = np.asarray(r.q)[apart] - np.asarray(ref.q)[k[apart]]
        angle = np.arange(d.shape[1]) % 3 == 2  # (angles by their sines and cosines, a turn more or less alike)
        d[:, angle] = np.angle(np.exp(1j * d[:, angle])) * L
        apart[apart] = np.nanmax(np.abs(d), axis=1) > 1e-8 * L
    past = np.zeros_like(lost)
    if kind in MANY_STRETCHES:
        past = (lost | extra | apart) & _past_limits(r, u, u0) & _past_limits(ref, u, u0)
    return (int((lost & ~past).sum()), int(past.sum()), int((extra & ~past).sum()),
            int((apart & ~past).sum()))


MANY_STRETCHES = ("geared_five_bar",)


def _past_limits(r, u, u0):
    """(N,) whether sweep r met a limit between the start u0 and each value u."""
    at = np.array([e.input for e in r.events if e.kind == "limit"])
    return np.array([bool(np.any((at > min(x, u0)) & (at < max(x, u0)))) for x in u], bool)


MODELS = {}  # with --warm: one model per mechanism, as a user's script sweeps it again and again


def sweep(kind, kw, values, engine):
    """(the sweep or None, its CPU seconds, the error's class name or None) on a fresh model
    (a Mechanism's compile() is kept, and a model remembers the poses it solved), or with
    --warm on the mechanism's model of the sweeps before."""
    key = json.dumps([kind, kw])
    model = MODELS.get(key) or CATALOGUE[kind](**kw).compile()
    if WARM:
        MODELS.clear()
        MODELS[key] = model
    t = time.process_time()
    try:
        r = model.sweep(values, engine=engine)
    except planar.PlanarError as e:
        return None, time.process_time() - t, type(e).__name__
    return r, time.process_time() - t, None


def moves(kind, kw, u0, rng, engine):
    """Scenario g: (its record's fields, the moves that differ from the sweep of their value
    alone on a fresh model: (move, value, why), at most three)."""
    model = CATALOGUE[kind](**kw).compile()
    warm = int(rng.integers(3))
    if warm == 1:
        model.sweep(u0 + np.linspace(0, 2 * np.pi * rng.choice([-1, 1]), 60), engine=engine)
    elif warm == 2:
        model.sweep(u0 + rng.uniform(-4, 4, 30), engine=engine)
    tracker = model.track(engine=engine)
    L = max(1.0, float(model.L))
    u, cpu, status, off, past = u0, 0.0, [], [], 0
    for k in range(40):
        kind_of_move = rng.random()
        u = float(u + rng.uniform(-0.06, 0.06) if kind_of_move < 0.6 else u0 + rng.uniform(-7, 7)
                  if kind_of_move < 0.8 else u + rng.uniform(-0.5, 0.5))
        t = time.process_time()
        try:
            got = tracker.move(u)
        except planar.PlanarError as e:
            off.append((k, u, type(e).__name__))
            continue
        finally:
            cpu += time.process_time() - t
        want = CATALOGUE[kind](**kw).compile().sweep([u], engine=engine)
        status.append(int(got.status[0]))
        why = (f"status {got.status[0]} against {want.status[0]}" if got.status[0] != want.status[0] else
               "events" if [e.kind for e in got.events] != [e.kind for e in want.events] else
               "pose" if not np.allclose(got.q, want.q, atol=1e-10 * L, rtol=0, equal_nan=True) else None)
        if why and kind in MANY_STRETCHES and all(_past_limits(res, [u], u0)[0] for res in (got, want)):
            past += 1
        elif why:
            off.append((k, u, why))
        if len(off) > 3:
            break
    st, counts = np.unique(status, return_counts=True)
    return dict(warm=warm, cpu=round(cpu, 3), status={Status(s).name: int(c) for s, c in zip(st, counts)},
                off=len(off), past=past, first=off[:3])


def run_seed(seed, kinds, engine, out):
    rng = np.random.default_rng(seed)
    kind = kinds[seed % len(kinds)]
    for _ in range(100):  # (a draw that does not assemble at its start: the next)
        m, kw = mechanism(kind, rng)
        if m is not None:
            break
    else:
        return
    u0 = float(m.compile().u0[0])
    work = {k: (kw, v) for k, v in scenarios(u0, rng).items()}
    f = near_end(kind, kw, rng) if kind not in ("gear_train", "planetary_gear_train") else None
    if f is not None:
        work["f"] = f
    for name, (args, values) in work.items():
        r, cpu, err = sweep(kind, args, values, engine)
        rec = dict(seed=seed, kind=kind, kw=kw, scenario=name, engine=engine, cpu=round(cpu, 3), error=err)
        if r is not None:
            st = np.asarray(r.status)
            rec["status"] = {Status(s).name: int(c) for s, c in zip(*np.unique(st, return_counts=True))}
            u = np.asarray(values, float)
            close = np.abs(u - float(r.model.u0[0])) <= NEAR
            grid = np.arange(u[close].min(), u[close].max() + 0.02, 0.02) if close.any() else np.zeros(0)
            dense = np.unique(np.concatenate([u[close], grid]))
            if dense.size:
                ref, _, rerr = sweep(kind, args, dense, engine)
                if ref is not None:
                    rec["lost"], rec["past"], rec["extra"], rec["apart"] = compare(r, ref, dense, r.model.L,
                                                                                   float(r.model.u0[0]), kind)
                else:
                    rec["ref_error"] = rerr
        out.write(json.dumps(rec) + "\n")
        out.flush()
    rec = dict(seed=seed, kind=kind, kw=kw, scenario="g", engine=engine, error=None)
    rec.update(moves(kind, kw, u0, rng, engine))
    out.write(json.dumps(rec) + "\n")
    out.flush()


def summary(path):
    recs = [json.loads(line) for line in open(path)]
    print(f"{len(recs)} sweeps, {len({r['seed'] for r in recs})} mechanisms")
    for key in ("error", "lost", "past", "extra", "apart", "off"):
        bad = [r for r in recs if r.get(key)]
        print(f"{key}: {len(bad)} sweeps", [(r["seed"], r["scenario"], r[key]) for r in bad[:20]])
    nc = [r for r in recs if r.get("status", {}).get("NOT_CONVERGED")]
    print("NOT_CONVERGED:", len(nc), [(r["seed"], r["scenario"]) for r in nc[:20]])
    slow = sorted(recs, key=lambda r: -r["cpu"])[:15]
    print("over 1 s:", sum(r["cpu"] > 1 for r in recs), [(r["seed"], r["kind"], r["scenario"], r["cpu"]) for r in slow])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("first", type=int, nargs="?", default=0)
    ap.add_argument("stop", type=int, nargs="?", default=20)
    ap.add_argument("--kinds", nargs="+", default=list(KINDS), choices=sorted(CATALOGUE))
    ap.add_argument("--engine", default="numpy", choices=("numpy", "numba"))
    ap.add_argument("--warm", action="store_true", help="each mechanism's sweeps on one model (it remembers poses)")
    ap.add_argument("--summary", metavar="JSONL")
    args = ap.parse_args(argv)
    if args.summary:
        return summary(args.summary)
    global WARM
    WARM = args.warm
    # (the modules a sweep imports on first use, outside the CPU times: a search past a gap)
    CATALOGUE["four_bar"](4.0, 2.0, 3.0, 4.0).compile().sweep([0.0, 3.0, 1e3], engine=args.engine)
    for seed in range(args.first, args.stop):
        run_seed(seed, args.kinds, args.engine, sys.stdout)


if __name__ == "__main__":
    main()
