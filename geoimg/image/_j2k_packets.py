"""Where each resolution level of a JPEG 2000 codestream ends, and the codestream cut after one: what makes a
geoimg ``.jp2`` progressive though OpenJPEG (through ``imagecodecs``) writes one quality layer and decodes only
whole codestreams.

A codestream of one tile and one quality layer, in a resolution-first progression (LRCP, RLCP or RPCL: with one
layer each holds a resolution's packets together), holds the packets of resolution 0 (the coarsest approximation)
first, then those of resolution 1, and so on. Its packet headers say how long each packet is
(ISO/IEC 15444-1, B.10: tag trees of the code-blocks' inclusion and zero bit-planes, the number of coding passes,
the lengths); :func:`resolution_ends` reads them. A codestream cut after resolution ``r`` keeps those packets,
and every later one becomes an empty packet (one byte, ``0x00``): a complete, standard codestream whose finer
wavelet details are zero, which any decoder opens as the same image at a coarser level of detail
(:func:`cut_after`). So the first k bytes of a file decode to the shape as far as they go.

Examples
--------
>>> import imagecodecs
>>> ramp = (np.add.outer(np.arange(64), np.arange(64)) * 500).astype(np.uint16)
>>> cs = bytes(imagecodecs.jpeg2k_encode(ramp, level=60, codecformat="j2k", resolutions=4))
>>> ends = resolution_ends(cs)
>>> len(ends), ends[-1] <= len(cs)
(4, True)
>>> coarse = imagecodecs.jpeg2k_decode(cut_after(cs, 1))
>>> coarse.shape, bool(np.abs(coarse.astype(float) - ramp).mean() < 300)
((64, 64), True)
"""
from __future__ import annotations

import math
import struct
from dataclasses import dataclass

import numpy as np

from ..errors import ImageFileError

__all__ = ["Layout", "read_layout", "resolution_ends", "cut_after", "without_comments", "EMPTY_PACKET"]

EMPTY_PACKET = b"\x00"          # a packet header whose first bit says "no code-block included"
RESOLUTION_FIRST = (0, 1, 2)    # LRCP, RLCP, RPCL
MAX_SIDE = 1 << 16              # no geometry image is wider
MAX_PACKETS = 1 << 20           # nor has this many packets
MAX_BLOCKS = 1 << 20            # nor this many code-blocks in one precinct's subband
MAX_SEGMENT_PASSES = 109        # coding passes in one codeword segment of a plain code-block


@dataclass(frozen=True)
class Layout:
    """What the packets of a one-tile codestream depend on, read from its main header."""

    width: int
    height: int
    components: int
    levels: int            # wavelet decomposition levels (resolutions - 1)
    cblk: tuple            # code-block width and height exponents
    precincts: tuple       # per resolution, the precincts' width and height exponents
    order: int             # the progression (0 LRCP, 1 RLCP, 2 RPCL)
    header_end: int        # where the tile-part (SOT) begins
    data_start: int        # where the first packet begins (after SOD)
    data_end: int          # where the tile-part's data ends


class _Bits:
    """Packet-header bits, with the bit stuffing after a 0xFF byte (B.10.1)."""

    def __init__(self, data: bytes, at: int, end: int):
        self.data, self.at, self.end = data, at, end
        self.buf, self.ct = 0, 0

    def bit(self) -> int:
        if self.ct == 0:
            self._byte()
        self.ct -= 1
        return (self.buf >> self.ct) & 1

    def bits(self, n: int) -> int:
        v = 0
        for _ in range(n):
            v = (v << 1) | self.bit()
        return v

    def _byte(self):
        if self.at >= self.end:
            raise EOFError
        self.buf = (self.buf << 8) & 0xFFFF
        self.ct = 7 if self.buf == 0xFF00 else 8
        self.buf |= self.data[self.at]
        self.at += 1

    def align(self) -> int:
        """End of the header: the position after it (a byte after 0xFF is part of it)."""
        if (self.buf & 0xFF) == 0xFF:
            self._byte()
        self.ct = 0
        return self.at


