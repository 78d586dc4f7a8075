"""sha256 of every golden output: EXR by decoded channels + geoimg attributes (the file holds a timestamp),
others by bytes.
"""

import hashlib
import sys
from pathlib import Path
import numpy as np
import OpenImageIO as oiio
root = Path(sys.argv[1])
for p in sorted(root.rglob("*")):
    if not p.is_file():
        continue
    if p.suffix == ".exr":
        inp = oiio.ImageInput.open(str(p))
        spec = inp.spec()
        data = inp.read_image(oiio.FLOAT)
        inp.close()
        h = hashlib.sha256(np.ascontiguousarray(data).tobytes())
        h.update(repr(list(spec.channelnames)).encode())
        for a in ("geoimg:metadata", "geoimg:domain"):
            h.update(repr(spec.getattribute(a)).encode())
        d = h.hexdigest()
    else:
        d = hashlib.sha256(p.read_bytes()).hexdigest()
    print(d, p.relative_to(root))
