"""The exceptions of flexmbd: one class per kind of failure.

Every exception carries the attributes ``file``, ``line``, ``column`` and ``item`` (where the
failure is, when known), ``stage`` (which analysis or stage failed), ``hint`` (what to try,
spelled as keyword arguments of this package) and ``result`` (the results computed before the
failure, for a static path or a simulation that stopped part-way; otherwise None).
"""


class FlexmbdError(Exception):
    """Base class of flexmbd's exceptions."""

    file = None
    line = None
    column = None
    item = None
    stage = None
    hint = None
    result = None


class ModelError(FlexmbdError, ValueError):
    """Invalid model input: ``file``, ``line``, ``column`` and ``item`` say where."""


class OptionError(FlexmbdError, ValueError):
    """An argument of an analysis that does not fit the model; ``item`` names the keyword."""


class NumericalError(FlexmbdError, RuntimeError):
    """A numerical failure (no convergence, a singular matrix); ``stage`` says where and
    ``hint`` what to try."""


class PathStoppedError(NumericalError):
    """A static path that stopped part-way; ``result`` holds the converged steps (a
    ``StaticResult`` or ``ModesResult``)."""


class SimulationStoppedError(NumericalError):
    """A time simulation that stopped before its end time; ``result`` holds the frames up to
    then (a ``SimulationResult``)."""


class TooLargeError(FlexmbdError, MemoryError):
    """A dense analysis that would need more memory than its limit allows; ``hint`` names the
    sparse alternative."""


class ReadError(FlexmbdError, OSError):
    """A model file that cannot be read."""


class FlexmbdWarning(UserWarning):
    """A warning of reading or mapping a model (e.g. what a SPACAR file's mapping
    approximates)."""