class _TagTree:
    """A tag tree over a grid of code-blocks (B.10.2), decoded bit by bit."""

    def __init__(self, w: int, h: int):
        self.parent: list[int] = []
        sizes = [(w, h)]
        while sizes[-1] != (1, 1):
            pw, ph = sizes[-1]
            sizes.append(((pw + 1) // 2, (ph + 1) // 2))
        offsets = np.cumsum([0] + [a * b for a, b in sizes])
        n = int(offsets[-1])
        self.value = [1 << 30] * n
        self.low = [0] * n
        self.parent = [-1] * n
        for k, (lw, lh) in enumerate(sizes[:-1]):
            pw = sizes[k + 1][0]
            for j in range(lh):
                for i in range(lw):
                    self.parent[offsets[k] + j * lw + i] = int(offsets[k + 1] + (j // 2) * pw + i // 2)

    def decode(self, bits: _Bits, leaf: int, threshold: int) -> bool:
        path = [leaf]
        while self.parent[path[-1]] >= 0:
            path.append(self.parent[path[-1]])
        low = 0
        for node in reversed(path):
            low = max(low, self.low[node])
            while low < threshold and low < self.value[node]:
                if bits.bit():
                    self.value[node] = low
                else:
                    low += 1
            self.low[node] = low
        return self.value[leaf] < threshold


def _segment(data: bytes, at: int) -> tuple[int, int, int]:
    """A marker segment at ``at``: (marker, start of its parameters, end of the segment)."""
    if at + 4 > len(data):
        raise EOFError
    marker, length = struct.unpack(">HH", data[at:at + 4])
    return marker, at + 4, at + 2 + length


def without_comments(cs: bytes) -> bytes:
    r"""``cs`` without the comment (COM) segments of its main header: the coder's name costs about 40 bytes a
    file, which a file of a few kilobytes spends better on the shape. A codestream whose main header cannot be
    walked comes back as it is.

    Examples
    --------
    >>> import imagecodecs
    >>> cs = bytes(imagecodecs.jpeg2k_encode(np.zeros((8, 8), np.uint8), codecformat="j2k"))
    >>> short = without_comments(cs)
    >>> b"\xff\x64" in cs[:80], len(short) < len(cs), imagecodecs.jpeg2k_decode(short).shape
    (True, True, (8, 8))
    """
    out, at = [cs[:2]], 2
    try:
        while True:
            marker, _, end = _segment(cs, at)
            if marker == 0xFF90 or end > len(cs):
                break
            if marker != 0xFF64:
                out.append(cs[at:end])
            at = end
    except EOFError:
        return cs
    return b"".join(out) + cs[at:] if cs[:2] == b"\xff\x4f" else cs


def read_layout(cs: bytes) -> Layout:
    """The layout of a codestream written as geoimg writes them (one tile, one layer, resolution-first, plain
    code-blocks, no SOP/EPH markers).

    Raises
    ------
    ImageFileError
        On a codestream of another kind, or one that ends inside its headers.
    """
    try:
        if cs[:2] != b"\xff\x4f":
            raise ImageFileError("not a JPEG 2000 codestream")
        at, siz, cod = 2, None, None
        while True:
            marker, p, end = _segment(cs, at)
            if end > len(cs):
                raise EOFError
            if marker == 0xFF51:
                siz = struct.unpack(">HIIIIIIIIH", cs[p:p + 36])
                if not 1 <= siz[9] <= 16384 or end - p < 36 + 3 * siz[9]:
                    raise ImageFileError("a SIZ segment too short for its components")
                subsampled = [cs[p + 36 + 3 * c + 1:p + 36 + 3 * c + 3] != b"\x01\x01" for c in range(siz[9])]
            elif marker == 0xFF52:
                cod = cs[p:end]
                if len(cod) < 10:
                    raise ImageFileError("a COD segment too short")
            elif marker in (0xFF53, 0xFF5E, 0xFF5F, 0xFF60):        # COC, RGN, POC, PPM: another kind of stream
                raise ImageFileError("its coding style varies by component or region")
            elif marker == 0xFF90:
                break
            at = end
        _, p, _ = _segment(cs, at)
        _, psot, _, _ = struct.unpack(">HIBB", cs[p:p + 8])
        sod = at + 14                                   # SOT's 12 bytes, then SOD
    except (EOFError, struct.error):
        raise ImageFileError("the codestream ends inside its headers") from None
    if siz is None or cod is None:
        raise ImageFileError("no SIZ or COD marker")
    _, xsiz, ysiz, x0, y0, xt, yt, xt0, yt0, comps = siz
    scod, order, layers = cod[0], cod[1], (cod[2] << 8) | cod[3]
    levels, xcb, ycb, style = cod[5], cod[6], cod[7], cod[8]
    if levels > 32 or xcb > 8 or ycb > 8 or xcb + ycb > 8:
        raise ImageFileError(f"{levels} wavelet levels, code-blocks of 2^{xcb + 2} x 2^{ycb + 2}: out of the standard")
    if (x0, y0, xt0, yt0) != (0, 0, 0, 0) or xt < xsiz or yt < ysiz or any(subsampled):
        raise ImageFileError("more than one tile, an offset or subsampled components")
    if not (0 < xsiz <= MAX_SIDE and 0 < ysiz <= MAX_SIDE):
        raise ImageFileError(f"an image of {xsiz} x {ysiz} pixels")
    if scod & 0x06 or order not in RESOLUTION_FIRST or layers != 1 or style != 0:
        raise ImageFileError("SOP/EPH markers, several layers, another progression or code-block style")
    sizes = cod[10:11 + levels] if scod & 1 else bytes([0xFF] * (levels + 1))
    if len(sizes) != levels + 1:
        raise ImageFileError("its precinct sizes are cut short")
    precincts = tuple((min(b & 0x0F, 15), min(b >> 4, 15)) for b in sizes)
    if any(min(pp) < 1 for pp in precincts[1:]):
        raise ImageFileError("precincts of one pixel past the coarsest resolution")
    if cs[sod - 2:sod] != b"\xff\x93":
        raise ImageFileError("no SOD marker where the tile-part's header ends")
    end = at + psot if psot else len(cs) - 2
    layout = Layout(xsiz, ysiz, comps, levels, (xcb + 2, ycb + 2), precincts, order, at, sod, min(end, len(cs)))
    counts = [_precinct_count(layout, r) for r in range(levels + 1)]
    if sum(counts) * comps > MAX_PACKETS:
        raise ImageFileError(f"{sum(counts) * comps} packets")
    return layout


def _precinct_count(layout: Layout, r: int) -> int:
    rw, rh = -(-layout.width // 2 ** (layout.levels - r)), -(-layout.height // 2 ** (layout.levels - r))
    return -(-rw // 2 ** layout.precincts[r][0]) * -(-rh // 2 ** layout.precincts[r][1])


def _packets(layout: Layout, r: int) -> list[list[tuple[int, int]]]:
    """The packets of resolution ``r`` in codestream order: for each, the code-block grids (columns, rows) of
    its precinct in each subband (LL at resolution 0; HL, LH, HH after).
    """
    W, H, nl = layout.width, layout.height, layout.levels
    pp = layout.precincts[r]
    level = nl if r == 0 else nl - r + 1
    offsets = [(0, 0)] if r == 0 else [(1, 0), (0, 1), (1, 1)]
    rw, rh = -(-W // 2 ** (nl - r)), -(-H // 2 ** (nl - r))
    if rw == 0 or rh == 0:
        return []
    bp = (pp[0] - (r > 0), pp[1] - (r > 0))                     # the precinct's size in a subband
    cb = (min(layout.cblk[0], bp[0]), min(layout.cblk[1], bp[1]))
    bands = []
    for xo, yo in offsets:
        half = 2 ** (level - 1) if level > 0 else 0
        bands.append((math.ceil(-half * xo / 2 ** level), math.ceil(-half * yo / 2 ** level),
                      math.ceil((W - half * xo) / 2 ** level), math.ceil((H - half * yo) / 2 ** level)))
    precincts = []
    for j in range(-(-rh // 2 ** pp[1])):
        for i in range(-(-rw // 2 ** pp[0])):
            grids = []
            for bx0, by0, bx1, by1 in bands:
                x0, x1 = max(bx0, i * 2 ** bp[0]), min(bx1, (i + 1) * 2 ** bp[0])
                y0, y1 = max(by0, j * 2 ** bp[1]), min(by1, (j + 1) * 2 ** bp[1])
                if x1 <= x0 or y1 <= y0:
                    grids.append((0, 0))
                else:
                    grids.append((-(-x1 // 2 ** cb[0]) - x0 // 2 ** cb[0], -(-y1 // 2 ** cb[1]) - y0 // 2 ** cb[1]))
            precincts.append(grids)
    if layout.order == 2:                                        # RPCL: position, then component
        return [g for g in precincts for _ in range(layout.components)]
    return [g for _ in range(layout.components) for g in precincts]      # LRCP, RLCP: component, then position


def _packet(cs: bytes, at: int, end: int, grids: list[tuple[int, int]]) -> int:
    """Where the packet that starts at ``at`` ends (its header read, its body's lengths summed)."""
    bits = _Bits(cs, at, end)
    if not bits.bit():
        return bits.align()
    body = 0
    for w, h in grids:
        if w * h == 0:
            continue
        if w * h > MAX_BLOCKS:
            raise ImageFileError(f"{w * h} code-blocks in one precinct")
        inclusion, zero = _TagTree(w, h), _TagTree(w, h)
        for leaf in range(w * h):
            if not inclusion.decode(bits, leaf, 1):           # first layer: included when its value is 0
                continue
            k = 0
            while not zero.decode(bits, leaf, k + 1):
                k += 1
            passes = 1
            if bits.bit():
                passes = 2
                if bits.bit():
                    n = bits.bits(2)
                    passes = 3 + n
                    if n == 3:
                        n = bits.bits(5)
                        passes = 6 + n
                        if n == 31:
                            passes = 37 + bits.bits(7)
            lblock = 3
            while bits.bit():
                lblock += 1
            while passes > 0:                              # a codeword segment holds at most 109 passes
                segment = min(passes, MAX_SEGMENT_PASSES)
                body += bits.bits(lblock + int(math.floor(math.log2(segment))))
                passes -= segment
    return bits.align() + body


def resolution_ends(cs: bytes) -> list[int]:
    """Where the packets of each resolution level end, coarsest first, as far as ``cs`` holds them whole (a
    truncated codestream gives fewer).

    Raises
    ------
    ImageFileError
        On a codestream of another kind (see :func:`read_layout`).
    """
    layout = read_layout(cs)
    ends, at = [], layout.data_start
    try:
        for r in range(layout.levels + 1):
            for grids in _packets(layout, r):
                at = _packet(cs, at, layout.data_end, grids)
            if at > layout.data_end:
                break
            ends.append(at)
    except EOFError:
        pass
    return ends


def cut_after(cs: bytes, r: int, ends: list[int] | None = None) -> bytes:
    """A complete codestream of ``cs``'s packets up to resolution ``r`` (0: the coarsest), every later packet
    empty: the same image with its finer details zero; ``ends`` is :func:`resolution_ends` of ``cs`` when the
    caller has read it already.

    Raises
    ------
    ImageFileError
        When ``cs`` does not hold resolution ``r`` whole, or is of another kind.
    """
    layout = read_layout(cs)
    ends = resolution_ends(cs) if ends is None else ends
    if not 0 <= r < len(ends):
        raise ImageFileError(f"the codestream holds {len(ends)} whole resolution levels, not {r + 1}")
    empty = EMPTY_PACKET * sum(len(_packets(layout, k)) for k in range(r + 1, layout.levels + 1))
    data = cs[layout.data_start:ends[r]] + empty
    sot = cs[layout.header_end:layout.data_start]
    psot = len(sot) + len(data)
    sot = sot[:6] + struct.pack(">I", psot) + sot[10:11] + b"\x01" + sot[12:]     # one tile-part, its length
    return cs[:layout.header_end] + sot + data + b"\xff\xd9"
