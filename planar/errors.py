"""The one exception hierarchy of planar.

Every error the library raises on purpose derives from :class:`PlanarError`, and its
message names the body, joint, driver or input at fault and what would fix it.

>>> import planar
>>> issubclass(planar.ConnectivityError, planar.PlanarError)
True
"""


class PlanarError(Exception):
    """Base of every error planar raises on purpose."""


class ModelError(PlanarError, ValueError):
    """The mechanism description is wrong: a bad name, number, or joint argument."""


class ConnectivityError(ModelError):
    """A body is not connected to the ground through joints."""


class MobilityError(ModelError):
    """The drivers do not match the degrees of freedom, or depend on each other."""


class RedundancyError(ModelError):
    """A redundant joint contradicts the others (for example a pivot declared twice, apart)."""


class AssemblyError(PlanarError):
    """The sketch cannot be assembled: the joints cannot all hold at once near it."""


class InputError(PlanarError, ValueError):
    """Sweep values, rates or options of the wrong shape or kind."""


class FileFormatError(ModelError):
    """A mechanism file is malformed: its message names the file, the field and what is wrong."""


class WriteError(PlanarError, OSError):
    """A file could not be written (a missing folder, no permission, a full disk): an OSError
    too, with the system's errno and reason and the file's name."""


class SynthesisError(PlanarError):
    """No mechanism meets the synthesis targets: the message says which target or design
    failed, and what to change (other free choices, ranges, more designs or another seed)."""


class IndeterminateWarning(UserWarning):
    """Reactions that are not unique (redundant joints): the minimum-norm split is returned."""


def shown(value):
    """``value`` as an error message shows it: its repr, at most 60 characters (an integer of
    more digits than Python writes, by its size).

    >>> shown("mm"), shown(10**5000)
    ("'mm'", 'an integer of 16610 bits')
    """
    try:
        return repr(value)[:60]
    except ValueError:
        return f"an integer of {value.bit_length()} bits"
