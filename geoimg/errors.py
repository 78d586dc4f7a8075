"""Exception types raised by geoimg; all derive from :class:`GeoimgError`."""


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
