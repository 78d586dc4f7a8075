from ._parametrize import AXES, PARAMETRIZATION_METHODS, Parametrization, parametrize, signed_face_areas
from ._cut import cut_coords
from ._charts import chart_coords
from ._disk import DISK_BALANCES, DISK_BOUNDARIES, disk_coords
from ._sphere import sphere_coords
from ._octahedral import area_ratio, grid_directions, sphere_to_square, square_jacobian, square_to_sphere
from ._stretch import map_stretch

__all__ = [
    "cut_coords",
    "chart_coords",
    "AXES",
    "DISK_BALANCES",
    "DISK_BOUNDARIES",
    "PARAMETRIZATION_METHODS",
    "Parametrization",
    "parametrize",
    "signed_face_areas",
    "map_stretch",
    "disk_coords",
    "sphere_coords",
    "area_ratio",
    "grid_directions",
    "sphere_to_square",
    "square_jacobian",
    "square_to_sphere",
]
