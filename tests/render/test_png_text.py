"""PNG text chunks are dropped; pixels and every other chunk stay byte for byte."""

import cv2
import numpy as np
import pytest

from designer.render.png_text import move_without_text, without_text_chunks


def with_text(data: bytes) -> bytes:
    import struct
    import zlib

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(
            ">I", zlib.crc32(kind + body))

    ihdr_end = 8 + 12 + 13  # signature + the IHDR chunk
    extra = (chunk(b"tEXt", b"RenderTime\x0000:01.23")
             + chunk(b"tIME", b"\x07\xea\x0b\x15\x0c\x00\x00"))
    return data[:ihdr_end] + extra + data[ihdr_end:]


def test_text_is_dropped_and_the_rest_kept(tmp_path):
    img = (np.random.default_rng(0).random((20, 30, 3)) * 255).astype(np.uint8)
    plain = cv2.imencode(".png", img)[1].tobytes()
    tagged = with_text(plain)
    assert tagged != plain and b"RenderTime" in tagged
    assert without_text_chunks(tagged) == plain
    src, dst = tmp_path / ".tmp.png", tmp_path / "IMG.png"
    src.write_bytes(tagged)
    move_without_text(src, dst)
    assert not src.exists() and dst.read_bytes() == plain
    np.testing.assert_array_equal(cv2.imread(str(dst)), img)
    with pytest.raises(ValueError, match="not a PNG"):
        without_text_chunks(b"GIF89a")
    with pytest.raises(ValueError, match="truncated"):
        without_text_chunks(tagged[:-20])
