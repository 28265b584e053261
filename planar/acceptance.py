"""The acceptance test both engines share: a solve stayed on its branch (:func:`certified`) and near
its prediction (:func:`on_course`). The compiled engine compiles these two functions into its loop;
this module imports nothing of planar, so the engine reads them without importing the sweep."""

JUMP = 0.2  # accepted distance from the predictor, as a fraction of the predicted move
ROUND = 1e-13  # scaled Newton correction below which a guess is at rounding level
CERT = 0.1  # accepted correction, as a fraction of the singularity measure at the solution


def certified(off, sing):
    """A solve that moved its guess by ``off`` (scaled) to a pose of singularity measure
    ``sing`` stayed on the guess's branch: the move is at rounding level or no more than CERT
    times the distance to the nearest other solution, which ``sing`` estimates (scalars or
    arrays; the compiled engine's loop calls it too).

    >>> bool(certified(1e-3, 0.3)), bool(certified(1e-3, 3e-3)), bool(certified(1e-14, 0.0))
    (True, False, True)
    """
    return (off <= CERT * sing) | (off <= ROUND)


def on_course(off, move):
    """A solve that moved its guess by ``off`` (scaled) from a prediction that moved the pose by
    ``move`` stayed near that prediction: within 1e-9, or JUMP times the predicted move
    (scalars or arrays; the compiled engine's loop calls it too).

    >>> bool(on_course(0.01, 0.1)), bool(on_course(0.05, 0.1))
    (True, False)
    """
    return (off <= 1e-9) | (off <= JUMP * move + 1e-9)
