"""A row (or rows) of shapes rendered alike, each titled, on one PNG: the benchmarks' pictures."""
from __future__ import annotations

from pathlib import Path


def render_sheet(rows: list[list[tuple[str, object]]], framing, out: Path, size: int = 360, azimuth: float = 35,
                 elevation: float = 15) -> None:
    """Render each (title, mesh or geometry image) of ``rows`` with one camera framed on ``framing``."""
    from PIL import Image, ImageDraw

    from geoimg.animation import Renderer

    width = max(len(row) for row in rows)
    sheet = Image.new("RGB", (size * width, size * len(rows)), "white")
    with Renderer(size, size, background=(1.0, 1.0, 1.0)) as r:
        camera = r.camera_for(framing, azimuth=azimuth, elevation=elevation)
        for i, row in enumerate(rows):
            for k, (title, shape) in enumerate(row):
                tile = Image.fromarray(r.render(shape, camera))
                ImageDraw.Draw(tile).text((12, 10), title, fill=(0, 0, 0))
                sheet.paste(tile, (size * k, size * i))
    out.parent.mkdir(parents=True, exist_ok=True)
    sheet.save(out)
