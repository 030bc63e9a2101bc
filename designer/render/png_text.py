"""Drop the text chunks Blender writes into PNG files (render times, date), keeping the
image data byte for byte: the same job then writes the same files on every run.

A PNG file is an 8-byte signature and chunks of (length, type, data, CRC); tEXt, zTXt,
iTXt and tIME chunks carry only text and time, never pixels (PNG specification, 11.3).
"""

from __future__ import annotations

import os
import struct
from pathlib import Path

from designer.atomic import write_bytes_atomic

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
TEXT_CHUNKS = {b"tEXt", b"zTXt", b"iTXt", b"tIME"}


def without_text_chunks(data: bytes) -> bytes:
    """The PNG ``data`` without its text and time chunks (other chunks untouched)."""
    if not data.startswith(PNG_SIGNATURE):
        raise ValueError("not a PNG file")
    out = [PNG_SIGNATURE]
    pos = len(PNG_SIGNATURE)
    while pos < len(data):
        if pos + 8 > len(data):
            raise ValueError("truncated PNG chunk header")
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind = data[pos + 4:pos + 8]
        end = pos + 12 + length
        if end > len(data):
            raise ValueError(f"truncated PNG chunk {kind!r}")
        if kind not in TEXT_CHUNKS:
            out.append(data[pos:end])
        pos = end
        if kind == b"IEND":
            break
    return b"".join(out)


def move_without_text(src: str | os.PathLike, dst: str | os.PathLike) -> None:
    """Write ``src`` (a PNG) to ``dst`` atomically without its text chunks; remove ``src``."""
    src = Path(src)
    write_bytes_atomic(dst, without_text_chunks(src.read_bytes()))
    src.unlink()
