"""A loaded mechanism file (:class:`MechanismFile`) and its sweep settings (:class:`SweepSettings`)."""

from dataclasses import dataclass, field

import numpy as np

from planar.errors import FileFormatError
from planar.model import Mechanism
from planar.units import Units

NUM = 181  # sweep values when a file's sweep gives no num


@dataclass(frozen=True)
class SweepSettings:
    """Sweep settings of a file, in the file's units: one ``start``, ``stop``, ``speed`` and
    ``acceleration`` per input, ``num`` values, and ``rocking`` (start -> stop -> start)."""

    start: tuple
    stop: tuple
    num: int = NUM
    speed: tuple = (1.0,)
    acceleration: tuple = (0.0,)
    rocking: bool = False

    def __post_init__(self):
        # (the file's own checks, on the fields as a file holds them: a number or a list of them)
        from planar.io.schema import KINDS, SWEEP_FIELDS, valid

        for name, kind in SWEEP_FIELDS.items():
            v = getattr(self, name)
            try:  # (numpy's numbers and arrays as Python's, tuples as lists)
                plain = np.asarray(v).tolist() if isinstance(v, (tuple, list, np.ndarray, np.generic)) else v
            except ValueError:  # (ragged)
                plain = None
            if not valid(kind, plain):
                raise FileFormatError(f"SweepSettings {name}: must be {KINDS[kind]}, got {v!r}")
            object.__setattr__(self, name, tuple(float(x) for x in np.ravel(plain)) if kind == "numbers" else plain)

    def values(self, model, units):
        """Input values (N, f) and rates (N, f), (N, f) in internal units for ``model``."""
        from planar import arguments

        f = len(model.drivers)
        if f == 0:
            raise FileFormatError(f"drivers: the mechanism has no driver to sweep: add {max(model.dof, 1)} to drivers, "
                                  f'like {{"joint": "O2"}} or {{"body": "crank"}}')
        arguments.size(model, self.num * (2 if self.rocking else 1), "the sweep (sweep.num)")
        cols = []
        for name, key in (("start", self.start), ("stop", self.stop), ("speed", self.speed),
                          ("acceleration", self.acceleration)):
            if len(key) not in (1, f):
                raise FileFormatError(f"sweep.{name}: has {len(key)} values but the mechanism has {f} "
                                      f"input(s) {list(model.input_names)}")
            cols.append(np.broadcast_to(np.asarray(key, float), (f,)))
        start, stop, speed, acc = cols
        t = np.linspace(0.0, 1.0, self.num)
        sign = np.ones_like(t)
        if self.rocking:
            t, sign = np.r_[t, t[-2::-1]], np.r_[sign, -sign[-2::-1]]
        U, Ud, Udd = [], [], []
        for k, is_len in enumerate(model.input_lengths):
            U.append(units.input_to_internal(start[k] + t * (stop[k] - start[k]), is_len, 0))
            # speed is a size: the rate points from start to stop (and back when rocking)
            forward = 1.0 if stop[k] >= start[k] else -1.0
            Ud.append(forward * sign * units.input_to_internal(abs(speed[k]), is_len, 1))
            Udd.append(np.full(t.shape, units.input_to_internal(acc[k], is_len, 2)))
        return np.stack(U, 1), np.stack(Ud, 1), np.stack(Udd, 1)


@dataclass(frozen=True)
class MechanismFile:
    """A loaded mechanism file: the built :class:`planar.Mechanism`, its :class:`Units`, the
    :class:`SweepSettings` (or None) and ``data``, the canonical document (what :func:`save`
    writes back)."""

    mechanism: Mechanism
    units: Units
    sweep: SweepSettings | None
    data: dict = field(repr=False)
