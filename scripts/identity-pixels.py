#!/usr/bin/env python3
"""Whether two images hold the same pixels, their recorded scene text aside.

    scripts/identity-pixels.py A B

For a change that changes what an image records of its scene (the `opalray.scene` text of a
PNG's iTXt chunk, of an OpenEXR header; the hash of it that keys a sweep's frames folder,
`sweep.json`'s `sweep`) but must not change a pixel: exits 0 when every byte but that text
(and, in OpenEXR, the chunk offsets that move with it) is the same, 1 when anything else
differs, 2 when a file cannot be read as a PNG, a single-part OpenEXR or JSON.
Used by `scripts/identity.sh check` on a file that `cmp` finds different.
"""

import json
import struct
import sys

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
EXR_MAGIC = b"\x76\x2f\x31\x01"
# What an image records of its scene, the only thing allowed to differ.
SCENE_KEY = b"opalray.scene"


def png_chunks(data):
    """The chunks of a PNG, less its text chunks naming the scene."""
    pos, chunks = len(PNG_SIGNATURE), []
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos : pos + 4])
        kind = data[pos + 4 : pos + 8]
        body = data[pos + 8 : pos + 8 + length]
        pos += 12 + length
        if kind in (b"iTXt", b"tEXt", b"zTXt") and body.startswith(SCENE_KEY + b"\0"):
            continue
        chunks.append((kind, body))
    return chunks


def exr_parts(data):
    """A single-part OpenEXR's header attributes (less the scene's), its chunk offsets
    relative to the first, and its chunk bytes."""
    (version,) = struct.unpack("<I", data[4:8])
    if version & 0x1000:
        raise ValueError("multi-part OpenEXR")
    pos, attrs = 8, []
    while data[pos] != 0:
        name_end = data.index(b"\0", pos)
        type_end = data.index(b"\0", name_end + 1)
        (size,) = struct.unpack("<i", data[type_end + 1 : type_end + 5])
        name = data[pos:name_end]
        value = data[type_end + 5 : type_end + 5 + size]
        pos = type_end + 5 + size
        if name != SCENE_KEY:
            attrs.append((name, data[name_end + 1 : type_end], value))
    header_end = pos + 1
    (first,) = struct.unpack("<Q", data[header_end : header_end + 8])
    count = (first - header_end) // 8
    offsets = struct.unpack(f"<{count}Q", data[header_end : header_end + 8 * count])
    return attrs, [o - first for o in offsets], data[first:]


def parts(path):
    with open(path, "rb") as f:
        data = f.read()
    if data.startswith(PNG_SIGNATURE):
        return png_chunks(data)
    if data.startswith(EXR_MAGIC):
        return exr_parts(data)
    if path.endswith(".json"):
        value = json.loads(data)
        # A frames folder's key: a hash of the scene's text.
        if isinstance(value, dict):
            value.pop("sweep", None)
        return value
    raise ValueError("neither PNG, OpenEXR nor JSON")


def main():
    if len(sys.argv) != 3:
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 2
    try:
        a, b = parts(sys.argv[1]), parts(sys.argv[2])
    except (ValueError, struct.error, IndexError, json.JSONDecodeError) as err:
        print(f"identity-pixels: {err}", file=sys.stderr)
        return 2
    return 0 if a == b else 1


if __name__ == "__main__":
    sys.exit(main())
