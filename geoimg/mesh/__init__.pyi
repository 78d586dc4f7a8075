from ._mesh import Mesh, pad_faces
from ._io import MESH_FORMATS, MESH_READ_FORMATS, load_mesh, mesh_file_jobs, save_mesh
from ._topology import Topology, boundary_loops, corner_fans, topology
from ._repair import (
    Repair,
    drop_degenerate_faces,
    drop_duplicate_faces,
    orient_faces,
    repair,
    split_components,
    split_fans,
)
from ._weld import Weld, weld_vertices
from ._terrain import grid_mesh, grid_triangles, load_dem
from ._metrics import boundary_distance, point_mesh_distance, sample_surface, surface_distance
from ._landmarks import average_geodesic_distance, suggest_landmarks

__all__ = [
    "Mesh",
    "pad_faces",
    "MESH_FORMATS",
    "MESH_READ_FORMATS",
    "Weld",
    "weld_vertices",
    "load_mesh",
    "save_mesh",
    "mesh_file_jobs",
    "Topology",
    "boundary_loops",
    "corner_fans",
    "topology",
    "Repair",
    "drop_degenerate_faces",
    "drop_duplicate_faces",
    "orient_faces",
    "repair",
    "split_components",
    "split_fans",
    "grid_mesh",
    "grid_triangles",
    "load_dem",
    "point_mesh_distance",
    "sample_surface",
    "surface_distance",
    "boundary_distance",
    "average_geodesic_distance",
    "suggest_landmarks",
]
