"""The package's exception classes (a minimal version; the Python-package work defines these
same names with their full documentation)."""


class TessellaError(ValueError):
    """Base class of tessella's errors about what it was given."""


class MeshError(TessellaError):
    """A mesh that cannot be refined (bad arrays, degenerate triangles, no triangles)."""


class OptionError(TessellaError):
    """An option that is unknown, out of range or in conflict with another."""


class FileFormatError(TessellaError):
    """A file that is not a well-formed mesh file of a format tessella reads or writes."""


class GpuError(TessellaError):
    """The GPU backend could not do what was asked."""
