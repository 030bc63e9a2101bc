"""Exceptions that carry a message meant for the user.

The command line prints ``str(error)`` on one line and exits non-zero; no traceback
reaches the user for bad input.
"""


class DesignerError(Exception):
    """Base class of every error caused by the user's input, not by a bug."""

    exit_code = 2


class CameraModelError(DesignerError, ValueError):
    """An interior orientation or distortion model that cannot describe a real camera."""


class NotInvertibleError(DesignerError, ArithmeticError):
    """A distortion model that folds over, so some pixel has no unique undistorted ray."""


class InvalidDataError(DesignerError, ValueError):
    """A value a data type or an exchange format cannot hold (a name with a comma, a
    non-finite coordinate, a repeated id); the message names the fix."""


class ParameterError(DesignerError):
    """A parameter given a value it may not have. Besides the library's message it carries
    the fields a program words it from without reading the message: ``name``, the
    parameter as the code calls it (``spacing_m``); ``value``, the value given; ``must``,
    what the value must be, in words (``greater than 0``, ``a whole number of 0.5 m grid
    cells``); ``unit``, the value's unit ("": none). The fields default to empty so that
    the error pickles like any other (they travel in its ``__dict__``)."""

    def __init__(self, message: str, *, name: str = "", value: object = None, must: str = "",
                 unit: str = "") -> None:
        super().__init__(message)
        self.name, self.value, self.must, self.unit = name, value, must, unit


class ParameterValueError(ParameterError, ValueError):
    """A :class:`ParameterError` of a function whose contract is a ValueError for a bad
    argument (the imaging effects' numbers): callers catching ValueError still catch it."""
