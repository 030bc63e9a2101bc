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
