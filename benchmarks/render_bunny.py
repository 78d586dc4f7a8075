"""Pictures of the bunny through the octahedral domain: its geometry image, the welded quad mesh, and the
samples-per-area map of the spherical parametrization. Run by hand: python benchmarks/render_bunny.py
"""
from pathlib import Path

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import geoimg
from geoimg.parametrization import area_ratio

HERE = Path(__file__).resolve().parent
mesh = geoimg.load_mesh(HERE.parents[1] / "shared" / "data" / "meshes" / "closed_genus0" / "bunny.off")
param = geoimg.parametrize(mesh, "sphere")
img = geoimg.fit_surface(mesh, param, geoimg.GaussianWeights()).sample(257)
quads = img.to_mesh()
fig, ax = plt.subplots(1, 3, figsize=(15, 5))
p = img.pixels
ax[0].imshow((p - p.min((0, 1))) / np.ptp(p, (0, 1)))
ax[0].set_title("octahedral geometry image (X, Y, Z as R, G, B)")
v, n = quads.vertices, quads.normals
order = np.argsort(v[:, 2])
shade = np.clip(n[order] @ np.array([0.3, 0.5, 0.8]) / np.linalg.norm([0.3, 0.5, 0.8]), 0, 1)
ax[1].scatter(v[order, 0], v[order, 1], c=shade, cmap="gray", s=0.3, vmin=0, vmax=1)
ax[1].set_aspect("equal")
ax[1].set_title(f"welded quad mesh, {quads.n_faces} quads (front view)")
tris, _ = mesh.triangulate()
s = param.coords
a3 = 0.5 * np.linalg.norm(np.cross(*(mesh.vertices[tris[:, k]] - mesh.vertices[tris[:, 0]] for k in (1, 2))), axis=1)
a2 = 0.5 * np.linalg.norm(np.cross(*(s[tris[:, k]] - s[tris[:, 0]] for k in (1, 2))), axis=1)
dens = a2 * area_ratio(s[tris].mean(1)) / a3
dens /= (dens * a3).sum() / a3.sum()
c = mesh.vertices[tris].mean(1)
o = np.argsort(c[:, 2])
sc = ax[2].scatter(c[o, 0], c[o, 1], c=np.log2(dens[o]), cmap="coolwarm", s=0.5, vmin=-3, vmax=3)
ax[2].set_aspect("equal")
ax[2].set_title("samples per unit area, log2 of ratio to the mean")
fig.colorbar(sc, ax=ax[2])
for a in ax:
    a.set_xticks([])
    a.set_yticks([])
fig.tight_layout()
fig.savefig(HERE / "bunny_octahedral.png", dpi=80)
print("wrote", HERE / "bunny_octahedral.png")
