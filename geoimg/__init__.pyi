# The one list of what `geoimg` exports: lazy_loader reads it at import (names are imported when first
# used) and type checkers read it as the package's interface.
from . import (animation as animation, batch as batch, cli as cli, errors as errors, image as image, mesh as mesh,
    parametrization as parametrization, spectrum as spectrum, surface as surface)
from .errors import (GeoimgError as GeoimgError, ImageError as ImageError, ImageFileError as ImageFileError,
    InputError as InputError, InputTypeError as InputTypeError, MeshError as MeshError,
    MeshFileError as MeshFileError, MissingDependency as MissingDependency,
    ParametrizationError as ParametrizationError, RenderError as RenderError, ResourceError as ResourceError)
from .mesh import (Mesh as Mesh, grid_mesh as grid_mesh, load_mesh as load_mesh, save_mesh as save_mesh)
from .parametrization import (Parametrization as Parametrization, parametrize as parametrize)
from .image import (ChartsDomain as ChartsDomain, CutDomain as CutDomain, Domain as Domain,
    GeometryImage as GeometryImage, OctahedralDomain as OctahedralDomain, PlanarDomain as PlanarDomain,
    grid_normals as grid_normals, load_image as load_image, save_image as save_image, save_preview as save_preview)
from .surface import (Surface as Surface, fit_surface as fit_surface, CoverageWeights as CoverageWeights,
    GaussianWeights as GaussianWeights)
from ._convert import (mesh_to_image as mesh_to_image, mesh_to_images as mesh_to_images)
from ._options import ConversionOptions as ConversionOptions
from ._compress import (Compressed as Compressed, compress as compress)
from .spectrum import (Harmonics as Harmonics, harmonics as harmonics, load_harmonics as load_harmonics)
__version__: str
