"""Mesh to geometry image in one call: load, parametrize, fit the weighted-mean surface, sample."""
from __future__ import annotations

from pathlib import Path

from .image import GeometryImage
from .mesh import Mesh, load_mesh
from .parametrization import Parametrization, parametrize
from .surface import fit_surface

__all__ = ["mesh_to_image"]


def mesh_to_image(mesh_or_path, resolution: int | None = None, s=1.0, method: str = "auto", *,
                  axis: str | None = None, boundary: str = "square", weights: str = "gaussian", n: int = 10,
                  tol: float = 1e-10, sliver_rule: str = "robust", normals: bool = True,
                  parametrization: Parametrization | None = None, progress=None) -> GeometryImage:
    """The geometry image of a mesh: :func:`~geoimg.parametrize`, :func:`~geoimg.fit_surface` and
    :meth:`~geoimg.Surface.sample` in one call.

    Parameters
    ----------
    mesh_or_path : Mesh or str or path-like
        A mesh, or a mesh file (see :func:`geoimg.load_mesh`).
    resolution : int, optional
        Pixels along the longer side; default from ``s`` (:meth:`~geoimg.Surface.auto_resolution`).
    s : float, per-face values or SmoothnessMap; default 1.0
        Smoothness (see :func:`geoimg.fit_surface`).
    method, axis, boundary
        The parametrization (see :func:`geoimg.parametrize`); ignored when ``parametrization`` is given.
    weights, n, tol, sliver_rule
        The fit (see :func:`geoimg.fit_surface`).
    normals : bool, default True
        Also store exact normals.
    parametrization : Parametrization, optional
        Use this one (for example shared by meshes with the same faces) instead of making one.
    progress : callable, optional
        Called with a short message at each stage.

    Returns
    -------
    GeometryImage
        Its metadata records the source file's name (``source``) and the parametrization method.

    Examples
    --------
    >>> import geoimg
    >>> m = geoimg.Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 1], [0, 1, 0]], [[0, 1, 2, 3]])
    >>> img = mesh_to_image(m, 9, s=2.0, method="heightfield", axis="z")
    >>> img.shape, img.metadata["parametrization"]
    ((9, 9), 'heightfield')
    """
    say = progress or (lambda message: None)
    source = ""
    if isinstance(mesh_or_path, Mesh):
        mesh = mesh_or_path
    elif isinstance(mesh_or_path, (str, Path)):
        say(f"loading {mesh_or_path}")
        mesh, source = load_mesh(mesh_or_path), Path(mesh_or_path).name
    else:
        raise TypeError(f"mesh_or_path: expected a geoimg.Mesh or a file path, got {type(mesh_or_path).__name__}")
    if parametrization is None:
        say(f"{mesh.n_vertices} vertices, {mesh.n_faces} faces; parametrizing ({method})")
        parametrization = parametrize(mesh, method, axis=axis, boundary=boundary, progress=progress)
    say(f"parametrized by {parametrization.method}; fitting the surface (s={s}, {weights} weights)")
    surface = fit_surface(mesh, parametrization, s, weights=weights, n=n, tol=tol, sliver_rule=sliver_rule)
    res = surface.auto_resolution() if resolution is None else resolution
    say(f"sampling {res} pixels along the longer side")
    image = surface.sample(res, normals=normals)
    image.metadata["source"] = source
    image.metadata["parametrization"] = parametrization.method
    return image
