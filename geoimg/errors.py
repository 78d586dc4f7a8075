"""Exception types raised by geoimg; all derive from :class:`GeoimgError`, so that one ``except`` catches
every refusal, and each also derives from the built-in kind it is (``ValueError``, ``TypeError``,
``MemoryError``, ``ImportError``).
"""

__all__ = ["GeoimgError", "MeshError", "MeshFileError", "ParametrizationError", "ImageFileError", "ImageError",
           "InputError", "InputTypeError", "ResourceError", "MissingDependency", "RenderError"]


class GeoimgError(Exception):
    """Base class of every error geoimg raises on purpose.

    Examples
    --------
    >>> import geoimg
    >>> try:
    ...     geoimg.Mesh([[0, 0, 0]], [[0, 1, 2]])
    ... except geoimg.GeoimgError as e:          # every refusal, whatever its kind
    ...     print(type(e).__name__)
    MeshError
    """


class MeshError(GeoimgError, ValueError):
    """A mesh (array or file) is malformed: bad indices, NaN coordinates, empty, corrupt.

    Examples
    --------
    >>> issubclass(MeshError, ValueError), issubclass(MeshError, GeoimgError)
    (True, True)
    """


class MeshFileError(MeshError):
    """A mesh file cannot be read or written (unknown format, truncated, corrupt).

    Examples
    --------
    >>> import geoimg, tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "junk.off"
    >>> _ = p.write_text("not an OFF file")
    >>> try:
    ...     geoimg.load_mesh(p)
    ... except MeshFileError:
    ...     print("refused")
    refused
    """


class ParametrizationError(GeoimgError, ValueError):
    """A parametrization cannot be built or does not fit its mesh.

    Examples
    --------
    >>> issubclass(ParametrizationError, ValueError)
    True
    """


class ImageFileError(GeoimgError, ValueError):
    """A geometry-image file cannot be read or written.

    Examples
    --------
    >>> import geoimg
    >>> try:
    ...     geoimg.load_image("missing.exr")
    ... except (ImageFileError, FileNotFoundError) as e:
    ...     print(type(e).__name__)
    FileNotFoundError
    """


class ImageError(GeoimgError, ValueError):
    """A geometry image (array, domain, mask) is malformed or does not fit its domain.

    Examples
    --------
    >>> import numpy as np, geoimg
    >>> try:
    ...     geoimg.GeometryImage(np.full((4, 4, 3), np.nan, np.float32))     # no surface there
    ... except ImageError:
    ...     print("refused")
    refused
    """


class InputError(GeoimgError, ValueError):
    """An argument's value is wrong (out of range, of the wrong shape, not finite, inconsistent).

    Examples
    --------
    >>> import geoimg
    >>> m = geoimg.grid_mesh([[0.0, 1.0], [1.0, 0.0]], (1.0, 1.0))
    >>> try:
    ...     geoimg.mesh_to_image(m, 9, s=0)
    ... except InputError as e:
    ...     print(isinstance(e, ValueError))
    True
    """


class InputTypeError(GeoimgError, TypeError):
    """An argument is of the wrong type.

    Examples
    --------
    >>> issubclass(InputTypeError, TypeError)
    True
    """


class ResourceError(GeoimgError, MemoryError):
    """Work that would need more memory than the machine (or ``GEOIMG_MAX_MEMORY``) allows, refused before
    it starts.

    Examples
    --------
    >>> issubclass(ResourceError, MemoryError)
    True
    """


class MissingDependency(GeoimgError, ImportError):
    """An optional package that a feature needs is not installed (the message names the install command).

    Examples
    --------
    >>> issubclass(MissingDependency, ImportError)
    True
    """


class RenderError(GeoimgError):
    """No OpenGL context could be made, or the scene cannot be drawn.

    Examples
    --------
    >>> issubclass(RenderError, GeoimgError)
    True
    """
