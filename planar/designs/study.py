"""A study: its table of designs (:func:`design_table`, :class:`Vary`), swept batch by batch
(:func:`sweep_part`: the designs' tables built at once where they can be, each batch on its
template's plan, the others swept alone) and joined into one :class:`DesignSweep`."""

import copy
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

from planar import arguments
from planar.blocks import plan as block_plan
import planar.designs.tables as design_tables
from planar.designs.batch import Results, sweep_batch
from planar.designs.results import DesignSweep, Models
from planar.designs.tables import compile_unplanned
from planar.errors import InputError, PlanarError
from planar.model import Mechanism
from planar.model.checks import SCALE
from planar.sweep import run_sweep
from planar.sweep.walk import WALK_STEPS


def design_table(designs):
    """The designs as a tuple of dicts: from a dict of columns (each a sequence with one
    value per design, or a number for all; a value may itself be a tuple, as a coupler
    point), or from a sequence of dicts.

    >>> design_table({"crank": [1.0, 2.0], "coupler_point": [(1, 0), (2, 0)], "rocker": 3.0})
    ({'crank': 1.0, 'coupler_point': (1, 0), 'rocker': 3.0}, {'crank': 2.0, 'coupler_point': (2, 0), 'rocker': 3.0})
    """
    if isinstance(designs, dict):
        cols = {}
        for k, v in designs.items():
            try:
                cols[k] = None if np.ndim(v) == 0 else _column(v)
            except (TypeError, ValueError):  # (ragged, or nested deeper than a point per design)
                got = f"an array of shape {v.shape}" if isinstance(v, np.ndarray) else repr(v)
                raise InputError(f"design column {k!r} must hold one value per design (a number, or a point (x, y)), "
                                 f"each of one shape: got {got}") from None
        sizes = {k: len(c) for k, c in cols.items() if c is not None}
        if not sizes or len(set(sizes.values())) != 1 or 0 in sizes.values():
            raise InputError("designs must be a dict of columns of equal, non-zero lengths (one value per design) "
                             f"with at least one column: got lengths {sizes}")
        D = next(iter(sizes.values()))
        return tuple({k: (designs[k] if c is None else c[d]) for k, c in cols.items()} for d in range(D))
    try:
        table = tuple(designs)
    except TypeError:
        table = ()
    if not table or not all(isinstance(d, dict) for d in table):
        raise InputError("designs must be a dict of parameter columns or a non-empty sequence of dicts")
    return table


def _column(c):
    """A column's values as plain Python numbers (a row of an array as a tuple)."""
    if isinstance(c, np.ndarray) and c.ndim <= 2:  # (at once)
        return c.tolist() if c.ndim == 1 else [tuple(r) for r in c.tolist()]
    return [_plain(v) for v in c]


def _plain(v):
    if isinstance(v, np.ndarray):
        return tuple(x.item() for x in v)
    return v.item() if isinstance(v, np.generic) else v


