"""The UTF-8 byte-order mark that some tools write before a text mesh file (OFF and PLY headers skip it)."""

__all__ = ["BOM"]

BOM = b"\xef\xbb\xbf"
