"""Exception types raised by geoimg; all derive from :class:`GeoimgError`, so that one ``except`` catches
every refusal, and each also derives from the built-in kind it is (``ValueError``, ``TypeError``,
``MemoryError``, ``ImportError``).
"""


class GeoimgError(Exception):
    """Base class of every error geoimg raises on purpose."""


class MeshError(GeoimgError, ValueError):
    """A mesh (array or file) is malformed: bad indices, NaN coordinates, empty, corrupt."""


class MeshFileError(MeshError):
    """A mesh file cannot be read or written (unknown format, truncated, corrupt)."""


class ParametrizationError(GeoimgError, ValueError):
    """A parametrization cannot be built or does not fit its mesh."""


class ImageFileError(GeoimgError, ValueError):
    """A geometry-image file cannot be read or written."""


class ImageError(GeoimgError, ValueError):
    """A geometry image (array, domain, mask) is malformed or does not fit its domain."""


class InputError(GeoimgError, ValueError):
    """An argument's value is wrong (out of range, of the wrong shape, not finite, inconsistent)."""


class InputTypeError(GeoimgError, TypeError):
    """An argument is of the wrong type."""


class ResourceError(GeoimgError, MemoryError):
    """Work that would need more memory than the machine (or ``GEOIMG_MAX_MEMORY``) allows, refused before
    it starts.
    """


class MissingDependency(GeoimgError, ImportError):
    """An optional package that a feature needs is not installed (the message names the install command)."""


class RenderError(GeoimgError):
    """No OpenGL context could be made, or the scene cannot be drawn."""