class Vary:
    """The designs of ``mechanism`` that differ from it by numbers only, as a builder for
    :func:`sweep_designs`: ``Vary(m)(**numbers)`` is ``m`` with the stated distances named
    "a-b" (:meth:`planar.Mechanism.distance`) and the starts of its drivers, named as the
    drivers, set to ``numbers`` (the others as ``m`` has them; ``numbers`` lists them all).
    A study of a ``Vary`` builds no Mechanism per design: the designs' tables come from the
    numbers at once, every sketch assembled from ``m``'s drawing together
    (:func:`planar.designs.tables.varied`).

    >>> from planar.mechanisms import four_bar
    >>> family = Vary(four_bar(coupler_point=(1.0, 0.5)))
    >>> list(family.numbers)
    ['O2-O4', 'O2-A', 'A-B', 'O4-B', 'A-C', 'B-C', 'crank']
    >>> study = sweep_designs(family, {"O2-A": [1.0, 1.5]}, np.radians(np.arange(0, 360, 45)))
    >>> A = study[1].model.sketch.position("A")
    >>> bool(study.ok.all()), study.batched.tolist(), bool(np.allclose(A, [1.5, 0.0], rtol=0, atol=1e-12))
    (True, [True, True], True)
    """

    def __init__(self, mechanism):
        if not isinstance(mechanism, Mechanism):
            raise InputError(f"Vary takes a planar.Mechanism, got {type(mechanism).__name__}")
        self.mechanism = copy.deepcopy(mechanism)  # the study's: later edits to the caller's do not reach it

    @cached_property
    def numbers(self):
        """name -> the value ``mechanism`` has: its stated distances, then its drivers' starts."""
        sk = self.mechanism.sketch()
        return {f"{d.a}-{d.b}": d.length for d in sk.dimensions} | dict(sk.starts)

    @cached_property
    def model(self):
        return compile_unplanned(self.mechanism)

    def check_all(self, designs, first=0):
        """:meth:`check` each of ``designs`` (dicts), the first wrong named as design first + d:
        a column at once where it is all finite floats."""
        if not isinstance(designs, (list, tuple)) or not all(isinstance(x, dict) for x in designs):
            raise InputError(f"check_all takes a list of designs, each a dict of numbers by name, got {designs!r}")
        if isinstance(first, bool) or not isinstance(first, (int, np.integer)):
            raise InputError(f"check_all's first (the index of the first design) must be a whole number, got {first!r}")
        for name in set().union(*designs):
            col = [x.get(name, 0.0) for x in designs]
            if (name not in self.numbers or not all(type(v) is float for v in col) or not np.isfinite(col).all()
                    or np.abs(col).max() > SCALE):
                break
        else:
            return
        for d, x in enumerate(designs):
            try:
                self.check(x)
            except InputError as e:
                raise InputError(f"design {first + d}: {e}") from None

    def check(self, numbers):
        """Refuse ``numbers`` (a dict: name -> value) that are no numbers of the mechanism or not finite."""
        if not isinstance(numbers, dict):
            raise InputError(f"a design's numbers are a dict of numbers by name, got {numbers!r}")
        unknown = sorted(set(numbers) - set(self.numbers), key=repr)
        if unknown:
            raise InputError(f"{unknown} are no numbers of mechanism {self.mechanism.name!r}: it has "
                             f"{sorted(self.numbers)} (stated distances 'a-b' and drivers' starts)")
        for name, value in numbers.items():
            if not arguments.finite_number(value):
                raise InputError(f"{name} must be a finite number, got {value!r}: give every design's numbers")
            if abs(float(value)) > SCALE:  # (as the builder refuses them: their squares overflow; a float32 as a float)
                raise InputError(f"{name} = {value!r} is beyond +-{SCALE:g}: give the design's numbers in another unit")

    def __call__(self, **numbers):
        self.check(numbers)
        m = copy.deepcopy(self.mechanism)
        for name, value in numbers.items():
            m.restate(name, value)
        return m


BATCH = 2048  # designs swept together: the batch's temporaries stay ~BATCH * N * 1 kB


def sweep_designs(build, designs, values, velocity=1.0, acceleration=0.0, *, fixed=None, batch=BATCH, **options):
    """Sweep each design ``build(**fixed, **design)`` over ``values`` with the input rates
    ``velocity`` and ``acceleration``, as :meth:`planar.Model.sweep` does (``options``: ``tol``,
    ``max_step``, ``outputs``, ``branch``, ``engine``). ``designs`` is a dict of parameter columns
    (equal lengths, or scalars) or a sequence of dicts. ``values`` is what every design
    sweeps ((N,), or (N, f) for f inputs), or one row per design ((D, N), or (D, N, f)), or a
    function of the design dict, for inputs that depend on the design (its start, its range):
    the function is what a study on a cluster should get (an array goes to every task). Designs are
    swept ``batch`` at a time (the batch's first design sets the scales: results agree with
    other batchings to rounding, and are bit-identical for the same ``batch``, as
    :func:`planar.cluster.sweep_designs_to_store` computes them). Returns a :class:`DesignSweep`.
    """
    table = design_table(designs)
    options = study_options(batch, options)
    check_fixed(fixed, table)
    rows = np.shape(values)[0] if isinstance(values, np.ndarray) and values.ndim == 3 else None
    if rows is not None and rows != len(table):
        raise InputError(f"values of shape {np.shape(values)} give {rows} designs their values (one row each), but "
                         f"there are {len(table)} designs: give one row per design")
    parts = (sweep_part(build, table, lo, min(lo + batch, len(table)), values, velocity, acceleration, fixed, options)
             for lo in range(0, len(table), batch))
    return join(table, parts)


