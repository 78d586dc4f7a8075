"""Geometry images: a regular grid of surface points stored as an (H, W, 3) float image of X, Y, Z."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .errors import GeoimgError
from .mesh import Mesh

__all__ = ["GeometryImage", "grid_normals", "DOMAINS"]

DOMAINS = ("planar", "octahedral")


def grid_normals(pixels: np.ndarray, orientation: int = 1) -> np.ndarray:
    """Unit normals of a geometry image from central differences of the grid (one-sided at the edges).

    Examples
    --------
    >>> u, v = np.meshgrid(np.linspace(0, 1, 4), np.linspace(0, 1, 3))
    >>> img = np.stack([u, v, 0 * u], axis=-1)
    >>> grid_normals(img)[1, 1].tolist()
    [0.0, 0.0, 1.0]
    """
    p = np.asarray(pixels, dtype=np.float64)
    pv, pu = np.gradient(p, axis=(0, 1))
    n = np.cross(pu, pv) * orientation
    norm = np.linalg.norm(n, axis=-1, keepdims=True)
    return np.divide(n, norm, out=np.zeros_like(n), where=norm > 0)


@dataclass(frozen=True, eq=False)
class GeometryImage:
    """A geometry image.

    Attributes
    ----------
    pixels : numpy.ndarray, shape (H, W, 3)
        X, Y, Z of the surface at each grid point (float32 or float64, kept as given).
    mask : numpy.ndarray of bool, shape (H, W), or None
        Pixels inside the parametrized region (None: all valid).
    domain : str
        ``"planar"``: the parameter rectangle, u along columns, v along rows. ``"octahedral"``: the
        unfolded sphere (an odd square, see :mod:`geoimg.octahedral`), whose sides are glued.
    normals : numpy.ndarray, shape (H, W, 3), or None
        Exact unit normals from the surface's derivatives, when known.
    metadata : dict
        How the image was made (s, weights, resolution, source, ...).

    Examples
    --------
    >>> img = GeometryImage(np.zeros((4, 5, 3), np.float32))
    >>> img.shape, img.to_mesh().n_faces
    ((4, 5), 12)
    """

    pixels: np.ndarray
    mask: np.ndarray | None = None
    domain: str = "planar"
    normals: np.ndarray | None = None
    metadata: dict = field(default_factory=dict)

    def __post_init__(self):
        p = np.asarray(self.pixels)
        if p.ndim != 3 or p.shape[2] != 3 or p.shape[0] < 2 or p.shape[1] < 2:
            raise ValueError(f"pixels: expected shape (H, W, 3) with H, W >= 2, got {p.shape}")
        if p.dtype not in (np.float32, np.float64):
            raise TypeError(f"pixels: expected float32 or float64, got {p.dtype}")
        if not np.isfinite(p).all():
            raise ValueError("pixels: contain NaN or infinite values")
        p = p.copy()
        p.setflags(write=False)
        object.__setattr__(self, "pixels", p)
        if self.mask is not None:
            m = np.asarray(self.mask)
            if m.shape != p.shape[:2]:
                raise ValueError(f"mask: expected shape {p.shape[:2]}, got {m.shape}")
            if m.dtype != bool:
                raise TypeError(f"mask: expected a boolean array, got {m.dtype}")
            m = m.copy()
            m.setflags(write=False)
            object.__setattr__(self, "mask", m)
        if self.normals is not None:
            n = np.asarray(self.normals)
            if n.shape != p.shape:
                raise ValueError(f"normals: expected shape {p.shape}, got {n.shape}")
            n = n.copy()
            n.setflags(write=False)
            object.__setattr__(self, "normals", n)
        if self.domain not in DOMAINS:
            raise ValueError(f"domain: expected one of {DOMAINS}, got {self.domain!r}")
        if self.domain == "octahedral":
            from .octahedral import check_size

            if p.shape[0] != p.shape[1]:
                raise ValueError(f"pixels: an octahedral image must be square, got {p.shape[:2]}")
            check_size(p.shape[0])
            if self.mask is not None and not np.all(self.mask):
                raise ValueError("mask: an octahedral image covers the whole sphere; it takes no mask")
        object.__setattr__(self, "metadata", dict(self.metadata))

    @property
    def shape(self) -> tuple[int, int]:
        """(H, W)."""
        return self.pixels.shape[:2]

    @property
    def valid(self) -> np.ndarray:
        """The mask, or all True when there is none."""
        return np.ones(self.shape, bool) if self.mask is None else self.mask

    def parameter_grid(self) -> tuple[np.ndarray, np.ndarray]:
        """The (u, v) of the columns and rows (from ``metadata['extent']``, else the unit square)."""
        ext = self.metadata.get("extent", [1.0, 1.0])
        return np.linspace(0, ext[0], self.shape[1]), np.linspace(0, ext[1], self.shape[0])

    def to_mesh(self) -> Mesh:
        """The regular quad mesh: a quad per 2x2 block of valid pixels, a vertex per pixel of a quad.

        (A valid pixel that no quad uses, e.g. an isolated one, gives no vertex.)

        Quads are oriented like the source mesh (``metadata['orientation']``). Vertices carry the pixel's
        (u, v) and a normal: the exact one when the image has ``normals``, else one from the grid.

        Returns
        -------
        Mesh
            (H - 1)(W - 1) quads when every pixel is valid.

        Raises
        ------
        GeoimgError
            If no 2 x 2 block of valid pixels exists.
        """
        if self.domain == "octahedral":
            return self._octahedral_mesh()
        H, W = self.shape
        v = self.valid
        keep = v[:-1, :-1] & v[:-1, 1:] & v[1:, 1:] & v[1:, :-1]
        if not keep.any():
            raise GeoimgError("to_mesh: the image has no 2 x 2 block of valid pixels, so no quad")
        used = np.zeros((H, W), bool)
        used[:-1, :-1] |= keep
        used[:-1, 1:] |= keep
        used[1:, 1:] |= keep
        used[1:, :-1] |= keep
        index = np.full((H, W), -1, np.int64)
        index[used] = np.arange(int(used.sum()))
        quads = np.stack([index[:-1, :-1][keep], index[:-1, 1:][keep], index[1:, 1:][keep],
                          index[1:, :-1][keep]], axis=1)
        orientation = int(self.metadata.get("orientation", 1))
        if orientation < 0:
            quads = quads[:, ::-1]
        normals = self.normals if self.normals is not None else grid_normals(self.pixels, orientation)
        u, v = self.parameter_grid()
        uu, vv = np.meshgrid(u, v)
        uv = np.stack([uu[used], vv[used]], axis=1)
        return Mesh(self.pixels[used].astype(np.float64), quads, uv=uv,
                    normals=np.asarray(normals, np.float64)[used])

    def _octahedral_mesh(self) -> Mesh:
        """(N-1)^2 quads with the glued boundary welded by index: a closed genus-0 mesh.
        A welded vertex takes the mean of its pixels (identical unless a filter broke the symmetry)."""
        from .octahedral import glued_groups, group_means

        n = self.shape[0]
        reps, index = glued_groups(n)
        grid = index.reshape(n, n)
        quads = np.stack([grid[:-1, :-1], grid[:-1, 1:], grid[1:, 1:], grid[1:, :-1]], axis=-1).reshape(-1, 4)
        if int(self.metadata.get("orientation", 1)) < 0:
            quads = quads[:, ::-1]
        normals = group_means(self.normals, index) if self.normals is not None else None
        if normals is not None:
            normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-300)
        u, v = self.parameter_grid()
        uu, vv = np.meshgrid(u, v)
        uv = np.stack([uu.ravel(), vv.ravel()], axis=1)[reps]
        return Mesh(group_means(self.pixels, index), quads, uv=uv, normals=normals)

    @property
    def boundary_mode(self) -> str:
        """The boundary rule the domain implies for :mod:`filters`: ``octahedral``, or ``reflect``."""
        return "octahedral" if self.domain == "octahedral" else "reflect"

    def apply(self, op, *args, **kwargs) -> "GeometryImage":
        """Run a :mod:`filters` operation on the pixels with the domain's boundary rule; a new image.

        ``mode`` is passed when ``op`` takes one and the call does not; geometry images among the
        arguments (to blend or composite) stand for their pixels and must share domain and size; a mask
        on an octahedral image is made symmetric on the glued boundary, and glued pixels of the result
        are averaged so they stay identical. ``mask=`` and ``feather=`` restrict any operation to a region
        (through its own mask argument, or by blending its result in). The exact normals are dropped (the
        filtered image is no longer the surface); the operation is recorded in ``metadata['filters']``.

        Examples
        --------
        >>> import filters
        >>> img = GeometryImage(np.random.default_rng(0).normal(size=(5, 5, 3)), domain="octahedral")
        >>> out = img.apply(filters.mean_filter, 3)
        >>> out.metadata["filters"], out.domain
        (['mean_filter(3, mode=octahedral)'], 'octahedral')
        """
        import inspect

        def pixels_of(x):
            if isinstance(x, GeometryImage):
                if x.domain != self.domain or x.shape != self.shape:
                    raise ValueError(f"image: expected a {self.domain} {self.shape} geometry image, got a "
                                     f"{x.domain} {x.shape} one (resample it with filters.resize first)")
                return x.pixels
            return x

        args = [pixels_of(a) for a in args]
        kwargs = {k: pixels_of(v) for k, v in kwargs.items()}
        params = inspect.signature(op).parameters
        if "mode" in params and "mode" not in kwargs:
            kwargs["mode"] = self.boundary_mode
        mask, feather = kwargs.get("mask"), kwargs.get("feather", 0.0)
        if mask is not None:
            from filters._checks import as_weights

            mask = kwargs["mask"] = as_weights(mask, self.shape)
            if self.domain == "octahedral":
                from .regions import symmetric_mask

                mask = kwargs["mask"] = symmetric_mask(mask)
        if mask is not None and "mask" not in params:   # any operation can be masked
            import filters

            kwargs.pop("mask")
            kwargs.pop("feather", None)
            weights = filters.feather(mask, feather, kwargs.get("mode", self.boundary_mode))
            out = filters.apply_masked(self.pixels, np.asarray(op(self.pixels, *args, **kwargs)), weights)
            kwargs.update(mask=mask, feather=feather)
        else:
            out = op(self.pixels, *args, **kwargs)
        out = np.asarray(out[0] if isinstance(out, tuple) else out)
        if out.shape != self.pixels.shape:
            raise ValueError(f"{getattr(op, '__name__', op)}: returned shape {out.shape}, not the image's "
                             f"{self.pixels.shape}")
        if self.domain == "octahedral":
            from .octahedral import average_glued

            out = average_glued(out)
        shown = [repr(a) if np.ndim(a) == 0 else f"<array {np.shape(a)}>" for a in args]
        shown += [f"{k}={v}" if isinstance(v, str) or np.ndim(v) == 0 else f"{k}=<array>" for k, v in kwargs.items()]
        meta = dict(self.metadata)
        meta["filters"] = list(meta.get("filters", [])) + [f"{getattr(op, '__name__', 'op')}({', '.join(shown)})"]
        return GeometryImage(out.astype(self.pixels.dtype), self.mask, domain=self.domain, metadata=meta)

    def save(self, path, *, overwrite: bool = False):
        """Write the image to OpenEXR (float32, lossless, with metadata); see :func:`geoimg.save_image`."""
        from .image_io import save_image

        return save_image(self, path, overwrite=overwrite)

    def preview(self, path, *, overwrite: bool = False):
        """Write a 16-bit PNG with each channel stretched to its range over valid pixels (masked: black)."""
        from .image_io import save_preview

        return save_preview(self, path, overwrite=overwrite)
