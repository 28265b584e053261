"""The one exception hierarchy (:mod:`planar.errors`): one ``except planar.PlanarError`` catches
every error planar raises on purpose, the errors of wrong arguments are ValueErrors as Python's
own are, and each is importable from ``planar``. Each error raised with its message is in
test_bad_input.py and test_model_errors.py.
"""

import inspect

import pytest

import planar
import planar.errors

ERRORS = {name: cls for name, cls in vars(planar.errors).items()
          if inspect.isclass(cls) and issubclass(cls, Exception) and cls.__module__ == "planar.errors"}


def test_every_error_is_a_planar_error_and_every_warning_a_user_warning():
    for name, cls in ERRORS.items():
        assert issubclass(cls, planar.PlanarError) != issubclass(cls, Warning), name
        if issubclass(cls, Warning):
            assert issubclass(cls, UserWarning), name


@pytest.mark.parametrize(
    "cls", ["ModelError", "ConnectivityError", "MobilityError", "RedundancyError", "FileFormatError", "InputError"]
)
def test_errors_of_wrong_arguments_are_value_errors(cls):
    assert issubclass(ERRORS[cls], ValueError)


@pytest.mark.parametrize("cls", ["AssemblyError", "SynthesisError"])
def test_errors_of_a_task_that_cannot_be_done_are_not_value_errors(cls):
    assert not issubclass(ERRORS[cls], ValueError)


def test_every_error_is_importable_from_planar():
    assert set(ERRORS) <= set(planar.__all__)
    for name, cls in ERRORS.items():
        assert getattr(planar, name) is cls