def join(designs, parts, first=0):
    """The :class:`DesignSweep` of ``designs`` (the table's from index ``first`` on) from its
    batches ``parts`` (an iterable: each batch's arrays are copied into the study's as it
    comes, then let go)."""
    out, kept, reasons, rates, points, template = None, [], [], None, {}, None
    for p in parts:
        kept.append(p)
        reasons.extend(e for e in p.errors if e is not None)
        if p.out is None:
            continue
        dims = p.out.q.shape[1:] + p.out.U.shape[2:]
        at = slice(p.lo - first, p.lo - first + len(p.errors))
        if out is None:
            whole = p.lo == first and len(p.errors) == len(designs)  # one batch: its arrays are the study's
            if not whole:
                arguments.size(p.template, len(designs) * dims[0], f"the study of {len(designs)} designs x {dims[0]} "
                               "values, a sweep", fix="sweep fewer designs, or on a cluster into a store "
                               "(planar.cluster.sweep_designs_to_store)")
            out, rates, template = p.out if whole else Results(len(designs), *dims), (p.Ud, p.Udd), p.template
        elif dims[0] != out.q.shape[1]:
            raise InputError(f"designs give different numbers of values {dims[0]} and {out.q.shape[1]}: a study "
                             "sweeps its designs over one number of values")
        else:
            _same_layout(p.template, template, f"design {p.lo}", f"design {first}")
        if out is not p.out:
            out.put(at, p.out)
        for n, (b, S) in p.points.items():
            body = points.setdefault(n, (b, np.full((len(designs), 2), np.nan)))
            if body[0] == b:
                body[1][at] = S
        p.out = None
    if out is None:
        raise InputError("no design could be built: " + "; ".join(reasons))
    errors = sum((tuple(p.errors) for p in kept), ())
    known = {p.lo - first + d: m for p in kept for d, m in p.models.items()}
    return DesignSweep(tuple(designs), Models(kept[0].build, kept[0].fixed, tuple(designs), errors, known), errors,
                       np.concatenate([p.batched for p in kept]), sum((p.events for p in kept), ()), *rates,
                       points=points, template=template, **out.arrays())


def check_fixed(fixed, table):
    """Refuse ``fixed`` (the numbers every design shares) that is no dict of parameter names, or
    names a parameter a design of ``table`` gives too (a Vary's numbers would take the design's)."""
    if fixed is not None and not (isinstance(fixed, dict) and all(isinstance(k, str) for k in fixed)):
        raise InputError(f"fixed must be a dict of the builder's parameters by name, got {fixed!r}")
    both = sorted(set(fixed or ()) & set().union(*table), key=repr)
    if both:
        raise InputError(f"{both} given both in fixed and in the designs: give each parameter once")


def study_options(batch, options):
    """The sweep ``options`` of a study, checked (and ``batch``, its designs per batch)."""
    if isinstance(batch, bool) or not isinstance(batch, (int, np.integer)) or batch < 1:
        raise InputError(f"batch must be a positive whole number of designs, got {batch!r}")
    options = arguments.sweep_options(options, run_sweep)
    other = sorted(set(options) - {"tol", "max_step", "outputs", "branch", "engine"})
    if other:
        raise InputError(f"sweep_designs takes the options tol, max_step, outputs, branch and engine, not {other}")
    return options


@dataclass(eq=False)
class _Part:
    """One batch of a study: designs lo.. of the table, the models compiled alone (design ->
    Model), ``errors`` (None, or why the design could not be built), ``batched`` and ``events``
    per design, the input rates, the arrays (:class:`Results`, None when no design of the
    batch could be built), the named points (name -> (body name, (D, 2) body-fixed)), the
    first structure's model (``template``) and the builder, to compile a design when asked."""

    lo: int
    models: dict
    errors: list
    batched: np.ndarray
    events: tuple
    Ud: np.ndarray
    Udd: np.ndarray
    out: object
    points: dict
    template: object
    build: object
    fixed: dict


