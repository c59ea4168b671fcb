"""The exceptions csgkit raises; each carries the library's message, which names what is
wrong and where (the operand, the vertex or face, the file and line or byte)."""


class CsgkitError(Exception):
    """Base class of every csgkit error; raised as such when an operation fails on valid
    input (a result without a certified float64 form, say)."""


class InputError(CsgkitError, ValueError):
    """The call cannot take its input: arrays of the wrong shape or with non-finite
    coordinates, an index out of range, a mesh that is not closed, an unknown operation or
    option value."""


class ReadError(CsgkitError):
    """A file could not be read, or its content is not a valid mesh or box file."""


class WriteError(CsgkitError):
    """A file could not be written (unknown extension, a folder that does not exist, ...);
    the destination is left as it was."""


class CancelledError(CsgkitError):
    """The progress callback returned False; nothing was produced."""
