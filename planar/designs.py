"""Parameter studies: the same sweep over many designs (dimension sets), with a leading axis.

A *design* is one set of keyword arguments to a builder (a catalogue function such as
:func:`planar.mechanisms.four_bar`, or any function of yours returning a
:class:`planar.Mechanism`). :func:`sweep_designs` builds, compiles and sweeps each design and
stacks the named outputs as (D, N, ...) arrays. Each design follows its own branch from its
own sketch, with its own events; a design that cannot be built or assembled is kept, with
NaN outputs, status NOT_ASSEMBLABLE and the error's message in ``errors``, so one bad row
never loses a study.

>>> import numpy as np
>>> from planar.mechanisms import four_bar
>>> study = sweep_designs(four_bar, {"crank": [1.0, 1.5, 2.0]}, np.radians(np.arange(0, 360, 45)),
...                       fixed=dict(ground=4.0, coupler=3.5, rocker=3.0))
>>> study.position("B").shape, study.ok.all()
((3, 8, 2), np.True_)
>>> study.designs[1]
{'crank': 1.5}
"""

from dataclasses import dataclass

import numpy as np

from planar.errors import InputError, PlanarError
from planar.results import Status


def design_table(designs):
    """The designs as a tuple of dicts: from a dict of columns (each a sequence with one
    value per design, or a number for all; a value may itself be a tuple, as a coupler
    point), or from a sequence of dicts.

    >>> design_table({"crank": [1.0, 2.0], "coupler_point": [(1, 0), (2, 0)], "rocker": 3.0})
    ({'crank': 1.0, 'coupler_point': (1, 0), 'rocker': 3.0}, {'crank': 2.0, 'coupler_point': (2, 0), 'rocker': 3.0})
    """
    if isinstance(designs, dict):
        cols = {k: (None if np.ndim(v) == 0 else list(v)) for k, v in designs.items()}
        sizes = {k: len(c) for k, c in cols.items() if c is not None}
        if not sizes or len(set(sizes.values())) != 1 or 0 in sizes.values():
            raise InputError("designs must be a dict of columns of equal, non-zero lengths (one value per design) "
                             f"with at least one column: got lengths {sizes}")
        D = next(iter(sizes.values()))
        return tuple({k: (designs[k] if c is None else _plain(c[d])) for k, c in cols.items()} for d in range(D))
    table = tuple(designs)
    if not table or not all(isinstance(d, dict) for d in table):
        raise InputError("designs must be a dict of parameter columns or a non-empty sequence of dicts")
    return table


def _plain(v):
    return v.item() if isinstance(v, np.generic) else v


def sweep_designs(build, designs, values, velocity=1.0, acceleration=0.0, *, fixed=None, **options):
    """Sweep each design ``build(**fixed, **design)`` over ``values`` with the input rates
    ``velocity`` and ``acceleration``, as :meth:`planar.Model.sweep` does (``options``: ``tol``,
    ``max_step``, ``outputs``, ``branch``). ``designs`` is a dict of parameter columns
    (equal lengths, or scalars) or a sequence of dicts; ``values`` may also be a function of
    the design dict, for inputs that depend on the design. Returns a :class:`DesignSweep`.
    """
    table = design_table(designs)
    fixed = {} if fixed is None else dict(fixed)
    sweeps, errors = [], []
    for d, design in enumerate(table):
        try:
            model = build(**fixed, **design).compile()
            U = values(design) if callable(values) else values
            sweeps.append(model.sweep(U, velocity, acceleration, **options))
            errors.append(None)
        except InputError:
            raise  # the call is wrong for every design: say so once
        except PlanarError as e:
            sweeps.append(None)
            errors.append(f"design {d} {design}: {e}")
    lengths = {len(s) for s in sweeps if s is not None}
    if not lengths:
        raise InputError("no design could be built: " + "; ".join(errors))
    if len(lengths) > 1:
        raise InputError(f"values give designs different numbers of points {sorted(lengths)}: a study needs one N")
    return DesignSweep(table, tuple(sweeps), tuple(errors), lengths.pop())


@dataclass(frozen=True, eq=False)
class DesignSweep:
    """Results of :func:`sweep_designs`: one :class:`planar.Sweep` per design (``sweeps``,
    None where ``errors`` says why the design could not be built or assembled), and the named
    outputs stacked with a leading design axis: ``position(name)`` (D, N, 2), ``angle(body)``
    (D, N), ``status`` (D, N), ... NaN, with status NOT_ASSEMBLABLE, for designs that failed.
    """

    designs: tuple
    sweeps: tuple
    errors: tuple
    N: int

    def __len__(self):
        return len(self.designs)

    def __getitem__(self, d):
        return self.sweeps[d]

    def __repr__(self):
        bad = sum(e is not None for e in self.errors)
        return f"DesignSweep(D={len(self)}, N={self.N}, failed designs={bad})"

    def _stack(self, get, tail=()):
        out = np.full((len(self), self.N) + tail, np.nan)
        for d, s in enumerate(self.sweeps):
            if s is not None:
                out[d] = get(s)
        out.flags.writeable = False
        return out

    @property
    def status(self):
        out = np.full((len(self), self.N), Status.NOT_ASSEMBLABLE, dtype=np.int8)
        for d, s in enumerate(self.sweeps):
            if s is not None:
                out[d] = s.status
        out.flags.writeable = False
        return out

    @property
    def ok(self):
        """(D, N) True where positions, velocities and accelerations are valid."""
        return np.array([s.ok if s is not None else np.zeros(self.N, bool) for s in self.sweeps])

    @property
    def events(self):
        """Per design, the singular positions its sweep met (empty for failed designs)."""
        return tuple(s.events if s is not None else () for s in self.sweeps)

    @property
    def inputs(self):
        return self._stack(lambda s: s.inputs, (self._width("inputs"),))

    def _width(self, attr):
        return next(getattr(s, attr).shape[1] for s in self.sweeps if s is not None)

    def position(self, name):
        return self._stack(lambda s: s.position(name), (2,))

    def velocity(self, name):
        return self._stack(lambda s: s.velocity(name), (2,))

    def acceleration(self, name):
        return self._stack(lambda s: s.acceleration(name), (2,))

    def angle(self, body):
        return self._stack(lambda s: s.angle(body))

    def omega(self, body):
        return self._stack(lambda s: s.omega(body))

    def alpha(self, body):
        return self._stack(lambda s: s.alpha(body))

    def coordinate(self, joint, derivative=0):
        return self._stack(lambda s: s.coordinate(joint, derivative))