def sweep_part(build, table, lo, hi, values, velocity, acceleration, fixed, options):
    """Designs lo..hi of ``table`` swept as one batch (``options`` as :func:`study_options`
    returns them): a :class:`_Part`."""
    fixed = {} if fixed is None else dict(fixed)
    D = hi - lo
    mechs, errors, models = [None] * D, [None] * D, {}
    vary = isinstance(build, Vary)

    def mechanism(d):  # design d's Mechanism, built when first needed (None, with its error, if it cannot be)
        if mechs[d] is None and errors[d] is None:
            who = getattr(build, '__name__', 'the builder')
            try:
                mechs[d] = build(**fixed, **table[lo + d])
            except InputError:
                raise  # the call is wrong for every design: say so once
            except PlanarError as e:
                errors[d] = f"design {lo + d} {table[lo + d]}: {e}"
            except TypeError as e:  # (a parameter the builder does not take: wrong for every design)
                raise InputError(f"design {lo + d} {table[lo + d]}: {who} refused its parameters ({e}): name only "
                                 f"parameters it takes") from e
            except (ValueError, ArithmeticError) as e:  # (a builder of the user's refusing this design's numbers)
                errors[d] = f"design {lo + d} {table[lo + d]}: {who} raised {type(e).__name__}: {e}"
            if errors[d] is None and not isinstance(mechs[d], Mechanism):  # (None too: it was taken as not built)
                raise InputError(f"design {lo + d}: {who} returned {type(mechs[d]).__name__}: a builder of designs "
                                 f"returns a planar.Mechanism")
        return mechs[d]

    def alone(d):  # design d compiled by itself (None, with its error, if it cannot be)
        if d not in models:
            try:
                models[d] = compile_unplanned(mechanism(d)) if mechanism(d) is not None else None
                if models[d] is not None:  # (refused as its sweep would refuse it)
                    models[d].require_driver()
            except PlanarError as e:
                models[d], errors[d] = None, f"design {lo + d} {table[lo + d]}: {e}"
        return models[d]

    # the designs' tables, a structure at a time: built at once from their numbers where they
    # can be (planar.designs.tables), else from each design compiled alone
    groups, left = [], []
    if vary:  # no Mechanism per design: the tables from the numbers
        numbers = [{**fixed, **table[lo + d]} for d in range(D)]  # (names checked next: any key)
        build.check_all(numbers, lo)
        t, rest = design_tables.varied(build.mechanism, build.model, numbers, options.get("engine", "numpy"))
        left = [d for d in rest if alone(d) is not None]
        if t is not None:
            same = [d for d in left if _structure(models[d]) == _structure(build.model)]
            # (t holds no design where every design's numbers were refused or left to be built)
            parts = ([t] if t.index.size else []) + ([design_tables.from_models([models[d] for d in same], same)]
                                                     if same else [])
            if parts:
                groups.append(design_tables.join(parts))
            left = [d for d in left if d not in same]
    else:
        left = [d for d in range(D) if mechanism(d) is not None]
    while left:
        ref = next((d for d in left if alone(d) is not None), None)
        if ref is None:
            break
        t, rest = design_tables.tables(mechs[ref], models[ref], [mechs[d] for d in left], options.get("engine", "numpy"))
        rest = [left[k] for k in rest]
        same = [d for d in rest if alone(d) is not None and _structure(models[d]) == _structure(models[ref])]
        parts = ([replace(t, index=np.array(left)[t.index])] if t is not None else [])
        if same:
            parts.append(design_tables.from_models([models[d] for d in same], same))
        groups.append(design_tables.join(parts))
        left = [d for d in rest if models[d] is not None and d not in same]
    if not groups:
        return _Part(lo, models, tuple(errors), np.zeros(D, bool), ((),) * D, None, None, None, {}, None, build, fixed)
    ref = groups[0].model
    U = {}
    shared = None
    for g in groups:
        for d in g.index:
            v = values_of(values, table[lo + d], lo + d, len(ref.drivers))
            if v is values and shared is not None:
                U[d] = shared
                continue
            U[d] = ref.as_inputs(v, "values")
            shared = U[d] if v is values else shared
    shapes = {U[d].shape for d in U}
    if len(shapes) > 1:
        raise InputError(f"values give designs different numbers of points {sorted(shapes)}: a study needs one N")
    N, f = next(iter(shapes))
    arguments.size(ref, D * N, f"a batch of {D} designs x {N} values, a sweep", fix="sweep fewer designs a batch "
                   "(batch=), or fewer values")
    tables = list(groups)  # (with the designs whose walk is too long for the batch: their points too)
    for k, g in enumerate(groups):
        _same_layout(g.model, ref, f"design {lo + g.index[0]} {table[lo + g.index[0]]}",
                     f"design {lo + groups[0].index[0]}")
        groups[k] = _check_walks(g, U, options["max_step"], alone)
    groups = [g for g in groups if g.index.size]
    Ud, Udd = ref.as_inputs(velocity, "velocity", N), ref.as_inputs(acceleration, "acceleration", N)
    arguments.rates(ref, Ud, Udd)
    out = Results(D, N, ref.n, f)
    for d in U:
        out.U[d] = U[d]
    batched = np.zeros(D, bool)
    while groups:  # each group on its first design's plan; the designs it does not fit, again
        g = groups.pop(0)
        try:
            block_plan(g.model)  # the structure is drivable (else each design is swept alone, and refused)
        except PlanarError:
            continue
        ok, fits = sweep_batch(g, out, Ud, Udd, options.get("tol", 1e-12), options["max_step"], options.get("outputs"),
                               options.get("engine", "numpy"))
        batched[g.index] = ok
        retry = np.flatnonzero(~fits)
        retry = retry[retry > 0]  # (the first fits its own plan)
        if retry.size and alone(g.index[retry[0]]) is not None:
            groups.insert(0, replace(g.take(retry), model=models[g.index[retry[0]]]))
    events = [()] * D
    for d in sorted(U):
        if batched[d] or alone(d) is None:
            continue
        try:  # swept alone: its events located, each value its status
            s = models[d].sweep(U[d], Ud, Udd, **options)
        except PlanarError as e:
            models[d], errors[d] = None, f"design {lo + d} {table[lo + d]}: {e}"
            continue
        out.put(d, s)
        events[d] = s.events
    points = {}  # every structure's named points (on the body the first names), NaN where a design has none
    for g in tables:
        for n, (b, S) in g.points.items():
            body = points.setdefault(n, (g.model.body_names[b], np.full((D, 2), np.nan)))
            if body[0] == g.model.body_names[b]:
                body[1][g.index] = S
    return _Part(lo, models, tuple(errors), batched, tuple(events), Ud, Udd, out, points, ref, build, fixed)


def _same_layout(model, ref, who, first):
    """Refuse ``model`` (of design ``who``) whose coordinates are not laid out as ``ref``'s (of
    design ``first``): a study's arrays and accessors read every design through one layout."""
    if (model.n, len(model.drivers), model.body_names) != (ref.n, len(ref.drivers), ref.body_names):
        raise InputError(f"{who} has bodies {list(model.body_names)} and {len(model.drivers)} inputs, {first} "
                         f"{list(ref.body_names)} and {len(ref.drivers)}: a study sweeps designs of one structure "
                         "(sweep the others in a study of their own)")


def _check_walks(g, U, step, alone):
    """Refuse the values (:func:`planar.arguments.values`) whose walk from a design's sketch is
    too long, for the designs of tables ``g`` at once (the first refused raises). Returns ``g``
    without the designs whose walk is longer than WALK_STEPS: those are swept alone (the sweep
    solves far values whole periods back; the batch walks every step: from a start of 1e6 rad,
    for minutes), or keep the error that compiling them alone gives (a start beyond +-2^23 rad)."""
    ref = g.model
    arguments.values(ref, U[g.index[0]], step)  # (no values, too many)
    scale = np.where(ref.input_lengths, g.L[:, None], 1.0)
    u = np.stack([U[d] for d in g.index])
    with np.errstate(over="ignore", invalid="ignore"):
        jumps = np.abs(np.diff(np.concatenate([g.u0[:, None], u], axis=1), axis=1)) / scale[:, None]
        steps = np.sum(np.max(jumps, axis=2), axis=1) / step
    for k in np.flatnonzero(~(steps <= arguments.MAX_STEPS)):
        if alone(g.index[k]) is not None:
            arguments.values(alone(g.index[k]), U[g.index[k]], step)
    far = np.flatnonzero(~(steps <= WALK_STEPS))
    return g.take(np.setdiff1d(np.arange(g.index.size), far)) if far.size else g


def values_of(values, design, d, f):
    """Design d's input values: ``values(design)`` for a function; row d of an array of one
    row per design, (D, N) for one input (f = 1) or (D, N, f); else ``values`` itself."""
    if callable(values):
        try:
            return values(design)
        except Exception as e:  # (the user's function: its error, named with the design it was given)
            raise InputError(f"values({design}) raised {type(e).__name__}: {e}: give a function of the design dict "
                             f"that returns its input values") from e
    try:
        a = np.asarray(values) if isinstance(values, (list, tuple, np.ndarray)) else None
    except ValueError:  # (ragged: the values as they are, which the sweep's checks refuse by name)
        a = None
    if a is not None and a.dtype != object and (a.ndim == 3 or (a.ndim == 2 and f == 1 and a.shape[1] != 1)):
        if d >= a.shape[0]:
            raise InputError(f"values of shape {a.shape} give {a.shape[0]} designs their values (one row each), "
                             f"not design {d}: give one row per design")
        return a[d]
    return values


def _structure(model):
    """What designs swept in one batch share: bodies, rows, joint classes and their places."""
    return (len(model.body_names), model.m,
            tuple((g.kind, g.members.tobytes(), g.bodies.tobytes(), g.rows.tobytes(), g.inputs.tobytes())
                  for g in model.system.groups),
            model.active_rows.tobytes(), model.redundant_rows.tobytes(), model.input_lengths.tobytes())
